#include "vssim/integrator.h"

#include "vssim/geometry.h"

#include "vssim/exact_integrator.h"

#include <cmath>

namespace vssim {
namespace {

// The robot's full state (v, w, x, y, theta) of model.md eq. 8 as a plain
// vector, so Euler and RK4 are written once over it.
using RobotVector = Eigen::Matrix<double, 5, 1>;

RobotVector pack(const RobotState& s) { return (RobotVector() << s.v, s.omega, s.x, s.y, s.theta).finished(); }

void unpack(const RobotVector& q, RobotState& s) {
    s.v = q(0);
    s.omega = q(1);
    s.x = q(2);
    s.y = q(3);
    s.theta = q(4);
}

// Right-hand side of eq. 8 for constant voltages.
RobotVector robotRate(const RobotModel& model, const RobotVector& q, const Voltages& e) {
    const Eigen::Vector2d du = velocityDerivative(model, q.head<2>(), e);
    const CosSin h = cosSin(q(4));
    RobotVector r;
    r << du(0), du(1), q(0) * h.c, q(0) * h.s, q(1);
    return r;
}

// The ball's state (x, y, vx, vy) and eq. 9: v' = -(beta_b/m_b) v, p' = v.
using BallVector = Eigen::Vector4d;

BallVector ballRate(double decay, const BallVector& q) { return BallVector(q(2), q(3), -decay * q(2), -decay * q(3)); }

template <typename Vector, typename Rate>
Vector stepOnce(const Vector& q, double h, Integrator method, Rate rate) {
    if (method == Integrator::Euler) return q + h * rate(q);
    const Vector k1 = rate(q);
    const Vector k2 = rate(q + (0.5 * h) * k1);
    const Vector k3 = rate(q + (0.5 * h) * k2);
    const Vector k4 = rate(q + h * k3);
    return q + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

// One RK4 step of eq. 8 in plain doubles: the same operations in the same
// order as stepOnce over robotRate (each stage's state q + (h/2) k, the
// rates (A u + G e, v cos theta, v sin theta, w), and q + (h/6)(k1 + 2 k2 +
// 2 k3 + k4) component by component), so the same bits, without the 5-vector
// temporaries that go through memory between the stages. G e does not change
// within the step and is computed once.
void rk4RobotStep(const RobotModel& model, RobotState& state, const Voltages& e, double h) {
    const double a00 = model.A(0, 0), a01 = model.A(0, 1), a10 = model.A(1, 0), a11 = model.A(1, 1);
    const double g0 = model.G(0, 0) * e.right + model.G(0, 1) * e.left;
    const double g1 = model.G(1, 0) * e.right + model.G(1, 1) * e.left;
    struct Rate {
        double dv, dw, dx, dy, dtheta;
    };
    const auto rate = [&](double v, double w, double theta) {
        const CosSin c = cosSin(theta);
        return Rate{(a00 * v + a01 * w) + g0, (a10 * v + a11 * w) + g1, v * c.c, v * c.s, w};
    };
    const double v = state.v, w = state.omega, x = state.x, y = state.y, theta = state.theta;
    const double half = 0.5 * h;
    const Rate k1 = rate(v, w, theta);
    const Rate k2 = rate(v + half * k1.dv, w + half * k1.dw, theta + half * k1.dtheta);
    const Rate k3 = rate(v + half * k2.dv, w + half * k2.dw, theta + half * k2.dtheta);
    const Rate k4 = rate(v + h * k3.dv, w + h * k3.dw, theta + h * k3.dtheta);
    const double sixth = h / 6.0;
    state.v = v + sixth * (((k1.dv + 2.0 * k2.dv) + 2.0 * k3.dv) + k4.dv);
    state.omega = w + sixth * (((k1.dw + 2.0 * k2.dw) + 2.0 * k3.dw) + k4.dw);
    state.x = x + sixth * (((k1.dx + 2.0 * k2.dx) + 2.0 * k3.dx) + k4.dx);
    state.y = y + sixth * (((k1.dy + 2.0 * k2.dy) + 2.0 * k3.dy) + k4.dy);
    state.theta = theta + sixth * (((k1.dtheta + 2.0 * k2.dtheta) + 2.0 * k3.dtheta) + k4.dtheta);
}

}  // namespace

void integrateRobot(const RobotModel& model, RobotState& state, const Voltages& e, double h, Integrator method) {
    if (method == Integrator::Exact) {
        integrateRobotExact(model, makeExactStepTable(model, h, exactPanelsFor(model, state, e, h)), state, e);
        return;
    }
    if (method == Integrator::Rk4) {
        rk4RobotStep(model, state, e, h);
        return;
    }
    const RobotVector q =
        stepOnce(pack(state), h, method, [&](const RobotVector& s) { return robotRate(model, s, e); });
    unpack(q, state);
}

double stableStepLimit(Integrator method, double fastestRate) {
    if (method == Integrator::Exact || !(fastestRate > 0.0)) return INFINITY;
    // |1 + z| <= 1 for Euler; |1 + z + z^2/2 + z^3/6 + z^4/24| <= 1 for RK4 on the negative real axis.
    return (method == Integrator::Euler ? 2.0 : 2.785293563405282) / fastestRate;
}

void integrateBall(const BallParams& params, BallState& state, double h, Integrator method) {
    if (method == Integrator::Exact) {
        integrateBallExact(params, state, h);
        return;
    }
    const double decay = params.friction / params.mass;  // 1/s
    const BallVector q = stepOnce(BallVector(state.x, state.y, state.vx, state.vy), h, method,
                                  [&](const BallVector& s) { return ballRate(decay, s); });
    state.x = q(0);
    state.y = q(1);
    state.vx = q(2);
    state.vy = q(3);
}

}  // namespace vssim
