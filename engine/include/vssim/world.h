// The world: every body of a scene, stepped together (model.md §2, §3, §5-§7).
//
// WorldModel is the constant part (built once from a Scene), WorldState the
// mutable part; stepWorld() advances a state by one step of simulated time.
// Simulation adds the scene's voltage-command schedule on top. Nothing here
// reads a clock or keeps global state: the same scene and commands always
// give bit-identical states.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vssim/ball.h"
#include "vssim/contact.h"
#include "vssim/field.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"
#include "vssim/scene.h"

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
    std::int64_t step = 0;           // steps taken; simulated time = step * dt
    double time = 0.0;               // s, always step * dt (not accumulated)
    std::vector<RobotState> robots;
    std::vector<Voltages> voltages;  // applied (clamped) voltages of each robot, V
    BallState ball;
};

WorldState initialWorldState(const Scene& scene);

// What one step did, for statistics and tests.
struct StepReport {
    int substeps = 0;   // integration sub-steps taken to keep motion per sub-step small
    int contacts = 0;   // contacts found after integration (all passes)
    int responses = 0;  // contacts whose velocities changed
};

// Advances the state by h seconds under its current voltages: integrate every
// body, then detect and resolve contacts. When a body could move more than
// kMaxTravelFraction of the smallest body's half-size in h, the step is split
// into equal sub-steps so that no collision is tunnelled through. Bodies never
// end outside the field. Does not touch state.step / state.time.
constexpr double kMaxTravelFraction = 0.25;
StepReport stepWorld(const WorldModel& model, WorldState& state, double h);

// A scene being run: the world plus its command schedule.
class Simulation {
public:
    explicit Simulation(const Scene& scene);

    const Scene& scene() const { return scene_; }
    const WorldModel& model() const { return model_; }
    const WorldState& state() const { return state_; }
    double dt() const { return model_.settings.dt; }

    // One step of dt: apply the commands due at this step boundary, then step.
    StepReport step();

    // Sets a robot's voltages now (clamped to its +-max_voltage; NaN -> 0 V).
    void setVoltages(int robot, const Voltages& e);

    // The step index at which a command at time t (s) takes effect: the first
    // step boundary at or after t, compared with a tolerance of 1e-9 steps so
    // that t = 0.03 s with dt = 1 ms is step 30, not 31.
    static std::int64_t stepIndexAtOrAfter(double t, double dt);

    RobotOutputs robotOutputs(int robot) const;

private:
    struct ScheduledCommand {
        std::int64_t step;
        int robot;
        Voltages voltages;
    };
    Scene scene_;
    WorldModel model_;
    WorldState state_;
    std::vector<ScheduledCommand> schedule_;  // sorted by step, stable (file order on ties)
    std::size_t nextCommand_ = 0;
};

}  // namespace vssim
