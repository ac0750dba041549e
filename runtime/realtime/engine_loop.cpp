#include "realtime/engine_loop.h"

#include <QJsonArray>
#include <algorithm>
#include <cmath>

namespace vssim {

// The camera period in whole steps of dt (at least one).
static std::int64_t stepsPerFrame(double framePeriod, double dt) {
    return std::max<std::int64_t>(1, std::llround(framePeriod / dt));
}

const char* runModeName(RunMode mode) {
    switch (mode) {
        case RunMode::Realtime: return "realtime";
        case RunMode::Max: return "max";
        case RunMode::Lockstep: return "lockstep";
    }
    return "?";
}

EngineLoop::EngineLoop(const Scene& scene, const EngineLoopSettings& settings, EngineSink& sink)
    : scene_(scene), settings_(settings), sink_(sink), mode_(settings.mode), speed_(settings.speed) {
    newMatch(scene_);
    restartFrames(0);
    control_.assign(scene.robots.size(), RobotControl{});
}

void EngineLoop::newMatch(const Scene& scene) {
    match_ = std::make_unique<Match>(scene);
    told_.reset();
    updateFrameSteps();
}

void EngineLoop::updateFrameSteps() {
    const double exact = settings_.framePeriod / match_->simulation().dt();
    frameSteps_ = stepsPerFrame(settings_.framePeriod, match_->simulation().dt());
    fractionalFrames_ = std::abs(exact - std::round(exact)) > 1e-6 && exact > 1.0;
    exactFrameSteps_ = fractionalFrames_ ? exact : static_cast<double>(frameSteps_);
}

double EngineLoop::framePeriod() const {
    return fractionalFrames_ ? settings_.framePeriod : static_cast<double>(frameSteps_) * simulation().dt();
}

std::int64_t EngineLoop::frameStepAt(std::int64_t k) const {
    // Camera instants keep their own schedule whatever the game tick: the
    // Match ticks inside any advance, so an instant between two ticks shows
    // the world after the last tick's decisions.
    if (!fractionalFrames_) return frameBase_ + k * frameSteps_;
    return frameBase_ + static_cast<std::int64_t>(std::ceil(static_cast<double>(k) * exactFrameSteps_ - 1e-9));
}

void EngineLoop::restartFrames(std::int64_t fromStep) {
    frameBase_ = fromStep;
    frameIndex_ = 1;
    nextFrameStep_ = frameStepAt(1);
}

void EngineLoop::start(std::int64_t nowNs) {
    reanchor(nowNs);
    // Nobody is there yet to be told of the game's start: the ones who come
    // read it from the snapshots (WELCOME), and hear of its changes.
    const GameState& g = match_->game();
    told_ = GameMark{g.phase, g.calls.size(), g.half, g.goals};
    emitInstant(nowNs);
}

void EngineLoop::applyManual() {
    // The Match holds a person's command against its teams' (Match::overrideDrive).
    for (std::size_t i = 0; i < control_.size(); ++i)
        match_->overrideDrive(static_cast<int>(i), control_[i].controller == RobotController::Manual
                                                       ? std::optional<DriveCommand>(control_[i].manual)
                                                       : std::nullopt);
}

void EngineLoop::tellGame(std::int64_t nowNs, bool force) {
    if (!match_->scene().game.rules.referee) return;
    const GameState& g = match_->game();
    const GameMark mark{g.phase, g.calls.size(), g.half, g.goals};
    if (!force && told_ && *told_ == mark) return;
    told_ = mark;
    sink_.gameChanged(*match_, frame_, nowNs);
}

bool EngineLoop::needsReferee(const EngineRequest& r) {
    if (match_->scene().game.rules.referee) return true;
    replyTo(r, "no_referee", "this scene is played without a referee (its game.referee is false)");
    return false;
}

void EngineLoop::reanchor(std::int64_t nowNs) {
    anchorNs_ = nowNs;
    anchorStep_ = simulation().state().step;
}

double EngineLoop::simTimeAt(std::int64_t nowNs) const {
    return (anchorStep_ + 1e-9 * static_cast<double>(nowNs - anchorNs_) * speed_ / simulation().dt()) *
           simulation().dt();
}

std::int64_t EngineLoop::stepAt(std::int64_t nowNs) const {
    // In steps, so that the anchor's own rounding does not accumulate.
    const double steps = anchorStep_ + 1e-9 * static_cast<double>(nowNs - anchorNs_) * speed_ / simulation().dt();
    return Simulation::stepIndexAtOrAfter(steps, 1.0);
}

std::int64_t EngineLoop::nextWakeNs() const {
    if (paused_ || fault_ || mode_ == RunMode::Lockstep) return std::numeric_limits<std::int64_t>::max();
    if (mode_ == RunMode::Max) return 0;
    const double wakeNs = static_cast<double>(anchorNs_) + std::ceil(static_cast<double>(nextFrameStep_ - anchorStep_) *
                                                                     simulation().dt() / speed_ * 1e9);
    // Saturate rather than overflow the conversion (a tiny speed factor).
    if (!(wakeNs < 9.2e18)) return std::numeric_limits<std::int64_t>::max();
    return static_cast<std::int64_t>(wakeNs);
}

void EngineLoop::emitInstant(std::int64_t nowNs) {
    tellGame(nowNs);
    sink_.cameraInstant(simulation(), frame_, nowNs);
}

bool EngineLoop::halt(std::int64_t nowNs) {
    if (fault_) return true;
    fault_ = findSimulationFault(simulation());
    if (!fault_) return false;
    if (mode_ != RunMode::Lockstep) paused_ = true;
    sink_.halted(*fault_, nowNs);
    return true;
}

bool EngineLoop::stillHalted() {
    if (fault_) fault_ = findSimulationFault(simulation());
    return fault_.has_value();
}

bool EngineLoop::advanceTo(std::int64_t target, std::int64_t nowNs) {
    while (nextFrameStep_ <= target) {
        match_->advanceTo(nextFrameStep_);
        if (halt(nowNs)) return false;  // no camera instant of a non-finite state
        ++frame_;
        // The next instant after this one (a tick boundary may hold two multiples of the period).
        do {
            nextFrameStep_ = frameStepAt(++frameIndex_);
        } while (nextFrameStep_ <= simulation().state().step);
        emitInstant(nowNs);
    }
    match_->advanceTo(target);
    return !halt(nowNs);
}

bool EngineLoop::catchUp(std::int64_t wallNs, std::int64_t nowNs, std::int64_t budgetSteps) {
    const std::int64_t target = stepAt(wallNs);
    const std::int64_t behind = target - simulation().state().step;
    if (behind <= 0) return behind == 0;
    // Fallen further behind than maxLag of wall time (a stalled machine, a
    // speed factor beyond what the engine sustains): drop the lag instead of
    // never catching up.
    if (static_cast<double>(behind) * simulation().dt() / speed_ > settings_.maxLag) {
        ++stats_.lagResets;
        reanchor(wallNs);
        return true;
    }
    advanceTo(behind > budgetSteps ? simulation().state().step + budgetSteps : target, nowNs);
    return true;
}

void EngineLoop::runUntil(std::int64_t nowNs) {
    if (paused_ || fault_ || mode_ == RunMode::Lockstep) return;
    if (mode_ == RunMode::Max) {
        advanceTo(nextFrameStep_, nowNs);
        return;
    }
    // A few frame periods per call at most, so that requests are read
    // between them even when the simulation runs behind.
    catchUp(nowNs, nowNs, kMaxFramesPerPass * frameSteps_);
}

void EngineLoop::restart(std::int64_t arrivalNs, std::int64_t nowNs) {
    newMatch(scene_);
    fault_.reset();  // the scene's own state is finite (the scene reader's ranges)
    applyManual();
    restartClock(arrivalNs, nowNs);  // its camera instant tells the sink of the new game
}

void EngineLoop::restartClock(std::int64_t arrivalNs, std::int64_t nowNs) {
    frame_ = 0;
    restartFrames(simulation().state().step);
    reanchor(arrivalNs);
    if (!fault_) emitInstant(nowNs);  // no camera instant of a non-finite state (new settings while halted)
}

void EngineLoop::handle(const EngineRequest& r, std::int64_t nowNs) {
    using Kind = EngineRequest::Kind;
    // In realtime mode every request acts at the instant it arrived.
    const bool command = r.kind == Kind::Voltages || r.kind == Kind::WheelSpeeds;
    if (running() && !catchUp(r.arrivalNs, nowNs, std::numeric_limits<std::int64_t>::max()) && command)
        ++stats_.lateCommands;
    switch (r.kind) {
        case Kind::Voltages:
        case Kind::WheelSpeeds: {
            auto take = [&](int robot, const DriveCommand& drive) {
                // Checked against the scene by the sender; a request made for
                // another scene (one replaced in between) is not for this world.
                if (robot < 0 || robot >= static_cast<int>(control_.size())) return;
                RobotControl& c = control_[robot];
                c.lastTcp = drive;
                c.client = r.client;  // -1: the server stopping a departed client's robots, or FIRASim
                if (c.controller == RobotController::Manual) {
                    c.tcpWhileManual = r.client >= 0;  // a person has it: TCP is ignored
                    return;
                }
                c.controller = r.client >= 0 ? RobotController::Tcp : RobotController::None;
                match_->drive(robot, drive);
            };
            for (const auto& [robot, e] : r.voltages) take(robot, DriveCommand::ofVoltages(e));
            for (const auto& [robot, w] : r.wheelSpeeds) take(robot, DriveCommand::ofWheelSpeeds(w));
            stats_.commandLatencyMs.add(1e-6 * static_cast<double>(nowNs - r.arrivalNs));
            if (running()) {
                const double arrivalTime = simTimeAt(r.arrivalNs);
                stats_.commandDelayMs.add(1e3 * std::max(0.0, simulation().state().time - arrivalTime));
            } else {
                stats_.commandDelayMs.add(0.0);
            }
            return;  // voltages get no reply (errors are the server's)
        }
        case Kind::ManualVoltages: {
            auto take = [&](int robot, const DriveCommand& drive) {
                if (robot < 0 || robot >= static_cast<int>(control_.size())) return;  // another scene's robot
                control_[robot].controller = RobotController::Manual;
                control_[robot].manual = drive;
            };
            for (const auto& [robot, e] : r.voltages) take(robot, DriveCommand::ofVoltages(e));
            for (const auto& [robot, w] : r.wheelSpeeds) take(robot, DriveCommand::ofWheelSpeeds(w));
            applyManual();
            return;
        }
        case Kind::ReleaseManual: {
            if (r.robot < 0 || r.robot >= static_cast<int>(control_.size())) break;  // another scene's robot
            RobotControl& c = control_[r.robot];
            if (c.controller == RobotController::Manual) {
                c.controller = c.client >= 0 ? RobotController::Tcp : RobotController::None;
                c.manual = DriveCommand{};
                // A remote team's robot: its last TCP voltages now; a built-in
                // team's: its team's from the next tick (0 V until then).
                match_->drive(r.robot, c.client >= 0 ? c.lastTcp : DriveCommand{});
                match_->overrideDrive(r.robot, std::nullopt);
                c.tcpWhileManual = false;
            }
            break;
        }
        case Kind::LoadScene:
            scene_ = *r.scene;
            control_.assign(scene_.robots.size(), RobotControl{});
            if (r.startPaused) paused_ = true;  // before the restart: not one step runs
            restart(r.arrivalNs, nowNs);
            break;
        case Kind::SetSettings: {
            const WorldState before = simulation().state();
            scene_.simulation = r.scene->simulation;
            // Who drives each team now (the desktop app may have changed it).
            scene_.game.yellow = match_->control(Team::Yellow);
            scene_.game.blue = match_->control(Team::Blue);
            Scene now = scene_;
            now.commands.clear();  // the schedule's times refer to the old clock
            newMatch(now);
            if (!now.game.rules.referee) {
                // No game to restart: the bodies stay, with their voltages,
                // a client's wheel speeds (its speed loop starting afresh)
                // and off the field if they were.
                for (std::size_t i = 0; i < before.robots.size(); ++i) {
                    const int robot = static_cast<int>(i);
                    match_->placeRobot(robot, before.robots[i]);
                    if (control_[i].controller != RobotController::Manual)
                        match_->drive(robot, before.speedLoops[i].active
                                                 ? DriveCommand::ofWheelSpeeds(before.speedLoops[i].target)
                                                 : DriveCommand::ofVoltages(before.voltages[i]));
                    if (before.offField[i]) match_->setOnField(robot, false);
                }
                match_->placeBall(before.ball);
                stillHalted();  // the same state: still non-finite, or mended by placements
            } else {
                fault_.reset();  // the kick-off's placement: every body at rest in its place
            }
            applyManual();
            restartClock(r.arrivalNs, nowNs);
            break;
        }
        case Kind::CallFoul:
            if (!needsReferee(r)) return;
            if (!match_->call(r.call, r.team, r.quadrant))
                return replyTo(r, "malformed", "a free ball needs a quadrant from 1 to 4");
            tellGame(nowNs);
            break;
        case Kind::HaltGame:
        case Kind::ResumeGame:
            if (!needsReferee(r)) return;
            if (match_->game().phase == GamePhase::Finished)
                return replyTo(r, "finished", "the match is over (reset starts it again)");
            if (r.kind == Kind::HaltGame)
                match_->halt();
            else
                match_->resume();
            tellGame(nowNs);
            break;
        case Kind::Placement: {
            if (!needsReferee(r)) return;
            if (match_->game().phase != GamePhase::Stop)
                return replyTo(r, "not_stopped",
                               QStringLiteral("placements are taken only while the game is stopped (STOP); it is %1")
                                   .arg(gamePhaseName(match_->game().phase)));
            const std::string why = match_->placeTeam(r.team, r.poses);
            if (!why.empty())
                return replyTo(r, "illegal_placement",
                               QStringLiteral("%1 (for the %2 of %3): the referee's placement stays")
                                   .arg(QString::fromStdString(why), callName(match_->game().last.call),
                                        match_->game().last.call == Call::FreeBall
                                            ? QStringLiteral("quadrant %1").arg(match_->game().last.quadrant)
                                            : QString::fromLatin1(teamLabel(match_->game().last.team))));
            stillHalted();
            break;
        }
        case Kind::SetTeamControl:
            match_->setControl(r.team, r.control);
            (r.team == Team::Yellow ? scene_.game.yellow : scene_.game.blue) = r.control;
            break;
        case Kind::Pause: paused_ = true; break;
        case Kind::Resume:
            if (stillHalted()) return replyTo(r, "non_finite", haltedMessage());
            if (paused_) {
                paused_ = false;
                reanchor(r.arrivalNs);
            }
            break;
        case Kind::Step: {
            if (!paused_ && mode_ != RunMode::Lockstep)
                return replyTo(r, "not_paused", "step works only while paused or in lockstep mode");
            if (stillHalted()) return replyTo(r, "non_finite", haltedMessage());
            const std::int64_t steps = Simulation::stepIndexAtOrAfter(r.duration, simulation().dt());
            match_->advanceTo(simulation().state().step + steps);
            if (halt(nowNs)) return replyTo(r, "non_finite", haltedMessage());
            ++frame_;
            restartFrames(simulation().state().step);
            emitInstant(nowNs);
            break;
        }
        case Kind::Reset:
            for (RobotControl& c : control_) c.lastTcp = DriveCommand{};
            restart(r.arrivalNs, nowNs);
            break;
        case Kind::PlaceRobot:
            if (r.robot >= 0 && r.robot < static_cast<int>(control_.size())) match_->placeRobot(r.robot, r.robotPose);
            break;
        case Kind::PlaceBall: match_->placeBall(r.ball); break;
        case Kind::SetOnField:
            if (r.robot >= 0 && r.robot < static_cast<int>(control_.size())) match_->setOnField(r.robot, r.onField);
            break;
        case Kind::Speed:
            if (mode_ == RunMode::Lockstep) return replyTo(r, "lockstep", "the speed cannot change in lockstep mode");
            mode_ = r.speed > 0 ? RunMode::Realtime : RunMode::Max;
            if (r.speed > 0) speed_ = r.speed;
            reanchor(r.arrivalNs);
            break;
        case Kind::Stats: {
            StatsReport report;
            report.commandLatencyMs = stats_.commandLatencyMs.summary();
            report.commandDelayMs = stats_.commandDelayMs.summary();
            report.lateCommands = stats_.lateCommands;
            report.lagResets = stats_.lagResets;
            return replyTo(r, {}, {}, report);
        }
    }
    replyTo(r);
}

QString EngineLoop::haltedMessage() const {
    return QStringLiteral("the simulation halted: %1; reset or load a scene").arg(fault_->message());
}

void EngineLoop::replyTo(const EngineRequest& r, const QString& error, const QString& message,
                         std::optional<StatsReport> stats) {
    if (r.client < 0) return;
    EngineReply reply;
    reply.client = r.client;
    reply.id = r.id;
    reply.kind = r.kind;
    reply.command = r.command;
    reply.ok = error.isEmpty();
    reply.error = error;
    reply.message = message;
    reply.time = simulation().state().time;
    reply.frame = frame_;
    reply.stats = std::move(stats);
    sink_.reply(reply);
}

}  // namespace vssim
