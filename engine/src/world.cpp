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
// Position passes for jams (a robot pinned between others and a wall, an
// inelastic pile) that the velocity passes leave overlapping: separation
// only, until the deepest overlap is below kSeparationTolerance.
constexpr int kSeparationPasses = 16;
constexpr double kSeparationTolerance = 1e-4;  // m
// Contacts shallower than this (m) end the velocity passes once the
// collisions proper have been answered: after a first pass that changed no
// velocity, or after any later pass. What such a pass finds is the rounding
// left by the previous separation (about 1e-17 m) or, in a jam (a robot
// pinched between another and a wall, a ball squeezed between robots), the
// overlaps that alternating separations and responses leave, shrinking by a
// constant factor per pass. Without this, bodies pressing on each other took
// all kContactPasses every step of a game (a third of the steps of a match
// between built-in teams), each pass moving them by a micrometre or less;
// the next step takes up whatever is left. Ten micrometres is a tenth of the
// jam tolerance (kSeparationTolerance).
constexpr double kResolvedDepth = 1e-5;
// Final passes against the walls only, which have infinite mass, so that no
// body is left outside the field.
constexpr int kContainmentPasses = 2;
// More of them while a wall contact deeper than kContainmentTolerance is
// left: a robot whose vertex meets a goal post is pushed by the post along
// a face and by a wall along its normal, which two passes may not settle.
// (In the box one pass settles the walls: the extra passes never run.)
constexpr int kExtraContainmentPasses = 6;
constexpr double kContainmentTolerance = 1e-12;  // m

// Whether a step moves the listed robots only (StepOptions::steppingRobots).
bool listedOnly(const StepOptions& options) {
    return options.frozen && options.frozenRobotSpeed && options.freeRobots && options.steppingRobots;
}

int substepsFor(const WorldModel& model, const WorldState& state, double h, const StepOptions& options) {
    const bool frozen = options.frozen && options.frozenRobotSpeed;
    double smallest = model.ball.radius;
    double fastest = frozen && options.freeBall ? options.frozenBallSpeed : std::hypot(state.ball.vx, state.ball.vy);
    if (listedOnly(options)) {
        // The same maximum (the free robots' speeds are finite, so where
        // they come in does not matter) and the same minimum.
        smallest = options.smallestHalfSize;
        for (const int i : *options.steppingRobots)
            fastest = std::max(fastest, pointSpeedBound(model.robots[i], state.robots[i], state.voltages[i]));
        fastest = std::max(fastest, options.frozenRobotFastest);
    } else {
        for (std::size_t i = 0; i < state.robots.size(); ++i) {
            smallest = std::min(smallest, 0.5 * model.sides[i]);
            const bool isFrozen = frozen && options.freeRobots && (*options.freeRobots)[i];
            fastest =
                std::max(fastest, isFrozen ? (*options.frozenRobotSpeed)[i]
                                           : pointSpeedBound(model.robots[i], state.robots[i], state.voltages[i]));
        }
    }
    const double travel = fastest * h;
    const double allowed = kMaxTravelFraction * smallest;
    // Also when travel is NaN or infinite: no number of sub-steps makes such
    // a state safe, and a million of them would only stall the run.
    if (!(travel > allowed) || !std::isfinite(travel)) return 1;
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

void flushToRest(RobotState& r) {
    flushToRest(r.v);
    flushToRest(r.omega);
}

void flushToRest(BallState& b) {
    flushToRest(b.vx);
    flushToRest(b.vy);
}

void flushToRest(WorldState& state) {
    for (RobotState& r : state.robots) flushToRest(r);
    flushToRest(state.ball);
}

bool atRest(const RobotState& r, const Voltages& e) {
    return r.v == 0.0 && r.omega == 0.0 && e.right == 0.0 && e.left == 0.0;
}

bool atRest(const BallState& b) { return b.vx == 0.0 && b.vy == 0.0; }

}  // namespace

static void integrateRobotBy(const WorldModel& model, WorldState& state, std::size_t i, double h,
                             ExactTableCache* tables) {
    RobotState& robot = state.robots[i];
    if (atRest(robot, state.voltages[i])) return;  // nothing would change
    const RobotModel& robotModel = model.robots[i];
    if (model.settings.integrator != Integrator::Exact) {
        integrateRobot(robotModel, robot, state.voltages[i], h, model.settings.integrator);
        return;
    }
    const int panels = exactPanelsFor(robotModel, robot, state.voltages[i], h);
    if (tables)
        integrateRobotExact(robotModel, tables->table(static_cast<int>(i), robotModel, h, panels), robot,
                            state.voltages[i]);
    else
        integrateRobotExact(robotModel, makeExactStepTable(robotModel, h, panels), robot, state.voltages[i]);
}

// Integrates the listed robots (and the ball, when `ball`) by h, no
// contacts, at a cost that grows with them only, and flushes their tiny
// speeds: stepWorld's listed steps and Simulation::advanceListed.
static void integrateListed(const WorldModel& model, WorldState& state, const std::vector<int>& robots, bool ball,
                            double h, ExactTableCache* tables) {
    for (const int i : robots) {
        integrateRobotBy(model, state, static_cast<std::size_t>(i), h, tables);
        flushToRest(state.robots[static_cast<std::size_t>(i)]);
    }
    if (ball && !atRest(state.ball)) integrateBall(model.ball, state.ball, h, model.settings.integrator);
    if (ball) flushToRest(state.ball);
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
    const bool listed = listedOnly(options);
    const BodiesView view{&state.robots,
                          &model.sides,
                          &state.ball,
                          model.ball.radius,
                          useBroadPhase(model, state),
                          options.freeRobots,
                          options.freeBall,
                          options.broadPhase,
                          listed ? options.steppingRobots : nullptr};

    for (int s = 0; s < report.substeps; ++s) {
        if (listed) {  // (the free bodies were flushed when they last moved, or set: Simulation)
            integrateListed(model, state, *options.steppingRobots, !options.freeBall, sub, options.tables);
        } else {
            for (std::size_t i = 0; i < state.robots.size(); ++i)
                if (!options.frozen || !options.freeRobots || !(*options.freeRobots)[i])
                    integrateRobotBy(model, state, i, sub, options.tables);
            if (!(options.frozen && options.freeBall) && !atRest(state.ball))
                integrateBall(model.ball, state.ball, sub, model.settings.integrator);
            flushToRest(state);
        }

        bool touching = false;
        int pass = 0;
        for (; pass < kContactPasses; ++pass) {
            const std::vector<Contact> contacts = detectContacts(model.field, view);
            if (contacts.empty()) break;
            touching = true;
            report.contacts += static_cast<int>(contacts.size());
            bool responded = false;
            double deepest = 0.0;
            for (const Contact& c : contacts) {
                if (respondToContact(c, bodies, model.settings.collision_model, model.settings.restitution)) {
                    ++report.responses;
                    responded = true;
                }
                separateBodies(c, bodies);
                deepest = std::max(deepest, c.depth);
            }
            // Nothing but the rounding of the last separation left: done.
            if ((!responded || pass > 0) && deepest < kResolvedDepth) break;
        }
        for (int extra = 0; pass == kContactPasses && extra < kSeparationPasses; ++extra) {
            const std::vector<Contact> contacts = detectContacts(model.field, view);
            double deepest = 0.0;
            for (const Contact& c : contacts) deepest = std::max(deepest, c.depth);
            if (!(deepest > kSeparationTolerance)) break;
            for (const Contact& c : contacts) separateBodies(c, bodies);
        }
        for (int pass = 0; touching && pass < kContainmentPasses + kExtraContainmentPasses; ++pass) {
            std::vector<Contact> walls;
            appendWallContacts(model.field, view, walls);
            if (pass >= kContainmentPasses) {
                double deepest = 0.0;
                for (const Contact& c : walls) deepest = std::max(deepest, c.depth);
                if (!(deepest > kContainmentTolerance)) break;
            }
            for (const Contact& c : walls) separateBodies(c, bodies);
        }
    }
    return report;
}

Simulation::Simulation(const Scene& scene)
    : scene_(scene), model_(makeWorldModel(scene)), state_(initialWorldState(scene)) {
    // Speeds under kRestSpeed are zero from the start, as after any step:
    // a body the plan leaves alone (free, frozen) must not keep one that a
    // step of everybody would have flushed.
    flushToRest(state_);
    schedule_.reserve(scene_.commands.size());
    for (std::size_t k = 0; k < scene_.commands.size(); ++k)
        schedule_.push_back({stepIndexAtOrAfter(scene_.commands[k].t, model_.settings.dt), k});
    // Scenes list their commands in time order almost always: then there is
    // nothing to sort (a stable sort of a game's 12,000 commands cost as much
    // as simulating four seconds of it).
    const auto byStep = [](const ScheduledCommand& a, const ScheduledCommand& b) { return a.step < b.step; };
    if (!std::is_sorted(schedule_.begin(), schedule_.end(), byStep))
        std::stable_sort(schedule_.begin(), schedule_.end(), byStep);
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
    if (state_.offField[robot]) return;
    state_.speedLoops[robot].active = false;
    state_.voltages[robot] = clampVoltages(model_.robots[robot].params, e);
}

void Simulation::setWheelSpeeds(int robot, const WheelSpeeds& target) {
    if (state_.offField[robot]) return;
    SpeedLoopState& loop = state_.speedLoops[robot];
    loop.target = clampWheelSpeeds(target, kMaxWheelSpeedTarget);
    if (loop.active) return;
    const double rate = model_.robots[robot].params.speed_controller.rate;
    const double dt = model_.settings.dt;
    // The loop's clock runs with simulated time: its first sample is its
    // first instant k / rate at or after now (1e-9 of a sample of slack, as
    // for commands, so that an instant on a step boundary counts as now).
    loop.active = true;
    loop.right = {};
    loop.left = {};
    loop.output = state_.voltages[robot];
    loop.sample = static_cast<std::int64_t>(std::ceil(state_.time * rate - 1e-9));
    loop.nextStep = stepIndexAtOrAfter(static_cast<double>(loop.sample) / rate, dt);
}

void Simulation::drive(int robot, const DriveCommand& command) {
    if (command.wheelSpeeds)
        setWheelSpeeds(robot, command.speeds);
    else
        setVoltages(robot, command.voltages);
}

void Simulation::setOnField(int robot, bool onField) {
    if (onField) {
        state_.offField[robot] = 0;
        return;
    }
    setVoltages(robot, {});
    state_.robots[robot].v = 0.0;
    state_.robots[robot].omega = 0.0;
    state_.offField[robot] = 1;
}

bool Simulation::anyOffField() const {
    return std::any_of(state_.offField.begin(), state_.offField.end(), [](char off) { return off != 0; });
}

void Simulation::runSpeedLoops() {
    const double dt = model_.settings.dt;
    for (std::size_t i = 0; i < state_.speedLoops.size(); ++i) {
        SpeedLoopState& loop = state_.speedLoops[i];
        if (!loop.active || loop.nextStep > state_.step) continue;
        const RobotModel& robot = model_.robots[i];
        // A loop faster than 1/dt samples once a step: its period is then a step.
        SpeedControllerParams params = robot.params.speed_controller;
        const bool everyStep = params.rate * dt >= 1.0;
        if (everyStep) params.rate = 1.0 / dt;
        const Eigen::Vector2d wheels = robot.TwInv * Eigen::Vector2d(state_.robots[i].v, state_.robots[i].omega);
        updateSpeedLoop(params, loop, {wheels(0), wheels(1)}, robot.params.max_voltage);
        state_.voltages[i] = loop.output;
        if (everyStep) {
            loop.nextStep = state_.step + 1;
            continue;
        }
        // The next instant after this step.
        do {
            ++loop.sample;
            loop.nextStep = stepIndexAtOrAfter(static_cast<double>(loop.sample) / params.rate, dt);
        } while (loop.nextStep <= state_.step);
    }
}

std::int64_t Simulation::nextLoopStep(std::int64_t limit) const {
    for (const SpeedLoopState& loop : state_.speedLoops)
        if (loop.active) limit = std::min(limit, loop.nextStep);
    return limit;
}

void Simulation::placeRobot(int robot, const RobotState& pose) {
    state_.robots[robot] = pose;
    if (state_.offField[robot]) state_.robots[robot].v = state_.robots[robot].omega = 0.0;  // stays at rest
    flushToRest(state_.robots[robot]);  // (as the constructor)
}

void Simulation::placeBall(const BallState& ball) {
    state_.ball = ball;
    flushToRest(state_.ball);
}

void Simulation::applyDueCommands() {
    while (nextCommand_ < schedule_.size() && schedule_[nextCommand_].step <= state_.step) {
        const VoltageCommand& c = scene_.commands[schedule_[nextCommand_++].command];
        if (c.wheelSpeeds)  // (drive(c.robot, c.drive()) without building the DriveCommand: a game applies thousands)
            setWheelSpeeds(c.robot, c.speeds);
        else
            setVoltages(c.robot, c.voltages);
    }
}

void Simulation::advanceListed(double h, const std::vector<int>& robots, bool ball) {
    integrateListed(model_, state_, robots, ball, h, tables());
}

void Simulation::advanceBodies(double h, const std::vector<char>* robots, bool ball) {
    for (std::size_t i = 0; i < state_.robots.size(); ++i)
        if (!robots || (*robots)[i]) integrateRobotBy(model_, state_, i, h, tables());
    if (ball && !atRest(state_.ball)) integrateBallExact(model_.ball, state_.ball, h);
    flushToRest(state_);
}

void Simulation::advanceBody(std::size_t body, double h) {
    if (body < state_.robots.size()) {
        integrateRobotBy(model_, state_, body, h, tables());
        flushToRest(state_.robots[body].v);
        flushToRest(state_.robots[body].omega);
    } else if (!atRest(state_.ball)) {
        integrateBallExact(model_.ball, state_.ball, h);
        flushToRest(state_.ball.vx);
        flushToRest(state_.ball.vy);
    }
}

void Simulation::finishStep(std::int64_t steps) {
    state_.step += steps;
    state_.time = static_cast<double>(state_.step) * model_.settings.dt;
}

StepReport Simulation::ordinaryStep() {
    StepOptions options = cachedTables();
    if (anyOffField()) options.freeRobots = &state_.offField;  // nothing touches them
    const StepReport report = stepWorld(model_, state_, model_.settings.dt, options);
    finishStep(1);
    return report;
}

StepReport Simulation::step() {
    applyDueCommands();
    runSpeedLoops();
    return ordinaryStep();
}

RobotOutputs Simulation::robotOutputs(int robot) const {
    return computeRobotOutputs(model_.robots[robot], state_.robots[robot], state_.voltages[robot]);
}

}  // namespace vssim
