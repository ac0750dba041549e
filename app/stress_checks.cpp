#include "stress_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vssim/collision_detect.h"
#include "vssim/collision_response.h"
#include "vssim/geometry.h"
#include "vssim/integrator.h"

namespace vssim::stress {

namespace {

QString number(double value) { return QString::number(value, 'e', 2); }

}  // namespace

bool isFinite(const WorldState& state) {
    for (const RobotState& r : state.robots)
        for (double v : {r.x, r.y, r.theta, r.v, r.omega})
            if (!std::isfinite(v)) return false;
    for (const Voltages& e : state.voltages)
        if (!std::isfinite(e.right) || !std::isfinite(e.left)) return false;
    for (double v : {state.ball.x, state.ball.y, state.ball.vx, state.ball.vy})
        if (!std::isfinite(v)) return false;
    return true;
}

double worstOutside(const WorldModel& model, const WorldState& state) {
    if (!isFinite(state)) return std::numeric_limits<double>::infinity();
    const Field& field = model.field;
    // Signed distance of a point beyond the chain of walls (negative on the floor), m.
    auto beyond = [&field](const Eigen::Vector2d& p) {
        const double d = nearestWall(field, p).distance;
        return onFloor(field, p) ? -d : d;
    };
    double worst = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < state.robots.size(); ++i) {
        const RobotState& r = state.robots[i];
        const double side = model.sides[i];
        if (clearOfWalls(field, {r.x, r.y}, boundingRadius(side))) continue;  // far inside: nothing to measure
        for (const Eigen::Vector2d& v : robotVertices(r, side)) worst = std::max(worst, beyond(v));
        // A post inside the square (no vertex beyond any wall): how deep.
        for (const Eigen::Vector2d& post : field.posts) {
            const Eigen::Vector2d local = toRobotFrame(r, post);
            worst = std::max(worst, std::min(0.5 * side - std::abs(local.x()), 0.5 * side - std::abs(local.y())));
        }
    }
    const Eigen::Vector2d ball(state.ball.x, state.ball.y);
    if (!clearOfWalls(field, ball, model.ball.radius)) worst = std::max(worst, beyond(ball) + model.ball.radius);
    return worst;
}

double worstOverlap(const WorldModel& model, const WorldState& state) {
    const BodiesView view{&state.robots, &model.sides, &state.ball, model.ball.radius, model.settings.broad_phase};
    double worst = 0.0;
    for (const Contact& c : detectContacts(model.field, view))
        if (c.b.kind != BodyKind::Wall && c.a.kind != BodyKind::Wall) worst = std::max(worst, c.depth);
    return worst;
}

double kineticEnergyOf(const WorldModel& model, const WorldState& state) {
    // kineticEnergy() takes the mutable Bodies a response works on, but only
    // reads them: the const_casts never lead to a write.
    const Bodies bodies{const_cast<std::vector<RobotState>*>(&state.robots), &model.robots,
                        const_cast<BallState*>(&state.ball), &model.ball};
    return kineticEnergy(bodies);
}

RunChecker::RunChecker(const WorldModel& model, const WorldState& initial, bool measureEnergy) : model_(model) {
    figures_.energyMeasured = measureEnergy;
    if (measureEnergy) energy_ = kineticEnergyOf(model, initial);
}

void RunChecker::beforeStep(const WorldState& state) {
    if (!figures_.energyMeasured) return;
    before_ = state;
    haveBefore_ = true;
}

bool RunChecker::afterStep(const WorldState& state, std::int64_t contacts, int substeps) {
    figures_.steps = state.step;
    figures_.contacts += contacts;
    if (!isFinite(state)) {
        if (figures_.finite) figures_.nonFiniteTime = state.time;
        figures_.finite = false;
        return false;
    }
    const double outside = worstOutside(model_, state);
    if (outside > figures_.outside) {
        figures_.outside = outside;
        figures_.outsideTime = state.time;
    }
    const double overlap = worstOverlap(model_, state);
    if (overlap > figures_.overlap) {
        figures_.overlap = overlap;
        figures_.overlapTime = state.time;
    }
    if (figures_.energyMeasured) {
        const double energy = kineticEnergyOf(model_, state);
        double reference = energy_;  // J: the energy before the step
        if (contacts > 0 && substeps == 1 && haveBefore_) {
            // The same step without contacts: every body integrated alone.
            WorldState free = before_;
            const double h = model_.settings.dt;
            for (std::size_t i = 0; i < free.robots.size(); ++i)
                integrateRobot(model_.robots[i], free.robots[i], free.voltages[i], h, model_.settings.integrator);
            integrateBall(model_.ball, free.ball, h, model_.settings.integrator);
            reference = kineticEnergyOf(model_, free);
        }
        haveBefore_ = false;
        if (contacts > 0 && energy > reference) {
            const double gain = energy - reference;  // J
            const double relative = energy_ > 0.0 ? gain / energy_ : std::numeric_limits<double>::infinity();
            figures_.energyGain = std::max(figures_.energyGain, gain);
            if (relative > figures_.energyGainRelative) {
                figures_.energyGainRelative = relative;
                figures_.energyTime = state.time;
            }
        }
        energy_ = energy;
    }
    return true;
}

QStringList failedChecks(const RunFigures& f) {
    QStringList failed;
    if (!f.finite) failed << QStringLiteral("NaN/inf in the state at t = %1 s").arg(f.nonFiniteTime);
    if (f.outside > kMaxOutside)
        failed << QStringLiteral("a body %1 m outside the field (limit %2 m) at t = %3 s")
                      .arg(number(f.outside), number(kMaxOutside))
                      .arg(f.outsideTime);
    if (f.overlap > kMaxOverlap)
        failed << QStringLiteral("overlap %1 m between bodies (limit %2 m) at t = %3 s")
                      .arg(number(f.overlap), number(kMaxOverlap))
                      .arg(f.overlapTime);
    if (f.energyMeasured && f.energyGainRelative > kMaxEnergyGain)
        failed << QStringLiteral(
                      "collisions created %1 of the kinetic energy in one step (limit %2; largest gain %3 J) "
                      "at t = %4 s")
                      .arg(number(f.energyGainRelative), number(kMaxEnergyGain), number(f.energyGain))
                      .arg(f.energyTime);
    if (f.determinismChecked && !f.deterministic)
        failed << QStringLiteral("not deterministic: a second run ended in a different state");
    return failed;
}

}  // namespace vssim::stress
