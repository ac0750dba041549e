// The STATE message's JSON (docs/protocol.md, STATE): the ground truth of
// every body at a camera instant, SI units; and the same as one client's
// camera reports it (its noise and vanishing bodies).
#pragma once

#include <QJsonObject>
#include <cstdint>

#include "vssim/camera_settings.h"
#include "vssim/game/game_state.h"
#include "vssim/world.h"

namespace vssim {

// With `game` (a scene with a referee), also the game's state: "game"
// (wire/game_message.h).
QJsonObject stateJson(const Simulation& sim, std::int64_t frame, const GameState* game = nullptr);

// `exact` (a stateJson) as a client whose camera is `camera` and whose draws
// are `stream` (delivery/camera_draws.h) sees it: each robot's x, y, theta
// and the ball's x, y through delivery/ground_truth_noise.h, at the frame
// `exact` names. With vanishing bodies (camera.vanish > 0) every robot and
// the ball get "visible": true, or false with no x, y (and theta); speeds,
// voltages, currents, on_field and the game stay exact. Without ground-truth
// noise, `exact` itself.
QJsonObject observedStateJson(const QJsonObject& exact, const CameraSettings& camera, std::uint64_t stream);

}  // namespace vssim
