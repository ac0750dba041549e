// The world's bodies as data (model.md §2, §3, §5-§7): WorldModel is the
// constant part of a scene (built once), WorldState the mutable part that
// stepWorld() (world.h) advances.
#pragma once

#include <cstdint>
#include <vector>

#include "vssim/ball.h"
#include "vssim/field.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"
#include "vssim/scene.h"
#include "vssim/speed_controller.h"

namespace vssim {

struct WorldModel {
    Field field;
    SimulationSettings settings;
    std::vector<RobotModel> robots;  // per robot, from its RobotParams
    std::vector<double> sides;       // per robot, m (copied out for collision detection)
    BallParams ball;
};

WorldModel makeWorldModel(const Scene& scene);

struct WorldState {
    std::int64_t step = 0;  // steps taken; simulated time = step * dt
    double time = 0.0;      // s, always step * dt (not accumulated)
    std::vector<RobotState> robots;
    std::vector<Voltages> voltages;  // applied (clamped) voltages of each robot, V
    BallState ball;
    // Per robot: its on-board speed loop (speed_controller.h), which sets
    // `voltages` at its samples while active.
    std::vector<SpeedLoopState> speedLoops;
    // Per robot: non-zero while it is off the field (FIRASim's turnon false):
    // it keeps its pose, at rest and at 0 V, and nothing touches it or is
    // touched by it; viewers (camera, vision, the app) do not show it.
    std::vector<char> offField;
};

WorldState initialWorldState(const Scene& scene);

// The first body whose state holds a NaN or an infinity: robot i as i, the
// ball as robots.size(); -1 when every number is finite. Such a state cannot
// be stepped on meaningfully (an unstable step, extreme parameters), so
// whoever runs the world checks it and stops.
int firstNonFiniteBody(const WorldState& state);

// Whether contact tests go through the broad phase (broad_phase.h): when the
// scene allows it and has enough robots for sorting to pay.
bool useBroadPhase(const WorldModel& model, const WorldState& state);

}  // namespace vssim
