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
Eigen::Vector2d aimPoint(const Field& field, const WorldState& state, const std::vector<Team>& teams, Team team) {
    const int target = -static_cast<int>(defendedSide(team));
    Eigen::Vector2d aim = goalCentre(field, target);
    for (std::size_t i = 0; i < teams.size(); ++i) {
        const Eigen::Vector2d p(state.robots[i].x, state.robots[i].y);
        if (teams[i] == team || !inGoalArea(field, target, p)) continue;
        aim.y() = (p.y() > 0.0 ? -0.3 : 0.3) * field.dimensions.goal_width;
        break;
    }
    return aim;
}

Eigen::Vector2d attacker(const Field& field, const RobotState& r, double side, const BallState& ball,
                         const Eigen::Vector2d& aim) {
    const Eigen::Vector2d b(ball.x, ball.y);
    const Eigen::Vector2d toGoal = (aim - b).normalized();
    const Eigen::Vector2d me(r.x, r.y);
    const Eigen::Vector2d fromMe = b - me;
    const double along = fromMe.dot(toGoal);  // > 0: I am on the right side of the ball
    const double across = std::abs(toGoal.x() * fromMe.y() - toGoal.y() * fromMe.x());
    // Lined up behind the ball: drive through it towards the goal.
    if (along > 0.0 && across < 0.03 && std::acos(std::clamp(fromMe.normalized().dot(toGoal), -1.0, 1.0)) < kLinedUp)
        return goTo(r, b + 0.2 * toGoal, kCruise);
    // Otherwise go round to the spot behind it, keeping clear of the ball
    // when coming from the wrong side.
    const Eigen::Vector2d behind = b - kBehindBall * toGoal;
    Eigen::Vector2d target = behind;
    if (along < 0.02) {
        const Eigen::Vector2d across(-toGoal.y(), toGoal.x());
        const double sign = across.dot(me - b) >= 0.0 ? 1.0 : -1.0;
        target = behind + sign * 0.08 * across;
    }
    const Eigen::Vector2d spot = reachable(field, target, side);
    // The spot behind the ball is against a wall: push the ball from where
    // I am if I am on the right side of it, or free it sideways.
    if ((spot - target).norm() > 0.02 && along > 0.0) return goTo(r, b + 0.1 * fromMe.normalized(), kCruise);
    return goTo(r, spot, kCruise);
}

Eigen::Vector2d goalkeeper(const Field& field, const RobotState& r, const BallState& ball, Team team) {
    const double s = defendedSide(team);
    const double hx = 0.5 * field.length;
    const double reach = 0.5 * field.dimensions.goal_width;
    const Eigen::Vector2d b(ball.x, ball.y);
    // The ball slow in our goal area: clear it (a ball stuck there is a penalty).
    if (inGoalArea(field, static_cast<int>(s), b) && std::hypot(ball.vx, ball.vy) < 0.2 && s * ball.x < hx) {
        const Eigen::Vector2d out(-s, 0.0);
        const Eigen::Vector2d me(r.x, r.y);
        if ((b - me).dot(out) > 0.0) return goTo(r, b + 0.15 * out, kCruise);
    }
    // Follow the ball's line across the goal mouth, predicting a little.
    const double y = std::clamp(ball.y + 0.1 * ball.vy, -reach, reach);
    const Eigen::Vector2d spot(s * (hx - kKeeperOffset), y);
    if ((spot - Eigen::Vector2d(r.x, r.y)).norm() < 0.015) return faceAlong(r, 0.5 * kPi);
    return goTo(r, spot, kCruise);
}

Eigen::Vector2d defender(const Field& field, const RobotState& r, double side, const BallState& ball, Team team) {
    const double s = defendedSide(team);
    const Eigen::Vector2d goal = goalCentre(field, static_cast<int>(s));
    const Eigen::Vector2d b(ball.x, ball.y);
    Eigen::Vector2d spot = goal + kDefenderDistance * (b - goal).normalized();
    // Keep out of the own goal area (two defenders there is a penalty).
    const double front = 0.5 * field.length - field.dimensions.goal_area_depth - 0.06;
    if (s * spot.x() > front && std::abs(spot.y()) < 0.5 * field.dimensions.goal_area_width + 0.06)
        spot.x() = s * front;
    // The ball on our side and nearer to us than to the spot: clear it.
    if (s * ball.x > 0.0 && (b - Eigen::Vector2d(r.x, r.y)).norm() < 0.15 && !inGoalArea(field, static_cast<int>(s), b))
        return attacker(field, r, side, ball, goalCentre(field, -static_cast<int>(s)));
    return goTo(r, reachable(field, spot, side), kCruise);
}

}  // namespace

Voltages voltagesFor(const RobotModel& robot, const RobotState& state, double v, double w) {
    const Eigen::Vector2d wanted(v, w);
    const Eigen::Vector2d now(state.v, state.omega);
    const Eigen::Vector2d ask = wanted + kVelocityGain * (wanted - now);
    const Eigen::Vector2d e = robot.steadyGain.inverse() * ask;  // [right, left], V
    return clampVoltages(robot.params, {e(0), e(1)});
}

void sparringVoltages(const WorldModel& model, const WorldState& state, const std::vector<Team>& teams,
                      const GameState& game, Team team, std::vector<Voltages>& voltages) {
    const int keeper = goalkeeperOf(game, teams, team);
    int order = 0;  // among the field players, in index order
    for (std::size_t i = 0; i < teams.size(); ++i) {
        if (teams[i] != team) continue;
        const RobotState& r = state.robots[i];
        Eigen::Vector2d u;
        if (static_cast<int>(i) == keeper && hasGoals(model.field)) {
            u = goalkeeper(model.field, r, state.ball, team);
        } else {
            const int players = static_cast<int>(std::count(teams.begin(), teams.end(), team)) - (keeper >= 0 ? 1 : 0);
            // With two or more field players the first defends.
            const bool defends = players >= 2 && order == 0 && hasGoals(model.field);
            u = defends
                    ? defender(model.field, r, model.sides[i], state.ball, team)
                    : attacker(model.field, r, model.sides[i], state.ball, aimPoint(model.field, state, teams, team));
            ++order;
        }
        voltages[i] = voltagesFor(model.robots[i], r, u(0), u(1));
    }
}

}  // namespace vssim
