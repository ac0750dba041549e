// Physical parameters of one differential-drive robot (model.md §1, §2, §9).
// SI units throughout. Subscript d (right) and e (left) as in model.md; the
// two sides are independent and nothing in the engine assumes they match.
#pragma once

#include "vssim/speed_controller.h"

namespace vssim {

// One wheel's DC motor, referred to the wheel (gearbox folded in).
struct MotorParams {
    double wheel_radius = 0.025;  // r_k, m
    double resistance = 12.0;     // R_k, armature resistance, ohm
    double k = 0.09;              // K_k, back-EMF = torque constant, V s/rad (= N m/A)
    double rotor_inertia = 1e-5;  // J_k, rotor + gear inertia at the wheel, kg m^2
    double friction = 1e-4;       // beta_k, motor viscous friction at the wheel, N m s/rad
};

struct RobotParams {
    double side = 0.075;                          // s, cube side, m
    double mass = 0.18;                           // m, kg
    double inertia = 0.18 * 0.075 * 0.075 / 6.0;  // J, yaw inertia, kg m^2 (uniform cube: m s^2/6)
    double wheel_base = 0.065;                    // b, distance between the wheels, m
    double friction_linear = 0.05;                // beta_l, N s/m
    double friction_angular = 0.0002;             // beta_theta, N m s/rad
    double max_voltage = 7.4;                     // e_max, commands are clamped to +-e_max, V
    MotorParams right;                            // side d
    MotorParams left;                             // side e
    // The on-board wheel-speed loop (firmware, not physics): used when the
    // robot is given wheel-speed targets instead of voltages.
    SpeedControllerParams speed_controller;
};

}  // namespace vssim
