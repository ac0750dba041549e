// The random scenes of `vssim stress` (docs/model.md, "Stress testing").
//
// Scene number k of seed s is a function of (s, k) only: a std::mt19937
// seeded through std::seed_seq{s, k}, mapped to numbers by this file's own
// arithmetic (std::uniform_real_distribution and friends differ between
// standard libraries; the engine and seed_seq do not). So `--seed s --only k`
// rebuilds exactly the scene a failure report names, on any platform.
#pragma once

#include <cstdint>

#include "vssim/scene.h"

namespace vssim::stress {

enum class SceneKind {
    Pile,         // 6-16 robots packed in a small region with the ball among them, full voltage, signs flipping
    Alternating,  // robots spread over the field, voltages alternating +-e_max every 2-100 ms
    CornerShots,  // the ball fired at 5-10 m/s into a corner, robots near the corners
    Extreme,      // extreme but plausible robot and ball parameters: stiff, asymmetric, light, heavy
    // On an official field (3 vs 3 or 5 vs 5, with goals and corner triangles):
    GoalCorners,  // robots in the goals and against the corner triangles, full voltage, the ball fired into a goal
    PostWedge,    // the ball against a goal post, a robot behind it pushing it into the post
    InGoal,       // a robot inside each goal, others in front of it, full voltage
};
constexpr int kSceneKinds = 7;  // scene k has kind (k - 1) mod 7

const char* sceneKindName(SceneKind kind);

// Step ranges, s. Euler and RK4 draw dt log-uniformly from [kMinDt, kMaxDt];
// the exact integrator, being unconditionally stable, from [kMinDt, kMaxExactDt].
constexpr double kMinDt = 0.25e-3;
constexpr double kMaxDt = 5e-3;
constexpr double kMaxExactDt = 20e-3;

// Extreme robots are limited to mechanical time constants of at least this
// (the default robot's are 72 and 84 ms), so that every explicit step of at
// most kMaxDt stays within Euler's stability limit dt < 2 tau.
constexpr double kMinTimeConstant = 3e-3;  // s

struct StressScene {
    int number = 1;  // 1-based; with the seed it identifies the scene
    SceneKind kind = SceneKind::Pile;
    Scene scene;                  // bodies and voltage commands for `seconds`; settings are set per run
    bool hasZeroVoltage = false;  // piles: also run zeroVoltage
    Scene zeroVoltage;            // the same bodies at random velocities, no commands (all voltages 0 V)
    double restitution = 0.5;     // this scene's random restitution in [0, 1) for the impulse model
    double dtEuler = 1e-3;        // s
    double dtRk4 = 1e-3;          // s
    double dtExact = 1e-3;        // s
};

StressScene makeStressScene(std::uint32_t seed, int number, double seconds);

}  // namespace vssim::stress
