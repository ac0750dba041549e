// What the engine thread publishes after every pass of its loop, for the
// GUI, the camera and the server to read: a complete, self-consistent copy.
// SnapshotBuffer hands out immutable shared snapshots: publishing swaps one
// pointer, so a reader copying (or holding) a snapshot never blocks the
// engine, and the engine never waits for a reader.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "realtime/engine_loop.h"
#include "vssim/robot_model.h"

namespace vssim {

struct Snapshot {
    double time = 0.0;       // simulated time, s
    std::int64_t step = 0;   // steps of dt taken
    std::int64_t frame = 0;  // camera instants since start/reset
    RunMode mode = RunMode::Realtime;
    bool paused = false;
    // Set when the loop halted on a non-finite state (engine_loop.h): the
    // bodies' numbers then hold NaN or infinity and are not to be drawn.
    std::optional<SimulationFault> fault;
    double speed = 1.0;                 // real-time factor (realtime mode)
    std::vector<RobotState> robots;     // m, rad, m/s, rad/s
    std::vector<char> offField;         // per robot: non-zero while off the field (FIRASim's turnon false)
    std::vector<Voltages> voltages;     // applied, V
    std::vector<RobotOutputs> outputs;  // wheel speeds (rad/s), currents (A), torques (N m)
    BallState ball;
    std::vector<RobotControl> control;  // who drives each robot
    // The game (game/match.h): its state (score, phase, half, clock, the
    // last call), and its rules and each team's control now.
    GameState game;
    GameSettings gameSettings;
    std::shared_ptr<const Scene> scene;  // the scene being run (changes only on LoadScene)
    double stepCost = 0.0;               // wall seconds spent per simulated second over the last pass
    std::int64_t publishedNs = 0;        // monotonicNs() at publication
};

// `scene`: the loop's scene, shared between snapshots until it changes.
Snapshot takeSnapshot(const EngineLoop& loop, std::shared_ptr<const Scene> scene, double stepCost, std::int64_t nowNs);

class SnapshotBuffer {
public:
    void publish(std::shared_ptr<const Snapshot> snapshot) { std::atomic_store(&current_, std::move(snapshot)); }
    // The newest snapshot (null before the first publication).
    std::shared_ptr<const Snapshot> latest() const { return std::atomic_load(&current_); }

private:
    std::shared_ptr<const Snapshot> current_;
};

}  // namespace vssim
