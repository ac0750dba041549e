// The state of a game: phase, half, clock, score, the referee's last call and
// the timers of its rules (shared vsss-game.md, "Rules"). Plain data; the
// referee (referee.h) updates it, a Match (match.h) owns it.
//
// Sides: GameRules::left_team defends the goal at x < 0 and attacks the goal
// at x > 0, the other team the other way round, for the whole match (the
// teams do not change ends at half time, so a client never has to flip its
// frame).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "vssim/scene.h"

namespace vssim {

enum class GamePhase {
    GameOn,    // playing: the clock runs, the rules apply
    Stop,      // after a call: robots held at 0 V, placed, GAME_ON after stop_duration
    Halt,      // stopped by hand: robots held at 0 V until resumed
    Finished,  // the last half is over
};

// The referee's calls (VSSReferee's fouls, less the ones it only announces).
enum class Call {
    None,
    KickOff,      // at the start of each half and after each goal, for `team`
    FreeBall,     // stuck ball: `quadrant`, no team
    PenaltyKick,  // for `team`, the attacker
    GoalKick,     // for `team`, the defender
};

// Quadrants 1-4 counter-clockwise from x > 0, y > 0 (0: none), as
// VSSReferee numbers them: Q1 x > 0, y > 0; Q2 x <= 0, y > 0; Q3 x <= 0,
// y <= 0; Q4 x > 0, y <= 0 (a ball on an axis goes left and down).
int quadrantOf(double x, double y);

struct RefereeCall {
    Call call = Call::None;
    Team team = Team::Yellow;  // the team the call favours (KickOff, PenaltyKick, GoalKick)
    int quadrant = 0;          // FreeBall: 1-4
    int half = 1;
    double clock = 0.0;  // game time in the half when it was called, s
    double time = 0.0;   // simulated time, s
    std::string reason;  // "goal by yellow", "ball stuck", "two defenders", "by hand", ...
};

struct GameState {
    GamePhase phase = GamePhase::Stop;
    int half = 1;                    // 1, 2, ...
    double clock = 0.0;              // game time played in this half, s
    double stopLeft = 0.0;           // Stop: time until GAME_ON, s
    std::array<int, 2> goals{};      // by team: [Yellow], [Blue]
    RefereeCall last;                // the call being played (or the last one)
    std::vector<RefereeCall> calls;  // every call of the match, in order
    // The rules' timers, s of game time.
    double ballStuckFor = 0.0;
    // Where the ball was at each tick of the last half second (oldest
    // first; emptied at each call), m: the stuck-ball rule takes the ball's
    // speed as its mean over that window, from its displacement, so that a
    // ball rattling in a jam or jerked along a wall in a scrum (velocity from
    // every contact, going nowhere) counts as stuck.
    std::vector<std::pair<double, double>> ballTrail;  // a ring of the window's length
    std::size_t trailNext = 0;                         // where the next position goes
    std::size_t trailSize = 0;                         // positions held (0 after a call)
    std::array<double, 2> crowdedDefenceFor{};  // by defending team: two or more defenders in its area with the ball
    std::array<double, 2>
        crowdedAttackFor{};            // by attacking team: two or more attackers in the other area with the ball
    std::vector<double> goalAreaTime;  // per robot: time spent in its own goal area (goalkeeper choice)
};

inline int teamIndex(Team team) { return team == Team::Yellow ? 0 : 1; }
inline Team otherTeam(Team team) { return team == Team::Yellow ? Team::Blue : Team::Yellow; }
// The x sign of the goal a team defends: -1 for rules.left_team, +1 for the other.
inline double defendedSide(const GameRules& rules, Team team) { return team == rules.left_team ? -1.0 : 1.0; }
// The team that defends the goal on `side` (the x sign of the goal: -1 or +1).
inline Team teamDefending(const GameRules& rules, int side) {
    return side < 0 ? rules.left_team : otherTeam(rules.left_team);
}

const char* gamePhaseName(GamePhase phase);
const char* callName(Call call);
const char* teamLabel(Team team);

}  // namespace vssim
