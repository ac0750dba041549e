// Everything a run needs, as plain data: the immutable description of a
// simulation (what a scene file holds). The mutable part is WorldState.
#pragma once

#include <string>
#include <vector>

#include "vssim/ball.h"
#include "vssim/camera_settings.h"
#include "vssim/collision_model.h"
#include "vssim/field.h"
#include "vssim/game_settings.h"
#include "vssim/integrator.h"
#include "vssim/robot_params.h"
#include "vssim/robot_state.h"

namespace vssim {

struct SimulationSettings {
    // The exact integrator by default: at the same step more accurate than RK4,
    // several times faster with its long steps, and stable for any motor
    // (docs/performance.md, "Accuracy against run time" and "Speed against the
    // peers"). Euler and RK4 stay selectable.
    Integrator integrator = Integrator::Exact;
    double dt = 0.001;  // fixed step h, s
    CollisionModel collision_model = CollisionModel::Paper;
    double restitution = 1.0;  // epsilon in [0, 1], impulse model only
    // Work-skipping switches (results do not depend on them beyond rounding;
    // they exist for benchmarks and tests, not scene files).
    bool broad_phase =
        true;  // sweep-and-prune robot pairs instead of all pairs from kBroadPhaseMinRobots robots on (broad_phase.h)
    bool long_steps = true;  // exact integrator: one long step where no contact is possible (world.h)
    // Exact integrator with long steps: each contact at its time of impact
    // (time_of_impact.h) rather than at the end of the step of dt it falls
    // in. Unlike the two switches above this one changes results (by the
    // contact's timing: up to a step); false gives the fixed-step contacts,
    // for tests and benchmarks that compare the two.
    bool time_of_impact = true;
};

struct RobotSpec {
    std::string name;  // unique, e.g. "yellow0"
    Team team = Team::Yellow;
    RobotParams params;
    RobotState initial;  // pose and body velocity at t = 0
};

// A voltage change: from the first step boundary at or after time t, the
// robot's motors see (right, left) volts until its next command; or, with
// `wheelSpeeds`, its speed loop follows those targets from then on.
struct VoltageCommand {
    double t = 0.0;     // s
    int robot = 0;      // index into Scene::robots
    Voltages voltages;  // V (clamped to +-max_voltage when applied)
    bool wheelSpeeds = false;  // true: `speeds` instead of `voltages`
    WheelSpeeds speeds;        // rad/s, through the robot's speed loop (speed_controller.h)
    DriveCommand drive() const { return wheelSpeeds ? DriveCommand::ofWheelSpeeds(speeds) : DriveCommand::ofVoltages(voltages); }
};

struct Scene {
    Field field = makeRectangularField(1.50, 1.30);
    SimulationSettings simulation;
    BallParams ball_params;
    BallState ball;  // initial ball state
    std::vector<RobotSpec> robots;
    std::vector<VoltageCommand> commands;  // any order; applied in time order, ties in file order
    GameSettings game;                     // the referee's rules and the teams' controllers (game/)
    CameraSettings camera;                 // the overhead camera (camera/); ideal by default
};

}  // namespace vssim
