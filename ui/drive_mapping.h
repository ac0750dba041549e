// Maps a driver's stick (or keys) to the two motor voltages of a
// differential-drive robot. Pure functions: no state, no Qt.
#pragma once

#include "vssim/robot_state.h"
#include "vssim/speed_controller.h"

namespace vssim {

enum class DriveMapping {
    // One stick: y is forward (+) / backward (-), x is the turn
    // (x > 0 turns clockwise, seen from above: the right wheel gets less).
    Arcade,
    // Two sticks, one per wheel: y is the left stick's y (left wheel),
    // x is the right stick's y (right wheel).
    Tank,
};

// Voltages (V) for stick values x, y in [-1, 1] (dimensionless; values
// outside are clamped, NaN counts as 0). maxVoltage (V, >= 0) is what a
// full deflection gives.
//
// Arcade: forward f = y, turn t = x;
//     right = (f - t) * maxVoltage,  left = (f + t) * maxVoltage,
//   and when |f| + |t| > 1 both sides are divided by |f| + |t|, so neither
//   exceeds maxVoltage and right/left keeps the ratio the stick asked for.
//   x = 0, y = 1: both +maxVoltage (straight ahead); x = 1, y = 0:
//   left +maxVoltage, right -maxVoltage (spin clockwise in place).
// Tank:
//     left = y * maxVoltage,  right = x * maxVoltage.
Voltages stickToVoltages(double x, double y, DriveMapping mapping, double maxVoltage);

// Driving through the robot's speed loop instead (the Drive dock's "wheel
// speeds" switch): the same stick, read as a fraction of the robot's free
// wheel speed. Each side's voltage / maxVoltage (clamped to [-1, 1]; NaN,
// or maxVoltage <= 0, gives 0) times freeWheelSpeed (rad/s, >= 0: what the
// wheels reach at maxVoltage on both motors).
WheelSpeeds voltagesToWheelSpeeds(const Voltages& volts, double maxVoltage, double freeWheelSpeed);

// Stick dead zone. value in [-1, 1] (clamped), deadzone in [0, 1)
// (dimensionless). |value| <= deadzone gives 0; beyond, the rest of the
// travel is rescaled linearly so the output grows continuously from 0 at
// the edge of the dead zone to +-1 at +-1, keeping the sign. deadzone <= 0
// only clamps; deadzone >= 1 always gives 0. NaN gives 0.
double applyDeadzone(double value, double deadzone);

}  // namespace vssim
