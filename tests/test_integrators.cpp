// Convergence order of the integrators (model.md §7): halving h divides the
// error by about 2^order, measured against a fine reference.
#include <QtTest>

#include "test_support.h"
#include "vssim/integrator.h"
#include "vssim/robot_model.h"

using namespace vssim;

namespace {

constexpr double kDuration = 1.0;  // s

// A curving, accelerating run of the asymmetric robot (pose couples to the
// velocity through cos/sin, so the whole state is exercised).
RobotState runRobot(Integrator method, double h) {
    const RobotModel m = makeRobotModel(test::asymmetricParams());
    RobotState s;
    s.v = 0.3;
    s.omega = -2.0;
    const int steps = static_cast<int>(std::lround(kDuration / h));
    for (int k = 0; k < steps; ++k) integrateRobot(m, s, {7.0, 3.0}, h, method);
    return s;
}

double poseError(const RobotState& a, const RobotState& b) {
    return std::max(
        {std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.theta - b.theta) * 0.05, std::abs(a.v - b.v) * 0.1});
}

BallState runBall(Integrator method, double h) {
    BallParams p;
    p.friction = 0.2;  // a strong decay, tau = 0.23 s, so the error is well above rounding
    BallState b;
    b.vx = 2.0;
    b.vy = -1.0;
    const int steps = static_cast<int>(std::lround(kDuration / h));
    for (int k = 0; k < steps; ++k) integrateBall(p, b, h, method);
    return b;
}

}  // namespace

class TestIntegrators : public QObject {
    Q_OBJECT
private slots:
    void robotOrder_data();
    void robotOrder();
    void ballOrderAgainstClosedForm_data();
    void ballOrderAgainstClosedForm();
};

void TestIntegrators::robotOrder_data() {
    QTest::addColumn<int>("method");
    QTest::addColumn<double>("h");
    QTest::addColumn<double>("order");
    QTest::newRow("euler") << int(Integrator::Euler) << 1e-3 << 1.0;
    QTest::newRow("rk4") << int(Integrator::Rk4) << 2e-2 << 4.0;
}

void TestIntegrators::robotOrder() {
    QFETCH(int, method);
    QFETCH(double, h);
    QFETCH(double, order);
    // Reference: RK4 at 1e-5 s, whose own error (~1e-16 relative) is far below
    // the errors measured here.
    const RobotState reference = runRobot(Integrator::Rk4, 1e-5);
    const double e1 = poseError(runRobot(Integrator(method), h), reference);
    const double e2 = poseError(runRobot(Integrator(method), h / 2), reference);
    const double e3 = poseError(runRobot(Integrator(method), h / 4), reference);
    const double expected = std::pow(2.0, order);
    const QString msg = QString("errors %1 %2 %3").arg(e1).arg(e2).arg(e3);
    QVERIFY2(e3 > 1e-12, qPrintable("error too small to measure: " + msg));
    for (double ratio : {e1 / e2, e2 / e3})
        QVERIFY2(ratio > 0.8 * expected && ratio < 1.2 * expected,
                 qPrintable(QString("ratio %1, expected %2; ").arg(ratio).arg(expected) + msg));
}

void TestIntegrators::ballOrderAgainstClosedForm_data() { robotOrder_data(); }

void TestIntegrators::ballOrderAgainstClosedForm() {
    QFETCH(int, method);
    QFETCH(double, h);
    QFETCH(double, order);
    // model.md §3: x(t) = x0 + v0 m/beta (1 - exp(-beta t/m)).
    const double decay = 0.2 / 0.046;
    const double travelled = (1.0 - std::exp(-decay * kDuration)) / decay;
    auto error = [&](double step) {
        const BallState b = runBall(Integrator(method), step);
        return std::max(std::abs(b.x - 2.0 * travelled), std::abs(b.y + 1.0 * travelled));
    };
    const double e1 = error(h), e2 = error(h / 2), e3 = error(h / 4);
    const double expected = std::pow(2.0, order);
    for (double ratio : {e1 / e2, e2 / e3})
        QVERIFY2(
            ratio > 0.8 * expected && ratio < 1.2 * expected,
            qPrintable(
                QString("ratio %1, expected %2 (errors %3 %4 %5)").arg(ratio).arg(expected).arg(e1).arg(e2).arg(e3)));
}

QTEST_GUILESS_MAIN(TestIntegrators)
#include "test_integrators.moc"
