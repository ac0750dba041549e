#include "vssim/body_gaps.h"

#include <algorithm>
#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

RobotState ballPose(const BallState& ball) {
    RobotState p;
    p.x = ball.x;
    p.y = ball.y;
    return p;
}

Separation separationBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                             const RobotState& poseB) {
    const Eigen::Vector2d centreA(poseA.x, poseA.y);
    if (b.kind == BodyKind::Wall) {
        const Wall& wall = model.field.walls[b.index];
        return a.kind == BodyKind::Ball ? ballWallSeparation(centreA, model.ball.radius, wall)
                                        : robotWallSeparation(poseA, model.sides[a.index], wall);
    }
    if (a.kind == BodyKind::Ball) return ballRobotSeparation(centreA, model.ball.radius, poseB, model.sides[b.index]);
    return robotRobotSeparation(poseA, model.sides[a.index], poseB, model.sides[b.index]);
}

void findBodyGaps(const WorldModel& model, const WorldState& state, const std::vector<char>& movingRobots,
                  bool ballMoving, double horizon, std::vector<BodyGap>& out, BodyGapScratch& scratch) {
    out.clear();
    const std::size_t n = state.robots.size();
    std::vector<double>& speed = scratch.speed;
    speed.assign(n + 1, 0.0);
    double fastest = 0.0;  // m/s
    for (std::size_t i = 0; i < n; ++i) {
        if (!movingRobots[i]) continue;
        speed[i] = pointSpeedBoundWithin(model.robots[i], state.robots[i], state.voltages[i], horizon);
        fastest = std::max(fastest, speed[i]);
    }
    if (ballMoving) speed[n] = std::hypot(state.ball.vx, state.ball.vy);
    auto reach = [&](std::size_t i) { return i < n ? boundingRadius(model.sides[i]) : model.ball.radius; };
    auto centre = [&](std::size_t i) {
        return i < n ? Eigen::Vector2d(state.robots[i].x, state.robots[i].y)
                     : Eigen::Vector2d(state.ball.x, state.ball.y);
    };
    auto pose = [&](std::size_t i) { return i < n ? state.robots[i] : ballPose(state.ball); };
    auto ref = [n](std::size_t i) { return i < n ? BodyRef{BodyKind::Robot, int(i)} : BodyRef{BodyKind::Ball, 0}; };
    // Bodies i (a) and j (b): kept when their bounding discs can meet within the horizon.
    auto offer = [&](std::size_t i, std::size_t j) {
        const double closing = speed[i] + speed[j];
        const double discGap = (centre(i) - centre(j)).norm() - reach(i) - reach(j);
        if (discGap > closing * horizon) return;
        const Separation s = separationBetween(model, ref(i), pose(i), ref(j), pose(j));
        out.push_back({ref(i), ref(j), s.distance, closing});
    };
    // Robot pairs, both moving (a frozen body is out of every moving one's
    // reach: long_step_planner.cpp): among the moving robots only, so that a
    // few moving among a thousand cost little. In index order either way.
    std::vector<int>& moving = scratch.moving;
    moving.clear();
    for (std::size_t i = 0; i < n; ++i)
        if (movingRobots[i]) moving.push_back(int(i));
    scratch.pairs.clear();
    if (model.settings.broad_phase && static_cast<int>(moving.size()) >= kBroadPhaseMinRobots) {
        scratch.movingPoses.clear();
        scratch.movingSides.clear();
        for (const int i : moving) {
            scratch.movingPoses.push_back(state.robots[i]);
            scratch.movingSides.push_back(model.sides[i]);
        }
        candidatePairs(scratch.movingPoses, scratch.movingSides, fastest * horizon, scratch.broadPhase, scratch.pairs);
        for (auto& [i, j] : scratch.pairs) i = moving[i], j = moving[j];  // increasing: the order is kept
    } else {
        for (std::size_t a = 0; a < moving.size(); ++a)
            for (std::size_t b = a + 1; b < moving.size(); ++b) scratch.pairs.emplace_back(moving[a], moving[b]);
    }
    for (const auto& [i, j] : scratch.pairs) offer(std::size_t(i), std::size_t(j));
    if (ballMoving)
        for (std::size_t i = 0; i < n; ++i)
            if (movingRobots[i]) offer(n, i);
    // Walls: skipped at once for a body clear of all of them by its reach and travel.
    for (std::size_t i = 0; i <= n; ++i) {
        if (i < n ? !movingRobots[i] : !ballMoving) continue;
        const double travel = speed[i] * horizon;
        const Eigen::Vector2d c = centre(i);
        if (clearOfWalls(model.field, c, reach(i) + travel)) continue;
        for (std::size_t w = 0; w < model.field.walls.size(); ++w) {
            const Wall& wall = model.field.walls[w];
            // Far in front of the wall's line (cheap), or far from the segment.
            if (wall.normal.dot(c - wall.a) - reach(i) > travel) continue;
            if (closestPointOnSegment(wall.a, wall.b, c).distance - reach(i) > travel) continue;
            const BodyRef wallRef{BodyKind::Wall, int(w)};
            const Separation s = separationBetween(model, ref(i), pose(i), wallRef, RobotState{});
            out.push_back({ref(i), wallRef, s.distance, speed[i]});
        }
    }
}

}  // namespace vssim
