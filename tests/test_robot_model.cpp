// The robot's motor dynamics (model.md §1-§2) against first principles and
// closed forms.
#include <QtTest>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "test_support.h"
#include "vssim/integrator.h"
#include "vssim/robot_model.h"

using namespace vssim;

namespace {

// Wheel-level Newton-Euler written from model.md §2 without the matrices:
// for a body velocity u, its rate du and voltages e, the residual of
// m v' + beta_l v = F and J w' + beta_theta w = T, with F and T from the
// wheel torques tau_k = K_k i_k - J_k w_k' - beta_k w_k.
Eigen::Vector2d newtonEulerResidual(const RobotParams& p, const Eigen::Vector2d& u, const Eigen::Vector2d& du,
                                    const Voltages& e) {
    const double rd = p.right.wheel_radius, re = p.left.wheel_radius, b = p.wheel_base;
    // u = Tw w_w inverted by hand: v = (rd wd + re we)/2, w = (rd wd - re we)/b.
    const double wd = (u(0) + u(1) * b / 2.0) / rd, we = (u(0) - u(1) * b / 2.0) / re;
    const double dwd = (du(0) + du(1) * b / 2.0) / rd, dwe = (du(0) - du(1) * b / 2.0) / re;
    const double id = (e.right - p.right.k * wd) / p.right.resistance;
    const double ie = (e.left - p.left.k * we) / p.left.resistance;
    const double taud = p.right.k * id - p.right.rotor_inertia * dwd - p.right.friction * wd;
    const double taue = p.left.k * ie - p.left.rotor_inertia * dwe - p.left.friction * we;
    const double F = taud / rd + taue / re;              // wheel forces add
    const double T = b / 2.0 * (taud / rd - taue / re);  // right wheel forward turns left (+w)
    return {p.mass * du(0) + p.friction_linear * u(0) - F, p.inertia * du(1) + p.friction_angular * u(1) - T};
}

}  // namespace

class TestRobotModel : public QObject {
    Q_OBJECT
private slots:
    void kinematicsMapsWheelSpeeds();
    void dynamicsSatisfyNewtonEuler_data();
    void dynamicsSatisfyNewtonEuler();
    void symmetricMatricesMatchHandDerivation();
    void steadyStateBalancesForces();
    void defaultRobotReachesDocumentedSpeeds();
    void symmetricResponseIsTwoFirstOrderLags();
    void asymmetricResponseMatchesMatrixExponential();
    void outputsAtStallAndSteadyState();
    void voltagesAreClamped();
};

void TestRobotModel::kinematicsMapsWheelSpeeds() {
    const RobotParams p = test::asymmetricParams();
    const RobotModel m = makeRobotModel(p);
    // Right wheel only at 10 rad/s: v = r_d*10/2, w = r_d*10/b (model.md §1).
    const Eigen::Vector2d u = m.Tw * Eigen::Vector2d(10.0, 0.0);
    QVERIFY(test::relativeError(u(0), p.right.wheel_radius * 5.0) < 1e-15);
    QVERIFY(test::relativeError(u(1), p.right.wheel_radius * 10.0 / p.wheel_base) < 1e-15);
    QVERIFY((m.Tw * m.TwInv - Eigen::Matrix2d::Identity()).norm() < 1e-14);
}

void TestRobotModel::dynamicsSatisfyNewtonEuler_data() {
    QTest::addColumn<bool>("asymmetric");
    QTest::addColumn<double>("v");
    QTest::addColumn<double>("omega");
    QTest::addColumn<double>("eRight");
    QTest::addColumn<double>("eLeft");
    QTest::newRow("default at rest, full forward") << false << 0.0 << 0.0 << 7.4 << 7.4;
    QTest::newRow("default moving, turning") << false << 1.2 << -8.0 << 3.0 << -2.0;
    QTest::newRow("asymmetric at rest") << true << 0.0 << 0.0 << 5.0 << 5.0;
    QTest::newRow("asymmetric moving") << true << -0.7 << 20.0 << -6.0 << 1.5;
}

void TestRobotModel::dynamicsSatisfyNewtonEuler() {
    QFETCH(bool, asymmetric);
    QFETCH(double, v);
    QFETCH(double, omega);
    QFETCH(double, eRight);
    QFETCH(double, eLeft);
    const RobotParams p = asymmetric ? test::asymmetricParams() : RobotParams{};
    const RobotModel m = makeRobotModel(p);
    const Eigen::Vector2d u(v, omega);
    const Voltages e{eRight, eLeft};
    const Eigen::Vector2d du = velocityDerivative(m, u, e);
    const Eigen::Vector2d r = newtonEulerResidual(p, u, du, e);
    // Force scale ~ 1 N, torque scale ~ 0.05 N m.
    QVERIFY2(std::abs(r(0)) < 1e-12 && std::abs(r(1)) < 1e-13,
             qPrintable(QString("residual %1 %2").arg(r(0)).arg(r(1))));
}

void TestRobotModel::symmetricMatricesMatchHandDerivation() {
    const RobotParams p;  // defaults are symmetric
    const RobotModel m = makeRobotModel(p);
    const double r = p.right.wheel_radius, b = p.wheel_base, Jw = p.right.rotor_inertia;
    const double c = p.right.k * p.right.k / p.right.resistance + p.right.friction;
    // With r_d = r_e and equal motors, M and B are diagonal (model.md §2).
    QVERIFY(test::relativeError(m.M(0, 0), p.mass + 2 * Jw / (r * r)) < 1e-14);
    QVERIFY(test::relativeError(m.M(1, 1), p.inertia + Jw * b * b / (2 * r * r)) < 1e-14);
    QVERIFY(std::abs(m.M(0, 1)) < 1e-18 && std::abs(m.M(1, 0)) < 1e-18);
    QVERIFY(test::relativeError(m.B(0, 0), p.friction_linear + 2 * c / (r * r)) < 1e-14);
    QVERIFY(test::relativeError(m.B(1, 1), p.friction_angular + c * b * b / (2 * r * r)) < 1e-14);
    QVERIFY(std::abs(m.B(0, 1)) < 1e-18);
    const double g = p.right.k / p.right.resistance;
    QVERIFY(test::relativeError(m.K(0, 0), g / r) < 1e-14);
    QVERIFY(test::relativeError(m.K(1, 1), -g * b / (2 * r)) < 1e-14);
}

void TestRobotModel::steadyStateBalancesForces() {
    const RobotParams p = test::asymmetricParams();
    const RobotModel m = makeRobotModel(p);
    for (const Voltages e : {Voltages{7.4, 7.4}, Voltages{5.0, -3.0}, Voltages{-2.0, 6.0}}) {
        const Eigen::Vector2d u = steadyStateVelocity(m, e);
        const Eigen::Vector2d r = newtonEulerResidual(p, u, Eigen::Vector2d::Zero(), e);
        QVERIFY(std::abs(r(0)) < 1e-13 && std::abs(r(1)) < 1e-14);
        QVERIFY(velocityDerivative(m, u, e).norm() < 1e-11);
    }
}

void TestRobotModel::defaultRobotReachesDocumentedSpeeds() {
    // model.md §9: "about 2 m/s and 50 rad/s at full voltage, time constants near 0.1 s".
    const RobotModel m = makeRobotModel(RobotParams{});
    const double v = steadyStateVelocity(m, {7.4, 7.4})(0);
    const double w = steadyStateVelocity(m, {7.4, -7.4})(1);
    QVERIFY2(v > 1.5 && v < 2.5, qPrintable(QString::number(v)));
    QVERIFY2(w > 35 && w < 65, qPrintable(QString::number(w)));
    const double tauV = m.M(0, 0) / m.B(0, 0), tauW = m.M(1, 1) / m.B(1, 1);
    QVERIFY2(tauV > 0.03 && tauV < 0.3 && tauW > 0.03 && tauW < 0.3, qPrintable(QString("%1 %2").arg(tauV).arg(tauW)));
}

void TestRobotModel::symmetricResponseIsTwoFirstOrderLags() {
    const RobotParams p;
    const RobotModel m = makeRobotModel(p);
    const Voltages e{6.0, 2.0};
    const Eigen::Vector2d uInf = steadyStateVelocity(m, e);
    RobotState s;
    s.v = -0.5;
    s.omega = 10.0;
    const double v0 = s.v, w0 = s.omega, h = 1e-4;
    for (int k = 1; k <= 5000; ++k) {
        integrateRobot(m, s, e, h, Integrator::Rk4);
        if (k % 1000) continue;
        const double t = k * h;
        const double v = uInf(0) + (v0 - uInf(0)) * std::exp(-m.B(0, 0) / m.M(0, 0) * t);
        const double w = uInf(1) + (w0 - uInf(1)) * std::exp(-m.B(1, 1) / m.M(1, 1) * t);
        QVERIFY2(std::abs(s.v - v) < 1e-11 && std::abs(s.omega - w) < 1e-10,
                 qPrintable(QString("t=%1: v %2 vs %3, w %4 vs %5").arg(t).arg(s.v).arg(v).arg(s.omega).arg(w)));
    }
}

void TestRobotModel::asymmetricResponseMatchesMatrixExponential() {
    const RobotParams p = test::asymmetricParams();
    const RobotModel m = makeRobotModel(p);
    QVERIFY(std::abs(m.M(0, 1)) > 1e-8);  // really coupled
    const Voltages e{7.0, -1.0};
    const Eigen::Vector2d uInf = steadyStateVelocity(m, e);
    // exp(-M^-1 B t) by eigen-decomposition (model.md §2 closed form).
    Eigen::EigenSolver<Eigen::Matrix2d> eig(-m.M.inverse() * m.B);
    const Eigen::Matrix2cd V = eig.eigenvectors();
    const Eigen::Vector2cd lambda = eig.eigenvalues();
    const Eigen::Vector2d u0(1.0, -20.0);
    RobotState s;
    s.v = u0(0);
    s.omega = u0(1);
    const double h = 1e-4;
    for (int k = 1; k <= 5000; ++k) {
        integrateRobot(m, s, e, h, Integrator::Rk4);
        if (k % 1000) continue;
        const double t = k * h;
        const Eigen::Vector2cd expL(std::exp(lambda(0) * t), std::exp(lambda(1) * t));
        const Eigen::Vector2d u =
            uInf + (V * expL.asDiagonal() * V.inverse() * (u0 - uInf).cast<std::complex<double>>()).real();
        QVERIFY2(std::abs(s.v - u(0)) < 1e-10 && std::abs(s.omega - u(1)) < 1e-9,
                 qPrintable(QString("t=%1: v %2 vs %3, w %4 vs %5").arg(t).arg(s.v).arg(u(0)).arg(s.omega).arg(u(1))));
    }
}

void TestRobotModel::outputsAtStallAndSteadyState() {
    const RobotParams p = test::asymmetricParams();
    const RobotModel m = makeRobotModel(p);
    const Voltages e{6.0, 4.0};
    // Stalled (held at rest): no back-EMF, i = e/R; the whole motor torque
    // K i goes into accelerating the rotor and the robot.
    RobotOutputs o = computeRobotOutputs(m, RobotState{}, e);
    QVERIFY(o.wheel_speed_right == 0.0 && o.wheel_speed_left == 0.0);
    QVERIFY(test::relativeError(o.current_right, 6.0 / p.right.resistance) < 1e-15);
    QVERIFY(test::relativeError(o.current_left, 4.0 / p.left.resistance) < 1e-15);
    // At steady state the wheel torque is K i - beta w (no acceleration) and
    // each wheel turns at (v +- w b/2)/r.
    const Eigen::Vector2d u = steadyStateVelocity(m, e);
    RobotState s;
    s.v = u(0);
    s.omega = u(1);
    o = computeRobotOutputs(m, s, e);
    const double wd = (u(0) + u(1) * p.wheel_base / 2) / p.right.wheel_radius;
    QVERIFY(test::relativeError(o.wheel_speed_right, wd) < 1e-13);
    const double id = (6.0 - p.right.k * wd) / p.right.resistance;
    QVERIFY(test::relativeError(o.current_right, id) < 1e-12);
    QVERIFY(test::relativeError(o.torque_right, p.right.k * id - p.right.friction * wd) < 1e-9);
}

void TestRobotModel::voltagesAreClamped() {
    RobotParams p;
    p.max_voltage = 6.0;
    const Voltages c = clampVoltages(p, {9.0, -12.0});
    QCOMPARE(c.right, 6.0);
    QCOMPARE(c.left, -6.0);
    const Voltages n = clampVoltages(p, {std::nan(""), 3.0});
    QCOMPARE(n.right, 0.0);
    QCOMPARE(n.left, 3.0);
    const Voltages inf = clampVoltages(p, {INFINITY, -INFINITY});
    QCOMPARE(inf.right, 6.0);
    QCOMPARE(inf.left, -6.0);
}

QTEST_GUILESS_MAIN(TestRobotModel)
#include "test_robot_model.moc"
