#include "vssim/robot_model.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace vssim {

RobotModel makeRobotModel(const RobotParams& p) {
    RobotModel m;
    m.params = p;
    const double rd = p.right.wheel_radius;
    const double re = p.left.wheel_radius;
    const double b = p.wheel_base;
    // model.md §1: u = Tw w_w.
    m.Tw << rd / 2.0, re / 2.0,
            rd / b, -re / b;
    m.TwInv = m.Tw.inverse();
    const Eigen::Matrix2d TwInvT = m.TwInv.transpose();  // T_w^{-T}, maps wheel torques to (F, T)

    // model.md §2 (eq. 7): M u' + B u = K e.
    const Eigen::Matrix2d rotor = Eigen::Vector2d(p.right.rotor_inertia, p.left.rotor_inertia).asDiagonal();
    const Eigen::Matrix2d motorDamping =
        Eigen::Vector2d(p.right.k * p.right.k / p.right.resistance + p.right.friction,
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
    return m;
}

static double clampOne(double e, double limit) {
    if (std::isnan(e)) return 0.0;
    return std::clamp(e, -limit, limit);
}

Voltages clampVoltages(const RobotParams& params, const Voltages& e) {
    return {clampOne(e.right, params.max_voltage), clampOne(e.left, params.max_voltage)};
}

Eigen::Vector2d velocityDerivative(const RobotModel& model, const Eigen::Vector2d& u, const Voltages& e) {
    return model.A * u + model.G * Eigen::Vector2d(e.right, e.left);
}

Eigen::Vector2d steadyStateVelocity(const RobotModel& model, const Voltages& e) {
    return model.B.lu().solve(model.K * Eigen::Vector2d(e.right, e.left));
}

RobotOutputs computeRobotOutputs(const RobotModel& model, const RobotState& state, const Voltages& e) {
    const RobotParams& p = model.params;
    const Eigen::Vector2d u(state.v, state.omega);
    const Eigen::Vector2d wheel = model.TwInv * u;                                 // (w_d, w_e), rad/s
    const Eigen::Vector2d wheelAccel = model.TwInv * velocityDerivative(model, u, e);  // rad/s^2
    RobotOutputs out;
    out.wheel_speed_right = wheel(0);
    out.wheel_speed_left = wheel(1);
    // model.md §2: i_k = (e_k - K_k w_k) / R_k;  tau_k = K_k i_k - J_k w'_k - beta_k w_k.
    out.current_right = (e.right - p.right.k * wheel(0)) / p.right.resistance;
    out.current_left = (e.left - p.left.k * wheel(1)) / p.left.resistance;
    out.torque_right = p.right.k * out.current_right - p.right.rotor_inertia * wheelAccel(0) -
                       p.right.friction * wheel(0);
    out.torque_left = p.left.k * out.current_left - p.left.rotor_inertia * wheelAccel(1) -
                      p.left.friction * wheel(1);
    return out;
}

}  // namespace vssim
