// Mutable state of one robot and its motor inputs (model.md eq. 8).
#pragma once

namespace vssim {

// Field frame: origin at the field centre, x along the long side, z up.
struct RobotState {
    double x = 0.0;      // centre of mass, m
    double y = 0.0;      // m
    double theta = 0.0;  // heading of the robot's forward axis from +x, rad (counter-clockwise)
    double v = 0.0;      // forward speed along the heading, m/s
    double omega = 0.0;  // yaw rate, rad/s (counter-clockwise positive)
};

// Armature voltages, V. Positive voltage drives a wheel forward.
struct Voltages {
    double right = 0.0;  // e_d
    double left = 0.0;   // e_e
};

}  // namespace vssim
