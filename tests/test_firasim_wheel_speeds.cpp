// A robot driven through FIRASim's interface tracks the wheel speeds it is
// sent, through the engine's on-board speed loop (speed_controller.h): the
// vision shows v = r (w_r + w_l) / 2 once the loop has settled, as the
// ground truth does. Lockstep (--firasim-sync), so the result is exact.
#include <QtTest>

#include <cmath>

#include "firasim_client.h"

using namespace vssim;
using namespace vssim::test;

class TestFirasimWheelSpeeds : public QObject {
    Q_OBJECT
private slots:
    void tracksWheelSpeeds();
};

void TestFirasimWheelSpeeds::tracksWheelSpeeds() {
    // Through the engine's speed loop: v = r (w_r + w_l) / 2 once settled,
    // omega = r (w_r - w_l) / b. Needs the engine's WheelSpeeds handling.
    const Scene scene = kickoff();
    const double r = scene.robots[0].params.right.wheel_radius;
    QCOMPARE(r, 0.025);
    Fira f(scene, true);
    QVERIFY(f.next());
    const double w = 15.0;  // rad/s: 0.375 m/s
    Environment env;
    for (int k = 0; k < 60; ++k) {  // 1 s
        Packet p;
        command(p, true, 0, w, w);
        env = f.step(p);
    }
    const fira_message::Robot* y0 = findRobot(env, true, 0);
    const double v = std::hypot(y0->vx(), y0->vy());
    const double expected = r * (w + w) / 2.0;
    qInfo("yellow 0 after 1 s at %g rad/s per wheel: v = %.4f m/s (r (w_r + w_l)/2 = %.4f m/s)", w, v, expected);
    QVERIFY2(std::abs(v - expected) < 0.05 * expected, qPrintable(QString::number(v)));
    // Blue, never commanded, has not moved.
    QCOMPARE(std::hypot(findRobot(env, false, 0)->vx(), findRobot(env, false, 0)->vy()), 0.0);
    // The vision is the ground truth.
    const WorldState truth = f.truthAt(env.step());
    QCOMPARE(y0->x(), truth.robots[0].x);
    QCOMPARE(v, std::abs(truth.robots[0].v));

    // Turning: w_r = 15, w_l = 5 rad/s for 1 s: v = r (w_r + w_l) / 2 = 0.25 m/s,
    // omega = r (w_r - w_l) / b = 3.85 rad/s (a circle of 6.5 cm, clear of the others).
    const double b = scene.robots[0].params.wheel_base;
    for (int k = 0; k < 60; ++k) {
        Packet p;
        command(p, true, 0, 15.0, 5.0);
        env = f.step(p);
    }
    const fira_message::Robot* turning = findRobot(env, true, 0);
    const double vTurn = std::hypot(turning->vx(), turning->vy());
    qInfo("turning: v = %.4f m/s (expected %.4f), omega = %.4f rad/s (expected %.4f)", vTurn, r * 10.0,
          turning->vorientation(), r * 10.0 / b);
    QVERIFY2(std::abs(vTurn - r * 10.0) < 0.05 * r * 10.0, qPrintable(QString::number(vTurn)));
    QVERIFY2(std::abs(turning->vorientation() - r * 10.0 / b) < 0.05 * r * 10.0 / b,
             qPrintable(QString::number(turning->vorientation())));
}

QTEST_MAIN(TestFirasimWheelSpeeds)
#include "test_firasim_wheel_speeds.moc"
