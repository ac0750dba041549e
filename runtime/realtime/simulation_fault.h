// A simulation whose state stopped being finite (NaN or infinity): what a run
// or the real-time loop reports when it stops, instead of stepping on garbage.
#pragma once

#include <QString>
#include <optional>

#include "vssim/world.h"

namespace vssim {

struct SimulationFault {
    double time = 0.0;  // s: the simulated instant at which the state was found non-finite
    int body = -1;      // robot index, or the robot count for the ball
    // e.g. robot "yellow0" (x = nan m, y = nan m, theta = 0.5 rad, v = inf m/s, omega = nan rad/s)
    QString bodyText;
    // "at t = 0.5 s, robot "yellow0" (...) has a non-finite state"
    QString message() const;
};

// The fault of the simulation's current state, or nothing when it is finite.
std::optional<SimulationFault> findSimulationFault(const Simulation& simulation);

}  // namespace vssim
