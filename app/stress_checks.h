// The checks of `vssim stress` (docs/model.md, "Stress testing"): plain
// functions of a world state, and a checker that keeps the worst figures of
// one run, so that tests can feed them hand-made states with a known fault.
#pragma once

#include <QStringList>
#include <cstdint>

#include "vssim/world.h"

namespace vssim::stress {

// Limits above which a run fails.
constexpr double kMaxOutside = 1e-9;     // m: any vertex or the ball's edge beyond the field
constexpr double kMaxOverlap = 1e-3;     // m: penetration between two bodies after a step
constexpr double kMaxEnergyGain = 1e-9;  // kinetic energy created in a step, relative to the energy before it

// Every double of the state (poses, velocities, voltages, ball) is finite.
bool isFinite(const WorldState& state);

// The largest distance by which a robot's vertex or the ball's edge lies
// beyond the field's walls (the chain: the goals are floor, the corner
// triangles and the solid behind the posts are not), or a post lies inside
// a robot, m; negative when everything is inside, +inf when the state is not
// finite.
double worstOutside(const WorldModel& model, const WorldState& state);

// The deepest contact between two bodies (robot-robot, robot-ball; wall
// contacts are worstOutside's business), m; 0 when nothing touches. The
// state must be finite.
double worstOverlap(const WorldModel& model, const WorldState& state);

// Total kinetic energy of the robots (1/2 u^T M u, rotor inertia included)
// and the ball, J (collision_response.h kineticEnergy).
double kineticEnergyOf(const WorldModel& model, const WorldState& state);

// The worst figures of one run. Times are simulated seconds.
struct RunFigures {
    std::int64_t steps = 0;           // steps of dt taken
    std::int64_t contacts = 0;        // contacts found, summed over the steps
    bool finite = true;               // no NaN or infinity ever appeared
    double nonFiniteTime = 0.0;       // s, when it first did
    double outside = 0.0;             // m, worst distance outside the field (0 when always inside)
    double outsideTime = 0.0;         // s
    double overlap = 0.0;             // m, worst overlap between bodies
    double overlapTime = 0.0;         // s
    bool energyMeasured = false;      // a zero-voltage run: the energy figures mean something
    double energyGain = 0.0;          // J, largest kinetic energy created by the contacts of one step (RunChecker)
    double energyGainRelative = 0.0;  // the largest such gain divided by the energy before the step
    double energyTime = 0.0;          // s, when the largest relative increase happened
    bool determinismChecked = false;
    bool deterministic = true;  // a second run ended in a bit-identical state
};

// Feeds one run's states to the checks, after every step (or every advance).
//
// Energy (zero-voltage runs only): over a step with contacts the kinetic
// energy may only fall, since the motors add nothing at 0 V and friction
// only dissipates. The reference is the energy the step would have ended
// with had there been no contacts: the state before the step integrated by
// the run's integrator alone (integrator.h). When the world split the step
// into sub-steps (contacts between them), it is the energy before the step,
// a looser bound. "Created" is the energy after the step minus the reference.
class RunChecker {
public:
    // measureEnergy: all voltages are zero for the whole run.
    RunChecker(const WorldModel& model, const WorldState& initial, bool measureEnergy);

    // The state about to be stepped (needed for the energy check only).
    void beforeStep(const WorldState& state);

    // The state after a step of the run that found `contacts` contacts in
    // `substeps` sub-steps (0: not known, e.g. after an advance of many
    // steps). Returns false once the state is not finite (stop the run there).
    bool afterStep(const WorldState& state, std::int64_t contacts, int substeps = 0);

    const RunFigures& figures() const { return figures_; }

private:
    const WorldModel& model_;
    RunFigures figures_;
    double energy_ = 0.0;  // J, after the last step
    WorldState before_;    // the state given to beforeStep
    bool haveBefore_ = false;
};

// What failed, one sentence each ("overlap 2.1e-03 m > 1e-03 m at t = 1.234 s");
// empty when the run passed every check.
QStringList failedChecks(const RunFigures& figures);

}  // namespace vssim::stress
