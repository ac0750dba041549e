// The ball (model.md §3): exponential decay, stopping distance, wall bounces.
#include <QtTest>

#include "test_support.h"
#include "vssim/integrator.h"
#include "vssim/world.h"

using namespace vssim;

class TestBall : public QObject {
    Q_OBJECT
private slots:
    void speedDecaysExponentially();
    void stoppingDistance();
    void bouncesOffWallLikeAMirror_data();
    void bouncesOffWallLikeAMirror();
    void neverLeavesTheFieldAtAnySpeed_data();
    void neverLeavesTheFieldAtAnySpeed();
};

void TestBall::speedDecaysExponentially() {
    const BallParams p;
    BallState b;
    b.vx = 1.5;
    b.vy = 0.8;
    const double v0 = std::hypot(b.vx, b.vy), heading = std::atan2(b.vy, b.vx), h = 1e-3;
    for (int k = 1; k <= 3000; ++k) {
        integrateBall(p, b, h, Integrator::Rk4);
        const double want = v0 * std::exp(-p.friction / p.mass * k * h);
        QVERIFY(test::relativeError(std::hypot(b.vx, b.vy), want) < 1e-12);
    }
    QVERIFY(std::abs(std::atan2(b.vy, b.vx) - heading) < 1e-14);  // free flight keeps the heading
}

void TestBall::stoppingDistance() {
    const BallParams p;
    BallState b;
    b.vx = 0.5;
    const double tau = p.mass / p.friction;  // s
    const int steps = static_cast<int>(std::lround(30.0 * tau / 1e-3));
    for (int k = 0; k < steps; ++k) integrateBall(p, b, 1e-3, Integrator::Rk4);
    // travelled -> v0 m/beta; after 30 tau the remainder is e^-30 of it.
    QVERIFY(test::relativeError(b.x, 0.5 * tau) < 1e-9);
}

void TestBall::bouncesOffWallLikeAMirror_data() {
    QTest::addColumn<int>("model");
    QTest::newRow("paper") << int(CollisionModel::Paper);
    QTest::newRow("impulse e=1") << int(CollisionModel::Impulse);
}

void TestBall::bouncesOffWallLikeAMirror() {
    QFETCH(int, model);
    Scene scene;
    scene.simulation.collision_model = CollisionModel(model);
    scene.ball_params.friction = 0.0;  // no decay: the speed must come back unchanged
    scene.ball.x = 0.2;
    scene.ball.y = -0.5;
    scene.ball.vx = 1.0;
    scene.ball.vy = -1.5;  // towards the bottom wall (y = -0.65)
    Simulation sim(scene);
    for (int k = 0; k < 300; ++k) sim.step();
    const BallState& b = sim.state().ball;
    QVERIFY(std::abs(b.vx - 1.0) < 1e-12);  // tangential component kept
    QVERIFY(std::abs(b.vy - 1.5) < 1e-12);  // normal component reversed
    // It travelled as a mirror image: x as if free; y reflected about the
    // line the centre touched, y = -0.65 + r_b.
    QVERIFY(std::abs(b.x - (0.2 + 0.3)) < 1e-9);
    const double mirrorY = -0.65 + scene.ball_params.radius;
    const double freeY = -0.5 - 1.5 * 0.3;
    QVERIFY2(std::abs(b.y - (2 * mirrorY - freeY)) < 2e-3,  // within one step's travel
             qPrintable(QString("y %1 vs %2").arg(b.y).arg(2 * mirrorY - freeY)));
}

void TestBall::neverLeavesTheFieldAtAnySpeed_data() {
    QTest::addColumn<double>("speed");
    QTest::addColumn<double>("dt");
    QTest::newRow("5 m/s, 1 ms") << 5.0 << 1e-3;
    QTest::newRow("50 m/s, 30 ms") << 50.0 << 0.03;
    QTest::newRow("500 m/s, 0.1 s") << 500.0 << 0.1;
}

void TestBall::neverLeavesTheFieldAtAnySpeed() {
    QFETCH(double, speed);
    QFETCH(double, dt);
    Scene scene;
    scene.simulation.dt = dt;
    scene.ball.vx = speed * std::cos(0.7);
    scene.ball.vy = speed * std::sin(0.7);
    Simulation sim(scene);
    const double r = scene.ball_params.radius;
    for (int k = 0; k < 200; ++k) {
        sim.step();
        const BallState& b = sim.state().ball;
        QVERIFY2(std::abs(b.x) <= 0.75 - r + 1e-12 && std::abs(b.y) <= 0.65 - r + 1e-12,
                 qPrintable(QString("step %1: ball at (%2, %3)").arg(k).arg(b.x).arg(b.y)));
    }
    // Elastic walls and sub-steps: the speed only decays by friction.
    const BallState& b = sim.state().ball;
    const double want = speed * std::exp(-scene.ball_params.friction / scene.ball_params.mass * sim.state().time);
    QVERIFY2(test::relativeError(std::hypot(b.vx, b.vy), want) < 1e-6,
             qPrintable(QString("speed %1 vs %2").arg(std::hypot(b.vx, b.vy)).arg(want)));
}

QTEST_GUILESS_MAIN(TestBall)
#include "test_ball.moc"
