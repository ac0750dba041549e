#include "vssim/time_of_impact.h"

#include <cmath>

namespace vssim {

RobotPath::RobotPath(const RobotModel& model, const RobotState& start, const RobotState& end, const Voltages& e,
                     double h)
    : h_(h) {
    // Derivatives of (x, y, theta) at an end: (v cos, v sin, w) and, from
    // eq. 8's u' = A u + G e, (v' cos - v w sin, v' sin + v w cos, w').
    auto ends = [&](const RobotState& s, std::array<double, 3>& p, std::array<double, 3>& d,
                    std::array<double, 3>& a) {
        const Eigen::Vector2d u(s.v, s.omega);
        const Eigen::Vector2d du = model.A * u + model.G * Eigen::Vector2d(e.right, e.left);
        const double c = std::cos(s.theta), sn = std::sin(s.theta);
        p = {s.x, s.y, s.theta};
        d = {s.v * c, s.v * sn, s.omega};
        a = {du(0) * c - s.v * s.omega * sn, du(0) * sn + s.v * s.omega * c, du(1)};
    };
    std::array<double, 3> p0, d0, a0, p1, d1, a1;
    ends(start, p0, d0, a0);
    ends(end, p1, d1, a1);
    for (int k = 0; k < 3; ++k) {
        // In s = t/h: values p, first derivatives h d, second h^2 a at s = 0 and 1.
        const double f0 = p0[k], g0 = h * d0[k], q0 = h * h * a0[k];
        const double f1 = p1[k], g1 = h * d1[k], q1 = h * h * a1[k];
        // The quintic with those six conditions, coefficients of s^0 .. s^5.
        const double jump = f1 - f0;
        c_[k] = {f0,
                 g0,
                 0.5 * q0,
                 10.0 * jump - 6.0 * g0 - 4.0 * g1 - 1.5 * q0 + 0.5 * q1,
                 -15.0 * jump + 8.0 * g0 + 7.0 * g1 + 1.5 * q0 - q1,
                 6.0 * jump - 3.0 * g0 - 3.0 * g1 - 0.5 * q0 + 0.5 * q1};
    }
}

RobotState RobotPath::at(double t) const {
    const double s = h_ > 0.0 ? t / h_ : 0.0;
    auto poly = [s](const std::array<double, 6>& c) {
        return c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * (c[4] + s * c[5]))));
    };
    RobotState r;
    r.x = poly(c_[0]);
    r.y = poly(c_[1]);
    r.theta = poly(c_[2]);
    return r;
}

Eigen::Vector2d ballPositionAfter(const BallParams& params, const BallState& start, double t) {
    const double k = params.friction / params.mass;  // 1/s
    const double travelTime = k > 0.0 ? -std::expm1(-k * t) / k : t;  // s, as integrateBallExact
    return {start.x + start.vx * travelTime, start.y + start.vy * travelTime};
}

}  // namespace vssim
