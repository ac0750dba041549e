// A whole headless match (vssim match, and the match benchmarks): the default
// scene and the loop that plays a Match to full time. Qt-free, like the game library it drives.
#pragma once

#include <cstdint>
#include <functional>

#include "vssim/game/match.h"

namespace vssim {

// The official 3 vs 3 field (1.50 x 1.30 m with goals), three default robots
// per team, the ball at the centre, the exact integrator at 1 ms (as the
// shipped kickoff_3v3), the referee on with the default rules (two halves of
// 300 s), both teams as given. Its robots start roughly in a kick-off layout;
// a Match with the referee on puts them on the referee's kick-off spots anyway.
Scene defaultMatchScene(TeamControl yellow, TeamControl blue);

// Plays `match` (fresh: stopped for the first kick-off) until full time
// (GamePhase::Finished), one game tick per advance. `afterTick`, when given,
// is called after every tick. Stops early, returning false, when the state
// stops being finite or when the simulated time passes `timeLimit` (s); true
// at full time. (A seeded Match jitters its placements itself: match.h.)
bool playToFullTime(Match& match, double timeLimit, const std::function<void()>& afterTick = {});

// A generous bound on the simulated time a match of these rules can take
// (the clock stops for every call), s: beyond it playToFullTime gives up.
double matchTimeLimit(const GameRules& rules);

}  // namespace vssim
