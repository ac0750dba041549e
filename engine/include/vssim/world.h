// The world: every body of a scene, stepped together (model.md §2, §3, §5-§7).
//
// WorldModel is the constant part (built once from a Scene), WorldState the
// mutable part (world_model.h); stepWorld() advances a state by one step of
// simulated time. The long-step planner (advanceTo) is in long_step_planner.cpp.
// Simulation adds the scene's voltage-command schedule on top. Nothing here
// reads a clock or keeps global state: the same scene, commands and calls
// always give bit-identical states (advanceTo cut differently agrees with
// itself to rounding; with step() too, but for the instants of contacts).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vssim/body_gaps.h"
#include "vssim/broad_phase.h"
#include "vssim/contact.h"
#include "vssim/exact_integrator.h"
#include "vssim/free_bodies.h"
#include "vssim/scene.h"
#include "vssim/time_of_impact.h"
#include "vssim/world_model.h"

namespace vssim {

// What one step did, for statistics and tests.
struct StepReport {
    int substeps = 0;   // integration sub-steps taken to keep motion per sub-step small
    int contacts = 0;   // contacts found after integration (all passes)
    int responses = 0;  // contacts whose velocities changed
};

// What Simulation::advanceTo did.
struct AdvanceReport {
    std::int64_t steps = 0;      // steps of dt advanced
    std::int64_t stepCalls = 0;  // ordinary steps (integration + contacts)
    std::int64_t longSteps = 0;  // contact-free long steps (exact integrator), each several dt
    std::int64_t replans = 0;    // stretches planned again: a contact brought a body near a free one
    std::int64_t contacts = 0;   // contacts found, summed over the steps
    std::int64_t impacts = 0;    // of those, answered at their time of impact (time_of_impact.h)
    std::int64_t freezes = 0;    // bodies frozen within a stretch, not at its start (time_of_impact)
    std::int64_t groupedStretches = 0;  // stretches whose moving bodies took them group by group (time_of_impact)
    std::int64_t groupFallbacks = 0;    // of the stretches tried so, those undone and taken with all groups together
    double firstImpact = NAN;    // s of simulated time: the earliest of those instants (NaN: none)
};

// Advances the state by h seconds under its current voltages: integrate every
// body (a robot at rest with zero voltage, or a ball at rest, is left as it
// is: its derivative is exactly zero), then detect and resolve contacts. When a body could move more than
// kMaxTravelFraction of the smallest body's half-size in h, the step is split
// into equal sub-steps so that no collision is tunnelled through. Bodies never
// end outside the field. Does not touch state.step / state.time.
constexpr double kMaxTravelFraction = 0.25;

// Optional parts of a step.
struct StepOptions {
    // Bodies known to be out of everybody's reach for this step
    // (Simulation::advanceTo): the contact tests skip them, and when
    // `frozen`, they are not integrated either (a long step moves them).
    const std::vector<char>* freeRobots = nullptr;  // non-zero entry: robot i is free
    bool freeBall = false;
    bool frozen = false;
    // With `frozen`, their speed bounds now (pointSpeedBound of their true
    // current state, m/s): the sub-steps depend on every body, frozen or not,
    // so that the results do not depend on how the run was planned.
    const std::vector<double>* frozenRobotSpeed = nullptr;
    double frozenBallSpeed = 0.0;
    // With `frozen`, frozenRobotSpeed and freeRobots, optionally: the robots
    // that are not free (increasing indices), the largest of
    // frozenRobotSpeed's entries, and the smallest of the ball's radius and
    // the robots' half sides (m): the step then looks at the listed robots
    // only, at a cost that does not grow with the free ones, to the same
    // results.
    const std::vector<int>* steppingRobots = nullptr;
    double frozenRobotFastest = 0.0;  // m/s
    double smallestHalfSize = 0.0;    // m
    // Exact integrator: reuse tables; null builds each table when needed.
    ExactTableCache* tables = nullptr;
    // Broad phase: keep the order along x between steps; null starts afresh.
    BroadPhaseScratch* broadPhase = nullptr;
};
StepReport stepWorld(const WorldModel& model, WorldState& state, double h, const StepOptions& options = {});

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

    // Advances to step index `target` (time target * dt), applying commands
    // at their steps. Other integrators take steps of dt; with the exact
    // integrator (and settings.long_steps), each stretch between voltage
    // changes is cut short only where contacts are possible. The bodies'
    // travel bounds (findFreeBodies) tell which bodies cannot touch anything
    // before the stretch ends: those take it in one step while the others
    // take steps of dt; when every body is free, the whole world takes one
    // step. A step whose contacts bring a body near a free one is undone and
    // taken again with everybody.
    // With settings.time_of_impact (the default) the others do not take steps
    // of dt either: conservative advancement on their gaps (body_gaps.h,
    // time_of_impact.h) moves them as many whole steps as no gap can close
    // in, and a step in which one may close finds the instant it does; the
    // contact is answered there, and the rest of that step and the steps
    // after it are ordinary ones until the bodies no longer touch (a robot
    // pushing on a wall stays on the grid). A moving body none of whose gaps
    // can close before the stretch ends freezes where it is and catches up
    // in one step at the stretch's end, like those free from its start
    // (AdvanceReport::freezes). Moving bodies that cannot reach each other
    // before the stretch ends (their discs of reach plus travel apart) fall
    // into groups, and each group takes the stretch on its own, the others
    // standing still meanwhile: a pair about to meet cuts the steps of its
    // own group only (AdvanceReport::groupedStretches). Should a contact
    // send a body of one group towards another after all, the stretch is
    // undone and taken again with the groups together
    // (AdvanceReport::groupFallbacks). The states then agree with
    // step()'s to rounding until the first contact, which comes up to a step
    // earlier: at its instant, not at the end of its step.
    // Without it, long steps end on multiples of dt, so the contacts happen
    // at the same steps as with step(), and the states agree with step() to
    // rounding. Either way the results do not depend on how the calls are
    // cut beyond rounding, and reruns are bit-identical.
    AdvanceReport advanceTo(std::int64_t target);

    // How many whole steps of dt (at most `wanted`) the bodies can move with
    // no contact possible; exposed for tests.
    std::int64_t contactFreeSteps(std::int64_t wanted) const;

    // Sets a robot's voltages now (clamped to its +-max_voltage; NaN -> 0 V);
    // its speed loop, if it was following wheel speeds, stops.
    void setVoltages(int robot, const Voltages& e);
    // Wheel-speed targets for a robot's speed loop (speed_controller.h), rad/s
    // (NaN -> 0, clamped to +-kMaxWheelSpeedTarget). A loop that was off
    // starts afresh (integrators at 0) and samples first at the first of its
    // instants k / rate at or after now; one already on keeps its state and
    // takes the new targets at its next sample. From then on the loop sets
    // the robot's voltages at each sample (the first step boundary at or
    // after k / rate, at most once a step) until setVoltages.
    void setWheelSpeeds(int robot, const WheelSpeeds& target);
    // Either of the two above.
    void drive(int robot, const DriveCommand& command);
    // Takes a robot off the field (false) or brings it back where it is
    // (true; placeRobot moves it): off the field it stops (0 V, at rest, its
    // loop off), is not integrated and takes part in no contact, and
    // setVoltages and setWheelSpeeds leave it alone (WorldState::offField).
    void setOnField(int robot, bool onField);
    bool onField(int robot) const { return !state_.offField[robot]; }
    // Moves a body now (a person dragging it, a client placing it). The
    // caller checks that it lies inside the field (robotInsideField,
    // discInsideField); overlaps with other bodies are resolved by the next
    // step's contacts.
    void placeRobot(int robot, const RobotState& pose);
    void placeBall(const BallState& ball);

    // The step index at which a command at time t (s) takes effect: the first
    // step boundary at or after t, compared with a tolerance of 1e-9 steps so
    // that t = 0.03 s with dt = 1 ms is step 30, not 31.
    static std::int64_t stepIndexAtOrAfter(double t, double dt);

    RobotOutputs robotOutputs(int robot) const;

    // The exact integrator's step tables are a cache (exact_integrator.h):
    // results never depend on it. By default each Simulation keeps its own.
    // A caller stepping many simulations of the same robots on one thread
    // (BatchWorld) may lend them one cache, so that the tables are built
    // once and stay warm in the processor's cache; it must outlive its use
    // and serve one thread at a time. nullptr: back to the simulation's own.
    void lendTableCache(ExactTableCache* cache) { lentTables_ = cache; }

private:
    // A command of scene_.commands (by index: a schedule of a thousand
    // robots' commands stays small) and the step it takes effect at.
    struct ScheduledCommand {
        std::int64_t step;
        std::size_t command;
    };
    Scene scene_;
    WorldModel model_;
    WorldState state_;
    void applyDueCommands();
    // The speed loops' samples due at the current step: each active loop
    // measures its wheels and sets the robot's voltages.
    void runSpeedLoops();
    // The step of the next sample of any active speed loop (or `limit`).
    std::int64_t nextLoopStep(std::int64_t limit) const;
    bool anyOffField() const;
    // Integrates the chosen bodies (all robots when `robots` is null) by h, no contacts.
    void advanceBodies(double h, const std::vector<char>* robots, bool ball);
    // The same for the listed robots (and the ball), at a cost that grows with them only.
    void advanceListed(double h, const std::vector<int>& robots, bool ball);
    // The same for one body: robot `body`, or the ball when it is the robot count.
    void advanceBody(std::size_t body, double h);
    void finishStep(std::int64_t steps);
    StepReport ordinaryStep();  // one stepWorld of dt, and the clock moves on by dt
    ExactTableCache* tables() { return lentTables_ ? lentTables_ : &tables_; }
    StepOptions cachedTables() {
        StepOptions options;
        options.tables = tables();
        options.broadPhase = &broadPhase_;
        return options;
    }
    // FrozenStart::frozen's values.
    static constexpr char kStepping = 0;    // moves with the bodies stepping now
    static constexpr char kFrozen = 1;      // free for the rest of the stretch: catches up at its end
    static constexpr char kOtherGroup = 2;  // of another group, taking the stretch before or after this one
    // Bodies frozen in a stretch: where, since when, and how far they may go.
    // Most freeze at its start; with time_of_impact a stepping body whose
    // gaps can no longer close before the stretch ends freezes then.
    struct FrozenStart {
        std::vector<char> frozen;          // per body, robots then the ball (kStepping, kFrozen, kOtherGroup)
        std::vector<std::int64_t> since;   // per body: steps into the stretch at which it froze
        std::vector<RobotState> robots;    // each frozen robot when it froze
        BallState ball;                    // the ball when it froze
        std::vector<double> x, y;    // m, each frozen body's centre when it froze
        std::vector<double> travel;  // m: the farthest it may go from there by the stretch's end
        std::vector<int> byX;        // the frozen bodies by increasing x
        double widest = 0.0;         // m: the largest reach plus travel of a frozen body
        double fastest = 0.0;        // m/s: the largest speed bound of a frozen body when it froze
    };
    // Adds the bodies `added` (already marked frozen, with x and travel set)
    // to byX, keeping it sorted (the added ones sorted, then merged), and to
    // widest. It sorts them in place.
    void addToFrozenOrder(FrozenStart& start, std::vector<int>& added) const;
    // bodiesByX_ sorted by the bodies' x now (ties by index; an x that is
    // not a number counts as +infinity): an insertion sort of the last
    // stretch's order, about one pass since bodies move little in a stretch
    // (sorting the frozen bodies afresh at every stretch cost a thousand
    // robots 3 % of their run, and formGroups sorted the stepping ones
    // twice more).
    void sortBodiesByX();
    // Body b of the planner's numbering (the robots, then the ball as body
    // n, the robot count): the radius of the disc around its centre that
    // holds it at any heading (m), that centre (m), the fastest any of its
    // points moves now (m/s), and the farthest any of its points can go
    // within `horizon` s under its voltages (m).
    double bodyReach(std::size_t b) const;
    Eigen::Vector2d bodyCentre(std::size_t b) const;
    double bodySpeed(std::size_t b) const;
    double bodyTravel(std::size_t b, double horizon) const;
    // Whether the stepping bodies still cannot reach the frozen ones, nor
    // another group's claims, within `remaining` s.
    // `margin` (s) adds that many seconds at each stepping body's speed bound, twice.
    bool frozenStillSafe(const FrozenStart& start, double remaining, double margin = 0.0) const;
    // The frozen bodies' speed bounds `done` steps into the stretch
    // (frozenSpeed_, and the ball's into options.frozenBallSpeed).
    void frozenSpeeds(const FrozenStart& start, std::int64_t done, StepOptions& options);
    // The loop of one stretch for the stepping bodies, from its start to
    // its end or to a contact that brings one of them within reach of a
    // body that is not stepping (`unsafe`: that step is undone, the state
    // is `done` steps into the stretch, returned).
    struct StretchLoop {
        std::int64_t stretch = 0;   // steps until the voltages can change
        bool skip = false;          // long steps (frozen bodies stand still)
        bool impacts = false;       // contacts at their time of impact
        bool nobodyFrozen = false;  // the step after a replan: nobody freezes
        double smallest = 0.0;      // m: the smallest half-size (sub-steps, world.h)
    };
    std::int64_t stepThroughStretch(FrozenStart& start, const StretchLoop& loop, StepOptions& options,
                                    AdvanceReport& report, bool& unsafe);
    // Groups (advanceTo): the stepping bodies whose discs of reach plus
    // travel over the stretch (start.travel) and a step's margin overlap,
    // linked in chains, are one group; groupOf_ numbers them by their lowest
    // body index. Returns how many, or 0 when the stretch is not to be
    // taken so: fewer than two, a body fast enough for sub-steps (every step
    // of a group must be the one the whole world would take), or a body not
    // finite. Fills claims_, groupMembers_ and groupFirst_. At a stretch's
    // start only: it takes the order along x from sortBodiesByX.
    int formGroups(const FrozenStart& start, double smallest);
    // Takes the stretch group by group (true), or leaves everything as it
    // was (false: fewer than two groups, or a contact sent a body towards
    // another group, and the stretch was undone).
    bool stepInGroups(FrozenStart& start, const StretchLoop& loop, StepOptions& options, AdvanceReport& report);
    // Where a body of a group may be within the stretch: a disc around its
    // centre at the stretch's start that holds it all along unless a
    // contact of its group changes its velocity; after each such contact,
    // grown to hold a disc around where it then is as well.
    struct Claim {
        double key = 0.0;         // m: the centre's x at the stretch's start (claims_ is sorted by it)
        double x = 0.0, y = 0.0;  // m: the disc's centre
        double reach = 0.0;       // m: its radius (the body's reach plus travel)
        int body = 0;
        int group = 0;
    };
    // Whether the disc of `reach` (m) around (x, y) is clear of every other group's claims.
    bool clearOfOtherGroups(double x, double y, double reach) const;
    // After a contact among the stepping bodies: frozenStillSafe, and with
    // groups, still slow enough for one sub-step, their claims grown to hold
    // where they may go from now on.
    bool apartAfterContact(const FrozenStart& start, double remaining, double margin);
    // With time_of_impact, `done` steps into a stretch of `stretch`: the
    // stepping bodies that gapSafeSteps found unconstrained (no gap of
    // theirs can come within kContactSkin before the stretch ends) freeze
    // now, unless they are within reach of a stepping body by the discs of
    // frozenStillSafe (a contact among the others would then undo the step
    // at once).
    // Returns how many froze.
    int freezeUnconstrained(FrozenStart& start, std::int64_t done, std::int64_t stretch, StepOptions& options);
    // The frozen bodies catch up to `done` steps into the stretch, each from
    // the step at which it froze.
    void catchUpFrozen(const FrozenStart& start, std::int64_t done, bool ballFrozen);
    // The longest power-of-two number of steps (<= remaining, >= 2) that the
    // stepping bodies can take with no contact possible, or 0.
    std::int64_t steppingFreeSteps(const FrozenStart& start, std::int64_t remaining);
    // With time_of_impact: how many whole steps (<= remaining) the stepping
    // bodies can take before any of their gaps (gaps_, found here) could
    // close; -1 when a gap is within kContactSkin now (bodies touching).
    // The steps end at the first step start at which a gap may be within
    // kContactSkin (touching: answered there, as in a call cut there).
    // Also marks in constrained_ the bodies with a gap that may come within
    // kContactSkin in `remaining` steps (not set when returning -1), and
    // keeps in gaps_ only the gaps that may come within kContactSkin before
    // the stretch ends.
    // With `known` (the last call's gaps_, in this stretch, with no contact
    // since and only steps taken without one) only those are measured
    // again: a pair out of reach, or whose gap could not come within the
    // skin before the stretch's end, when last measured, cannot since (the
    // bounds were over the rest of the stretch). The steps are those of
    // measuring every pair again, except where a fresh bound on a pair left
    // out would be looser than the one that let it go.
    std::int64_t gapSafeSteps(std::int64_t remaining, bool ballMoving, bool known);
    // One step of dt for the stepping bodies in which a gap of gaps_ may
    // close (pairs touching at its start are not searched: they meet at its
    // end): Free (none did: the step is taken), Contact (the step was taken
    // with the contact answered at its instant),
    // or Unresolved (the state is as before: take an ordinary step; when
    // only resting or touching pairs meet, or a grazing pass could not be
    // settled, and no other contact was found within the step).
    // After Contact, restoreStepping() puts the step's start back.
    enum class ImpactStep { Free, Contact, Unresolved };
    // The pairs of gaps_ within kContactSkin that approach are answered now,
    // except those closer than kRoundingGap (met at the step's end instead;
    // long_step_planner.cpp) (`now`: simulated time, s, for the report);
    // returns how many.
    int answerTouchingGaps(double now, AdvanceReport& report);
    // A body's pose in state_ (the ball's centre in x, y; a wall's is not used).
    RobotState poseNow(const BodyRef& body) const;
    // The contact of a gap's bodies in state_ when they are apart by at most
    // kContactSkin (normal and point from their nearest points), else none.
    std::optional<Contact> touchingContact(const BodyGap& g) const;
    // The stepping bodies at a searched step's start, kept and put back:
    // nothing else changes within it (a copy of the whole state costs a
    // thousand robots dearly at every step).
    void saveStepping(bool ballMoving);
    void restoreStepping(bool ballMoving);
    // `stepStart`: the step's start in simulated time, s (for the report).
    ImpactStep impactStep(bool ballMoving, double stepStart, const StepOptions& options, AdvanceReport& report);

    std::vector<ScheduledCommand> schedule_;  // sorted by step, stable (file order on ties)
    std::size_t nextCommand_ = 0;
    ExactTableCache tables_;
    ExactTableCache* lentTables_ = nullptr;  // lendTableCache's, used instead of tables_
    BroadPhaseScratch broadPhase_;  // the contact tests' order along x, kept between steps
    // Work buffers of advanceTo (kept to avoid allocations; not state).
    FreeBodies free_;
    FrozenStart frozenStart_;
    std::vector<char> frozenRobots_;
    std::vector<int> stepping_;        // the stepping robots (frozenRobots_'s zero entries), increasing
    std::vector<int> steppingBodies_;  // freezeUnconstrained's: stepping_, then the ball if it steps
    std::vector<double> frozenSpeed_;  // per robot, m/s (frozen ones only)
    WorldState beforeStep_;            // to undo a step that reached a frozen body
    bool forceOrdinaryStep_ = false;   // the next step (with time_of_impact: stretch) takes every body
    std::vector<BodyGap> gaps_;        // gapSafeSteps' gaps, used by impactStep
    std::vector<char> constrained_;    // gapSafeSteps': per body, a gap of it may come within kContactSkin before the stretch ends
    std::vector<char> catchUp_;        // catchUpFrozen's robots of one freezing step
    std::vector<double> stepReach_;    // freezeUnconstrained's reach + travel per stepping body, m
    std::vector<std::pair<double, int>> steppingByX_;  // freezeUnconstrained's stepping bodies: (x, body), sorted
    std::vector<std::pair<double, int>> bodiesByX_;  // (x, body) of every body (the ball: n) at the last stretch's start, sorted
    std::vector<int> newlyFrozen_;     // the bodies frozen in one go (a stretch's start, or freezeUnconstrained)
    BodyGapScratch gapScratch_;
    mutable ModeProgressCache progress_;  // impactStep's and bodyTravel's (a cache: const methods may fill it)
    std::vector<RobotPath> paths_;     // impactStep's robot paths over its step
    std::vector<char> pathReady_;
    std::vector<RobotState> stepStartRobots_;  // saveStepping's (stepping robots' entries only)
    BallState stepStartBall_;
    // Groups (stepInGroups): each stepping body's group (-1: none), the group stepping now (-1: all).
    std::vector<int> groupOf_;
    std::vector<int> groupRoot_;      // formGroups' union-find
    int currentGroup_ = -1;
    std::vector<Claim> claims_;       // one per stepping body, by increasing key
    std::vector<std::size_t> claimOf_;  // per body: its claim's place in claims_
    double claimsWidest_ = 0.0;       // m: the largest |x - key| + reach of claims_
    double groupSpeedLimit_ = 0.0;    // m/s: a body faster than this would make a step take sub-steps
    // To undo a stretch taken group by group: what the groups' steps can
    // change, which is the bodies stepping at its start (their states, and
    // their entries of FrozenStart, written if they freeze), FrozenStart's
    // flags and order, and the lists below (a copy of the whole world and
    // of FrozenStart cost a thousand robots about a tenth of their run).
    struct GroupUndo {
        std::vector<int> stepping;             // stepping_
        std::vector<char> frozenRobotFlags;    // frozenRobots_
        std::vector<RobotState> robots;        // state_.robots[i] for i in stepping_, in its order
        std::vector<RobotState> frozenRobots;  // start.robots[i], the same
        std::vector<std::int64_t> since;       // start.since, x, y, travel: stepping_'s robots, then the ball
        std::vector<double> x, y, travel;
        BallState ball, frozenBall;            // state_.ball, start.ball
        std::vector<char> frozen;              // start.frozen
        std::vector<int> byX;                  // start.byX
        double widest = 0.0, fastest = 0.0;    // start.widest, start.fastest
    };
    GroupUndo groupUndo_;
    // Saves the above (`save`) at a grouped stretch's start, or puts it back.
    void keepGroupUndo(FrozenStart& start, bool save);
    std::vector<int> groupMembers_;  // formGroups': the robots of group g at groupFirst_[g] to groupFirst_[g + 1]
    std::vector<std::size_t> groupFirst_, groupFill_;
};

}  // namespace vssim
