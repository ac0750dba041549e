// Driving by hand (ui/): the stick-to-voltage mappings and the dead zone,
// the keyboard's key combinations (and that they turn the simulated robot
// the way the keys say), the on-screen joystick's mouse handling, and that
// the SDL gamepad reader survives a machine with no gamepad.
#include <QtTest>

#include <QSignalSpy>
#include <cmath>

#include "drive_mapping.h"
#include "gamepad_input.h"
#include "joystick_widget.h"
#include "keyboard_driver.h"
#include "test_support.h"
#include "vssim/world.h"

using namespace vssim;

namespace {

constexpr double kMax = 7.4;  // V, the default max_voltage
constexpr double kTol = 1e-12;

bool near(double a, double b, double tol = kTol) { return std::abs(a - b) <= tol; }

KeyboardDriver holding(std::initializer_list<int> keys) {
    KeyboardDriver k;
    for (int key : keys) k.handleKey(key, true);
    return k;
}

}  // namespace

class TestDriveInput : public QObject {
    Q_OBJECT
private slots:
    // --- drive_mapping -------------------------------------------------
    void arcadeStraightAhead() {
        const Voltages v = stickToVoltages(0.0, 1.0, DriveMapping::Arcade, kMax);
        QCOMPARE(v.right, kMax);
        QCOMPARE(v.left, kMax);
        const Voltages half = stickToVoltages(0.0, 0.5, DriveMapping::Arcade, kMax);
        QVERIFY(near(half.right, 0.5 * kMax) && near(half.left, 0.5 * kMax));
        const Voltages back = stickToVoltages(0.0, -1.0, DriveMapping::Arcade, kMax);
        QCOMPARE(back.right, -kMax);
        QCOMPARE(back.left, -kMax);
        const Voltages zero = stickToVoltages(0.0, 0.0, DriveMapping::Arcade, kMax);
        QCOMPARE(zero.right, 0.0);
        QCOMPARE(zero.left, 0.0);
    }

    void arcadeFullTurnSpinsInPlace() {
        // x > 0: clockwise, right wheel backwards.
        const Voltages cw = stickToVoltages(1.0, 0.0, DriveMapping::Arcade, kMax);
        QCOMPARE(cw.right, -kMax);
        QCOMPARE(cw.left, kMax);
        const Voltages ccw = stickToVoltages(-1.0, 0.0, DriveMapping::Arcade, kMax);
        QCOMPARE(ccw.right, kMax);
        QCOMPARE(ccw.left, -kMax);
    }

    void arcadeDiagonalStaysWithinMaxAndKeepsRatio() {
        for (double x = -1.0; x <= 1.0001; x += 0.125) {
            for (double y = -1.0; y <= 1.0001; y += 0.125) {
                const Voltages v = stickToVoltages(x, y, DriveMapping::Arcade, kMax);
                QVERIFY2(std::abs(v.right) <= kMax + 1e-12 && std::abs(v.left) <= kMax + 1e-12,
                         qPrintable(QStringLiteral("x=%1 y=%2").arg(x).arg(y)));
                // Unscaled mix: right = y - x, left = y + x; the output is a
                // positive multiple of it (same direction, same ratio).
                const double r0 = y - x, l0 = y + x;
                QVERIFY(near(v.right * l0, v.left * r0, 1e-9));
                QVERIFY(v.right * r0 >= 0.0 && v.left * l0 >= 0.0);
                // A scaled mix uses the whole range on its larger side.
                if (std::abs(x) + std::abs(y) > 1.0)
                    QVERIFY(near(std::max(std::abs(v.right), std::abs(v.left)), kMax, 1e-12));
            }
        }
        // Full forward + full right: the right wheel stops, the left runs flat out.
        const Voltages fr = stickToVoltages(1.0, 1.0, DriveMapping::Arcade, kMax);
        QVERIFY(near(fr.right, 0.0));
        QVERIFY(near(fr.left, kMax));
        // Forward 1, turn 0.5: right 0.5 / 1.5, left 1.5 / 1.5 of max.
        const Voltages arc = stickToVoltages(0.5, 1.0, DriveMapping::Arcade, kMax);
        QVERIFY(near(arc.right, kMax / 3.0));
        QVERIFY(near(arc.left, kMax));
        // Inside the diamond |x| + |y| <= 1 nothing is scaled.
        const Voltages small = stickToVoltages(0.25, 0.5, DriveMapping::Arcade, kMax);
        QVERIFY(near(small.right, 0.25 * kMax));
        QVERIFY(near(small.left, 0.75 * kMax));
    }

    void arcadeClampsInputs() {
        const Voltages v = stickToVoltages(0.0, 3.0, DriveMapping::Arcade, kMax);
        QCOMPARE(v.right, kMax);
        QCOMPARE(v.left, kMax);
        const Voltages n = stickToVoltages(std::nan(""), std::nan(""), DriveMapping::Arcade, kMax);
        QCOMPARE(n.right, 0.0);
        QCOMPARE(n.left, 0.0);
    }

    void tankMapsEachWheelIndependently() {
        // y: left stick -> left wheel; x: right stick -> right wheel.
        const Voltages a = stickToVoltages(0.0, 1.0, DriveMapping::Tank, kMax);
        QCOMPARE(a.left, kMax);
        QCOMPARE(a.right, 0.0);
        const Voltages b = stickToVoltages(-0.5, 0.0, DriveMapping::Tank, kMax);
        QCOMPARE(b.left, 0.0);
        QCOMPARE(b.right, -0.5 * kMax);
        const Voltages c = stickToVoltages(1.0, 1.0, DriveMapping::Tank, kMax);  // no mixing, no scaling
        QCOMPARE(c.left, kMax);
        QCOMPARE(c.right, kMax);
        const Voltages d = stickToVoltages(0.3, -0.8, DriveMapping::Tank, 6.0);
        QVERIFY(near(d.left, -0.8 * 6.0));
        QVERIFY(near(d.right, 0.3 * 6.0));
        const Voltages e = stickToVoltages(-2.0, 2.0, DriveMapping::Tank, kMax);  // clamped
        QCOMPARE(e.left, kMax);
        QCOMPARE(e.right, -kMax);
    }

    void wheelSpeedsAreFractionsOfTheFreeSpeed() {
        // Full stick ahead: both wheels at the free speed; half back, half of it backwards.
        const WheelSpeeds full = voltagesToWheelSpeeds({7.4, 7.4}, 7.4, 70.0);
        QCOMPARE(full.right, 70.0);
        QCOMPARE(full.left, 70.0);
        const WheelSpeeds half = voltagesToWheelSpeeds({-3.7, 1.85}, 7.4, 70.0);
        QCOMPARE(half.right, -35.0);
        QCOMPARE(half.left, 17.5);
        // Beyond the battery: clamped to the free speed; NaN and a bad maximum: 0.
        QCOMPARE(voltagesToWheelSpeeds({100.0, 0.0}, 7.4, 70.0).right, 70.0);
        QCOMPARE(voltagesToWheelSpeeds({std::nan(""), 1.0}, 7.4, 70.0).right, 0.0);
        QCOMPARE(voltagesToWheelSpeeds({1.0, 1.0}, 0.0, 70.0).left, 0.0);
    }

    void deadzone() {
        const double dz = 0.15;
        QCOMPARE(applyDeadzone(0.0, dz), 0.0);
        QCOMPARE(applyDeadzone(0.1, dz), 0.0);
        QCOMPARE(applyDeadzone(-0.15, dz), 0.0);
        QCOMPARE(applyDeadzone(1.0, dz), 1.0);
        QCOMPARE(applyDeadzone(-1.0, dz), -1.0);
        QCOMPARE(applyDeadzone(1.5, dz), 1.0);
        QVERIFY(near(applyDeadzone(0.575, dz), 0.5));  // half way through the live range
        QVERIFY(near(applyDeadzone(-0.575, dz), -0.5));
        // Continuous at the edge: just beyond it, just above zero.
        QVERIFY(applyDeadzone(dz + 1e-9, dz) > 0.0);
        QVERIFY(applyDeadzone(dz + 1e-9, dz) < 1e-8);
        // Monotonic, odd, within [-1, 1], and without jumps.
        double previous = applyDeadzone(-1.0, dz);
        const double step = 1e-3;
        for (double v = -1.0 + step; v <= 1.0; v += step) {
            const double out = applyDeadzone(v, dz);
            QVERIFY(out >= previous);
            QVERIFY(out - previous <= step / (1.0 - dz) + 1e-12);  // Lipschitz: no jump
            QVERIFY(std::abs(out) <= 1.0);
            QVERIFY(near(applyDeadzone(-v, dz), -out));
            previous = out;
        }
        QCOMPARE(applyDeadzone(0.4, 0.0), 0.4);  // no dead zone: identity
        QCOMPARE(applyDeadzone(0.9, 1.0), 0.0);  // all dead
    }

    // --- keyboard_driver -----------------------------------------------
    void keyboardRecognisesDriveKeys() {
        KeyboardDriver k;
        QVERIFY(!k.active());
        for (int key :
             {Qt::Key_W, Qt::Key_A, Qt::Key_S, Qt::Key_D, Qt::Key_Up, Qt::Key_Down, Qt::Key_Left, Qt::Key_Right})
            QVERIFY(k.handleKey(key, true));
        QVERIFY(k.active());
        for (int key : {Qt::Key_Q, Qt::Key_E, Qt::Key_Space, Qt::Key_Escape, Qt::Key_Shift})
            QVERIFY(!k.handleKey(key, true));
        k.releaseAll();
        QVERIFY(!k.active());
        QVERIFY(!k.handleKey(Qt::Key_Space, true));
        QVERIFY(!k.active());  // a non-drive key is not held
        const Voltages idle = k.voltages(kMax);
        QCOMPARE(idle.right, 0.0);
        QCOMPARE(idle.left, 0.0);
    }

    void keyboardForwardAndBack() {
        const double f = 0.6 * kMax;
        for (int key : {Qt::Key_W, Qt::Key_Up}) {
            const Voltages v = holding({key}).voltages(kMax);  // default fraction 0.6
            QVERIFY(near(v.right, f) && near(v.left, f));
        }
        for (int key : {Qt::Key_S, Qt::Key_Down}) {
            const Voltages v = holding({key}).voltages(kMax);
            QVERIFY(near(v.right, -f) && near(v.left, -f));
        }
        const Voltages full = holding({Qt::Key_W}).voltages(kMax, 1.0);
        QCOMPARE(full.right, kMax);
        QCOMPARE(full.left, kMax);
        const Voltages over = holding({Qt::Key_W}).voltages(kMax, 2.0);  // fraction clamped
        QCOMPARE(over.right, kMax);
    }

    void keyboardTurnInPlace() {
        const double f = 0.6 * kMax;
        for (int key : {Qt::Key_A, Qt::Key_Left}) {  // counter-clockwise
            const Voltages v = holding({key}).voltages(kMax);
            QVERIFY(near(v.right, f) && near(v.left, -f));
        }
        for (int key : {Qt::Key_D, Qt::Key_Right}) {  // clockwise
            const Voltages v = holding({key}).voltages(kMax);
            QVERIFY(near(v.right, -f) && near(v.left, f));
        }
    }

    void keyboardCombinations() {
        const double f = 0.6 * kMax;
        // W + A: an arc to the left, left wheel slower, both forward.
        const Voltages wa = holding({Qt::Key_W, Qt::Key_A}).voltages(kMax);
        QVERIFY(near(wa.right, f));
        QVERIFY(near(wa.left, f / 3.0));
        QVERIFY(wa.right > wa.left && wa.left > 0.0);
        // W + D mirrors it.
        const Voltages wd = holding({Qt::Key_Up, Qt::Key_Right}).voltages(kMax);
        QVERIFY(near(wd.left, f) && near(wd.right, f / 3.0));
        // S + D: backwards, heading still rotating clockwise (right - left < 0).
        const Voltages sd = holding({Qt::Key_S, Qt::Key_D}).voltages(kMax);
        QVERIFY(near(sd.right, -f) && near(sd.left, -f / 3.0));
        QVERIFY(sd.right - sd.left < 0.0);
        // Opposite keys cancel.
        const Voltages ws = holding({Qt::Key_W, Qt::Key_S}).voltages(kMax);
        QCOMPARE(ws.right, 0.0);
        QCOMPARE(ws.left, 0.0);
        QVERIFY(holding({Qt::Key_W, Qt::Key_S}).active());
        const Voltages ad = holding({Qt::Key_A, Qt::Key_D}).voltages(kMax);
        QCOMPARE(ad.right, 0.0);
        QCOMPARE(ad.left, 0.0);
        // W + S + A: forward cancelled, a pure spin to the left remains.
        const Voltages wsa = holding({Qt::Key_W, Qt::Key_S, Qt::Key_A}).voltages(kMax);
        QVERIFY(near(wsa.right, f) && near(wsa.left, -f));
        // Every combination stays within fraction * max.
        const int keys[] = {Qt::Key_W, Qt::Key_A, Qt::Key_S, Qt::Key_D};
        for (int mask = 0; mask < 16; ++mask) {
            KeyboardDriver k;
            for (int i = 0; i < 4; ++i)
                if (mask & (1 << i)) k.handleKey(keys[i], true);
            const Voltages v = k.voltages(kMax);
            QVERIFY(std::abs(v.right) <= f + 1e-12 && std::abs(v.left) <= f + 1e-12);
            QCOMPARE(k.active(), mask != 0);
        }
    }

    void keyboardReleases() {
        KeyboardDriver k;
        k.handleKey(Qt::Key_W, true);
        k.handleKey(Qt::Key_W, true);  // auto-repeat: harmless
        k.handleKey(Qt::Key_Up, true);
        k.handleKey(Qt::Key_W, false);  // Up still held: still forward
        QVERIFY(k.active());
        QVERIFY(k.voltages(kMax).right > 0.0);
        k.handleKey(Qt::Key_Up, false);
        QVERIFY(!k.active());
        QCOMPARE(k.voltages(kMax).right, 0.0);

        k.handleKey(Qt::Key_W, true);
        k.handleKey(Qt::Key_A, true);
        k.handleKey(Qt::Key_A, false);  // back to straight ahead
        const Voltages straight = k.voltages(kMax);
        QVERIFY(near(straight.right, straight.left) && straight.right > 0.0);
        k.handleKey(Qt::Key_D, true);
        k.releaseAll();
        QVERIFY(!k.active());
        const Voltages none = k.voltages(kMax);
        QCOMPARE(none.right, 0.0);
        QCOMPARE(none.left, 0.0);
    }

    // W + A, sent to the simulated robot, turns it left: counter-clockwise,
    // curving towards +y when it starts facing +x.
    void keyboardTurnsTheRobotTheWayTheKeysSay() {
        auto drive = [](std::initializer_list<int> keys) {
            Scene scene;
            scene.robots.push_back(test::robotAt("r", 0.0, 0.0, 0.0));
            scene.ball.x = 0.6;  // far out of the way
            scene.ball.y = -0.5;
            Simulation sim(scene);
            sim.setVoltages(0, holding(keys).voltages(kMax));
            sim.advanceTo(300);  // 0.3 s
            return sim.state().robots[0];
        };
        const RobotState left = drive({Qt::Key_W, Qt::Key_A});
        QVERIFY2(left.theta > 0.05, qPrintable(QString::number(left.theta)));
        QVERIFY(left.omega > 0.0);
        QVERIFY(left.x > 0.0 && left.y > 0.0);
        const RobotState right = drive({Qt::Key_W, Qt::Key_D});
        QVERIFY(right.theta < -0.05 && right.omega < 0.0 && right.y < 0.0);
        const RobotState spin = drive({Qt::Key_A});
        QVERIFY(spin.omega > 0.0);
        QVERIFY(std::hypot(spin.x, spin.y) < 0.01);  // in place
        const RobotState ahead = drive({Qt::Key_W});
        QVERIFY(ahead.x > 0.05 && ahead.v > 0.0);
    }

    // --- joystick_widget -----------------------------------------------
    void joystickDragEmitsNormalisedPositions() {
        JoystickWidget w;
        QVERIFY(w.minimumSizeHint().width() >= 120 && w.minimumSizeHint().height() >= 120);
        w.resize(200, 200);
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QSignalSpy spy(&w, &JoystickWidget::moved);
        const QPointF c = w.centre();
        const double r = w.travelRadius();
        QVERIFY(r > 20.0);
        auto at = [&](double dx, double dy) { return (c + QPointF(dx, dy)).toPoint(); };
        const double tol = 1.0 / r;  // one pixel

        // Press on the centre: the knob is there, no deflection.
        QTest::mousePress(&w, Qt::LeftButton, {}, at(0, 0));
        QVERIFY(std::hypot(w.position().x(), w.position().y()) <= tol);

        // Half right.
        QTest::mouseMove(&w, at(r / 2, 0));
        QVERIFY(!spy.isEmpty());
        QVERIFY(near(spy.last().at(0).toDouble(), 0.5, tol));
        QVERIFY(near(spy.last().at(1).toDouble(), 0.0, tol));
        // Screen up is positive y.
        QTest::mouseMove(&w, at(0, -0.75 * r));
        QVERIFY(near(spy.last().at(0).toDouble(), 0.0, tol));
        QVERIFY(near(spy.last().at(1).toDouble(), 0.75, tol));
        QCOMPARE(w.position(), QPointF(spy.last().at(0).toDouble(), spy.last().at(1).toDouble()));
        // Down-left.
        QTest::mouseMove(&w, at(-0.3 * r, 0.4 * r));
        QVERIFY(near(spy.last().at(0).toDouble(), -0.3, tol));
        QVERIFY(near(spy.last().at(1).toDouble(), -0.4, tol));

        // Beyond the rim (even outside the widget): clipped to the unit disc,
        // direction kept.
        QTest::mouseMove(&w, at(3 * r, 0));
        QVERIFY(near(spy.last().at(0).toDouble(), 1.0, 1e-12));
        QVERIFY(near(spy.last().at(1).toDouble(), 0.0, tol));
        QTest::mouseMove(&w, at(2 * r, -2 * r));
        const double x = spy.last().at(0).toDouble(), y = spy.last().at(1).toDouble();
        QVERIFY(near(std::hypot(x, y), 1.0, 1e-12));
        QVERIFY(near(x, std::sqrt(0.5), tol) && near(y, std::sqrt(0.5), tol));

        // Release: back to the centre, with a moved(0, 0).
        QTest::mouseRelease(&w, Qt::LeftButton, {}, at(2 * r, -2 * r));
        QCOMPARE(spy.last().at(0).toDouble(), 0.0);
        QCOMPARE(spy.last().at(1).toDouble(), 0.0);
        QCOMPARE(w.position(), QPointF(0.0, 0.0));

        // Moving without a button does nothing.
        const int count = spy.count();
        QTest::mouseMove(&w, at(r / 2, r / 2));
        QCOMPARE(spy.count(), count);
        QCOMPARE(w.position(), QPointF(0.0, 0.0));

        // A press away from the centre jumps the knob there at once.
        QTest::mousePress(&w, Qt::LeftButton, {}, at(0, r));
        QCOMPARE(spy.count(), count + 1);
        QVERIFY(near(spy.last().at(1).toDouble(), -1.0, tol));
        QTest::mouseRelease(&w, Qt::LeftButton, {}, at(0, r));
        QCOMPARE(spy.last().at(0).toDouble(), 0.0);
        QCOMPARE(spy.last().at(1).toDouble(), 0.0);

        w.grab();  // paints without complaint
    }

    void joystickIgnoresOtherButtons() {
        JoystickWidget w;
        w.resize(150, 150);
        QSignalSpy spy(&w, &JoystickWidget::moved);
        QTest::mousePress(&w, Qt::RightButton, {}, QPoint(140, 75));
        QTest::mouseRelease(&w, Qt::RightButton, {}, QPoint(140, 75));
        QCOMPARE(spy.count(), 0);
        QCOMPARE(w.position(), QPointF(0.0, 0.0));
    }

    // --- gamepad_input -------------------------------------------------
    // No gamepad here (CI): construct, poll, stop, destroy. With one
    // plugged in, the same must hold except that it may connect.
    void gamepadWithoutDevices() {
        {
            GamepadInput pad;
            QVERIFY(!pad.connected());  // nothing is opened before start()
            QVERIFY(pad.name().isEmpty());
            if (!pad.available()) QVERIFY(!pad.errorString().isEmpty());
            QSignalSpy connected(&pad, &GamepadInput::connectedChanged);
            pad.start();
            QTest::qWait(60);  // a few polls
            pad.stop();
            pad.stop();
            pad.start();
            QTest::qWait(20);
            QCOMPARE(pad.connected(), !pad.name().isEmpty());
            if (!pad.connected()) QCOMPARE(connected.count(), 0);
            if (!pad.available()) QVERIFY(!pad.connected());
        }
        // Again (SDL shut down and initialised again), and two at once.
        GamepadInput a;
        GamepadInput b;
        QCOMPARE(a.available(), b.available());
        a.start();
        b.start();
        QTest::qWait(20);
        a.stop();
    }
};

QTEST_MAIN(TestDriveInput)
#include "test_drive_input.moc"
