#include "vssim/game/placement.h"

#include <cmath>

#include "vssim/collision_detect.h"
#include "vssim/game/pitch.h"
#include "vssim/game/referee.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kClearance = 0.01;      // m between a placed robot and any other body
constexpr double kBehindBall = 0.01;     // m between the kicker's face and the ball
constexpr double kOnGoalLine = 0.002;    // m between a goalkeeper's back and its goal line
constexpr double kSearchStep = 0.02;     // m between rings of the search for a free spot
constexpr int kSearchRings = 100;        // rings searched (2 m)
constexpr int kSearchRays = 24;          // spots per ring
constexpr double kFreeBallSlack = 0.01;  // m a robot may stand inside free_ball_distance

// The heading that faces the goal a team attacks.
double facingAttack(const GameRules& rules, Team team) { return defendedSide(rules, team) < 0.0 ? 0.0 : kPi; }

struct Placer {
    const WorldModel& model;
    const std::vector<Team>& teams;
    Placement& out;
    std::vector<char> placed;
    double ballRadius;

    bool clear(std::size_t i, const Eigen::Vector2d& p, double theta) const {
        const double side = model.sides[i];
        if (!robotInsideField(model.field, side, p.x(), p.y(), theta)) return false;
        const double reach = boundingRadius(side);
        if ((p - Eigen::Vector2d(out.ball.x, out.ball.y)).norm() < reach + ballRadius + kClearance) return false;
        for (std::size_t j = 0; j < placed.size(); ++j) {
            if (!placed[j] || j == i) continue;
            const Eigen::Vector2d q(out.robots[j].x, out.robots[j].y);
            if ((p - q).norm() < reach + boundingRadius(model.sides[j]) + kClearance) return false;
        }
        return true;
    }

    void put(std::size_t i, const Eigen::Vector2d& p, double theta) {
        out.robots[i] = RobotState{p.x(), p.y(), theta, 0.0, 0.0};
        placed[i] = 1;
    }

    // The first clear spot at or around `preferred` (rings of growing
    // radius) that `allowed` accepts; false when there is none.
    template <typename Allowed>
    bool putNear(std::size_t i, const Eigen::Vector2d& preferred, double theta, Allowed allowed) {
        for (int ring = 0; ring <= kSearchRings; ++ring) {
            const int rays = ring == 0 ? 1 : kSearchRays;
            for (int k = 0; k < rays; ++k) {
                const double angle = 2.0 * kPi * k / rays;
                const Eigen::Vector2d p =
                    preferred + ring * kSearchStep * Eigen::Vector2d(std::cos(angle), std::sin(angle));
                if (allowed(p) && clear(i, p, theta)) {
                    put(i, p, theta);
                    return true;
                }
            }
        }
        return false;
    }
};

// The team's robots in index order, its goalkeeper first.
std::vector<std::size_t> membersOf(const std::vector<Team>& teams, Team team, int goalkeeper) {
    std::vector<std::size_t> members;
    if (goalkeeper >= 0) members.push_back(static_cast<std::size_t>(goalkeeper));
    for (std::size_t i = 0; i < teams.size(); ++i)
        if (teams[i] == team && static_cast<int>(i) != goalkeeper) members.push_back(i);
    return members;
}

// The robot that takes a kick for `team`: its last robot that is not the
// goalkeeper, or the goalkeeper when it is alone; -1 for no robot.
int kickerOf(const std::vector<std::size_t>& members) {
    if (members.empty()) return -1;
    return static_cast<int>(members.back());
}

}  // namespace

Placement automaticPlacement(const WorldModel& model, const WorldState& state, const std::vector<Team>& teams,
                             const GameState& game, const GameRules& rules, const RefereeCall& call) {
    const Field& field = model.field;
    const double hx = 0.5 * field.length, hy = 0.5 * field.width;
    Placement out;
    out.robots = state.robots;
    for (RobotState& r : out.robots) r.v = 0.0, r.omega = 0.0;
    Placer placer{model, teams, out, std::vector<char>(teams.size(), 0), model.ball.radius};

    const int keeper[2] = {goalkeeperOf(game, teams, Team::Yellow), goalkeeperOf(game, teams, Team::Blue)};
    const std::vector<std::size_t> members[2] = {membersOf(teams, Team::Yellow, keeper[0]),
                                                 membersOf(teams, Team::Blue, keeper[1])};
    const double ballToFace = model.ball.radius + kBehindBall;

    // The ball, and the robots the call needs.
    Eigen::Vector2d ball(0.0, 0.0);
    switch (call.call) {
        case Call::None:
        case Call::KickOff: break;
        case Call::FreeBall: ball = freeBallMark(field, call.quadrant == 0 ? 1 : call.quadrant); break;
        case Call::PenaltyKick: ball = penaltyMark(field, static_cast<int>(defendedSide(rules, otherTeam(call.team)))); break;
        case Call::GoalKick: {
            const double s = defendedSide(rules, call.team);
            ball = Eigen::Vector2d(s * (hx - 0.7 * field.dimensions.goal_area_depth), 0.0);
            if (!(field.dimensions.goal_area_depth > 0.0)) ball = Eigen::Vector2d(s * 0.5 * hx, 0.0);
            break;
        }
    }
    out.ball = BallState{ball.x(), ball.y(), 0.0, 0.0};

    auto goalLine = [&](Team team, std::size_t i) {
        const double s = defendedSide(rules, team);
        return Eigen::Vector2d(s * (hx - 0.5 * model.sides[i] - kOnGoalLine), 0.0);
    };
    auto behindBall = [&](std::size_t i, double towards) {  // towards: +1 kicking to +x, -1 to -x
        return Eigen::Vector2d(ball.x() - towards * (ballToFace + 0.5 * model.sides[i]), ball.y());
    };
    auto anywhere = [](const Eigen::Vector2d&) { return true; };

    for (Team team : {Team::Yellow, Team::Blue}) {
        const int t = teamIndex(team);
        const double s = defendedSide(rules, team);
        const std::vector<std::size_t>& m = members[t];
        if (m.empty()) continue;
        const int kicker = kickerOf(m);
        switch (call.call) {
            case Call::None: break;
            case Call::KickOff:
                if (team == call.team) placer.putNear(kicker, behindBall(kicker, -s), facingAttack(rules, team), anywhere);
                break;
            case Call::FreeBall: {
                // Its robot nearest to the mark that is not the goalkeeper (or the goalkeeper alone).
                std::size_t chosen = m.front();
                double best = INFINITY;
                for (std::size_t k = m.size() > 1 ? 1 : 0; k < m.size(); ++k) {
                    const double d = std::hypot(state.robots[m[k]].x - ball.x(), state.robots[m[k]].y - ball.y());
                    if (d < best) best = d, chosen = m[k];
                }
                placer.putNear(chosen, ball + Eigen::Vector2d(s * rules.free_ball_distance, 0.0), facingAttack(rules, team),
                               anywhere);
                break;
            }
            case Call::PenaltyKick:
                if (team == call.team)
                    placer.putNear(kicker, behindBall(kicker, -s), facingAttack(rules, team), anywhere);
                else if (keeper[t] >= 0)
                    placer.put(keeper[t], goalLine(team, keeper[t]), 0.5 * kPi);
                break;
            case Call::GoalKick:
                if (team == call.team && keeper[t] >= 0)
                    placer.putNear(keeper[t], goalLine(team, keeper[t]), facingAttack(rules, team), anywhere);
                break;
        }
    }
    // Goalkeepers not needed elsewhere wait on their goal lines.
    for (Team team : {Team::Yellow, Team::Blue}) {
        const int k = keeper[teamIndex(team)];
        if (k >= 0 && !placer.placed[k]) placer.putNear(k, goalLine(team, k), 0.5 * kPi, anywhere);
    }
    // Everybody else on spots spread over the allowed half.
    const double fx[] = {0.45, 0.45, 0.25, 0.25, 0.65, 0.65, 0.1, 0.1, 0.8, 0.8};
    const double fy[] = {0.45, -0.45, 0.7, -0.7, 0.75, -0.75, 0.85, -0.85, 0.3, -0.3};
    constexpr int kSpots = 10;
    for (Team team : {Team::Yellow, Team::Blue}) {
        const int t = teamIndex(team);
        double s = defendedSide(rules, team);                                    // the half to fill
        if (call.call == Call::PenaltyKick) s = defendedSide(rules, call.team);  // away from the penalty goal
        const double circle = field.dimensions.centre_radius;
        const double minBall = call.call == Call::FreeBall ? rules.free_ball_distance : 0.0;
        const int ownGoal = static_cast<int>(defendedSide(rules, team));
        const int penaltyGoal = static_cast<int>(defendedSide(rules, otherTeam(call.team)));
        int spot = team == Team::Yellow ? 0 : 1;  // the two teams start on opposite wings
        for (std::size_t i : members[t]) {
            if (placer.placed[i]) continue;
            const double half = robotHalfExtent(model.sides[i], facingAttack(rules, team));
            auto allowed = [&](const Eigen::Vector2d& p) {
                if (!(s * p.x() >= half)) return false;  // wholly in the half
                if (p.norm() < circle + boundingRadius(model.sides[i])) return false;
                if ((p - ball).norm() < minBall + boundingRadius(model.sides[i])) return false;
                if (inGoalArea(field, ownGoal, p) || inGoalArea(field, -ownGoal, p)) return false;
                if (call.call == Call::PenaltyKick && inGoalArea(field, penaltyGoal, p)) return false;
                return true;
            };
            const Eigen::Vector2d preferred(s * fx[spot % kSpots] * hx, fy[spot % kSpots] * hy);
            ++spot;
            placer.putNear(i, preferred, facingAttack(rules, team), allowed);
        }
    }
    return out;
}

std::string checkTeamPlacement(const WorldModel& model, const std::vector<Team>& teams,
                               const std::vector<std::string>& names, const GameRules& rules, const RefereeCall& call,
                               Team team, const Placement& placement) {
    const Field& field = model.field;
    const Eigen::Vector2d ball(placement.ball.x, placement.ball.y);
    const double s = defendedSide(rules, team);
    const int penaltyGoal = static_cast<int>(defendedSide(rules, otherTeam(call.team)));
    auto who = [&names](std::size_t i) { return names[i] + " (robot " + std::to_string(i) + ")"; };
    int inCircle = 0, exceptions = 0;
    auto off = [&placement](std::size_t i) { return i < placement.offField.size() && placement.offField[i]; };
    for (std::size_t i = 0; i < teams.size(); ++i) {
        if (teams[i] != team || off(i)) continue;
        const RobotState& r = placement.robots[i];
        const double side = model.sides[i];
        if (!robotInsideField(field, side, r.x, r.y, r.theta)) return who(i) + " is not wholly on the floor";
        for (std::size_t j = 0; j < teams.size(); ++j)
            if (j != i && !off(j) && squareOverlap(r, side, placement.robots[j], model.sides[j]).overlapping)
                return who(i) + " overlaps " + who(j);
        if (robotBallContact(r, side, static_cast<int>(i), placement.ball, model.ball.radius))
            return who(i) + " overlaps the ball";
        const Eigen::Vector2d p(r.x, r.y);
        const double half = robotHalfExtent(side, r.theta);
        switch (call.call) {
            case Call::None: break;
            case Call::KickOff:
                if (!(s * p.x() >= half)) return who(i) + " is not wholly in its own half";
                if (p.norm() < field.dimensions.centre_radius) ++inCircle;
                break;
            case Call::FreeBall:
                if ((p - ball).norm() < rules.free_ball_distance - kFreeBallSlack)
                    return who(i) + " is closer to the ball than the free-ball distance";
                break;
            case Call::PenaltyKick: {
                const bool away = defendedSide(rules, call.team) * p.x() >= half;  // in the half away from that goal
                const bool keeperSpot = team != call.team && inGoalArea(field, penaltyGoal, p);
                const bool kickerSpot = team == call.team && !inGoalArea(field, penaltyGoal, p);
                if (!away && !(keeperSpot || kickerSpot)) return who(i) + " is not in the half away from the penalty";
                if (!away && ++exceptions > 1)
                    return who(i) + ": only the kicker and the goalkeeper may be in the penalty's half";
                break;
            }
            case Call::GoalKick:
                if (team != call.team && inGoalArea(field, static_cast<int>(defendedSide(rules, call.team)), p))
                    return who(i) + " is in the goal area of a goal kick against its team";
                if (team == call.team && inGoalArea(field, static_cast<int>(s), p) && ++exceptions > 1)
                    return who(i) + ": only the goalkeeper may be in the goal area";
                break;
        }
    }
    if (call.call == Call::KickOff && inCircle > (team == call.team ? 1 : 0))
        return team == call.team ? "more than one robot in the centre circle"
                                 : "a robot of the team not kicking off is in the centre circle";
    return {};
}

}  // namespace vssim
