#include "vssim/world.h"

#include <algorithm>
#include <cmath>

#include "vssim/broad_phase.h"
#include "vssim/collision_detect.h"
#include "vssim/collision_response.h"
#include "vssim/geometry.h"
#include "vssim/integrator.h"

namespace vssim {

namespace {

// Velocity passes per step: each detects all contacts, responds and separates.
constexpr int kContactPasses = 8;
// Final passes against the walls only, which have infinite mass, so that no
// body is left outside the field.
constexpr int kContainmentPasses = 2;

int substepsFor(const WorldModel& model, const WorldState& state, double h, const StepOptions& options) {
    const bool frozen = options.frozen && options.frozenRobotSpeed;
    double smallest = model.ball.radius;
    double fastest = frozen && options.freeBall ? options.frozenBallSpeed : std::hypot(state.ball.vx, state.ball.vy);
    for (std::size_t i = 0; i < state.robots.size(); ++i) {
        smallest = std::min(smallest, 0.5 * model.sides[i]);
        const bool isFrozen = frozen && options.freeRobots && (*options.freeRobots)[i];
        fastest = std::max(fastest, isFrozen ? (*options.frozenRobotSpeed)[i]
                                             : pointSpeedBound(model.robots[i], state.robots[i], state.voltages[i]));
    }
    const double travel = fastest * h;
    const double allowed = kMaxTravelFraction * smallest;
    if (!(travel > allowed)) return 1;  // also when travel is NaN
    return static_cast<int>(std::min(1e6, std::ceil(travel / allowed)));
}

// Speeds below this (m/s, rad/s) are set to exactly zero. A body coasting to
// rest decays exponentially and would otherwise end in the subnormal range of
// doubles, where x86 arithmetic runs about 100 times slower; 1e-200 is
// physically nothing and keeps every product (with dt, with parameters) normal.
constexpr double kRestSpeed = 1e-200;

void flushToRest(double& speed) {
    if (std::abs(speed) < kRestSpeed) speed = 0.0;
}

void flushToRest(WorldState& state) {
    for (RobotState& r : state.robots) {
        flushToRest(r.v);
        flushToRest(r.omega);
    }
    flushToRest(state.ball.vx);
    flushToRest(state.ball.vy);
}

bool atRest(const RobotState& r, const Voltages& e) {
    return r.v == 0.0 && r.omega == 0.0 && e.right == 0.0 && e.left == 0.0;
}

bool useBroadPhase(const WorldModel& model, const WorldState& state) {
    return model.settings.broad_phase && static_cast<int>(state.robots.size()) >= kBroadPhaseMinRobots;
}

bool atRest(const BallState& b) { return b.vx == 0.0 && b.vy == 0.0; }

// After a failed try at a long step for the bodies near contacts, this many
// steps of dt pass before the next try (a try costs about one step),
// doubling after each failure in a row up to the longest wait.
constexpr std::int64_t kFirstRetryWait = 2;
constexpr std::int64_t kLongestRetryWait = 16;

}  // namespace

WorldModel makeWorldModel(const Scene& scene) {
    WorldModel m;
    m.field = scene.field;
    m.settings = scene.simulation;
    m.ball = scene.ball_params;
    for (const RobotSpec& r : scene.robots) {
        m.robots.push_back(makeRobotModel(r.params));
        m.sides.push_back(r.params.side);
    }
    return m;
}

WorldState initialWorldState(const Scene& scene) {
    WorldState s;
    s.ball = scene.ball;
    for (const RobotSpec& r : scene.robots) {
        s.robots.push_back(r.initial);
        s.voltages.push_back({});
    }
    return s;
}

static void integrateRobotBy(const WorldModel& model, WorldState& state, std::size_t i, double h, ExactTableCache* tables) {
    RobotState& robot = state.robots[i];
    if (atRest(robot, state.voltages[i])) return;  // nothing would change
    const RobotModel& robotModel = model.robots[i];
    if (model.settings.integrator != Integrator::Exact) {
        integrateRobot(robotModel, robot, state.voltages[i], h, model.settings.integrator);
        return;
    }
    const int panels = exactPanelsFor(robotModel, robot, state.voltages[i], h);
    if (tables)
        integrateRobotExact(robotModel, tables->table(static_cast<int>(i), robotModel, h, panels), robot, state.voltages[i]);
    else
        integrateRobotExact(robotModel, makeExactStepTable(robotModel, h, panels), robot, state.voltages[i]);
}

StepReport stepWorld(const WorldModel& model, WorldState& state, double h, const StepOptions& options) {
    StepReport report;
    report.substeps = substepsFor(model, state, h, options);
    if (report.substeps > 1 && model.settings.integrator != Integrator::Exact) {
        // Splitting only matters where a body could reach something within
        // h; far from everything a long step cannot tunnel through anything.
        // (The exact integrator gets this from Simulation::advanceTo's plan,
        // which keeps long and fixed steps in agreement.)
        FreeBodies free;
        findFreeBodies(model, state, h, free);
        if (free.all) report.substeps = 1;
    }
    const double sub = h / report.substeps;
    Bodies bodies{&state.robots, &model.robots, &state.ball, &model.ball};
    const BodiesView view{&state.robots,      &model.sides,       &state.ball,      model.ball.radius,
                          useBroadPhase(model, state), options.freeRobots, options.freeBall, options.broadPhase};

    for (int s = 0; s < report.substeps; ++s) {
        for (std::size_t i = 0; i < state.robots.size(); ++i)
            if (!options.frozen || !options.freeRobots || !(*options.freeRobots)[i])
                integrateRobotBy(model, state, i, sub, options.tables);
        if (!(options.frozen && options.freeBall) && !atRest(state.ball))
            integrateBall(model.ball, state.ball, sub, model.settings.integrator);
        flushToRest(state);

        bool touching = false;
        for (int pass = 0; pass < kContactPasses; ++pass) {
            const std::vector<Contact> contacts = detectContacts(model.field, view);
            if (contacts.empty()) break;
            touching = true;
            report.contacts += static_cast<int>(contacts.size());
            for (const Contact& c : contacts) {
                if (respondToContact(c, bodies, model.settings.collision_model, model.settings.restitution))
                    ++report.responses;
                separateBodies(c, bodies);
            }
        }
        for (int pass = 0; touching && pass < kContainmentPasses; ++pass) {
            std::vector<Contact> walls;
            appendWallContacts(model.field, view, walls);
            for (const Contact& c : walls) separateBodies(c, bodies);
        }
    }
    return report;
}

Simulation::Simulation(const Scene& scene)
    : scene_(scene), model_(makeWorldModel(scene)), state_(initialWorldState(scene)) {
    for (const VoltageCommand& c : scene.commands)
        schedule_.push_back({stepIndexAtOrAfter(c.t, model_.settings.dt), c.robot, c.voltages});
    std::stable_sort(schedule_.begin(), schedule_.end(),
                     [](const ScheduledCommand& a, const ScheduledCommand& b) { return a.step < b.step; });
}

std::int64_t Simulation::stepIndexAtOrAfter(double t, double dt) {
    const double steps = std::ceil(t / dt - 1e-9);
    // Saturate instead of overflowing the conversion (undefined behaviour):
    // a command beyond 2^62 steps is never reached. NaN counts as never, too.
    constexpr double kNever = 4.6e18;
    if (!(steps < kNever)) return static_cast<std::int64_t>(kNever);
    return std::max<std::int64_t>(0, static_cast<std::int64_t>(steps));
}

void Simulation::setVoltages(int robot, const Voltages& e) {
    state_.voltages[robot] = clampVoltages(model_.robots[robot].params, e);
}

void Simulation::placeRobot(int robot, const RobotState& pose) {
    state_.robots[robot] = pose;
}

void Simulation::placeBall(const BallState& ball) {
    state_.ball = ball;
}

void Simulation::applyDueCommands() {
    while (nextCommand_ < schedule_.size() && schedule_[nextCommand_].step <= state_.step) {
        const ScheduledCommand& c = schedule_[nextCommand_++];
        setVoltages(c.robot, c.voltages);
    }
}

// How far robot i's centre can go within `horizon` as the integrator
// computes it (turning does not matter: a disc around the centre holds the
// robot at any heading). The exact integrator follows the true trajectory,
// which robotTravelBound bounds. Euler's and RK4's intermediate velocities
// can overshoot the true ones (by up to about 1.5 times at the edge of RK4's
// stability region), so for them: twice the speed bound, and only for one
// step well inside their stability regions; beyond that nothing is promised.
static double robotTravelForIntegrator(const WorldModel& model, const WorldState& state, std::size_t i, double horizon) {
    const RobotModel& robot = model.robots[i];
    if (model.settings.integrator == Integrator::Exact)
        return robotTravelBound(robot, state.robots[i], state.voltages[i], horizon, 0.0);
    if (!(horizon * robot.fastestRate <= 2.0)) return INFINITY;
    return 2.0 * velocityBound(robot, state.robots[i], state.voltages[i])(0) * horizon;
}

// Free flight of the ball is a straight line of length |v0| (1 - e^(-k T)) / k, m;
// Euler and RK4 move it by up to |v0| T in one step.
static double ballTravel(const WorldModel& model, const WorldState& state, double horizon) {
    const double decay = model.ball.friction / model.ball.mass;  // 1/s
    const double speed = std::hypot(state.ball.vx, state.ball.vy);
    if (model.settings.integrator != Integrator::Exact || !(decay > 0.0)) return speed * horizon;
    return speed * -std::expm1(-decay * horizon) / decay;
}

void findFreeBodies(const WorldModel& model, const WorldState& state, double horizon, FreeBodies& out) {
    const std::size_t n = state.robots.size();
    out.robotTravel.resize(n);
    double farthest = 0.0;  // m
    for (std::size_t i = 0; i < n; ++i) {
        out.robotTravel[i] = robotTravelForIntegrator(model, state, i, horizon);
        farthest = std::max(farthest, out.robotTravel[i]);
    }
    out.ballTravel = ballTravel(model, state, horizon);
    farthest = std::max(farthest, out.ballTravel);
    out.robots.assign(n, 1);
    out.ball = true;
    out.all = false;
    if (!std::isfinite(farthest)) {
        out.robots.assign(n, 0);
        out.ball = false;
        return;
    }
    // Discs around the centres that hold each body at any heading, m.
    auto reach = [&model](std::size_t i) { return model.sides[i] / std::sqrt(2.0); };
    const Eigen::Vector2d ball(state.ball.x, state.ball.y);
    // A body must cross a wall's line to touch the wall: the signed distance
    // to the line (negative behind it) is a cheap, conservative gap.
    for (const Wall& w : model.field.walls) {
        for (std::size_t i = 0; i < n; ++i) {
            const double gap = w.normal.x() * (state.robots[i].x - w.a.x()) + w.normal.y() * (state.robots[i].y - w.a.y());
            if (!(gap - reach(i) > out.robotTravel[i])) out.robots[i] = 0;
        }
        if (!(w.normal.dot(ball - w.a) - model.ball.radius > out.ballTravel)) out.ball = false;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d c(state.robots[i].x, state.robots[i].y);
        if (!((c - ball).norm() - reach(i) - model.ball.radius > out.robotTravel[i] + out.ballTravel))
            out.robots[i] = 0, out.ball = false;
    }
    // Only pairs whose discs, grown by the farthest any body can go, overlap
    // can limit each other.
    out.pairs.clear();
    if (useBroadPhase(model, state)) {
        candidatePairs(state.robots, model.sides, farthest, out.broadPhase, out.pairs);
    } else {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) out.pairs.emplace_back(int(i), int(j));
    }
    for (const auto& [i, j] : out.pairs) {
        const double dx = state.robots[i].x - state.robots[j].x, dy = state.robots[i].y - state.robots[j].y;
        const double gap = std::sqrt(dx * dx + dy * dy) - reach(i) - reach(j);
        if (!(gap > out.robotTravel[i] + out.robotTravel[j])) out.robots[i] = 0, out.robots[j] = 0;
    }
    out.all = out.ball && std::all_of(out.robots.begin(), out.robots.end(), [](char f) { return f != 0; });
}

std::int64_t Simulation::contactFreeSteps(std::int64_t wanted) const {
    // The largest k <= wanted for which every body is free for k steps
    // (freedom only shrinks as the horizon grows): a bisection.
    FreeBodies free;
    auto allFree = [&](std::int64_t k) {
        findFreeBodies(model_, state_, static_cast<double>(k) * model_.settings.dt, free);
        return free.all;
    };
    if (wanted <= 0 || !allFree(1)) return 0;
    if (allFree(wanted)) return wanted;
    std::int64_t lo = 1, hi = wanted;  // allFree(lo), !allFree(hi)
    while (hi - lo > 1) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        (allFree(mid) ? lo : hi) = mid;
    }
    return lo;
}

void Simulation::advanceBodies(double h, const std::vector<char>* robots, bool ball) {
    for (std::size_t i = 0; i < state_.robots.size(); ++i)
        if (!robots || (*robots)[i]) integrateRobotBy(model_, state_, i, h, &tables_);
    if (ball && !atRest(state_.ball)) integrateBallExact(model_.ball, state_.ball, h);
    flushToRest(state_);
}

void Simulation::finishStep(std::int64_t steps) {
    state_.step += steps;
    state_.time = static_cast<double>(state_.step) * model_.settings.dt;
}

std::int64_t Simulation::ordinaryStep() {
    const std::int64_t contacts = stepWorld(model_, state_, model_.settings.dt, cachedTables()).contacts;
    finishStep(1);
    return contacts;
}

bool Simulation::frozenStillSafe(const FrozenStart& start, double remaining, double margin) const {
    // A frozen body i, still at its start p_i0, moves at most travel_i in the
    // whole stretch. A stepping body j, now at p_j with its current state (a
    // collision may have sped it up), moves at most its travel bound over
    // the remaining time. Both discs must stay apart.
    const std::size_t n = state_.robots.size();
    auto reach = [this, n](std::size_t b) { return b < n ? model_.sides[b] / std::sqrt(2.0) : model_.ball.radius; };
    for (std::size_t j = 0; j <= n; ++j) {
        if (start.frozen[j]) continue;
        const double pjX = j < n ? state_.robots[j].x : state_.ball.x;
        const double pjY = j < n ? state_.robots[j].y : state_.ball.y;
        const double speed = j < n ? pointSpeedBound(model_.robots[j], state_.robots[j], state_.voltages[j])
                                   : std::hypot(state_.ball.vx, state_.ball.vy);
        const double jTravel = (j < n ? robotTravelForIntegrator(model_, state_, j, remaining)
                                      : ballTravel(model_, state_, remaining)) +
                               2.0 * speed * margin;
        for (std::size_t i = 0; i <= n; ++i) {
            if (!start.frozen[i]) continue;
            const double dx = pjX - start.x[i], dy = pjY - start.y[i];
            const double distance = std::sqrt(dx * dx + dy * dy);
            if (!(distance - reach(i) - reach(j) > start.travel[i] + jTravel)) return false;
        }
    }
    return true;
}

void Simulation::frozenSpeeds(const FrozenStart& start, double elapsed) {
    const std::size_t n = state_.robots.size();
    frozenSpeed_.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!start.frozen[i]) continue;
        RobotState now = start.robots[i];
        const Eigen::Vector2d u = velocityAfter(model_.robots[i], now, state_.voltages[i], elapsed);
        now.v = u(0);
        now.omega = u(1);
        frozenSpeed_[i] = pointSpeedBound(model_.robots[i], now, state_.voltages[i]);
    }
}

std::int64_t Simulation::steppingFreeSteps(const FrozenStart& start, std::int64_t remaining) {
    const std::size_t n = state_.robots.size();
    std::int64_t steps = 1;
    while (steps * 2 <= remaining) steps *= 2;
    for (; steps >= 2; steps /= 4) {
        const double horizon = static_cast<double>(steps) * model_.settings.dt;
        // Free among themselves and from the walls (the frozen bodies are
        // checked properly below: they are not where findFreeBodies sees them)...
        findFreeBodies(model_, state_, horizon, free_);
        bool allFree = start.frozen[n] || free_.ball;
        for (std::size_t i = 0; i < n && allFree; ++i) allFree = start.frozen[i] || free_.robots[i];
        // ...and out of the frozen bodies' reach.
        if (allFree && frozenStillSafe(start, horizon)) return steps;
    }
    return 0;
}

AdvanceReport Simulation::advanceTo(std::int64_t target) {
    AdvanceReport report;
    const std::int64_t first = state_.step;
    // The exact integrator plans each stretch between voltage changes; with
    // long steps it also skips the free bodies' steps.
    const bool plan = model_.settings.integrator == Integrator::Exact;
    const bool skip = plan && model_.settings.long_steps;
    const double dt = model_.settings.dt;
    const std::size_t n = state_.robots.size();
    while (state_.step < target) {
        applyDueCommands();
        std::int64_t next = target;
        if (nextCommand_ < schedule_.size()) next = std::min(next, schedule_[nextCommand_].step);
        const std::int64_t stretch = next - state_.step;  // steps until the voltages can change
        if (!plan || forceOrdinaryStep_) {
            forceOrdinaryStep_ = false;
            report.contacts += ordinaryStep();
            ++report.stepCalls;
            continue;
        }
        const double horizon = static_cast<double>(stretch) * dt;  // s
        findFreeBodies(model_, state_, horizon, free_);
        if (free_.all && skip) {  // nothing can touch anything: one step to the next voltage change
            advanceBodies(horizon, nullptr, true);
            finishStep(stretch);
            ++report.longSteps;
            continue;
        }
        const bool someFree = free_.ball || std::any_of(free_.robots.begin(), free_.robots.end(), [](char f) { return f != 0; });
        if (!someFree) {
            // Everybody may touch something before the stretch ends, but maybe
            // not soon: try shorter steps of a power of two times dt (few step
            // lengths, so their tables stay cached), else one ordinary step.
            std::int64_t steps = 1;
            if (skip) {
                while (steps * 2 < stretch) steps *= 2;
                for (; steps >= 2; steps /= 4) {
                    findFreeBodies(model_, state_, static_cast<double>(steps) * dt, free_);
                    if (free_.all) break;
                }
            }
            if (steps >= 2) {
                advanceBodies(static_cast<double>(steps) * dt, nullptr, true);
                finishStep(steps);
                ++report.longSteps;
            } else {
                report.contacts += ordinaryStep();
                ++report.stepCalls;
            }
            continue;
        }
        // Some bodies are free for the whole stretch: they stay where they are
        // while the others take steps of dt (no contact with them is possible
        // on the way), then they take the whole stretch in one step. Should a
        // contact among the others bring one of them near a free body after
        // all, that step is undone, the free ones catch up to the present, and
        // the step is taken again with everybody. The sub-steps count the free
        // bodies at their true current speeds, so every step is the one
        // step() would take. Without long steps the free bodies are
        // integrated with the others, step by step, under the same plan.
        FrozenStart& start = frozenStart_;
        start.frozen.assign(free_.robots.begin(), free_.robots.end());
        start.frozen.push_back(free_.ball);
        start.x.resize(n + 1);
        start.y.resize(n + 1);
        start.travel.assign(free_.robotTravel.begin(), free_.robotTravel.end());
        start.travel.push_back(free_.ballTravel);
        for (std::size_t i = 0; i < n; ++i) start.x[i] = state_.robots[i].x, start.y[i] = state_.robots[i].y;
        start.x[n] = state_.ball.x;
        start.y[n] = state_.ball.y;
        start.robots = state_.robots;
        start.ball = state_.ball;
        frozenRobots_.assign(start.frozen.begin(), start.frozen.begin() + static_cast<std::ptrdiff_t>(n));
        StepOptions options;
        options.freeRobots = &frozenRobots_;
        options.freeBall = start.frozen[n] != 0;
        options.frozen = skip;
        options.tables = &tables_;
        options.broadPhase = &broadPhase_;
        options.frozenRobotSpeed = &frozenSpeed_;
        const double ballDecay = model_.ball.friction / model_.ball.mass;  // 1/s
        // A frozen body's speed bound only falls along its free trajectory
        // (each mode's share moves towards its end), so when the bounds at the
        // start of the stretch cannot ask for sub-steps, none later can, and
        // the frozen bodies' current speeds are not needed.
        double smallest = model_.ball.radius, frozenFastest = start.frozen[n] ? std::hypot(state_.ball.vx, state_.ball.vy) : 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            smallest = std::min(smallest, 0.5 * model_.sides[i]);
            if (start.frozen[i])
                frozenFastest = std::max(frozenFastest, pointSpeedBound(model_.robots[i], state_.robots[i], state_.voltages[i]));
        }
        const bool frozenMayDecideSubsteps = !(frozenFastest * dt <= kMaxTravelFraction * smallest);
        frozenSpeed_.assign(n, 0.0);
        options.frozenBallSpeed = 0.0;
        steppingRobots_.resize(n);
        for (std::size_t i = 0; i < n; ++i) steppingRobots_[i] = !frozenRobots_[i];
        std::int64_t done = 0, nextTry = 0, wait = kFirstRetryWait;
        bool stillSafe = true, touching = false;
        while (done < stretch && stillSafe) {
            // The stepping bodies, too, may be free for a while (a robot
            // nearing a wall, not yet at it): a long step of a power of two
            // times dt for them. Not while touching; after a failed try, wait
            // (twice as long after each failure in a row).
            if (skip && !touching && done >= nextTry && stretch - done >= 2) {
                const std::int64_t steps = steppingFreeSteps(start, stretch - done);
                if (steps >= 2) {
                    advanceBodies(static_cast<double>(steps) * dt, &steppingRobots_, !options.freeBall);
                    done += steps;
                    ++report.longSteps;
                    wait = kFirstRetryWait;
                    continue;
                }
                nextTry = done + wait;
                wait = std::min(2 * wait, kLongestRetryWait);
            }
            if (skip && frozenMayDecideSubsteps) {
                const double elapsed = static_cast<double>(done) * dt;  // s into the stretch
                frozenSpeeds(start, elapsed);
                options.frozenBallSpeed = std::hypot(start.ball.vx, start.ball.vy) * std::exp(-ballDecay * elapsed);
            }
            beforeStep_ = state_;
            const StepReport r = stepWorld(model_, state_, dt, options);
            // A contact may have sent a stepping body towards a free one (the
            // contact tests skip free bodies): then undo this step, bring the
            // free bodies to the present and take the step again with
            // everybody. The margin covers what a body can move within the
            // step after a contact.
            if (r.contacts > 0 && !frozenStillSafe(start, static_cast<double>(stretch - done - 1) * dt, dt)) {
                state_ = beforeStep_;
                stillSafe = false;
                forceOrdinaryStep_ = true;
                ++report.replans;
                break;
            }
            report.contacts += r.contacts;
            ++report.stepCalls;
            ++done;
            touching = r.contacts > 0;
        }
        if (skip) {  // the frozen bodies catch up: by the whole stretch, or to the present
            advanceBodies(static_cast<double>(done) * dt, &frozenRobots_, options.freeBall);
            ++report.longSteps;
        }
        finishStep(done);
    }
    report.steps = state_.step - first;
    return report;
}

StepReport Simulation::step() {
    applyDueCommands();
    const StepReport report = stepWorld(model_, state_, model_.settings.dt, cachedTables());
    ++state_.step;
    state_.time = static_cast<double>(state_.step) * model_.settings.dt;
    return report;
}

RobotOutputs Simulation::robotOutputs(int robot) const {
    return computeRobotOutputs(model_.robots[robot], state_.robots[robot], state_.voltages[robot]);
}

}  // namespace vssim
