#include "vssim/game/referee.h"

#include <algorithm>
#include <cmath>

#include "vssim/game/pitch.h"

namespace vssim {

namespace {

// Timers reach their limit when within this of it (s): they add up ticks of
// 0.01 s, and 500 of them make 4.99999999999999 s, not 5.
constexpr double kTimerSlack = 1e-9;

bool reached(double timer, double limit) { return timer >= limit - kTimerSlack; }

// The stuck-ball rule's speed is the ball's mean speed over this long (s).
constexpr double kStuckWindow = 0.5;

// Robots off the field (WorldState::offField) play no part in the rules.
bool onField(const WorldState& state, std::size_t i) { return i >= state.offField.size() || !state.offField[i]; }

int robotsInArea(const WorldState& state, const Field& field, const std::vector<Team>& teams, Team team, int side) {
    int count = 0;
    for (std::size_t i = 0; i < state.robots.size(); ++i)
        if (teams[i] == team && onField(state, i) && inGoalArea(field, side, {state.robots[i].x, state.robots[i].y}))
            ++count;
    return count;
}

}  // namespace

std::vector<Team> robotTeams(const Scene& scene) {
    std::vector<Team> teams;
    for (const RobotSpec& r : scene.robots) teams.push_back(r.team);
    return teams;
}

int quadrantOf(double x, double y) {
    // VSSReferee's convention: a ball on the y axis (x = 0) is in a left
    // quadrant, one on the x axis (y = 0) in a lower one; the centre is Q3.
    if (x > 0.0) return y > 0.0 ? 1 : 4;
    return y > 0.0 ? 2 : 3;
}

const char* gamePhaseName(GamePhase phase) {
    switch (phase) {
        case GamePhase::GameOn: return "game_on";
        case GamePhase::Stop: return "stop";
        case GamePhase::Halt: return "halt";
        case GamePhase::Finished: return "finished";
    }
    return "?";
}

const char* callName(Call call) {
    switch (call) {
        case Call::None: return "none";
        case Call::KickOff: return "kickoff";
        case Call::FreeBall: return "free_ball";
        case Call::PenaltyKick: return "penalty_kick";
        case Call::GoalKick: return "goal_kick";
    }
    return "?";
}

const char* teamLabel(Team team) { return team == Team::Yellow ? "yellow" : "blue"; }

GameState initialGameState(const GameRules& rules, std::size_t robots) {
    GameState game;
    game.goalAreaTime.assign(robots, 0.0);
    if (!rules.referee) {
        game.phase = GamePhase::GameOn;
        return game;
    }
    makeCall(rules, game, Call::KickOff, Team::Yellow, 0, 0.0, "first half");
    return game;
}

int goalkeeperOf(const GameState& game, const std::vector<Team>& teams, Team team) {
    int best = -1;
    for (std::size_t i = 0; i < teams.size(); ++i) {
        if (teams[i] != team) continue;
        if (best < 0 || game.goalAreaTime[i] > game.goalAreaTime[best]) best = static_cast<int>(i);
    }
    return best;
}

RefereeCall makeCall(const GameRules& rules, GameState& game, Call call, Team team, int quadrant, double time,
                     std::string reason) {
    RefereeCall c;
    c.call = call;
    c.team = team;
    c.quadrant = quadrant;
    c.half = game.half;
    c.clock = game.clock;
    c.time = time;
    c.reason = std::move(reason);
    game.last = c;
    game.calls.push_back(c);
    game.phase = GamePhase::Stop;
    game.stopLeft = rules.stop_duration;
    game.ballStuckFor = 0.0;
    game.trailSize = 0;
    game.crowdedDefenceFor = {};
    game.crowdedAttackFor = {};
    return c;
}

std::optional<RefereeCall> refereeTick(const GameRules& rules, const WorldModel& model, const WorldState& state,
                                       const std::vector<Team>& teams, double elapsed, GameState& game) {
    if (!rules.referee) return std::nullopt;
    if (game.phase == GamePhase::Stop) {
        game.stopLeft -= elapsed;
        if (game.stopLeft <= kTimerSlack) {
            game.stopLeft = 0.0;
            game.phase = GamePhase::GameOn;
        }
        return std::nullopt;
    }
    if (game.phase != GamePhase::GameOn) return std::nullopt;

    const Field& field = model.field;
    const BallState& ball = state.ball;
    const Eigen::Vector2d ballAt(ball.x, ball.y);
    game.clock += elapsed;

    // A goal: the team attacking that goal scores; the other kicks off.
    if (const int side = goalScoredIn(field, ball, model.ball.radius)) {
        const Team defender = teamDefending(rules, side);
        const Team scorer = otherTeam(defender);
        ++game.goals[teamIndex(scorer)];
        return makeCall(rules, game, Call::KickOff, defender, 0, state.time,
                        std::string("goal by ") + teamLabel(scorer));
    }
    // The end of a half: the other team kicks off the next; after the last, full time.
    if (reached(game.clock, rules.half_duration)) {
        game.clock = rules.half_duration;
        if (game.half >= rules.halves) {
            game.phase = GamePhase::Finished;
            return std::nullopt;
        }
        ++game.half;
        game.clock = 0.0;
        const Team kicker = game.half % 2 == 1 ? Team::Yellow : Team::Blue;
        return makeCall(rules, game, Call::KickOff, kicker, 0, state.time, "half " + std::to_string(game.half));
    }
    // Time in the own goal area, for the goalkeeper.
    for (std::size_t i = 0; i < state.robots.size(); ++i)
        if (onField(state, i) &&
            inGoalArea(field, static_cast<int>(defendedSide(rules, teams[i])), {state.robots[i].x, state.robots[i].y}))
            game.goalAreaTime[i] += elapsed;

    // A stuck ball: a free ball in its quadrant, or a penalty in a goal area.
    // The ball's mean speed over the last kStuckWindow (or since the last
    // call, when that is shorter), from its displacement, m/s; the first
    // tick after a call has nothing to compare with and counts as moving.
    const std::size_t windowTicks = static_cast<std::size_t>(std::max(1.0, std::round(kStuckWindow / elapsed)));
    if (game.ballTrail.size() != windowTicks) {
        game.ballTrail.assign(windowTicks, {0.0, 0.0});
        game.trailNext = game.trailSize = 0;
    }
    double speed = INFINITY;
    if (game.trailSize > 0) {
        const auto& [oldX, oldY] = game.ballTrail[(game.trailNext + windowTicks - game.trailSize) % windowTicks];
        const double dx = ball.x - oldX, dy = ball.y - oldY;
        speed = std::sqrt(dx * dx + dy * dy) / (static_cast<double>(game.trailSize) * elapsed);
    }
    game.ballTrail[game.trailNext] = {ball.x, ball.y};
    game.trailNext = (game.trailNext + 1) % windowTicks;
    game.trailSize = std::min(game.trailSize + 1, windowTicks);
    game.ballStuckFor = speed < rules.stuck_ball_speed ? game.ballStuckFor + elapsed : 0.0;
    if (reached(game.ballStuckFor, rules.stuck_ball_time)) {
        for (Team defender : {Team::Yellow, Team::Blue})
            if (inGoalArea(field, static_cast<int>(defendedSide(rules, defender)), ballAt))
                return makeCall(rules, game, Call::PenaltyKick, otherTeam(defender), 0, state.time,
                                "ball stuck in the goal area");
        return makeCall(rules, game, Call::FreeBall, Team::Yellow, quadrantOf(ball.x, ball.y), state.time,
                        "ball stuck");
    }
    // Two defenders in their own goal area with the ball: a penalty for the
    // attackers; two attackers in the other goal area: a goal kick.
    for (Team team : {Team::Yellow, Team::Blue}) {
        const int own = static_cast<int>(defendedSide(rules, team));
        const int t = teamIndex(team);
        const bool defending = inGoalArea(field, own, ballAt) && robotsInArea(state, field, teams, team, own) >= 2;
        game.crowdedDefenceFor[t] = defending ? game.crowdedDefenceFor[t] + elapsed : 0.0;
        const bool attacking = inGoalArea(field, -own, ballAt) && robotsInArea(state, field, teams, team, -own) >= 2;
        game.crowdedAttackFor[t] = attacking ? game.crowdedAttackFor[t] + elapsed : 0.0;
    }
    for (Team team : {Team::Yellow, Team::Blue}) {
        if (reached(game.crowdedDefenceFor[teamIndex(team)], rules.crowded_area_time))
            return makeCall(rules, game, Call::PenaltyKick, otherTeam(team), 0, state.time, "two defenders");
        if (reached(game.crowdedAttackFor[teamIndex(team)], rules.crowded_area_time))
            return makeCall(rules, game, Call::GoalKick, otherTeam(team), 0, state.time, "two attackers");
    }
    return std::nullopt;
}

}  // namespace vssim
