// Fixed-step integrators for the robot (model.md eq. 8) and the ball (eq. 9),
// with voltages held constant over the step (model.md §7).
#pragma once

#include "vssim/ball.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"

namespace vssim {

enum class Integrator {
    Euler,  // explicit Euler, first order (the paper's)
    Rk4,    // classical Runge-Kutta, fourth order (the paper's)
    Exact,  // closed-form velocity and heading, Gauss-Legendre position (exact_integrator.h)
};

// Advances one robot by h seconds under constant (already clamped) voltages e.
// For Integrator::Exact this builds the step's table each call; the world
// precomputes and reuses them instead (exact_integrator.h).
void integrateRobot(const RobotModel& model, RobotState& state, const Voltages& e, double h, Integrator method);

// The longest step, s, for which `method` is stable on a linear system whose
// fastest mode decays at `fastestRate` (1/s, e.g. RobotModel::fastestRate):
// 2/rate for Euler, 2.785/rate for RK4 (the real-axis ends of their
// stability regions), infinite for the exact integrator.
double stableStepLimit(Integrator method, double fastestRate);

// Advances the ball by h seconds (free flight with viscous damping).
void integrateBall(const BallParams& params, BallState& state, double h, Integrator method);

}  // namespace vssim
