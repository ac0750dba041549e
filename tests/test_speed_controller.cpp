// The robots' on-board wheel-speed loop (vssim/speed_controller.h): the PI
// law and its anti-windup against hand computations, the encoder's counts,
// and a robot under the loop against an independent discrete-time model of
// the closed loop (zero-order hold on the exact solution of the motor
// dynamics, computed here with Eigen's matrix exponential).
#include <QtTest>
#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>

#include "io/scene_io.h"
#include "vssim/robot_model.h"
#include "vssim/speed_controller.h"
#include "vssim/state_hash.h"
#include "vssim/world.h"

using namespace vssim;

namespace {

// One robot alone in the middle of a big box: nothing touches it for seconds.
Scene loneRobot(Integrator integrator = Integrator::Exact) {
    Scene scene;
    scene.field = makeRectangularField(20.0, 20.0);
    scene.simulation.integrator = integrator;
    RobotSpec robot;
    robot.name = "yellow0";
    scene.robots.push_back(robot);
    scene.ball.x = 8.0;
    scene.ball.y = 8.0;
    return scene;
}

WheelSpeeds wheelSpeedsOf(const Simulation& sim, int robot) {
    const Eigen::Vector2d w =
        sim.model().robots[robot].TwInv *
        Eigen::Vector2d(sim.state().robots[robot].v, sim.state().robots[robot].omega);
    return {w(0), w(1)};
}

// The velocity dynamics u' = A u + G e (u = (v, w)) written from the robot's
// parameters, independently of the engine's RobotModel: the wheels' speeds
// are (v +- w b/2)/r; each motor's torque K (e - K w_wheel)/R minus its
// viscous friction drives the body through the wheel radius.
struct IndependentRobot {
    Eigen::Matrix2d A, G, toWheels;
    explicit IndependentRobot(const RobotParams& p) {
        const double r = p.right.wheel_radius, b = p.wheel_base;
        // Wheel speeds from (v, w): [w_d; w_e] = toWheels [v; w].
        toWheels << 1.0 / r, b / (2.0 * r), 1.0 / r, -b / (2.0 * r);
        // Generalised mass: the body plus each rotor's inertia seen through its wheel.
        const double jr = p.right.rotor_inertia, kMotor = p.right.k, res = p.right.resistance, beta = p.right.friction;
        Eigen::Matrix2d M;
        M << p.mass + 2.0 * jr / (r * r), 0.0, 0.0, p.inertia + 2.0 * jr * (b / 2) * (b / 2) / (r * r);
        // Damping: back-EMF K^2/R and the motors' friction at each wheel, plus the body's friction.
        const double wheelDamping = kMotor * kMotor / res + beta;  // N m s/rad at a wheel
        Eigen::Matrix2d B;
        B << p.friction_linear + 2.0 * wheelDamping / (r * r), 0.0, 0.0,
            p.friction_angular + 2.0 * wheelDamping * (b / 2) * (b / 2) / (r * r);
        // Input: each wheel's force K e / (R r), as force and yaw moment.
        Eigen::Matrix2d K;
        K << kMotor / (res * r), kMotor / (res * r), kMotor * b / (2.0 * res * r), -kMotor * b / (2.0 * res * r);
        A = -M.inverse() * B;
        G = M.inverse() * K;
    }
};

}  // namespace

class TestSpeedController : public QObject {
    Q_OBJECT
private slots:
    void piLawByHand();
    void antiWindupHoldsTheIntegrator();
    void nonFiniteInputsGiveZeroVolts();
    void encoderCountsWholeTurns();
    void robotMatchesTheDiscreteClosedLoop();
    void tracksTargetsWithoutSteadyError();
    void saturatesAtTheBattery();
    void samplesAtItsOwnRate();
    void voltagesTurnTheLoopOff();
    void longStepsAgreeWithSteps();
    void deterministic();
    void offFieldRobotIsLeftAlone();
    void sceneFileParametersAndCommands();
    void sceneFileErrors();
};

void TestSpeedController::piLawByHand() {
    SpeedControllerParams p;
    p.rate = 100.0;  // T = 10 ms
    p.kp = 0.5;
    p.ki = 4.0;
    WheelLoopState wheel;
    // Error 2 rad/s: integral 4 * 2 * 0.01 = 0.08 V, output 0.5 * 2 + 0.08.
    QCOMPARE(updateWheelLoop(p, wheel, 12.0, 10.0, 7.4), 1.0 + 0.08);
    QCOMPARE(wheel.integral, 0.08);
    // Error -1 rad/s: integral 0.08 - 0.04, output -0.5 + 0.04.
    QVERIFY(std::abs(updateWheelLoop(p, wheel, 9.0, 10.0, 7.4) - (-0.5 + 0.04)) < 1e-15);
    QVERIFY(std::abs(wheel.integral - 0.04) < 1e-15);
}

void TestSpeedController::antiWindupHoldsTheIntegrator() {
    SpeedControllerParams p;
    p.rate = 100.0;
    p.kp = 1.0;
    p.ki = 10.0;
    WheelLoopState wheel;
    // A huge error saturates at once: the output is the battery's, and the
    // integrator does not move (it would only deepen the saturation).
    for (int k = 0; k < 100; ++k) QCOMPARE(updateWheelLoop(p, wheel, 100.0, 0.0, 7.4), 7.4);
    QCOMPARE(wheel.integral, 0.0);
    // Below saturation it integrates again.
    const double out = updateWheelLoop(p, wheel, 1.0, 0.0, 7.4);
    QCOMPARE(wheel.integral, 10.0 * 1.0 * 0.01);
    QCOMPARE(out, 1.0 + 0.1);
    // Saturated the other way with an error that pulls back: integrates.
    wheel.integral = 7.0;
    const double back = updateWheelLoop(p, wheel, 0.0, 10.0, 7.4);  // error -10: kp e + I = -10 + 6 = -4
    QCOMPARE(wheel.integral, 7.0 - 1.0);
    QCOMPARE(back, -4.0);
    // The integrator itself never leaves +-maxVoltage.
    wheel.integral = 7.3;
    updateWheelLoop(p, wheel, 0.05, 0.0, 7.4);  // 7.3 + 0.005 stays inside; output 0.05 + 7.305 < 7.4
    QVERIFY(wheel.integral <= 7.4);
    p.kp = 0.0;
    for (int k = 0; k < 1000; ++k) updateWheelLoop(p, wheel, 1.0, 0.0, 7.4);
    QVERIFY(wheel.integral <= 7.4);
}

void TestSpeedController::nonFiniteInputsGiveZeroVolts() {
    SpeedControllerParams p;
    WheelLoopState wheel;
    wheel.integral = 1.5;
    QCOMPARE(updateWheelLoop(p, wheel, std::nan(""), 0.0, 7.4), 0.0);
    QCOMPARE(updateWheelLoop(p, wheel, 1.0, HUGE_VAL, 7.4), 0.0);
    QCOMPARE(wheel.integral, 1.5);
    const WheelSpeeds clamped = clampWheelSpeeds({std::nan(""), -1e9}, kMaxWheelSpeedTarget);
    QCOMPARE(clamped.right, 0.0);
    QCOMPARE(clamped.left, -kMaxWheelSpeedTarget);
}

void TestSpeedController::encoderCountsWholeTurns() {
    SpeedControllerParams p;
    p.encoder_counts = 512;
    const double period = 0.005;
    const double step = 2.0 * M_PI / (512 * period);  // one count per period, rad/s
    WheelLoopState wheel;
    // 2.5 counts a period: 2, 3, 2, 3... counts; on average the true speed.
    const double speed = 2.5 * step;
    double sum = 0.0;
    for (int k = 0; k < 100; ++k) {
        const double measured = measureWheelSpeed(p, wheel, speed, period);
        const double counts = measured / step;
        QVERIFY(std::abs(counts - std::round(counts)) < 1e-9);
        QVERIFY(std::round(counts) == 2.0 || std::round(counts) == 3.0);
        sum += measured;
    }
    QVERIFY(std::abs(sum / 100 - speed) < 1e-9 * speed);
    // Backwards: whole counts too, floor carried.
    WheelLoopState back;
    QCOMPARE(measureWheelSpeed(p, back, -0.5 * step, period), -1.0 * step);
    QCOMPARE(measureWheelSpeed(p, back, -0.5 * step, period), 0.0);
    // No encoder: the exact speed.
    p.encoder_counts = 0;
    QCOMPARE(measureWheelSpeed(p, wheel, 12.345, period), 12.345);
}

void TestSpeedController::robotMatchesTheDiscreteClosedLoop() {
    // A turning step (right 30, left 10 rad/s) from rest. Between samples
    // the voltages are held, so the closed loop is exactly a discrete-time
    // system: u[k+1] = Phi u[k] + Gamma e[k], Phi = exp(A T), Gamma =
    // integral of exp(A s) G over [0, T], from one matrix exponential of an
    // augmented matrix.
    const Scene scene = loneRobot();
    const RobotParams& params = scene.robots[0].params;
    const SpeedControllerParams& loop = params.speed_controller;
    const double T = 1.0 / loop.rate;
    const IndependentRobot robot(params);
    Eigen::Matrix4d augmented = Eigen::Matrix4d::Zero();
    augmented.topLeftCorner<2, 2>() = robot.A * T;
    augmented.topRightCorner<2, 2>() = robot.G * T;
    const Eigen::Matrix4d flow = augmented.exp();
    const Eigen::Matrix2d Phi = flow.topLeftCorner<2, 2>(), Gamma = flow.topRightCorner<2, 2>();

    Simulation sim(scene);
    const WheelSpeeds target{30.0, 10.0};
    sim.setWheelSpeeds(0, target);
    const int stepsPerSample = static_cast<int>(std::lround(T / sim.dt()));
    QCOMPARE(stepsPerSample, 5);
    Eigen::Vector2d u(0.0, 0.0);
    WheelLoopState right, left;
    double worst = 0.0;
    for (int k = 0; k < 200; ++k) {  // one second
        const Eigen::Vector2d w = robot.toWheels * u;
        Eigen::Vector2d e(updateWheelLoop(loop, right, target.right, w(0), params.max_voltage),
                          updateWheelLoop(loop, left, target.left, w(1), params.max_voltage));
        u = Phi * u + Gamma * e;
        for (int s = 0; s < stepsPerSample; ++s) sim.step();
        worst = std::max({worst, std::abs(sim.state().robots[0].v - u(0)),
                          std::abs(sim.state().robots[0].omega - u(1)) * params.wheel_base / 2});
        QCOMPARE(sim.state().voltages[0].right, e(0));  // the same voltages at every sample, bit for bit
    }
    QVERIFY2(worst < 1e-10, qPrintable(QString("worst speed difference %1 m/s").arg(worst)));
}

void TestSpeedController::tracksTargetsWithoutSteadyError() {
    for (Integrator integrator : {Integrator::Exact, Integrator::Rk4}) {
        Simulation sim(loneRobot(integrator));
        sim.setWheelSpeeds(0, {25.0, 15.0});
        while (sim.state().time < 1.5) sim.step();
        const WheelSpeeds w = wheelSpeedsOf(sim, 0);
        QVERIFY2(std::abs(w.right - 25.0) < 1e-6 && std::abs(w.left - 15.0) < 1e-6,
                 qPrintable(QString("wheels %1, %2 rad/s").arg(w.right).arg(w.left)));
        // The body: v = r (w_d + w_e)/2, w = r (w_d - w_e)/b.
        QVERIFY(std::abs(sim.state().robots[0].v - 0.025 * 20.0) < 1e-7);
        QVERIFY(std::abs(sim.state().robots[0].omega - 0.025 * 10.0 / 0.065) < 1e-5);
    }
}

void TestSpeedController::saturatesAtTheBattery() {
    // 300 rad/s is beyond the motors: full battery voltage, the free speed
    // (steadyStateVelocity at 7.4 V), and no wind-up: back to 20 rad/s, the
    // wheel comes down without undershooting far below it.
    Simulation sim(loneRobot());
    sim.setWheelSpeeds(0, {300.0, 300.0});
    while (sim.state().time < 1.0) sim.step();
    QCOMPARE(sim.state().voltages[0].right, 7.4);
    const Eigen::Vector2d free = steadyStateVelocity(sim.model().robots[0], {7.4, 7.4});
    QVERIFY(std::abs(sim.state().robots[0].v - free(0)) < 1e-3 * free(0));
    QVERIFY(std::abs(sim.state().speedLoops[0].right.integral) <= 7.4);
    sim.setWheelSpeeds(0, {20.0, 20.0});
    // Without anti-windup the integrator would hold ki * 290 rad/s * 1 s =
    // 2900 V by now and keep the wheel at full speed for seconds; with it,
    // the wheel is within 5 % of its new target in 0.3 s and stays there.
    double lowest = 1e9;
    while (sim.state().time < 1.3) {
        sim.step();
        lowest = std::min(lowest, wheelSpeedsOf(sim, 0).right);
    }
    QVERIFY2(std::abs(wheelSpeedsOf(sim, 0).right - 20.0) < 1.0,
             qPrintable(QString("%1 rad/s 0.3 s after").arg(wheelSpeedsOf(sim, 0).right)));
    QVERIFY2(lowest > 20.0 * 0.75, qPrintable(QString("undershoot to %1 rad/s").arg(lowest)));
    while (sim.state().time < 2.0) sim.step();
    QVERIFY(std::abs(wheelSpeedsOf(sim, 0).right - 20.0) < 1e-4);
}

void TestSpeedController::samplesAtItsOwnRate() {
    // 300 Hz with 1 ms steps: sample k at the first step at or after k/300 s,
    // i.e. steps 0, 4, 7, 10, 14, 17, 20...: the voltages change only there
    // (a small target: below saturation every sample changes them).
    Scene scene = loneRobot();
    scene.robots[0].params.speed_controller.rate = 300.0;
    Simulation sim(scene);
    sim.setWheelSpeeds(0, {2.0, 2.0});
    std::vector<std::int64_t> changes;
    Voltages last{-1.0, -1.0};
    for (int s = 0; s < 21; ++s) {
        const std::int64_t step = sim.state().step;
        sim.step();
        if (sim.state().voltages[0].right != last.right) changes.push_back(step);
        last = sim.state().voltages[0];
    }
    QCOMPARE(changes, (std::vector<std::int64_t>{0, 4, 7, 10, 14, 17, 20}));
    // A loop started at t = 3 ms samples first at 4 ms (its clock: multiples of 1/300 s).
    Simulation late(scene);
    for (int s = 0; s < 3; ++s) late.step();
    late.setWheelSpeeds(0, {20.0, 20.0});
    late.step();
    QCOMPARE(late.state().voltages[0].right, 0.0);
    late.step();
    QVERIFY(late.state().voltages[0].right > 0.0);
}

void TestSpeedController::voltagesTurnTheLoopOff() {
    Simulation sim(loneRobot());
    sim.setWheelSpeeds(0, {20.0, 20.0});
    for (int s = 0; s < 100; ++s) sim.step();
    QVERIFY(sim.state().speedLoops[0].active);
    sim.setVoltages(0, {1.0, -1.0});
    QVERIFY(!sim.state().speedLoops[0].active);
    for (int s = 0; s < 100; ++s) sim.step();
    QCOMPARE(sim.state().voltages[0].right, 1.0);
    QCOMPARE(sim.state().voltages[0].left, -1.0);
    // Back on: the integrators start from zero.
    sim.setWheelSpeeds(0, {5.0, 5.0});
    QCOMPARE(sim.state().speedLoops[0].right.integral, 0.0);
}

void TestSpeedController::longStepsAgreeWithSteps() {
    // The scene's own wheel-speed commands, run by step() and by advanceTo
    // (long steps where nothing can touch): the loop samples at the same
    // steps, so the states agree to rounding.
    Scene scene = loneRobot();
    VoltageCommand c;
    c.robot = 0;
    c.wheelSpeeds = true;
    c.speeds = {20.0, 10.0};
    scene.commands.push_back(c);
    c.t = 0.4;
    c.speeds = {-5.0, 15.0};
    scene.commands.push_back(c);
    Simulation a(scene), b(scene);
    for (int s = 0; s < 1000; ++s) a.step();
    b.advanceTo(1000);
    QCOMPARE(b.state().step, a.state().step);
    QVERIFY(std::abs(a.state().robots[0].x - b.state().robots[0].x) < 1e-12);
    QVERIFY(std::abs(a.state().robots[0].theta - b.state().robots[0].theta) < 1e-12);
    QVERIFY(std::abs(a.state().robots[0].v - b.state().robots[0].v) < 1e-12);
    QCOMPARE(b.state().voltages[0].right, a.state().voltages[0].right);
}

void TestSpeedController::deterministic() {
    Scene scene = loneRobot();
    scene.robots[0].params.speed_controller.encoder_counts = 360;
    auto run = [&scene] {
        Simulation sim(scene);
        sim.setWheelSpeeds(0, {33.0, -7.0});
        sim.advanceTo(700);
        return hashState(sim.state());
    };
    QCOMPARE(run(), run());
}

void TestSpeedController::offFieldRobotIsLeftAlone() {
    // A ball rolls through where a robot stands: with the robot on the field
    // it bounces; off the field it rolls on through, and the robot stays put
    // at rest, deaf to commands, until it comes back.
    Scene scene;
    scene.field = makeRectangularField(1.5, 1.3);
    RobotSpec robot;
    robot.name = "yellow0";
    scene.robots.push_back(robot);
    scene.ball.x = -0.3;
    scene.ball.vx = 1.0;
    Simulation on(scene), off(scene);
    off.setOnField(0, false);
    off.setWheelSpeeds(0, {30.0, 30.0});
    off.setVoltages(0, {5.0, 5.0});
    for (int s = 0; s < 500; ++s) on.step(), off.step();
    QVERIFY(on.state().ball.vx < 0.0);   // bounced back
    QVERIFY(off.state().ball.x > 0.1);   // passed through
    QCOMPARE(off.state().robots[0].x, 0.0);
    QCOMPARE(off.state().robots[0].v, 0.0);
    QCOMPARE(off.state().voltages[0].right, 0.0);
    QVERIFY(!off.state().speedLoops[0].active);
    off.setOnField(0, true);
    off.setWheelSpeeds(0, {30.0, 30.0});
    for (int s = 0; s < 200; ++s) off.step();
    QVERIFY(off.state().robots[0].v > 0.3);
}

void TestSpeedController::sceneFileParametersAndCommands() {
    const QByteArray json = R"({
        "robot_defaults": {"speed_controller": {"rate": 500, "kp": 0.4, "ki": 8, "encoder_counts": 1024}},
        "robots": [
            {"name": "a", "team": "yellow", "x": -0.3},
            {"name": "b", "team": "blue", "x": 0.3, "params": {"speed_controller": {"rate": 100}}}
        ],
        "commands": [
            {"t": 0, "robot": "a", "right_speed": 20, "left_speed": 10},
            {"t": 0.5, "robot": "a", "right": 1, "left": 1}
        ]
    })";
    QString error;
    const std::optional<Scene> scene = parseScene(json, &error);
    QVERIFY2(scene, qPrintable(error));
    QCOMPARE(scene->robots[0].params.speed_controller.rate, 500.0);
    QCOMPARE(scene->robots[0].params.speed_controller.encoder_counts, 1024);
    QCOMPARE(scene->robots[1].params.speed_controller.rate, 100.0);
    QCOMPARE(scene->robots[1].params.speed_controller.kp, 0.4);  // the defaults' other keys stay
    QVERIFY(scene->commands[0].wheelSpeeds);
    QCOMPARE(scene->commands[0].speeds.left, 10.0);
    QVERIFY(!scene->commands[1].wheelSpeeds);
    // Written and read back: the same scene.
    const std::optional<Scene> again = parseScene(sceneToJson(*scene), &error);
    QVERIFY2(again, qPrintable(error));
    QCOMPARE(again->robots[1].params.speed_controller.rate, 100.0);
    QVERIFY(again->commands[0].wheelSpeeds);
    QCOMPARE(again->commands[0].speeds.right, 20.0);
    // Played: robot a follows 20/10 rad/s until 0.5 s.
    Simulation sim(*scene);
    sim.advanceTo(400);
    QVERIFY(sim.state().speedLoops[0].active);
    QVERIFY(std::abs(wheelSpeedsOf(sim, 0).right - 20.0) < 0.5);
    sim.advanceTo(600);
    QVERIFY(!sim.state().speedLoops[0].active);
}

void TestSpeedController::sceneFileErrors() {
    const struct {
        const char* json;
        const char* where;
    } cases[] = {
        {R"({"robot_defaults": {"speed_controller": {"rate": 0}}})", "robot_defaults.speed_controller.rate"},
        {R"({"robot_defaults": {"speed_controller": {"kp": -1}}})", "robot_defaults.speed_controller.kp"},
        {R"({"robot_defaults": {"speed_controller": {"encoder_counts": 2.5}}})",
         "robot_defaults.speed_controller.encoder_counts"},
        {R"({"robot_defaults": {"speed_controller": {"gain": 1}}})", "gain"},
        {R"({"robots": [{"name": "a", "team": "yellow"}], "commands": [{"t": 0, "robot": "a", "right_speed": 2000}]})",
         "commands[0].right_speed"},
        {R"({"robots": [{"name": "a", "team": "yellow"}], "commands": [{"t": 0, "robot": "a", "right": 1, "left_speed": 2}]})",
         "commands[0]"},
    };
    for (const auto& c : cases) {
        QString error;
        QVERIFY2(!parseScene(c.json, &error), c.json);
        QVERIFY2(error.contains(c.where), qPrintable(error));
    }
}

QTEST_GUILESS_MAIN(TestSpeedController)
#include "test_speed_controller.moc"
