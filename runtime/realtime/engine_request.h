// What the server (or the desktop app) asks of the engine thread, and what
// the engine answers. Requests are validated against the scene before they
// are posted (robot indices, teams, finite numbers, inside the field); the
// engine checks only what depends on its own state (e.g. `step` needs a
// paused or lockstep engine).
#pragma once

#include <QJsonObject>
#include <QJsonValue>
#include <QString>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "io/scene_limits.h"
#include "realtime/stats_report.h"
#include "vssim/ball.h"
#include "vssim/game/game_state.h"
#include "vssim/robot_state.h"
#include "vssim/scene.h"
#include "vssim/speed_controller.h"

namespace vssim {

// Speeds a placed body may start with (PlaceRobot, PlaceBall, from a client
// or a person): those a scene file may give (io/scene_limits.h).
constexpr double kMaxPlacedRobotSpeed = scene_limits::kMaxRobotSpeed;  // m/s
constexpr double kMaxPlacedYawRate = scene_limits::kMaxYawRate;        // rad/s
constexpr double kMaxPlacedBallSpeed = scene_limits::kMaxBallSpeed;    // m/s
// The longest `step` a client may ask for at once, s of simulated time.
constexpr double kMaxStepDuration = 3600.0;
// ...and at most this many steps of dt (an hour at the default 1 ms): with a
// tiny dt an hour of simulated time would keep the engine busy for hours.
constexpr double kMaxStepSteps = 3.6e6;

struct EngineRequest {
    enum class Kind {
        Voltages,        // from a TCP client (`client`); ignored for robots under manual control
        WheelSpeeds,     // wheel-speed targets from a client (`client`; TCP WHEEL_SPEEDS or FIRASim):
                         // through each robot's speed loop (speed_controller.h); as Voltages otherwise
        ManualVoltages,  // from a person (keyboard, gamepad): the robots go under manual control
                         // (`voltages`, or `wheelSpeeds` through their speed loops)
        ReleaseManual,   // `robot` back to TCP control: its last TCP voltages (0 V if none) apply again
        Pause,
        Resume,
        Step,
        Reset,
        PlaceRobot,
        PlaceBall,
        Speed,
        Stats,
        LoadScene,    // replace the scene (`scene`) and start it from its beginning
        SetSettings,  // `scene->simulation` (integrator, dt, collisions): the bodies stay where they
                      // are, with their velocities and voltages; the clock restarts at 0 (in a game
                      // with a referee, the game restarts from its kick-off: engine_loop.h)
        // The game (a scene with a referee; refused with error "no_referee" otherwise):
        CallFoul,        // the referee calls `call` for `team` (`quadrant` 1-4 for a free ball), by hand
        HaltGame,        // HALT: every robot at 0 V, the game clock stopped, until ResumeGame
        ResumeGame,      // GAME_ON from HALT or STOP (not the loop's Resume: time may run while halted)
        Placement,       // `team`'s own placement during STOP: `poses`, checked against the call
        SetTeamControl,  // `team` is driven by `control` from now on (built-in, remote or idle)
        SetOnField,      // `robot` leaves the field (`onField` false: not simulated, not seen) or comes back
    };
    Kind kind = Kind::Voltages;
    std::int64_t arrivalNs = 0;                      // monotonicNs() when the message arrived
    int client = -1;                                 // the server's client number; -1: no reply wanted
    QJsonValue id;                                   // the client's request id, echoed in the reply
    QString command;                                 // the CONTROL command's name, echoed
    std::vector<std::pair<int, Voltages>> voltages;  // Voltages: (robot index, V)
    std::vector<std::pair<int, WheelSpeeds>> wheelSpeeds;  // WheelSpeeds: (robot index, rad/s)
    bool onField = true;                                   // SetOnField
    double duration = 0.0;                           // Step: simulated seconds (> 0)
    double speed = 1.0;                              // Speed: real-time factor (> 0); 0 means as fast as possible
    int robot = -1;                                  // PlaceRobot: robot index
    RobotState robotPose;                            // PlaceRobot: m, rad, m/s, rad/s
    BallState ball;                                  // PlaceBall: m, m/s
    // The sender's count of requests queued and not yet handled: the engine
    // decrements it after handling (a per-client quota against floods).
    std::shared_ptr<std::atomic<int>> queued;
    // The next request belongs with this one (EngineThread::postGroup): the
    // engine handles them in one pass, with no step in between.
    bool groupedWithNext = false;
    std::shared_ptr<const Scene> scene;             // LoadScene
    bool startPaused = false;                       // LoadScene: paused at t = 0 (otherwise as before)
    Call call = Call::None;                         // CallFoul
    Team team = Team::Yellow;                       // CallFoul, Placement, SetTeamControl
    int quadrant = 0;                               // CallFoul: 1-4 for a free ball
    std::vector<std::pair<int, RobotState>> poses;  // Placement: (robot index, pose)
    TeamControl control = TeamControl::Remote;      // SetTeamControl
};

struct EngineReply {
    int client = -1;
    QJsonValue id;
    EngineRequest::Kind kind = EngineRequest::Kind::Voltages;  // of the request answered
    QString command;
    bool ok = true;
    QString error;                     // error code when !ok (protocol.md, ERROR)
    QString message;                   // human-readable, when !ok
    double time = 0.0;                 // simulated time after the request, s
    std::int64_t frame = 0;            // camera instant number after the request
    std::optional<StatsReport> stats;  // a `stats` request's measurements, filled in on the way
    // Not a reply but news for every client (client -1): the game's state
    // changed (protocol.md, REFEREE), as its JSON.
    std::optional<QJsonObject> referee;
};

}  // namespace vssim
