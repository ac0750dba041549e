#include "vssim/robot_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

namespace {

// The modes of A (model.md §2): real eigenvalues lambda_1 >= lambda_2 (the
// slowest first) and the projectors P_1 = (A - lambda_2 I)/(lambda_1 - lambda_2),
// P_2 = I - P_1. When the two rates (nearly) coincide, A is (nearly) a
// multiple of I: one mode with P = I, at the slower rate.
void computeModes(RobotModel& m) {
    const double half = 0.5 * m.A.trace();
    const double disc = std::max(0.0, half * half - m.A.determinant());  // >= 0 in exact arithmetic
    const double root = std::sqrt(disc);
    m.modeRate = {half + root, half - root};
    m.fastestRate = std::max(std::abs(m.modeRate[0]), std::abs(m.modeRate[1]));
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    if (root > 1e-9 * m.fastestRate) {
        m.modeProjector[0] = (m.A - m.modeRate[1] * I) / (2.0 * root);
        m.modeProjector[1] = I - m.modeProjector[0];
    } else {
        m.modeRate[1] = m.modeRate[0];
        m.modeProjector[0] = I;
        m.modeProjector[1] = Eigen::Matrix2d::Zero();
    }
}

}  // namespace

RobotModel makeRobotModel(const RobotParams& p) {
    RobotModel m;
    m.params = p;
    const double rd = p.right.wheel_radius;
    const double re = p.left.wheel_radius;
    const double b = p.wheel_base;
    // model.md §1: u = Tw w_w.
    m.Tw << rd / 2.0, re / 2.0, rd / b, -re / b;
    m.TwInv = m.Tw.inverse();
    const Eigen::Matrix2d TwInvT = m.TwInv.transpose();  // T_w^{-T}, maps wheel torques to (F, T)

    // model.md §2 (eq. 7): M u' + B u = K e.
    const Eigen::Matrix2d rotor = Eigen::Vector2d(p.right.rotor_inertia, p.left.rotor_inertia).asDiagonal();
    const Eigen::Matrix2d motorDamping = Eigen::Vector2d(p.right.k * p.right.k / p.right.resistance + p.right.friction,
                                                         p.left.k * p.left.k / p.left.resistance + p.left.friction)
                                             .asDiagonal();
    const Eigen::Matrix2d gain =
        Eigen::Vector2d(p.right.k / p.right.resistance, p.left.k / p.left.resistance).asDiagonal();

    m.M = Eigen::Vector2d(p.mass, p.inertia).asDiagonal();
    m.M += TwInvT * rotor * m.TwInv;
    m.B = Eigen::Vector2d(p.friction_linear, p.friction_angular).asDiagonal();
    m.B += TwInvT * motorDamping * m.TwInv;
    m.K = TwInvT * gain;
    m.Minv = m.M.inverse();
    m.A = -m.Minv * m.B;
    m.G = m.Minv * m.K;
    m.steadyGain = m.B.lu().solve(m.K);
    computeModes(m);
    return m;
}

Eigen::Vector2d velocityDerivative(const RobotModel& model, const Eigen::Vector2d& u, const Voltages& e) {
    return model.A * u + model.G * Eigen::Vector2d(e.right, e.left);
}

Eigen::Vector2d steadyStateVelocity(const RobotModel& model, const Voltages& e) {
    return model.B.lu().solve(model.K * Eigen::Vector2d(e.right, e.left));
}

Eigen::Vector2d velocityAfter(const RobotModel& model, const RobotState& state, const Voltages& e, double t) {
    const Eigen::Vector2d target = model.steadyGain * Eigen::Vector2d(e.right, e.left);
    const Eigen::Vector2d offset = Eigen::Vector2d(state.v, state.omega) - target;
    Eigen::Vector2d u = target;
    for (int k = 0; k < 2; ++k) u += std::exp(model.modeRate[k] * t) * (model.modeProjector[k] * offset);
    return u;
}

Eigen::Vector2d velocityBound(const RobotModel& model, const RobotState& state, const Voltages& e) {
    const Eigen::Vector2d u0(state.v, state.omega);
    const Eigen::Vector2d target = model.steadyGain * Eigen::Vector2d(e.right, e.left);
    Eigen::Vector2d bound = Eigen::Vector2d::Zero();
    for (int k = 0; k < 2; ++k)
        bound += (model.modeProjector[k] * u0).cwiseAbs().cwiseMax((model.modeProjector[k] * target).cwiseAbs());
    if (!bound.allFinite()) return Eigen::Vector2d::Constant(INFINITY);
    return bound;
}

double yawRateBound(const RobotModel& model, const RobotState& state, const Voltages& e) {
    // (velocityBound's products, row 1 only: the same operations, so the same
    // bits; infinite where it is, for a state or voltages not finite, which
    // make its other row, or this one, not finite.)
    if (!std::isfinite(state.v) || !std::isfinite(state.omega)) return INFINITY;
    const Eigen::Vector2d target = model.steadyGain * Eigen::Vector2d(e.right, e.left);
    double bound = 0.0;
    for (int k = 0; k < 2; ++k) {
        const Eigen::Matrix2d& P = model.modeProjector[k];
        const double start = P(1, 0) * state.v + P(1, 1) * state.omega;
        const double end = P(1, 0) * target(0) + P(1, 1) * target(1);
        bound += std::max(std::abs(start), std::abs(end));
    }
    return std::isfinite(bound) && std::isfinite(target(0)) ? bound : INFINITY;
}

double pointSpeedBound(const RobotModel& model, const RobotState& state, const Voltages& e) {
    const Eigen::Vector2d bound = velocityBound(model, state, e);
    return bound(0) + boundingRadius(model.params.side) * bound(1);
}

ModeProgress modeProgress(const RobotModel& model, double T) {
    ModeProgress p;
    p.T = T;
    p.rate = model.modeRate;
    for (int k = 0; k < 2; ++k) p.covered[k] = -std::expm1(model.modeRate[k] * T);
    return p;
}

VelocityRange velocityRangeWithin(const RobotModel& model, const RobotState& state, const Voltages& e,
                                  const ModeProgress& progress) {
    const Eigen::Vector2d u0(state.v, state.omega);
    const Eigen::Vector2d target = model.steadyGain * Eigen::Vector2d(e.right, e.left);
    VelocityRange range;
    for (int k = 0; k < 2; ++k) {
        // The mode's share goes along a segment from P_k u0 towards P_k u_inf
        // and has covered the fraction 1 - e^(rate_k T) of it at T.
        const Eigen::Vector2d start = model.modeProjector[k] * u0, end = model.modeProjector[k] * target;
        const Eigen::Vector2d atHorizon = start + progress.covered[k] * (end - start);
        range.low += start.cwiseMin(atHorizon);
        range.high += start.cwiseMax(atHorizon);
        range.magnitude += start.cwiseAbs().cwiseMax(atHorizon.cwiseAbs());
    }
    if (!range.magnitude.allFinite()) range.magnitude = Eigen::Vector2d::Constant(INFINITY);
    return range;
}

double robotTravelBound(const RobotModel& model, const RobotState& state, const Voltages& e,
                        const ModeProgress& progress, double arm) {
    const double rho = arm;  // m
    const double T = progress.T;
    const Eigen::Vector2d u0(state.v, state.omega);
    const Eigen::Vector2d target = model.steadyGain * Eigen::Vector2d(e.right, e.left);
    double travel = 0.0;
    for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d start = model.modeProjector[k] * u0, end = model.modeProjector[k] * target;
        const double startSpeed = std::abs(start(0)) + rho * std::abs(start(1));  // m/s
        const double endSpeed = std::abs(end(0)) + rho * std::abs(end(1));        // m/s
        // int_0^T e^(l t) dt = (1 - e^(l T)) / (-l), or T when l = 0.
        const double rate = model.modeRate[k];
        const double decaying = rate < 0.0 ? progress.covered[k] / -rate : T;  // s
        travel += startSpeed * decaying + endSpeed * (T - decaying);
    }
    return std::isfinite(travel) ? travel : INFINITY;
}

double robotTravelBound(const RobotModel& model, const RobotState& state, const Voltages& e, double T, double arm) {
    return robotTravelBound(model, state, e, modeProgress(model, T), arm);
}

RobotOutputs computeRobotOutputs(const RobotModel& model, const RobotState& state, const Voltages& e) {
    const RobotParams& p = model.params;
    const Eigen::Vector2d u(state.v, state.omega);
    const Eigen::Vector2d wheel = model.TwInv * u;                                     // (w_d, w_e), rad/s
    const Eigen::Vector2d wheelAccel = model.TwInv * velocityDerivative(model, u, e);  // rad/s^2
    RobotOutputs out;
    out.wheel_speed_right = wheel(0);
    out.wheel_speed_left = wheel(1);
    // model.md §2: i_k = (e_k - K_k w_k) / R_k;  tau_k = K_k i_k - J_k w'_k - beta_k w_k.
    out.current_right = (e.right - p.right.k * wheel(0)) / p.right.resistance;
    out.current_left = (e.left - p.left.k * wheel(1)) / p.left.resistance;
    out.torque_right =
        p.right.k * out.current_right - p.right.rotor_inertia * wheelAccel(0) - p.right.friction * wheel(0);
    out.torque_left = p.left.k * out.current_left - p.left.rotor_inertia * wheelAccel(1) - p.left.friction * wheel(1);
    return out;
}

}  // namespace vssim
