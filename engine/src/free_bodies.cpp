#include "vssim/free_bodies.h"

#include <algorithm>
#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

// How far robot i's centre can go within `horizon` as the integrator
// computes it (turning does not matter: a disc around the centre holds the
// robot at any heading). The exact integrator follows the true trajectory,
// which robotTravelBound bounds. Euler's and RK4's intermediate velocities
// can overshoot the true ones (by up to about 1.5 times at the edge of RK4's
// stability region), so for them: twice the speed bound, and only for one
// step well inside their stability regions; beyond that nothing is promised.
double robotTravelForIntegrator(const WorldModel& model, const WorldState& state, std::size_t i, double horizon,
                                ModeProgressCache& progress) {
    const RobotModel& robot = model.robots[i];
    if (model.settings.integrator == Integrator::Exact) {
        return robotTravelBound(robot, state.robots[i], state.voltages[i], progress.get(robot, horizon), 0.0);
    }
    if (!(horizon * robot.fastestRate <= 2.0)) return INFINITY;
    return 2.0 * velocityBound(robot, state.robots[i], state.voltages[i])(0) * horizon;
}

// Free flight of the ball is a straight line of length |v0| (1 - e^(-k T)) / k, m;
// Euler and RK4 move it by up to |v0| T in one step.
double ballTravelForIntegrator(const WorldModel& model, const WorldState& state, double horizon) {
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
        out.robotTravel[i] = robotTravelForIntegrator(model, state, i, horizon, out.progress);
        farthest = std::max(farthest, out.robotTravel[i]);
    }
    out.ballTravel = ballTravelForIntegrator(model, state, horizon);
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
    auto reach = [&model](std::size_t i) { return boundingRadius(model.sides[i]); };
    const Eigen::Vector2d ball(state.ball.x, state.ball.y);
    // To touch a wall a body's centre must come within its reach of a wall
    // segment (posts included: they are the walls' ends); a centre off the
    // floor is not free (wallClearance is -infinity there).
    // clearOfWalls first: cheap, and where it clears a body (farther than
    // reach + travel from every wall, by a margin far above rounding) the
    // exact test would too, so the answer is the same, only sooner.
    auto clearOfTheWalls = [&model](const Eigen::Vector2d& c, double reach, double travel) {
        return clearOfWalls(model.field, c, reach + travel) || wallClearance(model.field, c) - reach > travel;
    };
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d c(state.robots[i].x, state.robots[i].y);
        if (!clearOfTheWalls(c, reach(i), out.robotTravel[i])) out.robots[i] = 0;
    }
    if (!clearOfTheWalls(ball, model.ball.radius, out.ballTravel)) out.ball = false;
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d c(state.robots[i].x, state.robots[i].y);
        if (!((c - ball).norm() - reach(i) - model.ball.radius > out.robotTravel[i] + out.ballTravel))
            out.robots[i] = 0, out.ball = false;
    }
    // Only pairs whose discs, grown by the farthest any body can go, overlap
    // can limit each other.
    auto pairMayMeet = [&](std::size_t i, std::size_t j) {
        const double dx = state.robots[i].x - state.robots[j].x, dy = state.robots[i].y - state.robots[j].y;
        const double gap = std::sqrt(dx * dx + dy * dy) - reach(i) - reach(j);
        if (!(gap > out.robotTravel[i] + out.robotTravel[j])) out.robots[i] = 0, out.robots[j] = 0;
    };
    out.pairs.clear();
    if (useBroadPhase(model, state)) {
        candidatePairs(state.robots, model.sides, farthest, out.broadPhase, out.pairs);
        for (const auto& [i, j] : out.pairs) pairMayMeet(std::size_t(i), std::size_t(j));
    } else {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) pairMayMeet(i, j);
    }
    out.all = out.ball && std::all_of(out.robots.begin(), out.robots.end(), [](char f) { return f != 0; });
}

}  // namespace vssim
