// Batched worlds (batch/): the thread pool, and BatchWorld's worlds each
// bit-identical to a lone Match given the same inputs, whatever the thread
// count; independent of one another; reset; bad arguments refused.
#include <QtTest>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "io/scene_io.h"
#include "test_support.h"
#include "vssim/batch/batch_world.h"
#include "vssim/batch/thread_pool.h"

using namespace vssim;

namespace {

Scene builtinScene(const char* name) {
    QString error;
    const std::optional<Scene> scene = loadSceneFile(resolveScenePath(name), &error);
    if (!scene) qFatal("%s", qPrintable(error));
    return *scene;
}

// Yellow remote against the built-in blue team, with the referee; the
// kick-off's Stop cut short so that the remote team's inputs count from 0.2 s.
Scene vsBuiltin() {
    Scene scene = builtinScene("vs_builtin_3v3");
    scene.game.rules.stop_duration = 0.2;
    return scene;
}

// The same bodies as a plain simulation: no referee, both teams remote.
Scene plainScene() {
    Scene scene = vsBuiltin();
    scene.game.rules.referee = false;
    scene.game.yellow = TeamControl::Remote;
    scene.game.blue = TeamControl::Remote;
    return scene;
}

// The input of world w, robot r, at control step k: different everywhere.
Voltages voltagesFor(int w, int r, int k) {
    return {4.0 + 2.0 * std::sin(0.3 * k + w + 0.7 * r), 4.5 + 2.0 * std::cos(0.2 * k + 1.3 * w - r)};
}
WheelSpeeds wheelSpeedsFor(int w, int r, int k) {
    return {20.0 + 10.0 * std::sin(0.25 * k + 0.5 * w + r), 25.0 + 8.0 * std::cos(0.15 * k + w + 0.3 * r)};
}

// Whether world w drives by wheel speeds at control step k (the others by voltages).
bool usesWheelSpeeds(int w, int k) { return (w + k / 5) % 3 == 1; }

struct Outcome {
    std::uint64_t hash;
    std::array<int, 2> goals;
    std::size_t calls;
    std::int64_t step;
    bool operator==(const Outcome& o) const {
        return hash == o.hash && goals == o.goals && calls == o.calls && step == o.step;
    }
};

Outcome outcomeOf(const Match& m) {
    return {hashState(m.simulation().state()), m.game().goals, m.game().calls.size(), m.simulation().state().step};
}

// Drives a batch for `controls` control steps of `seconds`, every world with
// its own inputs (through the whole-array calls), and returns each world's outcome.
std::vector<Outcome> runBatch(const Scene& scene, int worlds, int threads, std::uint64_t seed, int controls,
                              double seconds, int changedWorld = -1) {
    BatchWorld batch(scene, worlds, threads, seed);
    const int robots = batch.robots();
    std::vector<double> in(static_cast<std::size_t>(worlds * robots * 2));
    for (int k = 0; k < controls; ++k) {
        // Voltages for every world, then wheel speeds over them where a world uses them.
        for (int w = 0; w < worlds; ++w)
            for (int r = 0; r < robots; ++r) {
                Voltages e = voltagesFor(w, r, k);
                if (w == changedWorld) e.right = -e.right;
                in[2 * (w * robots + r)] = e.right;
                in[2 * (w * robots + r) + 1] = e.left;
            }
        batch.setVoltagesAll(in.data());
        for (int w = 0; w < worlds; ++w)
            if (usesWheelSpeeds(w, k))
                for (int r = 0; r < robots; ++r) batch.setWheelSpeeds(w, r, wheelSpeedsFor(w, r, k));
        batch.step(seconds);
    }
    std::vector<Outcome> out;
    for (int w = 0; w < worlds; ++w) out.push_back(outcomeOf(batch.match(w)));
    return out;
}

// The same for world w alone, as a lone Match advanced by `steps` per control step.
Outcome runLone(const Scene& scene, int w, std::uint64_t seed, int controls, std::int64_t steps) {
    Match m(scene, seed);
    for (int k = 0; k < controls; ++k) {
        for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) m.setVoltages(r, voltagesFor(w, r, k));
        if (usesWheelSpeeds(w, k))
            for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) m.setWheelSpeeds(r, wheelSpeedsFor(w, r, k));
        m.advanceTo(m.simulation().state().step + steps);
    }
    return outcomeOf(m);
}

template <typename Exception, typename F>
void expectThrow(F&& f, const char* needle) {
    try {
        f();
    } catch (const Exception& e) {
        QVERIFY2(std::string(e.what()).find(needle) != std::string::npos, e.what());
        return;
    } catch (const std::exception& e) {
        QFAIL(qPrintable(QString("wrong exception type: ") + e.what()));
    }
    QFAIL(qPrintable(QString("no exception; expected one mentioning ") + needle));
}

}  // namespace

class TestBatchWorld : public QObject {
    Q_OBJECT
private slots:
    void poolRunsEveryIndexOnce_data();
    void poolRunsEveryIndexOnce();
    void poolPropagatesTheLowestIndexException();
    void poolOfOneRunsOnTheCaller();
    void poolThreadIndices();
    void poolNestedLoopRunsSerially();
    void poolRefusesNegativeCount();
    void stepsRoundUpToWholeSteps();
    void worldsMatchLoneMatchesAtAnyThreadCount_data();
    void worldsMatchLoneMatchesAtAnyThreadCount();
    void worldsAreIndependent();
    void seedsPerWorld();
    void resetStartsAWorldAfresh();
    void copiesLayOutTheState();
    void placementsMoveOneWorld();
    void badArgumentsThrow();
};

void TestBatchWorld::poolRunsEveryIndexOnce_data() {
    QTest::addColumn<int>("threads");
    QTest::addColumn<int>("n");
    for (int threads : {1, 2, 3, 0})
        for (int n : {0, 1, 2, 5, 1000})
            QTest::addRow("%d threads, n = %d", threads, n) << threads << n;
}

void TestBatchWorld::poolRunsEveryIndexOnce() {
    QFETCH(int, threads);
    QFETCH(int, n);
    ThreadPool pool(threads);
    QCOMPARE(pool.size(), threads == 0 ? static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) : threads);
    // Several loops on the same pool, back to back.
    for (int round = 0; round < 20; ++round) {
        std::vector<std::atomic<int>> runs(static_cast<std::size_t>(n));
        for (auto& r : runs) r = 0;
        pool.parallelFor(static_cast<std::size_t>(n), [&](std::size_t i) { runs[i].fetch_add(1); });
        for (int i = 0; i < n; ++i) QCOMPARE(runs[static_cast<std::size_t>(i)].load(), 1);
    }
}

void TestBatchWorld::poolPropagatesTheLowestIndexException() {
    for (int threads : {1, 2, 3}) {
        ThreadPool pool(threads);
        std::vector<std::atomic<int>> runs(100);
        for (auto& r : runs) r = 0;
        try {
            pool.parallelFor(runs.size(), [&](std::size_t i) {
                runs[i].fetch_add(1);
                if (i == 71 || i == 13 || i == 40) throw std::runtime_error("index " + std::to_string(i));
            });
            QFAIL("no exception");
        } catch (const std::runtime_error& e) {
            QCOMPARE(std::string(e.what()), std::string("index 13"));
        }
        for (auto& r : runs) QCOMPARE(r.load(), 1);  // every index ran anyway
        // The pool goes on working.
        std::atomic<int> sum{0};
        pool.parallelFor(10, [&](std::size_t i) { sum += static_cast<int>(i); });
        QCOMPARE(sum.load(), 45);
    }
}

void TestBatchWorld::poolOfOneRunsOnTheCaller() {
    // One thread, or one index: the loop runs on the calling thread (no hand-over).
    const std::thread::id caller = std::this_thread::get_id();
    ThreadPool one(1);
    std::vector<std::thread::id> ran(50);
    one.parallelFor(ran.size(), [&](std::size_t i) { ran[i] = std::this_thread::get_id(); });
    for (const std::thread::id& id : ran) QVERIFY(id == caller);
    ThreadPool three(3);
    std::thread::id single;
    three.parallelFor(1, [&](std::size_t) { single = std::this_thread::get_id(); });
    QVERIFY(single == caller);
}

void TestBatchWorld::poolThreadIndices() {
    // Each call knows which of the pool's threads runs it: 0 is the caller,
    // and an index is never used by two threads at once.
    QCOMPARE(ThreadPool::threadIndex(), 0);
    ThreadPool pool(3);
    std::vector<std::atomic<int>> inUse(3);
    for (auto& u : inUse) u = 0;
    std::atomic<bool> clash{false}, outOfRange{false};
    std::atomic<int> callerRan{0};
    const std::thread::id caller = std::this_thread::get_id();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    pool.parallelFor(3000, [&](std::size_t) {
        const int t = ThreadPool::threadIndex();
        if (t < 0 || t >= 3) {
            outOfRange = true;
            return;
        }
        if (inUse[t].fetch_add(1) != 0) clash = true;
        if ((t == 0) != (std::this_thread::get_id() == caller)) clash = true;
        if (t == 0) ++callerRan;
        // The workers wait for the caller's first index (the indices are
        // taken as they come, so on a loaded machine the workers could
        // otherwise take them all before the caller starts; the 10 s, for
        // the whole loop, only guard against a caller that never takes
        // part, which then fails below).
        while (t != 0 && callerRan.load() == 0 && std::chrono::steady_clock::now() < deadline)
            std::this_thread::yield();
        volatile double x = 0;
        for (int k = 0; k < 200; ++k) x = x + k;
        inUse[t].fetch_sub(1);
    });
    QVERIFY(!outOfRange);
    QVERIFY(!clash);
    QVERIFY(callerRan.load() > 0);  // the caller takes part
    QCOMPARE(ThreadPool::threadIndex(), 0);
}

void TestBatchWorld::poolNestedLoopRunsSerially() {
    ThreadPool pool(2);
    std::atomic<int> inner{0};
    pool.parallelFor(4, [&](std::size_t) { pool.parallelFor(5, [&](std::size_t) { ++inner; }); });
    QCOMPARE(inner.load(), 20);
}

void TestBatchWorld::poolRefusesNegativeCount() {
    expectThrow<std::invalid_argument>([] { ThreadPool pool(-1); }, "-1");
}

void TestBatchWorld::stepsRoundUpToWholeSteps() {
    BatchWorld ticking(vsBuiltin(), 2, 1);
    QVERIFY(ticking.match(0).ticking());
    QCOMPARE(ticking.match(0).tickSteps(), std::int64_t(10));
    // Whole steps, not whole ticks: a call may end between two ticks, as a
    // lone Match's (or World's) may; the ticks still come at their steps.
    QCOMPARE(ticking.stepsFor(0.03), std::int64_t(30));
    QCOMPARE(ticking.stepsFor(0.0301), std::int64_t(31));
    QCOMPARE(ticking.stepsFor(1e-12), std::int64_t(1));
    QCOMPARE(ticking.step(0.015), std::int64_t(15));
    QCOMPARE(ticking.step(0.015), std::int64_t(15));
    std::vector<std::int64_t> steps(2);
    ticking.copySteps(steps.data());
    QCOMPARE(steps, (std::vector<std::int64_t>{30, 30}));
    Match lone(vsBuiltin(), 0);
    lone.advanceTo(30);
    QCOMPARE(outcomeOf(ticking.match(0)), outcomeOf(lone));

    BatchWorld plain(plainScene(), 2, 2);
    QVERIFY(!plain.match(0).ticking());
    QCOMPARE(plain.stepsFor(0.03), std::int64_t(30));
    QCOMPARE(plain.stepsFor(0.0301), std::int64_t(31));
    QCOMPARE(plain.stepsFor(1e-12), std::int64_t(1));
    plain.step(0.0301);
    plain.step(0.0301);
    plain.copySteps(steps.data());
    QCOMPARE(steps, (std::vector<std::int64_t>{62, 62}));
}

void TestBatchWorld::worldsMatchLoneMatchesAtAnyThreadCount_data() {
    QTest::addColumn<bool>("referee");
    QTest::addRow("referee and built-in team") << true;
    QTest::addRow("plain simulation") << false;
}

void TestBatchWorld::worldsMatchLoneMatchesAtAnyThreadCount() {
    QFETCH(bool, referee);
    const Scene scene = referee ? vsBuiltin() : plainScene();
    constexpr int kWorlds = 5, kControls = 40;
    constexpr double kSeconds = 0.0305;  // rounds up to 31 steps: calls end between game ticks
    constexpr std::uint64_t kSeed = 11;
    const std::int64_t steps = BatchWorld(scene, 1, 1).stepsFor(kSeconds);
    QCOMPARE(steps, std::int64_t(31));
    std::vector<Outcome> lone;
    for (int w = 0; w < kWorlds; ++w) lone.push_back(runLone(scene, w, kSeed + w, kControls, steps));
    // The inputs count: without the seeds, the worlds still differ.
    for (int w = 1; w < kWorlds; ++w)
        QVERIFY(runLone(scene, w, 0, kControls, steps).hash != runLone(scene, 0, 0, kControls, steps).hash);
    // The worlds differ from one another (their inputs and seeds do).
    for (int w = 1; w < kWorlds; ++w) QVERIFY(lone[w].hash != lone[0].hash);
    for (int threads : {1, 2, 3}) {
        const std::vector<Outcome> batch = runBatch(scene, kWorlds, threads, kSeed, kControls, kSeconds);
        for (int w = 0; w < kWorlds; ++w)
            QVERIFY2(batch[w] == lone[w], qPrintable(QString("world %1, %2 threads").arg(w).arg(threads)));
    }
}

void TestBatchWorld::worldsAreIndependent() {
    const Scene scene = vsBuiltin();
    constexpr int kWorlds = 4, kControls = 30;
    const std::vector<Outcome> base = runBatch(scene, kWorlds, 3, 0, kControls, 0.03);
    const std::vector<Outcome> changed = runBatch(scene, kWorlds, 3, 0, kControls, 0.03, /*changedWorld=*/2);
    for (int w = 0; w < kWorlds; ++w) {
        if (w == 2)
            QVERIFY(changed[w].hash != base[w].hash);
        else
            QVERIFY2(changed[w] == base[w], qPrintable(QString("world %1").arg(w)));
    }
}

void TestBatchWorld::seedsPerWorld() {
    const Scene scene = builtinScene("kickoff_3v3");
    BatchWorld unseeded(scene, 3, 2, 0);
    BatchWorld seeded(scene, 3, 2, 100);
    for (int w = 0; w < 3; ++w) {
        QCOMPARE(unseeded.seedOf(w), std::uint64_t(0));
        QCOMPARE(seeded.seedOf(w), std::uint64_t(100 + w));
    }
    unseeded.step(2.0);
    seeded.step(2.0);
    Match lone(scene, 101);
    lone.advanceTo(2000);
    QCOMPARE(outcomeOf(seeded.match(1)), outcomeOf(lone));
    // Unseeded worlds play the same game; seeded ones each their own.
    QCOMPARE(outcomeOf(unseeded.match(0)), outcomeOf(unseeded.match(2)));
    QVERIFY(outcomeOf(seeded.match(0)).hash != outcomeOf(seeded.match(2)).hash);
}

void TestBatchWorld::resetStartsAWorldAfresh() {
    const Scene scene = vsBuiltin();
    constexpr int kWorlds = 3;
    BatchWorld batch(scene, kWorlds, 2, 5);
    auto drive = [&](int controls) {
        for (int k = 0; k < controls; ++k) {
            for (int w = 0; w < kWorlds; ++w)
                for (int r = 0; r < batch.robots(); ++r) batch.setVoltages(w, r, voltagesFor(w, r, k));
            batch.step(0.03);
        }
    };
    drive(20);
    std::vector<Outcome> first;
    for (int w = 0; w < kWorlds; ++w) first.push_back(outcomeOf(batch.match(w)));
    batch.reset(1);
    QCOMPARE(outcomeOf(batch.match(1)), outcomeOf(Match(scene, 6)));
    QCOMPARE(batch.match(1).simulation().state().step, std::int64_t(0));
    QCOMPARE(outcomeOf(batch.match(0)), first[0]);
    QCOMPARE(outcomeOf(batch.match(2)), first[2]);
    // A reset forgets the world's inputs: stepped with none, it matches a fresh Match.
    batch.step(0.03);
    Match fresh(scene, 6);
    fresh.advanceTo(30);
    QCOMPARE(outcomeOf(batch.match(1)), outcomeOf(fresh));
    // resetAll, then the same inputs again: the same outcomes.
    batch.resetAll();
    for (int w = 0; w < kWorlds; ++w) QCOMPARE(outcomeOf(batch.match(w)), outcomeOf(Match(scene, 5 + w)));
    drive(20);
    for (int w = 0; w < kWorlds; ++w) QCOMPARE(outcomeOf(batch.match(w)), first[w]);
}

void TestBatchWorld::copiesLayOutTheState() {
    const Scene scene = builtinScene("kickoff_3v3");
    constexpr int kWorlds = 3;
    BatchWorld batch(scene, kWorlds, 2, 1);
    batch.step(3.0);
    const int robots = batch.robots();
    QCOMPARE(robots, 6);
    std::vector<double> r(static_cast<std::size_t>(kWorlds * robots * 5)), b(kWorlds * 4);
    std::vector<int> s(kWorlds * 2);
    batch.copyRobots(r.data());
    batch.copyBalls(b.data());
    batch.copyScores(s.data());
    for (int w = 0; w < kWorlds; ++w) {
        const WorldState& st = batch.match(w).simulation().state();
        for (int i = 0; i < robots; ++i) {
            const RobotState& x = st.robots[i];
            const double* p = &r[5 * (w * robots + i)];
            QCOMPARE(p[0], x.x);
            QCOMPARE(p[1], x.y);
            QCOMPARE(p[2], x.theta);
            QCOMPARE(p[3], x.v);
            QCOMPARE(p[4], x.omega);
        }
        const double* q = &b[4 * w];
        QCOMPARE(q[0], st.ball.x);
        QCOMPARE(q[1], st.ball.y);
        QCOMPARE(q[2], st.ball.vx);
        QCOMPARE(q[3], st.ball.vy);
        QCOMPARE(s[2 * w], batch.match(w).game().goals[0]);
        QCOMPARE(s[2 * w + 1], batch.match(w).game().goals[1]);
        QVERIFY(batch.finite(w));
    }
}

void TestBatchWorld::placementsMoveOneWorld() {
    // A placement in world 1 gives world 1 the state a lone Match placed the
    // same way has, step for step; the other worlds stay as they were.
    const Scene scene = plainScene();
    BatchWorld batch(scene, 3, 2);
    Match lone(scene, 0);
    const RobotState pose{0.1, -0.2, 1.0, 0.3, -2.0};
    const BallState ball{-0.3, 0.25, 1.5, -0.5};
    batch.placeRobot(1, 0, pose);
    batch.placeBall(1, ball);
    lone.placeRobot(0, pose);
    lone.placeBall(ball);
    batch.setWheelSpeeds(1, 0, {20.0, -10.0});
    lone.setWheelSpeeds(0, {20.0, -10.0});
    const std::int64_t steps = batch.step(0.3);
    lone.advanceTo(steps);
    QCOMPARE(outcomeOf(batch.match(1)), outcomeOf(lone));
    QCOMPARE(outcomeOf(batch.match(0)), outcomeOf(batch.match(2)));
    QVERIFY(!(outcomeOf(batch.match(0)) == outcomeOf(batch.match(1))));

    // Wheel speeds, world-major: what each robot's outputs say.
    const int robots = batch.robots();
    std::vector<double> wheels(static_cast<std::size_t>(3 * robots * 2));
    batch.copyWheelSpeeds(wheels.data());
    for (int w = 0; w < 3; ++w)
        for (int i = 0; i < robots; ++i) {
            const RobotOutputs o = batch.match(w).simulation().robotOutputs(i);
            QCOMPARE(wheels[2 * (w * robots + i)], o.wheel_speed_right);
            QCOMPARE(wheels[2 * (w * robots + i) + 1], o.wheel_speed_left);
        }
    QVERIFY(std::abs(wheels[2 * robots] - 20.0) < 0.5);  // world 1, robot 0: its speed loop's target

    const double nan = std::numeric_limits<double>::quiet_NaN();
    expectThrow<std::out_of_range>([&] { batch.placeRobot(3, 0, pose); }, "placeRobot: world 3");
    expectThrow<std::out_of_range>([&] { batch.placeRobot(0, robots, pose); }, "placeRobot: robot");
    expectThrow<std::invalid_argument>([&] { batch.placeRobot(2, 0, {nan, 0, 0, 0, 0}); }, "world 2, robot 0");
    expectThrow<std::invalid_argument>([&] { batch.placeBall(0, {0, 0, 0, nan}); }, "placeBall: world 0");
    expectThrow<std::out_of_range>([&] { batch.placeBall(-1, ball); }, "placeBall: world -1");
    expectThrow<std::invalid_argument>([&] { batch.copyWheelSpeeds(nullptr); }, "null pointer");
}

void TestBatchWorld::badArgumentsThrow() {
    const Scene scene = vsBuiltin();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    expectThrow<std::invalid_argument>([&] { BatchWorld(scene, 0); }, "at least 1");
    expectThrow<std::invalid_argument>([&] { BatchWorld(scene, 2, -3); }, "-3");

    BatchWorld batch(scene, 2, 2);
    QCOMPARE(batch.threads(), 2);
    QCOMPARE(BatchWorld(scene, 2, 8).threads(), 2);  // never more threads than worlds
    expectThrow<std::out_of_range>([&] { batch.setVoltages(2, 0, {}); }, "world 2 out of range (2 worlds)");
    expectThrow<std::out_of_range>([&] { batch.setVoltages(-1, 0, {}); }, "world -1");
    expectThrow<std::out_of_range>([&] { batch.setVoltages(0, 6, {}); }, "robot 6 out of range (6 robots)");
    expectThrow<std::out_of_range>([&] { batch.setWheelSpeeds(0, -1, {}); }, "robot -1");
    const double infinity = std::numeric_limits<double>::infinity();
    expectThrow<std::invalid_argument>([&] { batch.setVoltages(1, 2, {nan, 0.0}); },
                                       "world 1, robot 2: the right voltage is nan");
    expectThrow<std::invalid_argument>([&] { batch.setWheelSpeeds(0, 0, {0.0, nan}); },
                                       "world 0, robot 0: the left wheel speed is nan");
    expectThrow<std::invalid_argument>([&] { batch.setVoltages(0, 1, {-infinity, 0.0}); }, "right voltage is -inf");
    expectThrow<std::out_of_range>([&] { batch.match(2); }, "match: world 2");
    expectThrow<std::out_of_range>([&] { batch.reset(5); }, "reset: world 5");
    expectThrow<std::out_of_range>([&] { batch.finite(-1); }, "world -1");
    expectThrow<std::out_of_range>([&] { batch.seedOf(2); }, "world 2");

    for (double seconds : {nan, 0.0, -0.5, inf, -inf, 1e300})
        expectThrow<std::invalid_argument>([&] { batch.step(seconds); }, "BatchWorld::step");
    expectThrow<std::invalid_argument>([&] { batch.step(nan); }, "NaN");
    expectThrow<std::invalid_argument>([&] { batch.step(-1.0); }, "positive");

    expectThrow<std::invalid_argument>([&] { batch.setVoltagesAll(nullptr); }, "setVoltagesAll: null pointer");
    expectThrow<std::invalid_argument>([&] { batch.setWheelSpeedsAll(nullptr); }, "null pointer");
    expectThrow<std::invalid_argument>([&] { batch.copyRobots(nullptr); }, "copyRobots: null pointer");
    expectThrow<std::invalid_argument>([&] { batch.copyBalls(nullptr); }, "null pointer");
    expectThrow<std::invalid_argument>([&] { batch.copyScores(nullptr); }, "null pointer");
    expectThrow<std::invalid_argument>([&] { batch.copySteps(nullptr); }, "null pointer");

    // A NaN anywhere in the array: nothing is applied, not even the values before it.
    std::vector<double> in(2 * 6 * 2, 6.0);
    in.back() = nan;
    expectThrow<std::invalid_argument>([&] { batch.setVoltagesAll(in.data()); }, "world 1, robot 5: the left voltage is nan");
    batch.step(0.03);
    BatchWorld untouched(scene, 2, 1);
    untouched.step(0.03);
    for (int w = 0; w < 2; ++w) QCOMPARE(outcomeOf(batch.match(w)), outcomeOf(untouched.match(w)));
    QVERIFY(outcomeOf(batch.match(0)).step == 30);
}

QTEST_APPLESS_MAIN(TestBatchWorld)
#include "test_batch_world.moc"
