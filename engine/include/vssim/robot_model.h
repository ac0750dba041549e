// Matrices of the robot's motor dynamics, M u' + B u = K e (model.md §2,
// eq. 7), precomputed once from RobotParams, plus the derived outputs.
#pragma once

#include <Eigen/Core>

#include "vssim/robot_params.h"
#include "vssim/robot_state.h"

namespace vssim {

struct RobotModel {
    RobotParams params;
    Eigen::Matrix2d Tw;     // wheel speeds (w_d, w_e) -> body velocity (v, w)
    Eigen::Matrix2d TwInv;  // body velocity -> wheel speeds
    Eigen::Matrix2d M;      // generalized mass matrix, [kg, kg m; kg m, kg m^2]
    Eigen::Matrix2d B;      // generalized damping matrix
    Eigen::Matrix2d K;      // voltage input matrix
    Eigen::Matrix2d Minv;   // M^-1
    Eigen::Matrix2d A;      // -M^-1 B: u' = A u + G e
    Eigen::Matrix2d G;      // M^-1 K
};

RobotModel makeRobotModel(const RobotParams& params);

// Voltages clamped to +-max_voltage; NaN becomes 0 V (a dead input, never a NaN state).
Voltages clampVoltages(const RobotParams& params, const Voltages& e);

// u' = A u + G e, the velocity part of eq. 8.
Eigen::Vector2d velocityDerivative(const RobotModel& model, const Eigen::Vector2d& u,
                                   const Voltages& e);

// u_inf = B^-1 K e, the steady state under constant voltages.
Eigen::Vector2d steadyStateVelocity(const RobotModel& model, const Voltages& e);

// Quantities a user wants to see; not part of the state.
struct RobotOutputs {
    double wheel_speed_right = 0.0;  // w_d, rad/s
    double wheel_speed_left = 0.0;   // w_e, rad/s
    double current_right = 0.0;      // i_d, A
    double current_left = 0.0;       // i_e, A
    double torque_right = 0.0;       // tau_d delivered to the wheel, N m
    double torque_left = 0.0;        // tau_e, N m
};

RobotOutputs computeRobotOutputs(const RobotModel& model, const RobotState& state,
                                 const Voltages& e);

}  // namespace vssim
