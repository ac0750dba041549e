#include "vssim/world.h"

#include <algorithm>
#include <cmath>

#include "vssim/collision_detect.h"
#include "vssim/collision_response.h"
#include "vssim/integrator.h"

namespace vssim {

namespace {

// Velocity passes per step: each detects all contacts, responds and separates.
constexpr int kContactPasses = 8;
// Final passes against the walls only, which have infinite mass, so that no
// body is left outside the field.
constexpr int kContainmentPasses = 2;

double robotReachSpeed(const RobotModel& m, const RobotState& r, const Voltages& e) {
    // A bound on the fastest point of the robot over a step: the larger of the
    // current and the steady-state body velocity (motion under constant
    // voltage is a damped approach to the steady state).
    const double radius = m.params.side / std::sqrt(2.0);
    const Eigen::Vector2d target = steadyStateVelocity(m, e);
    const double now = std::abs(r.v) + std::abs(r.omega) * radius;
    const double later = std::abs(target(0)) + std::abs(target(1)) * radius;
    return std::max(now, later);
}

int substepsFor(const WorldModel& model, const WorldState& state, double h) {
    double smallest = model.ball.radius;
    double fastest = std::hypot(state.ball.vx, state.ball.vy);
    for (std::size_t i = 0; i < state.robots.size(); ++i) {
        smallest = std::min(smallest, 0.5 * model.sides[i]);
        fastest = std::max(fastest, robotReachSpeed(model.robots[i], state.robots[i], state.voltages[i]));
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

StepReport stepWorld(const WorldModel& model, WorldState& state, double h) {
    StepReport report;
    report.substeps = substepsFor(model, state, h);
    const double sub = h / report.substeps;
    const Integrator method = model.settings.integrator;
    Bodies bodies{&state.robots, &model.robots, &state.ball, &model.ball};
    const BodiesView view{&state.robots, &model.sides, &state.ball, model.ball.radius};

    for (int s = 0; s < report.substeps; ++s) {
        for (std::size_t i = 0; i < state.robots.size(); ++i)
            integrateRobot(model.robots[i], state.robots[i], state.voltages[i], sub, method);
        integrateBall(model.ball, state.ball, sub, method);
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
    const double steps = t / dt;
    return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(steps - 1e-9)));
}

void Simulation::setVoltages(int robot, const Voltages& e) {
    state_.voltages[robot] = clampVoltages(model_.robots[robot].params, e);
}

StepReport Simulation::step() {
    while (nextCommand_ < schedule_.size() && schedule_[nextCommand_].step <= state_.step) {
        const ScheduledCommand& c = schedule_[nextCommand_++];
        setVoltages(c.robot, c.voltages);
    }
    const StepReport report = stepWorld(model_, state_, model_.settings.dt);
    ++state_.step;
    state_.time = static_cast<double>(state_.step) * model_.settings.dt;
    return report;
}

RobotOutputs Simulation::robotOutputs(int robot) const {
    return computeRobotOutputs(model_.robots[robot], state_.robots[robot], state_.voltages[robot]);
}

}  // namespace vssim
