// The automatic referee (shared vsss-game.md, "Rules"; docs/game.md): goals,
// halves, a stuck ball, two defenders, two attackers, the goalkeeper. It
// looks at the world once per tick of game time and changes the GameState;
// placing the bodies after a call is placement.h's job, and a Match
// (match.h) puts the two together.
#pragma once

#include <optional>
#include <vector>

#include "vssim/game/game_state.h"
#include "vssim/world_model.h"

namespace vssim {

// The teams of a scene's robots, by robot index.
std::vector<Team> robotTeams(const Scene& scene);

// A fresh game: Stop for the first half's kick-off (by the yellow team).
GameState initialGameState(const GameRules& rules, std::size_t robots);

// The goalkeeper of `team`: its robot that has spent the longest time in
// its own goal area (ties: the lowest index), or -1 when it has no robot.
int goalkeeperOf(const GameState& game, const std::vector<Team>& teams, Team team);

// One tick of `elapsed` seconds of simulated time that ended at `state`:
// Stop counts down to GAME_ON; GameOn runs the clock and applies the rules,
// in this order: a goal, the end of a half, a ball stuck, two defenders,
// two attackers. Returns the call made, if any (also appended to
// game.calls; the phase is then Stop and every timer is reset).
std::optional<RefereeCall> refereeTick(const GameRules& rules, const WorldModel& model, const WorldState& state,
                                       const std::vector<Team>& teams, double elapsed, GameState& game);

// A call made by hand (the desktop app) or by a rule: records it, stops the
// game for rules.stop_duration and resets the timers.
RefereeCall makeCall(const GameRules& rules, GameState& game, Call call, Team team, int quadrant, double time,
                     std::string reason);

}  // namespace vssim
