// Shared fixtures for the engine tests: parameter sets and small scenes.
#pragma once

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <string>
#include <vector>

#include "vssim/robot_params.h"
#include "vssim/scene.h"
#include "vssim/state_hash.h"
#include "vssim/world.h"

namespace vssim::test {

// A robot whose sides differ everywhere (a real robot's never match).
inline RobotParams asymmetricParams() {
    RobotParams p;
    p.mass = 0.2;
    p.inertia = 2.1e-4;
    p.wheel_base = 0.062;
    p.right = {0.0255, 11.0, 0.095, 1.3e-5, 1.2e-4};
    p.left = {0.0245, 12.5, 0.085, 0.8e-5, 0.9e-4};
    return p;
}

// Relative difference, safe at zero.
inline double relativeError(double got, double want) { return std::abs(got - want) / std::max(1e-300, std::abs(want)); }

// FNV-1a over the bytes of every double of a world state: equal hashes mean
// bit-identical states (vssim/state_hash.h, shared with `vssim stress`).
using vssim::hashState;

// A scene on a square box (walls at +-fieldSide/2, m) with the given
// robots (default parameters, named r0, r1, ...) and the ball, integrated
// exactly.
inline Scene boxScene(const std::vector<RobotState>& robots, const BallState& ball, double fieldSide = 3.0) {
    Scene s;
    s.field = makeRectangularField(fieldSide, fieldSide);
    s.simulation.integrator = Integrator::Exact;
    for (std::size_t i = 0; i < robots.size(); ++i) {
        RobotSpec r;
        r.name = "r" + std::to_string(i);
        r.initial = robots[i];
        s.robots.push_back(r);
    }
    s.ball = ball;
    return s;
}

// The largest distance between the same body's centre in two states, m.
inline double maxPositionDifference(const WorldState& a, const WorldState& b) {
    double d = std::hypot(a.ball.x - b.ball.x, a.ball.y - b.ball.y);
    for (std::size_t i = 0; i < a.robots.size(); ++i)
        d = std::max(d, std::hypot(a.robots[i].x - b.robots[i].x, a.robots[i].y - b.robots[i].y));
    return d;
}

// The references a run with contacts at their time of impact is judged
// against: the same scene with fixed steps of its dt (contacts at the end
// of a step, up to dt late) and with fixed steps of 10 us (at most 10 us
// late).
struct FixedStepReferences {
    Scene grid;
    Scene fine;
};
inline FixedStepReferences fixedStepReferences(const Scene& scene) {
    FixedStepReferences r{scene, scene};
    r.grid.simulation.long_steps = false;
    r.fine.simulation.long_steps = false;
    r.fine.simulation.dt = 1e-5;
    return r;
}

inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

inline RobotSpec robotAt(const char* name, double x, double y, double theta, double v = 0.0) {
    RobotSpec r;
    r.name = name;
    r.initial.x = x;
    r.initial.y = y;
    r.initial.theta = theta;
    r.initial.v = v;
    return r;
}

}  // namespace vssim::test
