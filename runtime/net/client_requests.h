// Checking what clients ask (docs/protocol.md: HELLO, VOLTAGES, CONTROL)
// against the protocol and the scene, before anything reaches the engine.
// Each check returns an error code (protocol.md, ERROR) and a message that
// says what was wrong and where, or nothing.
#pragma once

#include <QJsonObject>
#include <QString>
#include <optional>
#include <utility>
#include <vector>

#include "io/printable_text.h"
#include "realtime/engine_request.h"
#include "vssim/scene.h"
#include "wire/frame_packet.h"

namespace vssim {

struct RequestError {
    QString code;     // e.g. "malformed", "bad_robot"
    QString message;  // human-readable: what and where
};

enum class ClientRole { Yellow, Blue, Observer };
QString roleName(ClientRole role);

struct Hello {
    ClientRole role = ClientRole::Observer;
    QString name;
    std::optional<ImageSubscription> images;  // none: no images
    bool state = false;
    // HELLO's `camera`: this client's own delivery and ground-truth noise
    // over the scene's camera (kHelloCameraKeys only, checked); empty: none.
    QJsonObject camera;
};

// The keys a HELLO's `camera` may have: the per-client part of CameraSettings
// (delivery and ground-truth noise). Image formation is the scene's.
extern const QStringList kHelloCameraKeys;

std::optional<Hello> parseHello(const QJsonObject& json, RequestError* error);

// A VOLTAGES message's entries: robots that exist, belong to the client's
// team, and finite volts.
std::optional<RequestError> checkVoltages(const std::vector<std::pair<int, Voltages>>& entries, const Scene& scene,
                                          ClientRole role);
// The same for WHEEL_SPEEDS (rad/s; finite, and clamped to +-kMaxWheelSpeedTarget later).
std::optional<RequestError> checkWheelSpeeds(const std::vector<std::pair<int, WheelSpeeds>>& entries,
                                             const Scene& scene, ClientRole role);

// A CONTROL message, as an engine request (arrival time, client and id are
// the caller's to fill in).
std::optional<EngineRequest> parseControl(const QJsonObject& json, const Scene& scene, RequestError* error);

// A PLACEMENT message (docs/protocol.md): a team's own poses for its robots
// during STOP, as an engine request (Kind::Placement). Checked here: the
// layout, robots that exist and belong to the client's team, each once,
// finite numbers, inside the field; the engine checks the rest (the phase,
// the rules of the call: Match::placeTeam).
std::optional<EngineRequest> parsePlacement(const QJsonObject& json, const Scene& scene, ClientRole role,
                                            RequestError* error);

// Whether a CONTROL request leaves the game as it is (only `stats`): what a
// read-only observer may send.
bool leavesTheGameAlone(const EngineRequest& request);

}  // namespace vssim
