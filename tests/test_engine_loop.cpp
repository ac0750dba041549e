// The real-time loop (runtime/realtime/engine_loop.h) driven by made-up wall
// times: commands act at their arrival instant, camera instants fall every
// 30 ms of simulated time, the modes behave as documented, and everything
// agrees bit for bit with an offline Simulation given the same commands.
#include <QtTest>

#include <array>
#include <cmath>

#include "realtime/engine_loop.h"
#include "test_support.h"
#include "vssim/field.h"

using namespace vssim;

namespace {

constexpr std::int64_t kMs = 1'000'000;  // ns

// On RK4, not the default exact integrator: the tests compare the loop with
// an offline run bit for bit, which holds for fixed steps however the loop
// cuts the time; exact's long steps split at other places agree only to
// rounding (docs/model.md, "Long steps"). runawayBall needs it too: exact
// damps even that ball's velocity without overflowing.
Scene twoRobots() {
    Scene scene;
    scene.simulation.integrator = Integrator::Rk4;
    scene.robots.push_back(test::robotAt("yellow0", -0.3, 0.0, 0.0));
    scene.robots.push_back(test::robotAt("blue0", 0.3, 0.2, 3.0));
    scene.robots[1].team = Team::Blue;
    scene.ball.x = 0.1;
    scene.ball.vx = 0.4;
    return scene;
}

struct RecordingSink : EngineSink {
    struct Instant {
        std::int64_t frame, step;
        std::uint64_t hash;
    };
    std::vector<Instant> instants;
    std::vector<EngineReply> replies;
    void cameraInstant(const Simulation& sim, std::int64_t frame, std::int64_t) override {
        instants.push_back({frame, sim.state().step, hashState(sim.state())});
    }
    void reply(const EngineReply& r) override { replies.push_back(r); }
    std::vector<SimulationFault> faults;
    void halted(const SimulationFault& fault, std::int64_t) override { faults.push_back(fault); }
    struct GameNews {
        std::int64_t frame, step;
        GamePhase phase;
        std::size_t calls;
        std::array<int, 2> goals;
    };
    std::vector<GameNews> games;
    void gameChanged(const Match& match, std::int64_t frame, std::int64_t) override {
        const GameState& g = match.game();
        games.push_back({frame, match.simulation().state().step, g.phase, g.calls.size(), g.goals});
    }
};

// The built-in kick-off scene as a game: the referee on, the built-in team
// on both sides (resources/scenes/kickoff_3v3.json, written out here).
Scene kickoffMatch() {
    Scene scene;
    scene.field = makeField(officialDimensions(FieldType::Vsss3v3));
    const char* names[] = {"yellow0", "yellow1", "yellow2", "blue0", "blue1", "blue2"};
    const double xs[] = {-0.68, -0.35, -0.2, 0.68, 0.35, 0.2}, ys[] = {0.0, 0.25, -0.1, 0.0, -0.25, 0.1};
    for (int i = 0; i < 6; ++i) {
        scene.robots.push_back(test::robotAt(names[i], xs[i], ys[i], i < 3 ? 0.0 : M_PI));
        scene.robots.back().team = i < 3 ? Team::Yellow : Team::Blue;
    }
    scene.game.rules.referee = true;
    scene.game.yellow = TeamControl::Builtin;
    scene.game.blue = TeamControl::Builtin;
    return scene;
}

// A robot's distance from where it was, m.
double moved(const RobotState& a, const RobotState& b) { return std::hypot(a.x - b.x, a.y - b.y); }

// A scene no file may hold (the reader refuses a ball of 1e-308 kg): its
// friction rate of 2e306 /s overflows the ball's velocity in the first step.
Scene runawayBall() {
    Scene scene = twoRobots();
    scene.ball_params.mass = 1e-308;
    return scene;
}

EngineRequest voltages(std::int64_t arrivalNs, int robot, double right, double left) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::Voltages;
    r.arrivalNs = arrivalNs;
    r.voltages = {{robot, Voltages{right, left}}};
    return r;
}

EngineRequest control(EngineRequest::Kind kind, std::int64_t arrivalNs = 0, double duration = 0.0) {
    EngineRequest r;
    r.kind = kind;
    r.arrivalNs = arrivalNs;
    r.client = 1;
    r.duration = duration;
    return r;
}

// The offline reference: the same scene with the commands in its schedule.
std::uint64_t offlineHash(Scene scene, const std::vector<VoltageCommand>& commands, std::int64_t steps) {
    scene.commands = commands;
    Simulation sim(scene);
    sim.advanceTo(steps);
    return hashState(sim.state());
}

}  // namespace

class TestEngineLoop : public QObject {
    Q_OBJECT
private slots:
    void cameraInstantsEveryFramePeriod() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        const std::int64_t t0 = 5'000 * kMs;  // an arbitrary clock origin
        loop.start(t0);
        QCOMPARE(loop.frameSteps(), 30);
        QCOMPARE(loop.nextWakeNs(), t0 + 30 * kMs);
        loop.runUntil(t0 + 100 * kMs);
        QCOMPARE(loop.simulation().state().step, 100);
        QCOMPARE(sink.instants.size(), std::size_t(4));  // 0, 30, 60, 90 ms
        for (std::size_t n = 0; n < sink.instants.size(); ++n) {
            QCOMPARE(sink.instants[n].frame, std::int64_t(n));
            QCOMPARE(sink.instants[n].step, std::int64_t(30 * n));
            QCOMPARE(sink.instants[n].hash, offlineHash(twoRobots(), {}, 30 * n));
        }
        QCOMPARE(loop.nextWakeNs(), t0 + 120 * kMs);
    }

    void commandTakesEffectAtItsArrivalInstant() {
        // A command that arrives 12.3 ms after the start acts from step 13
        // (the first step boundary at or after it), not at the next image
        // (step 30), even though the loop only handles it at 25 ms.
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.handle(voltages(12'300'000, 0, 6.0, 4.0), 25 * kMs);
        QCOMPARE(loop.simulation().state().step, 13);
        loop.runUntil(60 * kMs);
        const std::uint64_t want = offlineHash(twoRobots(), {{0.013, 0, {6.0, 4.0}}}, 60);
        QCOMPARE(hashState(loop.simulation().state()), want);
        QVERIFY(want != offlineHash(twoRobots(), {{0.030, 0, {6.0, 4.0}}}, 60));
        QCOMPARE(loop.stats().lateCommands, 0);
        // Simulated delay: 13 ms - 12.3 ms; wall latency: 25 ms - 12.3 ms.
        QVERIFY(std::abs(loop.stats().commandDelayMs.summary().median - 0.7) < 1e-6);
        QVERIFY(std::abs(loop.stats().commandLatencyMs.summary().median - 12.7) < 1e-9);
    }

    void speedFactorScalesSimulatedTime() {
        EngineLoopSettings settings;
        settings.speed = 2.5;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(1000 * kMs);
        loop.handle(voltages(1000 * kMs + 4 * kMs, 1, -3.0, 2.0), 1000 * kMs + 5 * kMs);  // at 10 ms simulated
        QCOMPARE(loop.simulation().state().step, 10);
        QCOMPARE(loop.nextWakeNs(), 1000 * kMs + 12 * kMs);  // 30 ms simulated / 2.5
        loop.runUntil(1000 * kMs + 40 * kMs);                // 100 ms simulated
        QCOMPARE(loop.simulation().state().step, 100);
        QCOMPARE(hashState(loop.simulation().state()), offlineHash(twoRobots(), {{0.010, 1, {-3.0, 2.0}}}, 100));
    }

    void lateCommandActsNow() {
        // The loop already simulated past the arrival instant (it was busy):
        // the command acts at the current step and is counted as late.
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.runUntil(50 * kMs);
        loop.handle(voltages(20 * kMs, 0, 5.0, 5.0), 51 * kMs);
        QCOMPARE(loop.stats().lateCommands, 1);
        QCOMPARE(loop.simulation().state().step, 50);
        QCOMPARE(loop.simulation().state().voltages[0].right, 5.0);
    }

    void pauseHoldsTimeAndStepAdvances() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.handle(control(EngineRequest::Kind::Step, 1 * kMs, 0.05), 2 * kMs);
        QCOMPARE(sink.replies.back().ok, false);
        QCOMPARE(sink.replies.back().error, QString("not_paused"));
        loop.handle(control(EngineRequest::Kind::Pause, 40 * kMs), 41 * kMs);
        QCOMPARE(loop.simulation().state().step, 40);  // simulated up to the pause's arrival
        QCOMPARE(loop.nextWakeNs(), std::numeric_limits<std::int64_t>::max());
        loop.runUntil(900 * kMs);
        QCOMPARE(loop.simulation().state().step, 40);
        const std::size_t instants = sink.instants.size();
        loop.handle(control(EngineRequest::Kind::Step, 950 * kMs, 0.0105), 950 * kMs);  // rounds up to 11 steps
        QCOMPARE(loop.simulation().state().step, 51);
        QCOMPARE(sink.instants.size(), instants + 1);
        QCOMPARE(sink.instants.back().step, 51);
        QVERIFY(sink.replies.back().ok);
        QCOMPARE(sink.replies.back().time, loop.simulation().state().time);
        QCOMPARE(sink.replies.back().frame, sink.instants.back().frame);
        // Resume: time runs again from the wall time of the resume.
        loop.handle(control(EngineRequest::Kind::Resume, 1000 * kMs), 1000 * kMs);
        loop.runUntil(1010 * kMs);
        QCOMPARE(loop.simulation().state().step, 61);
        // The next image comes 30 ms of simulated time after the last one.
        QCOMPARE(loop.nextWakeNs(), 1000 * kMs + 30 * kMs);
    }

    void lockstepIsDeterministicAndMatchesOffline() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        auto run = [&](RecordingSink& sink) {
            EngineLoop loop(twoRobots(), settings, sink);
            loop.start(0);
            // Wall times are deliberately irregular: lockstep ignores them.
            loop.handle(voltages(7 * kMs, 0, 7.0, 3.0), 1234 * kMs);
            loop.handle(control(EngineRequest::Kind::Step, 0, 0.03), 99 * kMs);
            loop.runUntil(5'000 * kMs);
            loop.handle(voltages(1, 1, -2.0, 6.0), 17 * kMs);
            loop.handle(control(EngineRequest::Kind::Step, 0, 0.03), 18 * kMs);
            loop.handle(control(EngineRequest::Kind::Step, 0, 0.5), 19 * kMs);
            return hashState(loop.simulation().state());
        };
        RecordingSink a, b;
        const std::uint64_t hashA = run(a), hashB = run(b);
        QCOMPARE(hashA, hashB);
        QCOMPARE(a.instants.size(), std::size_t(4));
        for (std::size_t i = 0; i < a.instants.size(); ++i) QCOMPARE(a.instants[i].hash, b.instants[i].hash);
        QCOMPARE(a.instants[2].step, 60);
        QCOMPARE(hashA, offlineHash(twoRobots(), {{0.0, 0, {7.0, 3.0}}, {0.03, 1, {-2.0, 6.0}}}, 560));
    }

    void visionKeepsItsRateWhateverTheGameTick() {
        // FIRASim's 60 Hz in a match of the built-in teams (10 ms ticks):
        // instant k at the first 1 ms step at or after k/60 s (17, 17, 16 ms),
        // not on the next tick boundary (20, 20, 10 ms), and each one the
        // state the Match reaches offline at that step.
        EngineLoopSettings settings;
        settings.mode = RunMode::Max;
        settings.framePeriod = 1.0 / 60.0;
        RecordingSink sink;
        EngineLoop loop(kickoffMatch(), settings, sink);
        QVERIFY(loop.match().ticking());
        loop.start(0);
        for (int i = 0; i < 120; ++i) loop.runUntil(0);
        QCOMPARE(sink.instants.size(), std::size_t(121));
        for (std::size_t k = 0; k < sink.instants.size(); ++k)
            QCOMPARE(sink.instants[k].step, static_cast<std::int64_t>(std::ceil(1000.0 * k / 60.0 - 1e-9)));
        Match offline(kickoffMatch());
        for (std::size_t k = 1; k < sink.instants.size(); ++k) {
            offline.advanceTo(sink.instants[k].step);
            QCOMPARE(sink.instants[k].hash, hashState(offline.simulation().state()));
        }
    }

    void maxModeAdvancesOneFramePeriodPerCall() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Max;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        QCOMPARE(loop.nextWakeNs(), std::int64_t(0));
        for (int i = 0; i < 5; ++i) loop.runUntil(0);
        QCOMPARE(loop.simulation().state().step, 150);
        QCOMPARE(sink.instants.size(), std::size_t(6));
        // A command in max mode acts at the current instant.
        loop.handle(voltages(0, 0, 2.0, 2.0), 0);
        loop.runUntil(0);
        QCOMPARE(hashState(loop.simulation().state()), offlineHash(twoRobots(), {{0.15, 0, {2.0, 2.0}}}, 180));
    }

    void speedChangesAndMaxSwitch() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        EngineRequest faster = control(EngineRequest::Kind::Speed, 30 * kMs);
        faster.speed = 4.0;
        loop.handle(faster, 30 * kMs);
        QCOMPARE(loop.simulation().state().step, 30);
        loop.runUntil(40 * kMs);
        QCOMPARE(loop.simulation().state().step, 70);
        EngineRequest max = control(EngineRequest::Kind::Speed, 40 * kMs);
        max.speed = 0.0;
        loop.handle(max, 40 * kMs);
        QCOMPARE(loop.mode(), RunMode::Max);
    }

    void resetRestoresTheInitialState() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        const std::uint64_t initial = hashState(loop.simulation().state());
        loop.handle(voltages(1 * kMs, 0, 5.0, -5.0), 1 * kMs);
        loop.runUntil(200 * kMs);
        QVERIFY(hashState(loop.simulation().state()) != initial);
        loop.handle(control(EngineRequest::Kind::Reset, 200 * kMs), 200 * kMs);
        QCOMPARE(hashState(loop.simulation().state()), initial);
        QCOMPARE(loop.frame(), 0);
        QCOMPARE(sink.instants.back().frame, 0);
        QCOMPARE(loop.nextWakeNs(), 230 * kMs);
    }

    void placeMovesBodies() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        EngineRequest place = control(EngineRequest::Kind::PlaceRobot);
        place.robot = 1;
        place.robotPose = {0.5, -0.4, 1.0, 0.0, 0.0};
        loop.handle(place, 0);
        EngineRequest ball = control(EngineRequest::Kind::PlaceBall);
        ball.ball = {-0.6, 0.5, 0.0, 0.0};
        loop.handle(ball, 0);
        const WorldState& s = loop.simulation().state();
        QCOMPARE(s.robots[1].x, 0.5);
        QCOMPARE(s.robots[1].theta, 1.0);
        QCOMPARE(s.ball.x, -0.6);
        QCOMPARE(s.ball.vx, 0.0);
        QCOMPARE(sink.replies.size(), std::size_t(2));
    }

    void fallingBehindDropsTheLag() {
        EngineLoopSettings settings;
        settings.maxLag = 0.5;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        loop.runUntil(10'000 * kMs);  // 10 s late: as if the machine had stalled
        QCOMPARE(loop.stats().lagResets, 1);
        QCOMPARE(loop.simulation().state().step, 0);  // the lag is dropped, not simulated
        // Re-anchored: the next image is one frame period after now.
        QCOMPARE(loop.nextWakeNs(), 10'000 * kMs + 30 * kMs);
        // A request after a stall is held to the same rule.
        loop.handle(voltages(20'000 * kMs, 0, 1.0, 1.0), 20'000 * kMs);
        QCOMPARE(loop.stats().lagResets, 2);
        QCOMPARE(loop.simulation().state().step, 0);
        QCOMPARE(loop.simulation().state().voltages[0].right, 1.0);
    }

    void catchingUpIsDoneInSlices() {
        // Behind by less than maxLag: runUntil simulates at most
        // kMaxFramesPerPass frame periods per call, so requests get read in
        // between; the next calls catch up.
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.runUntil(300 * kMs);
        QCOMPARE(loop.simulation().state().step, kMaxFramesPerPass * 30);
        QVERIFY(loop.nextWakeNs() < 300 * kMs);  // more to do at once
        loop.runUntil(300 * kMs);
        loop.runUntil(300 * kMs);
        QCOMPARE(loop.simulation().state().step, 300);
        QCOMPARE(loop.stats().lagResets, 0);
    }

    void clockRestartsAtTheRequestsArrival() {
        // A resume, speed change or reset handled later than it arrived
        // counts time from its arrival.
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        EngineRequest same = control(EngineRequest::Kind::Speed, 30 * kMs);
        same.speed = 1.0;
        loop.handle(same, 80 * kMs);
        loop.runUntil(100 * kMs);
        QCOMPARE(loop.simulation().state().step, 100);
        loop.handle(control(EngineRequest::Kind::Pause, 100 * kMs), 100 * kMs);
        loop.handle(control(EngineRequest::Kind::Resume, 500 * kMs), 540 * kMs);
        loop.handle(voltages(510 * kMs, 0, 2.0, 2.0), 540 * kMs);  // 10 ms after the resume
        QCOMPARE(loop.stats().lateCommands, 0);
        QCOMPARE(loop.simulation().state().step, 110);
        loop.handle(control(EngineRequest::Kind::Reset, 600 * kMs), 650 * kMs);
        loop.runUntil(650 * kMs);
        QCOMPARE(loop.simulation().state().step, 50);
    }

    void tinySpeedDoesNotOverflowTheWakeTime() {
        EngineLoopSettings settings;
        settings.speed = 1e-13;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(1000 * kMs);
        QCOMPARE(loop.nextWakeNs(), std::numeric_limits<std::int64_t>::max());
        settings.speed = kMinSpeed;
        EngineLoop slow(twoRobots(), settings, sink);
        slow.start(0);
        QCOMPARE(slow.nextWakeNs(), 30'000 * kMs);  // 30 ms of simulated time take 30 s
    }

    void manualControlOverridesTcpForThatRobotOnly() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        auto tcp = voltages(0, 0, 3.0, 3.0);
        tcp.client = 7;
        loop.handle(tcp, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::Tcp);
        QCOMPARE(loop.control()[0].client, 7);
        EngineRequest manual = voltages(0, 0, -5.0, 5.0);
        manual.kind = EngineRequest::Kind::ManualVoltages;
        loop.handle(manual, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::Manual);
        QCOMPARE(loop.simulation().state().voltages[0].right, -5.0);
        // TCP for the manual robot is ignored (and remembered); for the other robot it applies.
        auto ignored = voltages(0, 0, 1.0, 2.0);
        ignored.client = 7;
        loop.handle(ignored, 0);
        QCOMPARE(loop.simulation().state().voltages[0].right, -5.0);
        QVERIFY(loop.control()[0].tcpWhileManual);
        auto other = voltages(0, 1, 4.0, 4.0);
        other.client = 8;
        loop.handle(other, 0);
        QCOMPARE(loop.simulation().state().voltages[1].right, 4.0);
        // Letting go: the last TCP voltages apply again.
        EngineRequest release = control(EngineRequest::Kind::ReleaseManual);
        release.robot = 0;
        loop.handle(release, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::Tcp);
        QCOMPARE(loop.simulation().state().voltages[0].right, 1.0);
        QCOMPARE(loop.simulation().state().voltages[0].left, 2.0);
        // The client leaves: the server stops its robots (client -1). They
        // are nobody's now, not "TCP client -1"'s.
        auto stop = voltages(0, 0, 0.0, 0.0);
        stop.voltages.push_back({1, Voltages{}});
        loop.handle(stop, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::None);
        QCOMPARE(loop.control()[1].controller, RobotController::None);
        QCOMPARE(loop.simulation().state().voltages[0].right, 0.0);
    }

    void wheelSpeedsFromClientsAndByHandGoThroughTheSpeedLoop() {
        // A client's wheel speeds turn robot 0's loop on; a person driving it
        // by wheel speeds keeps it on with their targets; letting go gives it
        // back the client's last command (wheel speeds again); VOLTAGES turn
        // the loop off. The loop's voltages follow from its own law.
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        EngineRequest tcp;
        tcp.kind = EngineRequest::Kind::WheelSpeeds;
        tcp.client = 7;
        tcp.wheelSpeeds = {{0, WheelSpeeds{10.0, 10.0}}};
        loop.handle(tcp, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::Tcp);
        QVERIFY(loop.simulation().state().speedLoops[0].active);
        EngineRequest step = control(EngineRequest::Kind::Step);
        step.duration = 0.0001;  // one step: the loop's first sample, from rest
        loop.handle(step, 0);
        const SpeedControllerParams& pi = loop.scene().robots[0].params.speed_controller;
        QCOMPARE(loop.simulation().state().voltages[0].right, pi.kp * 10.0 + pi.ki * 10.0 / pi.rate);
        EngineRequest manual;
        manual.kind = EngineRequest::Kind::ManualVoltages;
        manual.wheelSpeeds = {{0, WheelSpeeds{-20.0, 20.0}}};
        loop.handle(manual, 0);
        QCOMPARE(loop.control()[0].controller, RobotController::Manual);
        QCOMPARE(loop.simulation().state().speedLoops[0].target.right, -20.0);
        QVERIFY(loop.simulation().state().speedLoops[0].active);
        EngineRequest release = control(EngineRequest::Kind::ReleaseManual);
        release.robot = 0;
        loop.handle(release, 0);
        QCOMPARE(loop.simulation().state().speedLoops[0].target.right, 10.0);
        QVERIFY(loop.simulation().state().speedLoops[0].active);
        auto volts = voltages(0, 0, 2.0, 2.0);
        volts.client = 7;
        loop.handle(volts, 0);
        QVERIFY(!loop.simulation().state().speedLoops[0].active);
        QCOMPARE(loop.simulation().state().voltages[0].right, 2.0);
    }

    void offFieldRequestTakesARobotOutOfThePhysics() {
        RecordingSink sink;
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        EngineLoop loop(twoRobots(), settings, sink);
        loop.start(0);
        EngineRequest off = control(EngineRequest::Kind::SetOnField);
        off.robot = 1;
        off.onField = false;
        loop.handle(off, 0);
        QVERIFY(!loop.simulation().onField(1));
        auto drive = voltages(0, 1, 5.0, 5.0);
        drive.client = 3;
        loop.handle(drive, 0);
        QCOMPARE(loop.simulation().state().voltages[1].right, 0.0);  // deaf while off
        EngineRequest on = off;
        on.onField = true;
        loop.handle(on, 0);
        QVERIFY(loop.simulation().onField(1));
        loop.handle(drive, 0);
        QCOMPARE(loop.simulation().state().voltages[1].right, 5.0);
    }

    void requestsForAnotherScenesRobotsAreIgnored() {
        // A request made for the scene being replaced (the server stopping a
        // departed client's robots 3 to 5, the app driving robot 5) can reach
        // a world with fewer robots: it changes nothing, and writes nowhere.
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        const std::uint64_t before = hashState(loop.simulation().state());
        EngineRequest stop = voltages(0, 3, 0.0, 0.0);
        stop.voltages.push_back({5, Voltages{1.0, 1.0}});
        stop.voltages.push_back({-1, Voltages{1.0, 1.0}});
        loop.handle(stop, 0);
        EngineRequest manual = stop;
        manual.kind = EngineRequest::Kind::ManualVoltages;
        loop.handle(manual, 0);
        EngineRequest release = control(EngineRequest::Kind::ReleaseManual);
        release.robot = 7;
        loop.handle(release, 0);
        EngineRequest place = control(EngineRequest::Kind::PlaceRobot);
        place.robot = 2;
        loop.handle(place, 0);
        QCOMPARE(hashState(loop.simulation().state()), before);
        QCOMPARE(loop.control()[0].controller, RobotController::None);
        QCOMPARE(loop.control()[1].controller, RobotController::None);
    }

    void loadSceneReplacesTheWorld() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.runUntil(100 * kMs);
        Scene three = twoRobots();
        three.robots.push_back(test::robotAt("yellow1", 0.0, -0.4, 1.0));
        three.simulation.dt = 0.002;
        EngineRequest load = control(EngineRequest::Kind::LoadScene, 100 * kMs);
        load.scene = std::make_shared<const Scene>(three);
        loop.handle(load, 100 * kMs);
        QCOMPARE(loop.simulation().state().robots.size(), std::size_t(3));
        QCOMPARE(loop.control().size(), std::size_t(3));
        QCOMPARE(loop.frame(), 0);
        QCOMPARE(loop.frameSteps(), 15);  // 30 ms of 2 ms steps
        loop.runUntil(160 * kMs);
        QCOMPARE(loop.simulation().state().step, 30);
        QCOMPARE(hashState(loop.simulation().state()), offlineHash(three, {}, 30));
        // Loaded to start paused (the app's File > Open): not one step runs.
        EngineRequest paused = control(EngineRequest::Kind::LoadScene, 170 * kMs);
        paused.scene = std::make_shared<const Scene>(three);
        paused.startPaused = true;
        loop.handle(paused, 170 * kMs);
        loop.runUntil(400 * kMs);
        QVERIFY(loop.paused());
        QCOMPARE(loop.simulation().state().step, 0);
    }

    void setSettingsKeepsTheBodies() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.handle(voltages(1 * kMs, 0, 5.0, 4.0), 1 * kMs);
        loop.runUntil(90 * kMs);
        const WorldState before = loop.simulation().state();
        Scene exact = twoRobots();
        exact.simulation.integrator = Integrator::Exact;
        EngineRequest set = control(EngineRequest::Kind::SetSettings, 90 * kMs);
        set.scene = std::make_shared<const Scene>(exact);
        loop.handle(set, 90 * kMs);
        const WorldState& after = loop.simulation().state();
        QCOMPARE(after.step, 0);
        QCOMPARE(after.robots[0].x, before.robots[0].x);
        QCOMPARE(after.robots[0].v, before.robots[0].v);
        QCOMPARE(after.voltages[0].right, 5.0);
        QCOMPARE(after.ball.vx, before.ball.vx);
        QCOMPARE(loop.scene().simulation.integrator, Integrator::Exact);
        // Reset still goes back to the scene's own start.
        loop.handle(control(EngineRequest::Kind::Reset, 100 * kMs), 100 * kMs);
        QCOMPARE(loop.simulation().state().robots[0].x, -0.3);
    }

    void haltsOnANonFiniteState() {
        // Realtime: the loop stops at the first frame whose state is not
        // finite, emits no camera instant of it, tells the sink once, pauses,
        // and refuses to resume or step until the state is finite again.
        RecordingSink sink;
        EngineLoop loop(runawayBall(), {}, sink);
        loop.start(0);
        loop.runUntil(100 * kMs);
        QCOMPARE(sink.instants.size(), std::size_t(1));  // instant 0 only
        QCOMPARE(sink.faults.size(), std::size_t(1));
        QCOMPARE(sink.faults[0].body, 2);  // the ball, after the two robots
        QCOMPARE(sink.faults[0].time, loop.simulation().state().time);
        QVERIFY2(sink.faults[0].message().startsWith("at t = 0.03 s, the ball (x = "),
                 qPrintable(sink.faults[0].message()));
        QVERIFY(loop.fault().has_value());
        QVERIFY(loop.paused());
        QCOMPARE(loop.nextWakeNs(), std::numeric_limits<std::int64_t>::max());
        const std::int64_t step = loop.simulation().state().step;
        loop.runUntil(500 * kMs);
        QCOMPARE(loop.simulation().state().step, step);
        for (const EngineRequest::Kind kind : {EngineRequest::Kind::Resume, EngineRequest::Kind::Step}) {
            loop.handle(control(kind, 600 * kMs, 0.01), 600 * kMs);
            QCOMPARE(sink.replies.back().ok, false);
            QCOMPARE(sink.replies.back().error, QString("non_finite"));
            QVERIFY2(sink.replies.back().message.startsWith("the simulation halted: at t = 0.03 s, the ball"),
                     qPrintable(sink.replies.back().message));
        }
        QCOMPARE(loop.simulation().state().step, step);
        QCOMPARE(sink.faults.size(), std::size_t(1));
        // Placing the ball at rest mends the state: stepping works again.
        EngineRequest ball = control(EngineRequest::Kind::PlaceBall);
        ball.ball = {0.0, -0.5, 0.0, 0.0};
        loop.handle(ball, 700 * kMs);
        loop.handle(control(EngineRequest::Kind::Step, 700 * kMs, 0.01), 700 * kMs);
        QVERIFY(sink.replies.back().ok);
        QVERIFY(!loop.fault().has_value());
        QCOMPARE(loop.simulation().state().step, step + 10);
        // A reset clears a halt too (and the runaway scene halts again).
        loop.handle(control(EngineRequest::Kind::Reset, 800 * kMs), 800 * kMs);
        QVERIFY(!loop.fault().has_value());
        QCOMPARE(loop.simulation().state().step, 0);
    }

    void lockstepStepHaltsWithAnError() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(runawayBall(), settings, sink);
        loop.start(0);
        loop.handle(control(EngineRequest::Kind::Step, 0, 0.05), 0);
        QCOMPARE(sink.replies.back().error, QString("non_finite"));
        QCOMPARE(sink.instants.size(), std::size_t(1));  // no image of a NaN world
        QCOMPARE(sink.faults.size(), std::size_t(1));
        QCOMPARE(sink.faults[0].time, 0.05);
        QVERIFY(!loop.paused());  // lockstep has no pause: the next step is refused instead
        loop.handle(control(EngineRequest::Kind::Step, 0, 0.05), 0);
        QCOMPARE(sink.replies.back().error, QString("non_finite"));
        QCOMPARE(loop.simulation().state().time, 0.05);
    }

    void lockstepGameIsBitIdenticalWhereverItIsCut() {
        // A match of the built-in team against itself, stepped in lockstep
        // with durations that do not fall on game ticks: each step ends
        // where its duration says (not on a tick boundary), and two runs
        // agree bit for bit with each other and with the Match run offline
        // through the same steps. (The long steps of the exact integrator
        // round differently when cut elsewhere, so the same steps: a run
        // repeats bit for bit with the same schedule.)
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        const double durations[] = {0.03, 0.017, 0.5, 0.0001, 1.3, 2.0, 0.03, 3.0, 0.25};
        auto run = [&](RecordingSink& sink) {
            EngineLoop loop(kickoffMatch(), settings, sink);
            loop.start(0);
            for (double d : durations) loop.handle(control(EngineRequest::Kind::Step, 0, d), 0);
            return hashState(loop.simulation().state());
        };
        RecordingSink a, b;
        const std::uint64_t hashA = run(a), hashB = run(b);
        QCOMPARE(hashA, hashB);
        QCOMPARE(a.instants.size(), std::size_t(1 + std::size(durations)));
        std::int64_t step = 0;
        Match offline(kickoffMatch());
        for (std::size_t i = 1; i < a.instants.size(); ++i) {
            step += static_cast<std::int64_t>(std::ceil(durations[i - 1] / 0.001 - 1e-9));
            QCOMPARE(a.instants[i].step, step);
            QCOMPARE(a.instants[i].hash, b.instants[i].hash);
            offline.advanceTo(step);
            QCOMPARE(a.instants[i].hash, hashState(offline.simulation().state()));
        }
        // The game was told of GAME_ON at 4 s, before the instant that first
        // shows it (not of its start: nobody could listen yet).
        QVERIFY(!a.games.empty());
        QCOMPARE(a.games[0].phase, GamePhase::GameOn);
        std::size_t first = 0;
        while (a.instants[first].step < 4'000) ++first;
        QCOMPARE(a.games[0].frame, std::int64_t(first));
        QCOMPARE(a.games[0].step, a.instants[first].step);
        QCOMPARE(a.games.size(), b.games.size());
    }

    void aResetStartsTheMatchAgainAndSaysSo() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(kickoffMatch(), settings, sink);
        loop.start(0);
        QVERIFY(sink.games.empty());
        loop.handle(control(EngineRequest::Kind::Step, 0, 5.0), 0);
        QCOMPARE(sink.games.size(), std::size_t(1));
        loop.handle(control(EngineRequest::Kind::Reset), 0);
        QCOMPARE(sink.games.size(), std::size_t(2));
        QCOMPARE(sink.games.back().phase, GamePhase::Stop);
        QCOMPARE(sink.games.back().frame, 0);
        QCOMPARE(sink.games.back().step, 0);
        QCOMPARE(loop.match().game().clock, 0.0);
    }

    void gameRequestsNeedAReferee() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        for (auto kind : {EngineRequest::Kind::CallFoul, EngineRequest::Kind::HaltGame, EngineRequest::Kind::ResumeGame,
                          EngineRequest::Kind::Placement}) {
            EngineRequest r = control(kind, 1 * kMs);
            r.call = Call::KickOff;
            loop.handle(r, 1 * kMs);
            QCOMPARE(sink.replies.back().error, QString("no_referee"));
        }
        QVERIFY(sink.games.empty());       // no referee, no game news
        QVERIFY(!loop.match().ticking());  // the plain Simulation
    }

    void callHaltResumeAndPlacement() {
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(kickoffMatch(), settings, sink);
        loop.start(0);
        QCOMPARE(loop.match().game().phase, GamePhase::Stop);
        // A legal placement during the kick-off's STOP moves the robot.
        EngineRequest place = control(EngineRequest::Kind::Placement);
        place.team = Team::Yellow;
        RobotState pose;
        pose.x = -0.5, pose.y = 0.3, pose.theta = 0.5;
        place.poses = {{1, pose}};
        loop.handle(place, 0);
        QVERIFY(sink.replies.back().ok);
        QCOMPARE(loop.simulation().state().robots[1].x, -0.5);
        QCOMPARE(loop.simulation().state().robots[1].theta, 0.5);
        // An illegal one (in the other half) is refused and nothing moves.
        const WorldState before = loop.simulation().state();
        place.poses = {{1, RobotState{0.4, 0.3, 0.0, 0.0, 0.0}}};
        loop.handle(place, 0);
        QCOMPARE(sink.replies.back().error, QString("illegal_placement"));
        QVERIFY2(sink.replies.back().message.contains("yellow1 (robot 1)"), qPrintable(sink.replies.back().message));
        QCOMPARE(hashState(loop.simulation().state()), hashState(before));
        // GAME_ON by hand; then a placement is out of phase.
        loop.handle(control(EngineRequest::Kind::ResumeGame), 0);
        QVERIFY(sink.replies.back().ok);
        QCOMPARE(loop.match().game().phase, GamePhase::GameOn);
        QCOMPARE(sink.games.back().phase, GamePhase::GameOn);
        loop.handle(place, 0);
        QCOMPARE(sink.replies.back().error, QString("not_stopped"));
        // HALT holds every robot at 0 V; a free ball by hand stops the game and places the ball.
        loop.handle(control(EngineRequest::Kind::Step, 0, 0.5), 0);
        loop.handle(control(EngineRequest::Kind::HaltGame), 0);
        QCOMPARE(loop.match().game().phase, GamePhase::Halt);
        for (const Voltages& v : loop.simulation().state().voltages) QCOMPARE(v.right, 0.0);
        EngineRequest call = control(EngineRequest::Kind::CallFoul);
        call.call = Call::FreeBall;
        call.quadrant = 3;
        loop.handle(call, 0);
        QVERIFY(sink.replies.back().ok);
        QCOMPARE(loop.match().game().last.call, Call::FreeBall);
        QCOMPARE(sink.games.back().phase, GamePhase::Stop);
        QVERIFY(loop.simulation().state().ball.x < 0 && loop.simulation().state().ball.y < 0);
    }

    void manualControlOverridesTheBuiltinTeam() {
        // A person drives yellow0 (a built-in team's robot): their voltages
        // hold through the team's ticks while the game is on; let go, the
        // built-in team has it again from the next tick.
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(kickoffMatch(), settings, sink);
        loop.start(0);
        loop.handle(control(EngineRequest::Kind::ResumeGame), 0);
        EngineRequest manual;
        manual.kind = EngineRequest::Kind::ManualVoltages;
        manual.voltages = {{0, Voltages{5.0, -5.0}}};
        loop.handle(manual, 0);
        loop.handle(control(EngineRequest::Kind::Step, 0, 0.255), 0);
        QCOMPARE(loop.simulation().state().voltages[0].right, 5.0);
        QCOMPARE(loop.simulation().state().voltages[0].left, -5.0);
        QVERIFY(std::abs(loop.simulation().state().robots[0].omega) > 1.0);  // spinning on the spot
        // While the game is stopped it gets 0 V like every robot.
        loop.handle(control(EngineRequest::Kind::HaltGame), 0);
        QCOMPARE(loop.simulation().state().voltages[0].right, 0.0);
        loop.handle(control(EngineRequest::Kind::ResumeGame), 0);
        QCOMPARE(loop.simulation().state().voltages[0].right, 5.0);
        EngineRequest release;
        release.kind = EngineRequest::Kind::ReleaseManual;
        release.robot = 0;
        loop.handle(release, 0);
        loop.handle(control(EngineRequest::Kind::Step, 0, 0.01), 0);
        QVERIFY(loop.simulation().state().voltages[0].right != 5.0 ||
                loop.simulation().state().voltages[0].left != -5.0);
    }

    void teamControlChangesAtOnce() {
        // The yellow team idle: its robots stay at 0 V while blue plays.
        EngineLoopSettings settings;
        settings.mode = RunMode::Lockstep;
        RecordingSink sink;
        EngineLoop loop(kickoffMatch(), settings, sink);
        loop.start(0);
        EngineRequest idle = control(EngineRequest::Kind::SetTeamControl);
        idle.team = Team::Yellow;
        idle.control = TeamControl::Idle;
        loop.handle(idle, 0);
        QCOMPARE(loop.match().control(Team::Yellow), TeamControl::Idle);
        const WorldState start = loop.simulation().state();
        loop.handle(control(EngineRequest::Kind::Step, 0, 6.0), 0);
        const WorldState& now = loop.simulation().state();
        double yellowMoved = 0.0, blueMoved = 0.0;
        for (int i = 0; i < 3; ++i) yellowMoved += moved(now.robots[i], start.robots[i]);
        for (int i = 3; i < 6; ++i) blueMoved += moved(now.robots[i], start.robots[i]);
        QVERIFY2(blueMoved > 0.05, qPrintable(QString::number(blueMoved)));
        QVERIFY2(yellowMoved < blueMoved, qPrintable(QString("%1 %2").arg(yellowMoved).arg(blueMoved)));
        for (int i = 0; i < 3; ++i) QCOMPARE(now.voltages[i].right, 0.0);
    }

    void statsReply() {
        RecordingSink sink;
        EngineLoop loop(twoRobots(), {}, sink);
        loop.start(0);
        loop.handle(voltages(1 * kMs, 0, 1.0, 1.0), 3 * kMs);
        EngineRequest stats = control(EngineRequest::Kind::Stats, 4 * kMs);
        stats.command = "stats";
        loop.handle(stats, 4 * kMs);
        QVERIFY(sink.replies.back().stats.has_value());
        const SampleSummary latency = sink.replies.back().stats->commandLatencyMs;
        QCOMPARE(latency.count, 1);
        QCOMPARE(latency.median, 2.0);
    }
};

QTEST_APPLESS_MAIN(TestEngineLoop)
#include "test_engine_loop.moc"
