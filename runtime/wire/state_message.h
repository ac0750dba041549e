// The STATE message's JSON (docs/protocol.md, STATE): the ground truth of
// every body at a camera instant, SI units.
#pragma once

#include <QJsonObject>
#include <cstdint>

#include "vssim/game/game_state.h"
#include "vssim/world.h"

namespace vssim {

// With `game` (a scene with a referee), also the game's state: "game"
// (wire/game_message.h).
QJsonObject stateJson(const Simulation& sim, std::int64_t frame, const GameState* game = nullptr);

}  // namespace vssim
