#include "vssim/game/sparring_team.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "vssim/game/pitch.h"
#include "vssim/game/referee.h"

namespace vssim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kCruise = 1.2;             // m/s, top speed asked for (a default robot reaches ~1.6)
constexpr double kTurnGain = 8.0;           // rad/s per rad of heading error
constexpr double kMaxTurn = 12.0;           // rad/s
constexpr double kSpeedGain = 4.0;          // m/s per m of distance
constexpr double kVelocityGain = 2.0;       // correction on the velocity error, 1 (fraction of the error added)
constexpr double kBehindBall = 0.09;        // m: where an attacker lines up behind the ball
constexpr double kLinedUp = 0.35;           // rad: lined up well enough to push the ball
constexpr double kKeeperOffset = 0.05;      // m in front of the goal line
constexpr double kDefenderDistance = 0.32;  // m from the own goal's centre

double wrap(double angle) { return std::remainder(angle, 2.0 * kPi); }

// Body velocity that takes the robot to `target`, driving forwards or
// backwards, whichever needs less turning (a differential robot is symmetric).
Eigen::Vector2d goTo(const RobotState& r, const Eigen::Vector2d& target, double cruise) {
    const Eigen::Vector2d d = target - Eigen::Vector2d(r.x, r.y);
    const double distance = d.norm();
    if (distance < 0.005) return {0.0, 0.0};
    double error = wrap(std::atan2(d.y(), d.x()) - r.theta);
    double direction = 1.0;
    if (std::abs(error) > 0.5 * kPi) {
        error = wrap(error - kPi);
        direction = -1.0;
    }
    const double speed = std::min(cruise, kSpeedGain * distance) * std::max(0.0, std::cos(error));
    const double w = std::clamp(kTurnGain * error, -kMaxTurn, kMaxTurn);
    return {direction * speed, w};
}

// Turn on the spot towards `heading` (either way round: a face is a face).
Eigen::Vector2d faceAlong(const RobotState& r, double heading) {
    const double error = wrap(2.0 * (heading - r.theta)) / 2.0;  // modulo pi
    return {0.0, std::clamp(kTurnGain * error, -kMaxTurn, kMaxTurn)};
}

// The nearest point to p where a robot of this size fits without touching a
// wall: inside the walls by half a diagonal, out of the corner triangles.
Eigen::Vector2d reachable(const Field& field, const Eigen::Vector2d& p, double side) {
    const double margin = 0.75 * side;
    const double hx = 0.5 * field.length - margin, hy = 0.5 * field.width - margin;
    Eigen::Vector2d q(std::clamp(p.x(), -hx, hx), std::clamp(p.y(), -hy, hy));
    const double diagonal = 0.5 * (field.length + field.width) - field.dimensions.corner_leg - 1.5 * side;
    const double excess = std::abs(q.x()) + std::abs(q.y()) - diagonal;  // past a corner triangle's line
    if (excess > 0.0) {
        q.x() -= (q.x() >= 0.0 ? 0.5 : -0.5) * excess;
        q.y() -= (q.y() >= 0.0 ? 0.5 : -0.5) * excess;
    }
    return q;
}

// Where to shoot: the middle of the goal, or the wider side of it when an
// opponent stands in the goal area.
Eigen::Vector2d aimPoint(const Field& field, const WorldState& state, const std::vector<Team>& teams, Team team,
                         int target) {
    Eigen::Vector2d aim = goalCentre(field, target);
    for (std::size_t i = 0; i < teams.size(); ++i) {
        const Eigen::Vector2d p(state.robots[i].x, state.robots[i].y);
        if (teams[i] == team || !inGoalArea(field, target, p)) continue;
        aim.y() = (p.y() > 0.0 ? -0.3 : 0.3) * field.dimensions.goal_width;
        break;
    }
    return aim;
}

// One robot of the team deciding its move: where to go, around the other
// robots, or through the ball.
struct Player {
    const Field& field;
    const WorldState& state;
    std::size_t self;
    double side;  // m
    double own;   // the x sign of the goal the team defends (-1, +1)

    const RobotState& me() const { return state.robots[self]; }
    Eigen::Vector2d at() const { return {me().x, me().y}; }

    // Towards `target`, going round the first robot in the way: one within
    // kClear of the straight path in the next kLookAhead metres.
    Eigen::Vector2d travel(const Eigen::Vector2d& target) const {
        constexpr double kLookAhead = 0.25, kClear = 0.09, kDetour = 0.13;  // m
        const Eigen::Vector2d d = target - at();
        const double distance = d.norm();
        if (distance < 1e-9) return goTo(me(), target, kCruise);
        const Eigen::Vector2d u = d / distance;
        // Pressed against a robot in the way: back off first.
        for (std::size_t j = 0; j < state.robots.size(); ++j) {
            if (j == self) continue;
            const Eigen::Vector2d o = Eigen::Vector2d(state.robots[j].x, state.robots[j].y) - at();
            const double ahead = o.dot(u), distance2 = o.squaredNorm();
            if (ahead > 0.0 && distance2 < 1.44 * side * side && ahead > 0.7 * std::sqrt(distance2))
                return goTo(me(), at() - 0.1 * u, kCruise);
        }
        double nearest = std::min(distance, kLookAhead);
        Eigen::Vector2d detour = target;
        for (std::size_t j = 0; j < state.robots.size(); ++j) {
            if (j == self) continue;
            const Eigen::Vector2d o = Eigen::Vector2d(state.robots[j].x, state.robots[j].y) - at();
            const double ahead = o.dot(u), off = u.x() * o.y() - u.y() * o.x();
            if (ahead <= 0.0 || ahead >= nearest || std::abs(off) >= kClear) continue;
            nearest = ahead;
            const Eigen::Vector2d left(-u.y(), u.x());
            detour = at() + ahead * u + (off > 0.0 ? -kDetour : kDetour) * left;  // pass on the far side
        }
        return goTo(me(), reachable(field, detour, side), kCruise);
    }

    // Get behind the ball on its line to `aim` and drive it there.
    Eigen::Vector2d attack(const BallState& ball, const Eigen::Vector2d& aim) const {
        const Eigen::Vector2d b(ball.x, ball.y);
        const Eigen::Vector2d toGoal = (aim - b).normalized();
        const Eigen::Vector2d fromMe = b - at();
        const double along = fromMe.dot(toGoal);  // > 0: I am on the right side of the ball
        const double across = std::abs(toGoal.x() * fromMe.y() - toGoal.y() * fromMe.x());
        // Lined up behind the ball: drive through it.
        if (along > 0.0 && across < 0.03 &&
            along > std::cos(kLinedUp) * fromMe.norm())  // within kLinedUp of the line to the goal
            return goTo(me(), b + 0.2 * toGoal, kCruise);
        // Otherwise go round to the spot behind it, keeping clear of the ball
        // when coming from the wrong side.
        const Eigen::Vector2d behind = b - kBehindBall * toGoal;
        Eigen::Vector2d target = behind;
        if (along < 0.02) {
            const Eigen::Vector2d sideways(-toGoal.y(), toGoal.x());
            const double sign = sideways.dot(at() - b) >= 0.0 ? 1.0 : -1.0;
            target = behind + sign * 0.08 * sideways;
        }
        const Eigen::Vector2d spot = reachable(field, target, side);
        // The spot behind the ball is against a wall: push the ball from
        // where I am if I am on the right side of it.
        if ((spot - target).norm() > 0.02 && along > 0.0) return goTo(me(), b + 0.1 * fromMe.normalized(), kCruise);
        return travel(spot);
    }

    Eigen::Vector2d keepGoal(const BallState& ball) const {
        const double s = own;
        const double hx = 0.5 * field.length;
        const double reach = 0.5 * field.dimensions.goal_width;
        const Eigen::Vector2d b(ball.x, ball.y);
        // The ball slow in our goal area: clear it towards the other goal (a
        // ball stuck there is a penalty against us).
        if (inGoalArea(field, static_cast<int>(s), b) && std::hypot(ball.vx, ball.vy) < 0.2 && s * ball.x < hx)
            return attack(ball, goalCentre(field, -static_cast<int>(s)));
        // Follow the ball's line across the goal mouth, predicting a little.
        const double y = std::clamp(ball.y + 0.1 * ball.vy, -reach, reach);
        const Eigen::Vector2d spot(s * (hx - kKeeperOffset), y);
        if ((spot - at()).norm() < 0.015) return faceAlong(me(), 0.5 * kPi);
        return goTo(me(), spot, kCruise);
    }

    // Behind the ball on the own side, off its line to the own goal, ready
    // for a rebound: the k-th supporter on alternating sides.
    Eigen::Vector2d support(const BallState& ball, int k) const {
        const double s = own;
        const Eigen::Vector2d b(ball.x, ball.y);
        const Eigen::Vector2d spot(b.x() + s * 0.25, b.y() + (k % 2 == 0 ? 0.2 : -0.2));
        return travel(reachable(field, spot, side));
    }

    Eigen::Vector2d defend(const BallState& ball) const {
        const double s = own;
        const Eigen::Vector2d goal = goalCentre(field, static_cast<int>(s));
        const Eigen::Vector2d b(ball.x, ball.y);
        Eigen::Vector2d spot = goal + kDefenderDistance * (b - goal).normalized();
        // Keep out of the own goal area (two defenders there is a penalty).
        const double front = 0.5 * field.length - field.dimensions.goal_area_depth - 0.06;
        if (s * spot.x() > front && std::abs(spot.y()) < 0.5 * field.dimensions.goal_area_width + 0.06)
            spot.x() = s * front;
        return travel(reachable(field, spot, side));
    }
};

}  // namespace

Voltages voltagesFor(const RobotModel& robot, const RobotState& state, double v, double w) {
    const Eigen::Vector2d wanted(v, w);
    const Eigen::Vector2d now(state.v, state.omega);
    const Eigen::Vector2d ask = wanted + kVelocityGain * (wanted - now);
    const Eigen::Vector2d e = robot.steadyGain.inverse() * ask;  // [right, left], V
    return clampVoltages(robot.params, {e(0), e(1)});
}

void sparringVoltages(const WorldModel& model, const WorldState& state, const std::vector<Team>& teams,
                      const GameRules& rules, const GameState& game, Team team, std::vector<Voltages>& voltages) {
    const double own = defendedSide(rules, team);
    const int keeper = hasGoals(model.field) ? goalkeeperOf(game, teams, team) : -1;
    // The striker: the field player nearest to the ball (ties: the lowest
    // index). Only it goes for the ball, so that teammates never fight over
    // it; of the others the first defends and the rest support.
    const Eigen::Vector2d ball(state.ball.x, state.ball.y);
    int striker = -1;
    double nearest = INFINITY;
    for (std::size_t i = 0; i < teams.size(); ++i) {
        if (teams[i] != team || static_cast<int>(i) == keeper) continue;
        const double d = (Eigen::Vector2d(state.robots[i].x, state.robots[i].y) - ball).norm();
        if (d < nearest) nearest = d, striker = static_cast<int>(i);
    }
    int others = 0;  // field players that are not the striker, in index order
    for (std::size_t i = 0; i < teams.size(); ++i) {
        if (teams[i] != team) continue;
        const Player player{model.field, state, i, model.sides[i], own};
        Eigen::Vector2d u;
        if (static_cast<int>(i) == keeper)
            u = player.keepGoal(state.ball);
        else if (static_cast<int>(i) == striker)
            u = player.attack(state.ball, aimPoint(model.field, state, teams, team, -static_cast<int>(own)));
        else
            u = others++ == 0 && hasGoals(model.field) ? player.defend(state.ball) : player.support(state.ball, others);
        voltages[i] = voltagesFor(model.robots[i], state.robots[i], u(0), u(1));
    }
}

}  // namespace vssim
