// The exact integrator (exact_integrator.h, model.md §2, §7): the matrix flow
// against independent closed forms, the velocity and heading exact for any
// step, the position against an independent fine RK4 and a circle, the ball
// against eq. 9's closed form, and stability where Euler and RK4 blow up.
#include <QtTest>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstring>
#include <random>

#include "io/scene_io.h"
#include "test_support.h"
#include "vssim/exact_integrator.h"
#include "vssim/geometry.h"
#include "vssim/integrator.h"
#include "vssim/linear_flow.h"
#include "vssim/robot_model.h"

using namespace vssim;

namespace {

// exp(A t), its integral and double integral from A's eigen-decomposition
// (real, distinct eigenvalues lambda): the scalar forms e^(l t),
// (e^(l t) - 1)/l and (e^(l t) - 1 - l t)/l^2 per mode. Written
// independently of linear_flow.cpp (which uses Taylor series and doubling).
LinearFlow flowByEigenvectors(const Eigen::Matrix2d& A, double t) {
    Eigen::EigenSolver<Eigen::Matrix2d> solver(A);
    const Eigen::Matrix2d V = solver.eigenvectors().real();
    const Eigen::Vector2d l = solver.eigenvalues().real();
    Eigen::Vector2d phi, psi, omega;
    for (int k = 0; k < 2; ++k) {
        phi(k) = std::exp(l(k) * t);
        psi(k) = std::expm1(l(k) * t) / l(k);
        // (e^x - 1 - x)/l^2 with x = l t; its series where x is small
        // (the closed form cancels there).
        const double x = l(k) * t;
        double series = 0.0, term = 0.5;  // sum of x^j / (j + 2)!
        for (int j = 0; j < 30; ++j, term *= x / (j + 2)) series += term;
        omega(k) = std::abs(x) > 1.0 ? (std::expm1(x) - x) / (l(k) * l(k)) : t * t * series;
    }
    LinearFlow f;
    f.t = t;
    f.Phi = V * phi.asDiagonal() * V.inverse();
    f.Psi = V * psi.asDiagonal() * V.inverse();
    f.Omega = V * omega.asDiagonal() * V.inverse();
    return f;
}

double maxRelative(const Eigen::Matrix2d& got, const Eigen::Matrix2d& want) {
    return (got - want).cwiseAbs().maxCoeff() / std::max(1e-300, want.cwiseAbs().maxCoeff());
}

// RK4 with a tiny step as an independent reference for the pose.
RobotState referenceRk4(const RobotModel& m, RobotState s, const Voltages& e, double duration) {
    const int steps = static_cast<int>(std::lround(duration / 1e-5));
    for (int k = 0; k < steps; ++k) integrateRobot(m, s, e, duration / steps, Integrator::Rk4);
    return s;
}

// The robot of resources/scenes/stiff_robot.json: extremely stiff motors
// (tiny rotor inertia, low resistance, strong motor), whose fastest mode
// decays in 36 us. The same scene feeds the stability benchmark.
RobotParams stiffParams() {
    QString error;
    const std::optional<Scene> scene = loadSceneFile(VSSIM_SOURCE_DIR "/resources/scenes/stiff_robot.json", &error);
    if (!scene || scene->robots.empty()) qFatal("stiff_robot.json: %s", qPrintable(error));
    return scene->robots[0].params;
}

// The worst relative error of an entry of the three flows `f` against the
// Taylor series of A t summed in long double to 40 terms (independent of
// linear_flow.cpp's Cayley-Hamilton sums), relative to that entry.
double worstEntryError(const LinearFlow& f, const Eigen::Matrix2d& A, double t) {
    // sum_j (A t)^j / (j + m)! for m = 0, 1, 2, in long double.
    long double power[2][2] = {{1, 0}, {0, 1}}, sums[3][2][2] = {};
    long double inverseFactorial[43];
    inverseFactorial[0] = 1;
    for (int j = 1; j < 43; ++j) inverseFactorial[j] = inverseFactorial[j - 1] / j;
    for (int j = 0; j <= 40; ++j) {
        for (int m = 0; m < 3; ++m)
            for (int r = 0; r < 2; ++r)
                for (int c = 0; c < 2; ++c) sums[m][r][c] += power[r][c] * inverseFactorial[j + m];
        long double next[2][2];
        for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c)
                next[r][c] = (static_cast<long double>(A(r, 0)) * power[0][c] +
                              static_cast<long double>(A(r, 1)) * power[1][c]) *
                             static_cast<long double>(t);
        std::memcpy(power, next, sizeof power);
    }
    const Eigen::Matrix2d* got[3] = {&f.Phi, &f.Psi, &f.Omega};
    const long double scale[3] = {1.0L, static_cast<long double>(t), static_cast<long double>(t) * t};
    double worst = 0.0;
    for (int m = 0; m < 3; ++m)
        for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c) {
                const long double want = sums[m][r][c] * scale[m];
                if (want == 0.0L) {
                    if ((*got[m])(r, c) != 0.0) return HUGE_VAL;  // (an entry that must be zero)
                    continue;
                }
                const long double error = std::fabs(static_cast<long double>((*got[m])(r, c)) - want);
                if (!std::isfinite(static_cast<double>(error))) return HUGE_VAL;  // (a NaN entry fails, not skipped)
                worst = std::max(worst, static_cast<double>(error / std::fabs(want)));
            }
    return worst;
}

}  // namespace

class TestExactIntegrator : public QObject {
    Q_OBJECT
private slots:
    void flowMatchesEigenDecomposition_data();
    void flowMatchesEigenDecomposition();
    void flowOfZeroAndSingularMatrices();
    void velocityAndHeadingExactForAnyStep_data();
    void velocityAndHeadingExactForAnyStep();
    void positionMatchesFineReference_data();
    void positionMatchesFineReference();
    void steadyTurnIsACircle();
    void ballMatchesClosedForm();
    void stableWhereExplicitMethodsDiverge();
    void stepBoundsHold();
    void stiffRobotAccurateAtLongSteps();
    void positionQuadratureIsOrderTen();
    void flowExactToRoundingAtEveryScale();
    void flowOfACoupledRobotEntryByEntry();
    void flowsAlongAStepAreEachFlow();
    void tableCacheGivesTheTablesItWouldBuild();
};

void TestExactIntegrator::flowMatchesEigenDecomposition_data() {
    QTest::addColumn<double>("t");
    for (double t : {1e-6, 1e-3, 0.03, 0.5, 4.0}) QTest::newRow(qPrintable(QString("t=%1").arg(t))) << t;
}

void TestExactIntegrator::flowMatchesEigenDecomposition() {
    QFETCH(double, t);
    for (const RobotParams& p : {RobotParams{}, test::asymmetricParams()}) {
        const Eigen::Matrix2d A = makeRobotModel(p).A;
        const LinearFlow got = linearFlow(A, t), want = flowByEigenvectors(A, t);
        QVERIFY2(maxRelative(got.Phi, want.Phi) < 1e-13, qPrintable(QString::number(maxRelative(got.Phi, want.Phi))));
        QVERIFY2(maxRelative(got.Psi, want.Psi) < 1e-13, qPrintable(QString::number(maxRelative(got.Psi, want.Psi))));
        QVERIFY2(maxRelative(got.Omega, want.Omega) < 1e-12,
                 qPrintable(QString::number(maxRelative(got.Omega, want.Omega))));
    }
    // A rotation generator (complex modes): exp = rotation, integral known.
    Eigen::Matrix2d R;
    R << 0.0, -3.0, 3.0, 0.0;
    const LinearFlow f = linearFlow(R, t);
    Eigen::Matrix2d rot, rotIntegral;
    rot << std::cos(3 * t), -std::sin(3 * t), std::sin(3 * t), std::cos(3 * t);
    rotIntegral << std::sin(3 * t) / 3, (std::cos(3 * t) - 1) / 3, (1 - std::cos(3 * t)) / 3, std::sin(3 * t) / 3;
    QVERIFY((f.Phi - rot).cwiseAbs().maxCoeff() < 1e-13);
    QVERIFY((f.Psi - rotIntegral).cwiseAbs().maxCoeff() < 1e-13 * std::max(1.0, t));
}

void TestExactIntegrator::flowOfZeroAndSingularMatrices() {
    // A = 0 (a frictionless body): Phi = I, Psi = t I, Omega = t^2/2 I.
    const LinearFlow zero = linearFlow(Eigen::Matrix2d::Zero(), 0.7);
    QCOMPARE(zero.Phi, Eigen::Matrix2d::Identity().eval());
    QVERIFY((zero.Psi - 0.7 * Eigen::Matrix2d::Identity()).norm() < 1e-15);
    QVERIFY((zero.Omega - 0.245 * Eigen::Matrix2d::Identity()).norm() < 1e-15);
    // A nilpotent A (singular, not diagonalizable): exp(A t) = I + A t exactly.
    Eigen::Matrix2d N;
    N << 0.0, 2.0, 0.0, 0.0;
    const LinearFlow f = linearFlow(N, 1.5);
    QVERIFY((f.Phi - (Eigen::Matrix2d::Identity() + 1.5 * N)).norm() < 1e-14);
    QVERIFY((f.Psi - (1.5 * Eigen::Matrix2d::Identity() + 1.125 * N)).norm() < 1e-14);
    QVERIFY((f.Omega - (1.125 * Eigen::Matrix2d::Identity() + (1.5 * 1.5 * 1.5 / 6) * N)).norm() < 1e-14);
}

void TestExactIntegrator::velocityAndHeadingExactForAnyStep_data() {
    QTest::addColumn<double>("h");
    for (double h : {1e-4, 1e-3, 0.03, 0.25, 2.0}) QTest::newRow(qPrintable(QString("h=%1").arg(h))) << h;
}

void TestExactIntegrator::velocityAndHeadingExactForAnyStep() {
    // model.md §2: u(t) = u_inf + exp(A t)(u0 - u_inf) for constant e, and
    // theta(t) = theta0 + int omega, from the eigen-decomposition above.
    QFETCH(double, h);
    const RobotModel m = makeRobotModel(test::asymmetricParams());
    const Voltages e{6.5, -2.0};
    RobotState s;
    s.v = 0.4;
    s.omega = 7.0;
    s.theta = 0.3;
    const Eigen::Vector2d u0(s.v, s.omega);
    const Eigen::Vector2d uInf = steadyStateVelocity(m, e);
    const double duration = 4.0;  // s: several time constants
    const int steps = static_cast<int>(std::lround(duration / h));
    for (int k = 0; k < steps; ++k) integrateRobot(m, s, e, h, Integrator::Exact);
    const double t = steps * h;
    const LinearFlow f = flowByEigenvectors(m.A, t);
    const Eigen::Vector2d u = uInf + f.Phi * (u0 - uInf);
    const double theta = 0.3 + uInf(1) * t + (f.Psi * (u0 - uInf))(1);
    // To rounding: a few ulps per step, accumulated over the steps.
    const double tolerance = 1e-15 * (steps + 10);
    QVERIFY2(std::abs(s.v - u(0)) < tolerance,
             qPrintable(QString("v %1 vs %2").arg(s.v, 0, 'g', 17).arg(u(0), 0, 'g', 17)));
    QVERIFY2(std::abs(s.omega - u(1)) < 10 * tolerance,
             qPrintable(QString("w %1 vs %2").arg(s.omega, 0, 'g', 17).arg(u(1), 0, 'g', 17)));
    QVERIFY2(std::abs(s.theta - theta) < 10 * tolerance * std::max(1.0, std::abs(theta)),
             qPrintable(QString("theta %1 vs %2").arg(s.theta, 0, 'g', 17).arg(theta, 0, 'g', 17)));
}

void TestExactIntegrator::positionMatchesFineReference_data() {
    QTest::addColumn<double>("h");
    for (double h : {1e-3, 0.01, 0.03, 0.1}) QTest::newRow(qPrintable(QString("h=%1").arg(h))) << h;
}

void TestExactIntegrator::positionMatchesFineReference() {
    // Against RK4 at 10 us (error ~1e-14 m here): the exact step's position
    // error stays at rounding level even for steps of 100 ms.
    QFETCH(double, h);
    const RobotModel m = makeRobotModel(test::asymmetricParams());
    const Voltages e{7.4, 1.0};
    RobotState start;
    start.v = -0.5;
    start.omega = 20.0;
    const double duration = 0.3;  // s
    RobotState s = start;
    const int steps = static_cast<int>(std::lround(duration / h));
    for (int k = 0; k < steps; ++k) integrateRobot(m, s, e, h, Integrator::Exact);
    const RobotState want = referenceRk4(m, start, e, steps * h);
    const double err = std::hypot(s.x - want.x, s.y - want.y);
    QVERIFY2(err < 1e-11, qPrintable(QString("position error %1 m").arg(err)));
    // RK4 at the same step is far worse at the long steps (the point of the method).
    if (h >= 0.03) {
        RobotState r = start;
        for (int k = 0; k < steps; ++k) integrateRobot(m, r, e, h, Integrator::Rk4);
        QVERIFY(std::hypot(r.x - want.x, r.y - want.y) > 1000 * err);
    }
}

void TestExactIntegrator::steadyTurnIsACircle() {
    // At the steady state of constant voltages the robot drives a circle of
    // radius v/w: x = x0 + (v/w)(sin(theta0 + w t) - sin theta0), and
    // y = y0 - (v/w)(cos(theta0 + w t) - cos theta0). One step of 1 s.
    const RobotModel m = makeRobotModel(RobotParams{});
    const Voltages e{7.0, 3.0};
    const Eigen::Vector2d u = steadyStateVelocity(m, e);
    RobotState s;
    s.x = 0.1;
    s.y = -0.2;
    s.theta = 0.4;
    s.v = u(0);
    s.omega = u(1);
    integrateRobot(m, s, e, 1.0, Integrator::Exact);
    const double radius = u(0) / u(1);
    QVERIFY(std::abs(s.x - (0.1 + radius * (std::sin(0.4 + u(1)) - std::sin(0.4)))) < 1e-13);
    QVERIFY(std::abs(s.y - (-0.2 - radius * (std::cos(0.4 + u(1)) - std::cos(0.4)))) < 1e-13);
    QVERIFY(std::abs(s.theta - (0.4 + u(1))) < 1e-13);
}

void TestExactIntegrator::ballMatchesClosedForm() {
    // Eq. 9: v(t) = v0 e^(-k t), x(t) = x0 + v0 (1 - e^(-k t)) / k, any step.
    BallParams p;
    for (double h : {1e-3, 0.5, 10.0}) {
        BallState b;
        b.vx = 2.0;
        b.vy = -1.5;
        const int steps = static_cast<int>(std::lround(10.0 / h));
        for (int k = 0; k < steps; ++k) integrateBall(p, b, h, Integrator::Exact);
        const double k = p.friction / p.mass;
        QVERIFY(test::relativeError(b.vx, 2.0 * std::exp(-k * 10.0)) < 1e-12);
        QVERIFY(test::relativeError(b.x, 2.0 * (1 - std::exp(-k * 10.0)) / k) < 1e-12);
        QVERIFY(test::relativeError(b.y, -1.5 * (1 - std::exp(-k * 10.0)) / k) < 1e-12);
    }
}

void TestExactIntegrator::stableWhereExplicitMethodsDiverge() {
    // The stiff robot's fastest mode: Euler is stable only for h < 2/|l|,
    // RK4 for h < 2.785/|l|. At a step ten times beyond, they blow up; the
    // exact step lands on the steady state.
    const RobotModel m = makeRobotModel(stiffParams());
    const double limit = 2.0 / m.fastestRate;  // s, Euler's limit
    const double h = 10.0 * 2.785 / m.fastestRate;
    const Voltages e{5.0, 5.0};
    const Eigen::Vector2d uInf = steadyStateVelocity(m, e);
    RobotState euler, rk4, exact;
    for (int k = 0; k < 200; ++k) {
        integrateRobot(m, euler, e, h, Integrator::Euler);
        integrateRobot(m, rk4, e, h, Integrator::Rk4);
        integrateRobot(m, exact, e, h, Integrator::Exact);
    }
    QVERIFY2(limit < 1e-3, qPrintable(QString("not stiff: Euler's limit %1 s").arg(limit)));
    QVERIFY(!(std::abs(euler.v) < 1e3));
    QVERIFY(!(std::abs(rk4.v) < 1e3));
    QVERIFY(test::relativeError(exact.v, uInf(0)) < 1e-9);
}

void TestExactIntegrator::stepBoundsHold() {
    // pointSpeedBound bounds |v| + |w| s/sqrt2 at every instant of the exact
    // trajectory, from random starts and voltages (asymmetric robot).
    const RobotModel m = makeRobotModel(test::asymmetricParams());
    const double rho = m.params.side / std::sqrt(2.0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> volt(-7.4, 7.4), speed(-2.5, 2.5), yaw(-60.0, 60.0);
    // A random start (speed and yaw rate) and random voltages, drawn in that order.
    auto randomStart = [&] {
        RobotState s;
        s.v = speed(rng);
        s.omega = yaw(rng);
        const Voltages e{volt(rng), volt(rng)};
        return std::pair{s, e};
    };
    for (int trial = 0; trial < 200; ++trial) {
        auto [s, e] = randomStart();
        const double bound = pointSpeedBound(m, s, e);
        for (int k = 0; k < 400; ++k) {
            integrateRobot(m, s, e, 2e-3, Integrator::Exact);
            QVERIFY(std::abs(s.v) + rho * std::abs(s.omega) <= bound);
        }
    }
    // yawRateBound (the panel count's) is velocityBound's yaw rate, bit for
    // bit, and bounds |w| along the exact trajectory; infinite for a broken state.
    for (const RobotModel& model : {m, makeRobotModel(RobotParams{})}) {
        for (int trial = 0; trial < 200; ++trial) {
            auto [s, e] = randomStart();
            const double bound = yawRateBound(model, s, e);
            QVERIFY(bound == velocityBound(model, s, e)(1));  // (QCOMPARE would allow a fuzz)
            for (int k = 0; k < 100; ++k) {
                integrateRobot(model, s, e, 5e-3, Integrator::Exact);
                QVERIFY(std::abs(s.omega) <= bound);
            }
        }
        for (const double broken : {NAN, INFINITY, -INFINITY}) {
            RobotState s;
            s.v = broken;
            QCOMPARE(yawRateBound(model, s, {1.0, 2.0}), INFINITY);
            s.v = 0.0, s.omega = broken;
            QCOMPARE(yawRateBound(model, s, {1.0, 2.0}), INFINITY);
        }
    }
    // robotTravelBound bounds the path length of every corner of the robot
    // (measured along the exact trajectory in steps of 0.5 ms) at every T,
    // and with arm 0 the distance the centre has moved.
    for (int trial = 0; trial < 200; ++trial) {
        auto [s, e] = randomStart();
        const RobotState start = s;
        std::array<Eigen::Vector2d, 4> corners = robotVertices(s, m.params.side);
        double path = 0.0;  // m, the longest corner path so far
        std::array<double, 4> paths{};
        for (int k = 1; k <= 400; ++k) {
            integrateRobot(m, s, e, 5e-4, Integrator::Exact);
            const std::array<Eigen::Vector2d, 4> now = robotVertices(s, m.params.side);
            for (int j = 0; j < 4; ++j) paths[j] += (now[j] - corners[j]).norm(), path = std::max(path, paths[j]);
            corners = now;
            const double bound = robotTravelBound(m, start, e, k * 5e-4, rho);
            QVERIFY(std::hypot(s.x - start.x, s.y - start.y) <=
                    robotTravelBound(m, start, e, k * 5e-4, 0.0) * (1 + 1e-12));
            QVERIFY2(path <= bound * (1 + 1e-12),
                     qPrintable(
                         QString("trial %1, T=%2: path %3 > bound %4").arg(trial).arg(k * 5e-4).arg(path).arg(bound)));
        }
    }
    // And it is tight where it can be: a symmetric robot driving straight
    // from rest travels exactly the bound (every point moves with v).
    const RobotModel symmetric = makeRobotModel(RobotParams{});
    RobotState straight;
    for (int k = 0; k < 100; ++k) integrateRobot(symmetric, straight, {5.0, 5.0}, 1e-3, Integrator::Exact);
    QVERIFY(test::relativeError(robotTravelBound(symmetric, RobotState{}, {5.0, 5.0}, 0.1, 0.05), straight.x) < 1e-9);
    // The yaw-rate bound from rest at full opposite voltages holds at the
    // steady state (closed form B^-1 K e).
    QVERIFY(std::abs(steadyStateVelocity(m, {7.4, -7.4})(1)) <=
            velocityBound(m, RobotState{}, {7.4, -7.4})(1) * (1 + 1e-12));
}

void TestExactIntegrator::stiffRobotAccurateAtLongSteps() {
    // The stiff robot's fast transient (36 us) inside steps of 1 ms to 30 ms:
    // graded panels resolve it with few panels, and the position matches RK4
    // at 2 us (well inside RK4's 101 us stability limit) over 90 ms.
    const RobotModel m = makeRobotModel(stiffParams());
    const Voltages e{6.0, -2.0};
    RobotState reference;
    reference.v = 2.0;
    for (int k = 0; k < 45000; ++k) integrateRobot(m, reference, e, 2e-6, Integrator::Rk4);
    for (const double h : {1e-3, 2e-3, 5e-3, 0.03}) {
        const ExactStepTable table = makeExactStepTable(m, h, exactPanelsFor(m, RobotState{}, e, h));
        int panels = 0;
        for (const ExactPanel& p : table.kinds) panels += p.repeat;
        QVERIFY2(table.kinds.size() > 2 && panels < 100, qPrintable(QString("h=%1: %2 panels").arg(h).arg(panels)));
        RobotState exact;
        exact.v = 2.0;
        const int steps = static_cast<int>(std::lround(0.09 / h));
        for (int k = 0; k < steps; ++k) integrateRobotExact(m, table, exact, e);
        const double err = std::hypot(exact.x - reference.x, exact.y - reference.y);
        QVERIFY2(err < 1e-10, qPrintable(QString("h=%1: position error %2 m").arg(h).arg(err)));
        QVERIFY(std::abs(exact.theta - reference.theta) < 1e-9);
    }
}

void TestExactIntegrator::positionQuadratureIsOrderTen() {
    // The exact step's only approximation is the position quadrature:
    // 5-point Gauss-Legendre, order 10. On a steady turn (a circle, closed
    // form) over 8 rad, forcing 4 and then 8 panels divides the error by
    // about 2^10.
    const RobotModel m = makeRobotModel(RobotParams{});
    const Voltages e{7.4, -5.0};
    const Eigen::Vector2d u = steadyStateVelocity(m, e);
    const double h = 8.0 / u(1);  // s: eight radians of turn
    auto error = [&](int panels) {
        RobotState s;
        s.v = u(0);
        s.omega = u(1);
        integrateRobotExact(m, makeExactStepTable(m, h, panels), s, e);
        const double r = u(0) / u(1);
        return std::hypot(s.x - r * std::sin(u(1) * h), s.y + r * (std::cos(u(1) * h) - 1.0));
    };
    const double coarse = error(4), fine = error(8);
    QVERIFY2(coarse > 1e-12, "the error is at rounding: the test cannot see the order");
    const double order = std::log2(coarse / fine);
    QVERIFY2(order > 9.0 && order < 11.0,
             qPrintable(QString("order %1 (errors %2, %3 m)").arg(order).arg(coarse).arg(fine)));
}

void TestExactIntegrator::flowExactToRoundingAtEveryScale() {
    // The Taylor series stops as soon as its remainder is below rounding,
    // so a short flow takes few terms: at every scale from 1 ns to 0.3 s
    // (|A t| from 3e-9 to 0.9, with and without a doubling) the flow of a
    // rotation generator and of a diagonal A equals their closed forms to a
    // few units of rounding (a term too few would show as an error of
    // |A t|^K / K!, far above these limits for any t here).
    Eigen::Matrix2d R;
    R << 0.0, -3.0, 3.0, 0.0;
    Eigen::Matrix2d D = Eigen::Matrix2d::Zero();
    D(0, 0) = -2.5;
    D(1, 1) = -0.4;
    double worstPhi = 0.0, worstPsi = 0.0, worstOmega = 0.0;
    for (int k = 0; k <= 160; ++k) {
        const double t = 1e-9 * std::pow(3e8, k / 160.0);  // s
        const LinearFlow f = linearFlow(R, t);
        // Rotation by 3t and its integral; 1 - cos written as 2 sin^2 (no cancellation).
        const double c = std::cos(3 * t), s = std::sin(3 * t), oneMinusCos = 2 * std::pow(std::sin(1.5 * t), 2);
        Eigen::Matrix2d rot, rotIntegral;
        rot << c, -s, s, c;
        rotIntegral << s / 3, -oneMinusCos / 3, oneMinusCos / 3, s / 3;
        worstPhi = std::max(worstPhi, (f.Phi - rot).cwiseAbs().maxCoeff());
        worstPsi = std::max(worstPsi, (f.Psi - rotIntegral).cwiseAbs().maxCoeff() / t);
        const LinearFlow g = linearFlow(D, t);
        for (int i = 0; i < 2; ++i) {
            const double x = D(i, i) * t;
            double tail = 0.0, term = 0.5;  // (e^x - 1 - x) / x^2 = sum x^j / (j + 2)!
            for (int j = 0; j < 40; ++j, term *= x / (j + 2)) tail += term;
            worstPhi = std::max(worstPhi, test::relativeError(g.Phi(i, i), std::exp(x)));
            worstPsi = std::max(worstPsi, test::relativeError(g.Psi(i, i), std::expm1(x) / D(i, i)));
            worstOmega = std::max(worstOmega, test::relativeError(g.Omega(i, i), t * t * tail));
        }
        QCOMPARE(g.Phi(0, 1), 0.0);
        QCOMPARE(g.Omega(1, 0), 0.0);
    }
    QVERIFY2(worstPhi < 1e-15, qPrintable(QString("Phi: %1").arg(worstPhi)));
    QVERIFY2(worstPsi < 1e-15, qPrintable(QString("Psi: %1").arg(worstPsi)));
    QVERIFY2(worstOmega < 1e-15, qPrintable(QString("Omega: %1").arg(worstOmega)));
}

void TestExactIntegrator::flowOfACoupledRobotEntryByEntry() {
    // A robot whose wheels couple (asymmetric motors: A not diagonal, its
    // trace not zero), and a stronger coupling still: each entry of the
    // three flows, small off-diagonal ones included, against the Taylor
    // series summed in long double to 40 terms (independent of the
    // Cayley-Hamilton sums), relative to that entry, from 1 ns to 30 ms.
    Eigen::Matrix2d coupled;
    coupled << -15.0, 3.0, 0.5, -40.0;
    for (const Eigen::Matrix2d& A : {makeRobotModel(test::asymmetricParams()).A, coupled}) {
        QVERIFY(A(0, 1) != 0.0 && A(1, 0) != 0.0 && A.trace() != 0.0);
        double worst = 0.0;
        for (int k = 0; k <= 70; ++k) {
            const double t = 1e-9 * std::pow(3e7, k / 70.0);  // s
            worst = std::max(worst, worstEntryError(linearFlow(A, t), A, t));
        }
        QVERIFY2(worst < 2e-15, qPrintable(QString("worst relative error of an entry: %1").arg(worst)));
    }
}

void TestExactIntegrator::flowsAlongAStepAreEachFlow() {
    // linearFlowsAlong (one series for a panel's nodes and end) against the
    // long-double series at each fraction of t, entry by entry, for robots
    // with and without coupling, a stiff one, a rotation and zero, from 1 ns
    // to 0.3 s (the longer ones scaled: then each is linearFlow's, bit for
    // bit); a fraction of 1 gives linearFlow's bits, and so does 0 (the
    // identity and zeros), and so do fractions outside [0, 1].
    Eigen::Matrix2d coupled, rotation;
    coupled << -15.0, 3.0, 0.5, -40.0;
    rotation << 0.0, -3.0, 3.0, 0.0;
    const std::array<double, 10> fractions = {0.0469100770306680, 0.2307653449471585, 0.5, 0.7692346550528415,
                                              0.9530899229693320, 1.0, 0.0, 0.37, 1.5, -0.2};
    int shared = 0, scaled = 0;
    for (const Eigen::Matrix2d& A : {makeRobotModel(RobotParams{}).A, makeRobotModel(test::asymmetricParams()).A,
                                     makeRobotModel(stiffParams()).A, coupled, rotation, Eigen::Matrix2d::Zero().eval()}) {
        double worst = 0.0;
        for (int k = 0; k <= 60; ++k) {
            const double t = 1e-9 * std::pow(3e8, k / 60.0);  // s
            std::array<LinearFlow, fractions.size()> flows;
            linearFlowsAlong(A, t, fractions.data(), static_cast<int>(fractions.size()), flows.data());
            const bool isShared = (A * t).cwiseAbs().rowwise().sum().maxCoeff() <= 0.5;
            (isShared ? shared : scaled) += 1;
            for (std::size_t i = 0; i < fractions.size(); ++i) {
                const double tau = fractions[i] * t;
                const LinearFlow one = linearFlow(A, tau);
                QCOMPARE(flows[i].t, tau);
                if (!isShared || !(fractions[i] > 0.0 && fractions[i] < 1.0)) {
                    QVERIFY2(flows[i].Phi == one.Phi && flows[i].Psi == one.Psi && flows[i].Omega == one.Omega,
                             qPrintable(QString("t = %1 s, fraction %2: not linearFlow's bits").arg(t).arg(fractions[i])));
                    continue;
                }
                worst = std::max(worst, worstEntryError(flows[i], A, tau));
            }
        }
        qInfo("worst relative error of an entry, shared series: %.2g", worst);
        QVERIFY2(worst < 2e-15, qPrintable(QString("worst relative error of an entry: %1").arg(worst)));
    }
    QVERIFY(shared > 100 && scaled > 50);  // both ways are tried
}

void TestExactIntegrator::tableCacheGivesTheTablesItWouldBuild() {
    // Every table the cache hands out is, bit for bit, the one
    // makeExactStepTable builds for its key: for two robot dynamics in turn,
    // over more distinct keys than the cache keeps (so that it fills and
    // starts again), with keys asked for again at random, for a robot whose
    // model is replaced, and for a NaN step length.
    const RobotModel models[] = {makeRobotModel(RobotParams{}), makeRobotModel(test::asymmetricParams())};
    auto same = [](const ExactStepTable& a, const ExactStepTable& b) {
        if (!(a.h == b.h || (std::isnan(a.h) && std::isnan(b.h))) || a.panels != b.panels ||
            a.kinds.size() != b.kinds.size())
            return false;
        for (std::size_t k = 0; k < a.kinds.size(); ++k) {
            const ExactPanel &p = a.kinds[k], &q = b.kinds[k];
            if (p.length != q.length || p.repeat != q.repeat || p.flow.Phi != q.flow.Phi || p.flow.Psi != q.flow.Psi ||
                p.flow.Omega != q.flow.Omega || p.weights != q.weights || p.speedFromV != q.speedFromV ||
                p.speedFromW != q.speedFromW || p.headingFromV != q.headingFromV || p.headingFromW != q.headingFromW ||
                p.speedFromG0 != q.speedFromG0 || p.speedFromG1 != q.speedFromG1 ||
                p.headingFromG0 != q.headingFromG0 || p.headingFromG1 != q.headingFromG1)
                return false;
        }
        return true;
    };
    ExactTableCache cache;
    std::mt19937 rng(5);
    std::vector<double> lengths;  // s: steps of dt, and instants of contacts
    for (int k = 1; k <= 30; ++k) lengths.push_back(1e-3 * k);
    std::uniform_real_distribution<double> instant(0.0, 1e-3);
    for (int k = 0; k < 2500; ++k) lengths.push_back(instant(rng));
    std::uniform_int_distribution<std::size_t> pick(0, lengths.size() - 1);
    std::uniform_int_distribution<int> panels(0, 3);
    for (int k = 0; k < 6000; ++k) {
        const int robot = k % 3;  // robots 0 and 2 share the first dynamics
        const RobotModel& m = models[robot == 1];
        // Mostly steps of dt, as a run asks; the rest at random.
        const double h = k % 4 == 0 ? lengths[pick(rng)] : lengths[k % 30];
        const int p = panels(rng);
        QVERIFY2(same(cache.table(robot, m, h, p), makeExactStepTable(m, h, p)),
                 qPrintable(QString("call %1: robot %2, h = %3 s, %4 panels").arg(k).arg(robot).arg(h).arg(p)));
    }
    // Robot 0 now has the other dynamics: it gets their tables, not its old ones.
    QVERIFY(same(cache.table(0, models[1], 1e-3, 1), makeExactStepTable(models[1], 1e-3, 1)));
    QVERIFY(same(cache.table(0, models[0], 1e-3, 1), makeExactStepTable(models[0], 1e-3, 1)));
    QVERIFY(std::isnan(cache.table(1, models[1], NAN, 1).h));  // (its flows are NaN: nothing to compare)
}

QTEST_GUILESS_MAIN(TestExactIntegrator)
#include "test_exact_integrator.moc"
