// The game in the protocol's JSON (docs/protocol.md: WELCOME `game`, REFEREE,
// STATE `game`): the game's state (phase, the call being played, half,
// clock, score) and its settings (the rules, each team's control).
#pragma once

#include <QJsonObject>

#include "vssim/game/game_state.h"
#include "vssim/game_settings.h"

namespace vssim {

// {"phase", "call", "team", "quadrant", "half", "clock", "stop_left",
//  "goals": {"yellow", "blue"}, "reason", "call_time", "call_clock"}.
QJsonObject gameStateJson(const GameState& game);

// The game as a scene file's `game` object writes it (docs/scenes.md), with
// the teams' current controls.
QJsonObject gameSettingsJson(const GameRules& rules, TeamControl yellow, TeamControl blue);

}  // namespace vssim
