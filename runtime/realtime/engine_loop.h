// The real-time loop of model.md §8, as plain logic: no thread, no clock of
// its own. The engine thread (engine_thread.h) feeds it requests stamped with
// their arrival time and the current time, both from monotonicNs(); tests
// feed it made-up times.
//
// Modes:
//   realtime  simulated time = anchor + speed * (wall time - wall anchor);
//             a request takes effect at the simulated instant it arrived (the
//             first step boundary at or after it); a camera instant every
//             frame period of simulated time.
//   max       as fast as possible: one frame period per runUntil() call;
//             requests take effect between frame periods.
//   lockstep  time advances only on `step` requests; each ends with a camera
//             instant. Same scene and same requests: bit-identical results.
// Paused (realtime or max): time stands still; `step` works as in lockstep.
// Halted: the state became non-finite (NaN or infinity: an unstable step,
// extreme parameters). The loop stops there, before the camera instant that
// would show it, tells the sink once (EngineSink::halted) and pauses
// (realtime, max); until a reset or a new scene, or placements that make the
// state finite again, `step` and `resume` are refused with error
// "non_finite" and time stands still.
//
// The game: the loop plays the scene as a Match (game/match.h): the referee
// and the built-in teams act at every game tick (the scene's game.tick);
// with the referee off and no built-in team the Match is exactly the plain
// Simulation. Camera instants keep their own schedule whatever the tick
// (FIRASim's 1/60 s puts each instant on the first step at or after its
// multiple of the period: 17, 17 and 16 ms with 1 ms steps) and a `step`
// lasts its own duration in whole steps of dt: the Match ticks inside any
// advance, so every instant a client sees comes after the referee's and the
// built-in team's decisions at the last tick, and lockstep runs repeat bit
// for bit (the same steps and camera schedule give the same states; the
// exact integrator's long steps round differently where a run is cut
// elsewhere, so a run with another schedule drifts apart). A change of
// the game's state (phase, call, half, score) is told to the sink
// (gameChanged) before the camera instant that first shows it, or at once
// when a request made it.
//
// Wheel speeds (TCP WHEEL_SPEEDS, FIRASim) are handled like voltages and go
// to the robot's speed loop (Match::setWheelSpeeds).
//
// Voltages: a TCP client's go to the Match (Match::setVoltages: applied to
// a remote team's robots while the game is on, ignored for a built-in or
// idle team's). A person's (ManualVoltages) override the robot whatever its
// team's control: they are applied again after every tick while the game is
// on, and the robot gets 0 V while it is stopped, like every other robot.
// Let go (ReleaseManual), a remote team's robot gets its last TCP voltages
// again at once, a built-in team's robot its team's voltages from the next
// tick.
//
// New simulation settings (SetSettings) make a new Match: in a game with a
// referee it starts again from its kick-off (score 0:0, first half; the
// Match cannot carry a game over to another step); otherwise the bodies stay
// where they are, as before.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>

#include "realtime/engine_request.h"
#include "realtime/sample_stats.h"
#include "realtime/simulation_fault.h"
#include "vssim/game/match.h"
#include "vssim/scene.h"
#include "vssim/world.h"

namespace vssim {

enum class RunMode { Realtime, Max, Lockstep };

// Who drives a robot now.
enum class RobotController { None, Tcp, Manual };
struct RobotControl {
    RobotController controller = RobotController::None;
    int client = -1;              // the TCP client whose voltages it last took (Tcp), or -1
    DriveCommand lastTcp;         // a client's last command (V or rad/s), also while under manual control
    bool tcpWhileManual = false;  // TCP voltages arrived (and were ignored) under manual control
    DriveCommand manual;          // the person's command while under manual control (V, or rad/s through the loop)
};
const char* runModeName(RunMode mode);

// Where the loop's output goes: camera instants and replies.
class EngineSink {
public:
    virtual ~EngineSink() = default;
    // A camera instant: the simulation is exactly at frame `frame`'s time.
    virtual void cameraInstant(const Simulation& sim, std::int64_t frame, std::int64_t nowNs) = 0;
    virtual void reply(const EngineReply& reply) = 0;
    // The simulation's state stopped being finite at fault.time: the loop
    // has halted (see above). Called once per halt; nothing by default.
    virtual void halted(const SimulationFault& fault, std::int64_t nowNs) {
        (void)fault;
        (void)nowNs;
    }
    // The game's state changed (phase, call, half or score; with a referee
    // only), or the game started again: at a reset and a new scene (not at
    // start(), before anyone could listen). `frame`
    // is the camera instant it comes before (or the current one, after a
    // request). Nothing by default.
    virtual void gameChanged(const Match& match, std::int64_t frame, std::int64_t nowNs) {
        (void)match;
        (void)frame;
        (void)nowNs;
    }
};

struct EngineLoopSettings {
    RunMode mode = RunMode::Realtime;
    double speed = 1.0;         // real-time factor (realtime mode), > 0
    double framePeriod = 0.03;  // camera period, s of simulated time (on average: see "fractionalFrames_")
    double maxLag = 0.5;        // s of wall time: further behind than this, realtime drops the lag
};

// The real-time factors a realtime loop accepts (faster: max mode).
constexpr double kMinSpeed = 1e-3;
constexpr double kMaxSpeed = 100.0;
// Frame periods runUntil() simulates at most per call.
constexpr std::int64_t kMaxFramesPerPass = 4;

// What the loop measured (wall-clock figures in ms).
struct EngineLoopStats {
    SampleStats commandLatencyMs;   // from a voltage command's arrival to its application, wall clock
    SampleStats commandDelayMs;     // simulated time from arrival instant to the step it took effect at
    std::int64_t lateCommands = 0;  // commands that arrived for an instant already simulated
    std::int64_t lagResets = 0;     // times realtime fell more than maxLag behind and dropped the lag
};

class EngineLoop {
public:
    EngineLoop(const Scene& scene, const EngineLoopSettings& settings, EngineSink& sink);

    // Anchors simulated time to nowNs and emits camera instant 0.
    void start(std::int64_t nowNs);
    // Applies one request (at its arrival instant, in realtime mode; a
    // resume, speed change or reset restarts the clock from its arrival).
    void handle(const EngineRequest& request, std::int64_t nowNs);
    // Realtime: simulates up to nowNs (camera instants on the way). Max: one
    // frame period. Paused or lockstep: nothing.
    void runUntil(std::int64_t nowNs);
    // When runUntil next has work: the wall time of the next camera instant
    // (realtime), 0 (max: now), or the largest int64 (paused, lockstep).
    std::int64_t nextWakeNs() const;

    const Simulation& simulation() const { return match_->simulation(); }
    const Match& match() const { return *match_; }
    const Scene& scene() const { return scene_; }
    const std::vector<RobotControl>& control() const { return control_; }
    std::int64_t frame() const { return frame_; }
    std::int64_t frameSteps() const { return frameSteps_; }
    // The camera period, s: whole steps (frameSteps), or on average the
    // settings' period when it is not a whole number of steps (see below).
    double framePeriod() const;
    RunMode mode() const { return mode_; }
    bool paused() const { return paused_; }
    // Why the loop halted (see above), or nothing while the state is finite.
    const std::optional<SimulationFault>& fault() const { return fault_; }
    double speed() const { return speed_; }
    const EngineLoopStats& stats() const { return stats_; }
    // The simulated time (s) that wall time nowNs maps to (realtime, running).
    double simTimeAt(std::int64_t nowNs) const;

private:
    Scene scene_;
    EngineLoopSettings settings_;
    std::vector<RobotControl> control_;  // per robot
    EngineSink& sink_;
    std::unique_ptr<Match> match_;
    RunMode mode_;
    bool paused_ = false;
    double speed_;
    std::int64_t frameSteps_;     // steps of dt per frame period
    std::int64_t frame_ = 0;      // camera instants since start/reset
    std::int64_t nextFrameStep_;  // step index of the next camera instant
    // A period of whole steps gives an instant every frameSteps_ steps; any
    // other (1/60 s in steps of 1 ms) gives instant k of a schedule at the
    // first step at or after k periods from frameBase_: the right rate on
    // average, within a step of each multiple of the period.
    bool fractionalFrames_ = false;
    double exactFrameSteps_ = 1.0;   // steps per period, not rounded
    std::int64_t frameBase_ = 0;     // the step the schedule counts from
    std::int64_t frameIndex_ = 1;    // k of nextFrameStep_
    std::int64_t frameStepAt(std::int64_t k) const;
    void restartFrames(std::int64_t fromStep);  // instant 1 of a new schedule from `fromStep`
    std::int64_t anchorNs_ = 0;   // wall time at which the simulation was at anchorStep_
    std::int64_t anchorStep_ = 0;
    EngineLoopStats stats_;
    std::optional<SimulationFault> fault_;
    // What gameChanged last told: phase, calls made, half, goals.
    struct GameMark {
        GamePhase phase = GamePhase::GameOn;
        std::size_t calls = 0;
        int half = 0;
        std::array<int, 2> goals{};
        bool operator==(const GameMark& o) const {
            return phase == o.phase && calls == o.calls && half == o.half && goals == o.goals;
        }
    };
    std::optional<GameMark> told_;

    // The Match for scene `scene` (the loop's own, or one without commands).
    void newMatch(const Scene& scene);
    // The camera period in whole steps, and whole game ticks while the Match ticks.
    void updateFrameSteps();
    // Hands the Match the person's voltages for the robots under manual
    // control (Match::overrideDrive; 0 V while the game is stopped), after
    // a new Match or a change of who drives.
    void applyManual();
    // Tells the sink when the game's state changed (or always, `force`).
    void tellGame(std::int64_t nowNs, bool force = false);
    // A game request's check: the referee must be on.
    bool needsReferee(const EngineRequest& request);

    bool running() const { return mode_ == RunMode::Realtime && !paused_ && !fault_; }
    // Checks the state after an advance: on the first non-finite one, halts
    // (pauses outside lockstep) and tells the sink. True while halted.
    bool halt(std::int64_t nowNs);
    // Whether the loop is still halted, once placements may have mended the state.
    bool stillHalted();
    // Simulated time restarts from the current step at wall time wallNs.
    void reanchor(std::int64_t wallNs);
    // Realtime: advances towards the step of wall time wallNs, by at most
    // budgetSteps; drops the lag when it exceeds maxLag. False when the
    // simulation is already past that step (the request came late).
    bool catchUp(std::int64_t wallNs, std::int64_t nowNs, std::int64_t budgetSteps);
    // Advances to step `target`, with a camera instant at each one passed;
    // stops early (false) when the state becomes non-finite.
    bool advanceTo(std::int64_t target, std::int64_t nowNs);
    // The first step boundary at or after the simulated instant of nowNs.
    std::int64_t stepAt(std::int64_t nowNs) const;
    void emitInstant(std::int64_t nowNs);
    // The scene from its beginning: time 0, frame 0 (emitted).
    void restart(std::int64_t arrivalNs, std::int64_t nowNs);
    // Frame 0 now (emitted), the clock anchored at arrivalNs.
    void restartClock(std::int64_t arrivalNs, std::int64_t nowNs);
    QString haltedMessage() const;  // for replies while halted
    void replyTo(const EngineRequest& request, const QString& error = {}, const QString& message = {},
                 std::optional<StatsReport> stats = std::nullopt);
};

}  // namespace vssim
