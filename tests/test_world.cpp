// The world as a whole: command timing, invariants of long chaotic runs,
// determinism, and the paper's Figure 13.
#include <QtTest>

#include <optional>
#include <random>

#include "test_support.h"
#include "vssim/collision_detect.h"
#include "vssim/exact_integrator.h"
#include "vssim/geometry.h"
#include "vssim/state_hash.h"
#include "vssim/world.h"

using namespace vssim;

namespace {

// A pile: n robots at random non-overlapping places and headings, the ball
// among them, every robot at full voltage with random signs that change
// every 0.5 s.
Scene randomPile(std::uint32_t seed, int n, CollisionModel model, double restitution = 1.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(-0.6, 0.6), uy(-0.5, 0.5), angle(-M_PI, M_PI);
    Scene scene;
    scene.simulation.collision_model = model;
    scene.simulation.restitution = restitution;
    scene.ball.x = 0.0;
    scene.ball.y = 0.0;
    scene.ball.vx = 3.0;
    scene.ball.vy = -2.0;
    while (static_cast<int>(scene.robots.size()) < n) {
        RobotSpec r = test::robotAt("r", ux(rng), uy(rng), angle(rng));
        bool free = std::hypot(r.initial.x, r.initial.y) > 0.08;
        for (const RobotSpec& o : scene.robots)
            free = free && std::hypot(r.initial.x - o.initial.x, r.initial.y - o.initial.y) > 0.11;
        if (!free) continue;
        r.name = "r" + std::to_string(scene.robots.size());
        scene.robots.push_back(r);
    }
    std::uniform_int_distribution<int> sign(0, 1);
    for (double t = 0.0; t < 60.0; t += 0.5)
        for (int i = 0; i < n; ++i) scene.commands.push_back({t, i, {sign(rng) ? 7.4 : -7.4, sign(rng) ? 7.4 : -7.4}});
    return scene;
}

bool finite(const WorldState& s) {
    for (const RobotState& r : s.robots)
        for (double v : {r.x, r.y, r.theta, r.v, r.omega})
            if (!std::isfinite(v)) return false;
    return std::isfinite(s.ball.x) && std::isfinite(s.ball.y) && std::isfinite(s.ball.vx) && std::isfinite(s.ball.vy);
}

// Largest distance by which any vertex is beyond a wall, or the ball's edge.
double worstOutside(const Scene& scene, const WorldState& s) {
    double worst = 0.0;
    const double hx = scene.field.length / 2, hy = scene.field.width / 2;
    for (std::size_t i = 0; i < s.robots.size(); ++i)
        for (const Eigen::Vector2d& v : robotVertices(s.robots[i], scene.robots[i].params.side))
            worst = std::max({worst, std::abs(v.x()) - hx, std::abs(v.y()) - hy});
    const double r = scene.ball_params.radius;
    return std::max({worst, std::abs(s.ball.x) + r - hx, std::abs(s.ball.y) + r - hy});
}

double worstOverlap(const Scene& scene, const WorldState& s) {
    std::vector<double> sides;
    for (const RobotSpec& r : scene.robots) sides.push_back(r.params.side);
    double worst = 0.0;
    for (const Contact& c : detectContacts(scene.field, {&s.robots, &sides, &s.ball, scene.ball_params.radius}))
        if (c.b.kind != BodyKind::Wall) worst = std::max(worst, c.depth);
    return worst;
}

}  // namespace

class TestWorld : public QObject {
    Q_OBJECT
private slots:
    void commandTakesEffectAtItsStep();
    void commandsApplyInTimeThenFileOrder();
    void voltagesAreClampedWhenApplied();
    void freeRobotMatchesIntegrator();
    void pileStaysSane_data();
    void pileStaysSane();
    void deterministic();
    void paperFigure13RobotStopsAtWall();
    void collisionModelsDiffer();
    void brokenStatesDoNotStall();
    void tinySpeedsAreZeroFromTheStart();
};

void TestWorld::brokenStatesDoNotStall() {
    // A robot whose position or speed is NaN, or whose speed is infinite
    // (set through the API; scene files refuse them), breaks the world, but
    // must not stall it: no sub-steps (a million of them used to be taken
    // for an infinite speed) and one exact panel (there used to be 2^20, a
    // fifth of a second per step), so 200 steps take no time.
    const RobotModel model = makeRobotModel(RobotParams{});
    for (const double bad : {double(NAN), double(INFINITY)}) {
        RobotState r;
        r.omega = bad;
        QCOMPARE(exactPanelsFor(model, r, Voltages{3.0, 3.0}, 0.03), 1);
        Scene scene;
        scene.robots.push_back(test::robotAt("a", 0.0, 0.0, 0.0, bad));
        WorldState state = initialWorldState(scene);
        QCOMPARE(stepWorld(makeWorldModel(scene), state, 0.001).substeps, 1);
    }
    for (int variant = 0; variant < 3; ++variant) {
        Scene scene;
        scene.field = makeRectangularField(3.0, 3.0);
        for (int i = 0; i < 4; ++i) {
            scene.robots.push_back(test::robotAt("r", -1.0 + 0.6 * i, 1.4 - 0.01 * i, 0.0, 0.5));
            scene.commands.push_back({0.0, i, Voltages{3.0, 3.0}});
        }
        RobotState& broken = scene.robots[3].initial;
        (variant == 0 ? broken.x : broken.v) = variant == 2 ? INFINITY : NAN;
        Simulation sim(scene);
        QElapsedTimer timer;
        timer.start();
        for (std::int64_t k = 10; k <= 200; k += 10) sim.advanceTo(k);
        QCOMPARE(sim.state().step, std::int64_t(200));
        // (Not a timing test: before the fix this took about 40 s; now
        // microseconds. Half a minute leaves any loaded machine room.)
        QVERIFY2(timer.elapsed() < 30000, qPrintable(QString("variant %1: %2 ms").arg(variant).arg(timer.elapsed())));
    }
}

void TestWorld::tinySpeedsAreZeroFromTheStart() {
    // Speeds under 1e-200 are flushed to zero (world.cpp, kRestSpeed) when
    // a simulation starts and when a body is placed, as after every step:
    // so a body the planner leaves alone never keeps one that a step of
    // everybody would have flushed, and the plan does not change results.
    Scene scene;
    scene.robots.push_back(test::robotAt("a", 0.0, 0.0, 0.0, 1e-250));
    scene.ball.vx = -1e-250;
    Simulation sim(scene);
    QCOMPARE(sim.state().robots[0].v, 0.0);
    QCOMPARE(sim.state().ball.vx, 0.0);
    RobotState placed;
    placed.omega = 1e-210;
    placed.v = 0.25;
    sim.placeRobot(0, placed);
    QCOMPARE(sim.state().robots[0].omega, 0.0);
    QCOMPARE(sim.state().robots[0].v, 0.25);
    BallState ball;
    ball.vy = 1e-220;
    sim.placeBall(ball);
    QCOMPARE(sim.state().ball.vy, 0.0);
}

void TestWorld::commandTakesEffectAtItsStep() {
    QCOMPARE(Simulation::stepIndexAtOrAfter(0.03, 0.001), std::int64_t(30));
    QCOMPARE(Simulation::stepIndexAtOrAfter(0.0301, 0.001), std::int64_t(31));
    QCOMPARE(Simulation::stepIndexAtOrAfter(0.0, 0.001), std::int64_t(0));
    QCOMPARE(Simulation::stepIndexAtOrAfter(0.3, 0.1), std::int64_t(3));  // 0.3/0.1 = 2.9999999999999996
    QCOMPARE(Simulation::stepIndexAtOrAfter(0.7, 0.1), std::int64_t(7));  // 0.7/0.1 = 6.999999999999999

    Scene scene;
    scene.robots.push_back(test::robotAt("a", 0, 0, 0));
    scene.commands.push_back({0.03, 0, {5.0, 5.0}});
    Simulation sim(scene);
    for (int k = 0; k < 30; ++k) sim.step();
    QCOMPARE(sim.state().robots[0].v, 0.0);  // nothing acted during steps 0..29
    QCOMPARE(sim.state().voltages[0].right, 0.0);
    sim.step();
    QCOMPARE(sim.state().voltages[0].right, 5.0);
    QVERIFY(sim.state().robots[0].v > 0.0);
    QCOMPARE(sim.state().time, 31 * 0.001);
}

void TestWorld::commandsApplyInTimeThenFileOrder() {
    // Commands in any order in the scene take effect in time order, and of
    // two at the same step the later in the file wins (the schedule keeps
    // indices into the scene's list: a copy of the simulation must read its
    // own copy of it).
    Scene scene;
    scene.robots.push_back(test::robotAt("a", 0, 0, 0));
    scene.robots.push_back(test::robotAt("b", 0.5, 0, 0));
    scene.commands = {{0.005, 0, {1.0, 1.0}}, {0.002, 0, {2.0, 2.0}}, {0.002, 0, {3.0, 3.0}},
                      {0.0045, 1, {4.0, -4.0}}, {0.0, 1, {0.5, 0.5}}};
    Simulation sim(scene);
    const std::vector<std::pair<double, double>> expected = {  // right voltages of a, b after each step boundary
        {0.0, 0.5}, {0.0, 0.5}, {3.0, 0.5}, {3.0, 0.5}, {3.0, 0.5}, {1.0, 4.0}, {1.0, 4.0}};
    std::optional<Simulation> copy;
    for (std::size_t k = 0; k < expected.size(); ++k) {
        if (k == 3) copy.emplace(sim);  // taken mid-schedule
        sim.step();
        if (copy) copy->step();
        QCOMPARE(sim.state().voltages[0].right, expected[k].first);
        QCOMPARE(sim.state().voltages[1].right, expected[k].second);
        if (copy) QCOMPARE(hashState(copy->state()), hashState(sim.state()));
    }
    QCOMPARE(sim.state().voltages[1].left, -4.0);
}

void TestWorld::voltagesAreClampedWhenApplied() {
    Scene scene;
    scene.robots.push_back(test::robotAt("a", 0, 0, 0));
    scene.robots[0].params.max_voltage = 5.0;
    scene.commands.push_back({0.0, 0, {12.0, -9.0}});
    Simulation sim(scene);
    sim.step();
    QCOMPARE(sim.state().voltages[0].right, 5.0);
    QCOMPARE(sim.state().voltages[0].left, -5.0);
}

void TestWorld::freeRobotMatchesIntegrator() {
    // A robot far from everything: the world adds nothing to the integrator.
    Scene scene;
    scene.ball.x = 0.6;
    scene.ball.y = 0.5;
    scene.robots.push_back(test::robotAt("a", -0.2, 0, 0.3));
    scene.robots[0].params = test::asymmetricParams();
    scene.commands.push_back({0.0, 0, {2.0, 1.5}});
    scene.simulation.integrator = Integrator::Rk4;  // the one it is compared with below
    Simulation sim(scene);
    RobotState alone = scene.robots[0].initial;
    const RobotModel m = makeRobotModel(scene.robots[0].params);
    for (int k = 0; k < 200; ++k) {
        sim.step();
        integrateRobot(m, alone, {2.0, 1.5}, 0.001, Integrator::Rk4);
    }
    QCOMPARE(sim.state().robots[0].x, alone.x);
    QCOMPARE(sim.state().robots[0].theta, alone.theta);
}

void TestWorld::pileStaysSane_data() {
    QTest::addColumn<int>("model");
    QTest::addColumn<double>("restitution");
    QTest::addColumn<int>("integrator");
    QTest::newRow("paper, rk4") << int(CollisionModel::Paper) << 1.0 << int(Integrator::Rk4);
    QTest::newRow("impulse e=1, rk4") << int(CollisionModel::Impulse) << 1.0 << int(Integrator::Rk4);
    QTest::newRow("impulse e=0.3, euler") << int(CollisionModel::Impulse) << 0.3 << int(Integrator::Euler);
}

void TestWorld::pileStaysSane() {
    QFETCH(int, model);
    QFETCH(double, restitution);
    QFETCH(int, integrator);
    Scene scene = randomPile(7, 12, CollisionModel(model), restitution);
    scene.simulation.integrator = Integrator(integrator);
    Simulation sim(scene);
    double maxOutside = 0.0, maxOverlap = 0.0;
    std::int64_t contacts = 0;
    while (sim.state().time < 60.0 - 1e-9) {
        contacts += sim.step().contacts;
        QVERIFY2(finite(sim.state()), qPrintable(QString("non-finite state at t=%1").arg(sim.state().time)));
        maxOutside = std::max(maxOutside, worstOutside(scene, sim.state()));
        maxOverlap = std::max(maxOverlap, worstOverlap(scene, sim.state()));
    }
    QVERIFY2(contacts > 1000, qPrintable(QString("only %1 contacts: not a pile").arg(contacts)));
    QVERIFY2(maxOutside <= 1e-9, qPrintable(QString("a body %1 m outside the field").arg(maxOutside)));
    QVERIFY2(maxOverlap <= 1e-3, qPrintable(QString("overlap %1 m").arg(maxOverlap)));
}

void TestWorld::deterministic() {
    // A chaotic scene (many collisions): two runs are bit-identical.
    auto run = [] {
        Simulation sim(randomPile(11, 10, CollisionModel::Paper));
        for (int k = 0; k < 10000; ++k) sim.step();
        return test::hashState(sim.state());
    };
    const std::uint64_t first = run();
    QCOMPARE(run(), first);
    // ... and the hash sees a one-ulp change in the initial state.
    Scene perturbed = randomPile(11, 10, CollisionModel::Paper);
    perturbed.robots[0].initial.x = std::nextafter(perturbed.robots[0].initial.x, 1.0);
    Simulation sim(perturbed);
    for (int k = 0; k < 10000; ++k) sim.step();
    QVERIFY(test::hashState(sim.state()) != first);
}

void TestWorld::paperFigure13RobotStopsAtWall() {
    // The paper's Figure 13: a robot at zero voltage runs into the bottom wall
    // at an angle, turns against it and stops (the motors' back-EMF brakes it).
    Scene scene;
    scene.robots.push_back(test::robotAt("a", 0.0, -0.55, -M_PI / 3, 1.5));
    Simulation sim(scene);
    double closestToWall = 1.0;  // m, lowest vertex above y = -0.65
    for (int k = 0; k < 3000; ++k) {
        sim.step();
        for (const Eigen::Vector2d& v : robotVertices(sim.state().robots[0], 0.075))
            closestToWall = std::min(closestToWall, v.y() + 0.65);
    }
    const RobotState& r = sim.state().robots[0];
    QVERIFY2(closestToWall < 1e-4, qPrintable(QString("the robot stayed %1 m from the wall").arg(closestToWall)));
    QVERIFY2(closestToWall >= -1e-12, "a vertex went through the wall");
    QVERIFY2(std::abs(r.theta - (-M_PI / 3)) > 0.05, "the wall did not turn the robot");
    QVERIFY2(std::abs(r.v) < 1e-6 && std::abs(r.omega) < 1e-5, qPrintable(QString("v %1 w %2").arg(r.v).arg(r.omega)));
}

void TestWorld::collisionModelsDiffer() {
    // The option is really used: the same robot-ball hit gives different outcomes.
    auto ballSpeed = [](CollisionModel model) {
        Scene scene;
        scene.simulation.collision_model = model;
        scene.simulation.restitution = 0.5;
        scene.robots.push_back(test::robotAt("a", -0.2, 0.01, 0.0, 1.0));
        scene.commands.push_back({0.0, 0, {7.4, 7.4}});
        Simulation sim(scene);
        for (int k = 0; k < 300; ++k) sim.step();
        return std::hypot(sim.state().ball.vx, sim.state().ball.vy);
    };
    const double paper = ballSpeed(CollisionModel::Paper), impulse = ballSpeed(CollisionModel::Impulse);
    QVERIFY(paper > 0.1 && impulse > 0.1);
    QVERIFY(std::abs(paper - impulse) > 0.05);
}

QTEST_GUILESS_MAIN(TestWorld)
#include "test_world.moc"
