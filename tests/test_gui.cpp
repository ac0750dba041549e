// The desktop app under a real X server (xvfb-run, xcb platform: the field
// view is a QOpenGLWidget): dragging a robot with the mouse moves it in the
// engine and undo puts it back; keys drive the selected robot; manual control
// overrides TCP for that robot only and letting go hands it back; pause,
// step, reset; open/save round trip; a screenshot shows the robots where the
// snapshot says. VSSIM_SCREENSHOT=FILE saves the window's screenshot there.
#include <QAction>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QFileInfo>
#include <QLabel>
#include <QPointer>
#include <QPushButton>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QtTest>
#include <cmath>
#include <map>
#include <tuple>

#include "vssim/camera/camera_colours.h"
#include "field_view.h"
#include "io/scene_io.h"
#include "main_window.h"
#include "net/protocol_client.h"
#include "remote_window.h"
#include "scoreboard.h"
#include "vssim/game/pitch.h"

using namespace vssim;

namespace {

// The built-in kick-off as it is: a match of the built-in team against itself.
Scene kickoffMatch() {
    QString error;
    std::optional<Scene> scene = loadSceneFile(":/scenes/kickoff_3v3.json", &error);
    if (!scene) qFatal("%s", qPrintable(error));
    return *scene;
}

// The kick-off's bodies as plain physics: nothing moves unless the test
// moves it (no referee, both teams remote, no commands).
Scene kickoff() {
    Scene scene = kickoffMatch();
    scene.commands.clear();
    scene.game = GameSettings{};
    return scene;
}

ServerSettings anyPort() {
    ServerSettings s;
    s.port = 0;
    return s;
}

QAction* action(QMainWindow& window, const char* name) { return window.findChild<QAction*>(name); }

// Waits until the engine's snapshot satisfies `pred`.
template <typename Pred>
bool waitFor(MainWindow& w, Pred pred, int timeoutMs = 5000) {
    QElapsedTimer t;
    t.start();
    while (t.elapsed() < timeoutMs) {
        const auto s = w.session().latest();
        if (s && pred(*s)) return true;
        QTest::qWait(10);
    }
    return false;
}

QPoint at(FieldView& view, double x, double y) { return view.toWidget(x, y).toPoint(); }

void moveMouse(FieldView& view, QPoint p) {
    QMouseEvent move(QEvent::MouseMove, QPointF(p), view.mapToGlobal(QPointF(p)), Qt::NoButton, Qt::LeftButton,
                     Qt::NoModifier);
    QApplication::sendEvent(&view, &move);
}

}  // namespace

class TestGui : public QObject {
    Q_OBJECT
private slots:
    void dragRobotMovesItAndUndoPutsItBack() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        action(w, "action.playPause")->trigger();  // pause: only the drag moves it
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        FieldView& view = w.fieldView();
        const RobotState start = w.session().latest()->robots[0];  // yellow0 at (-0.68, 0)
        QTest::mousePress(&view, Qt::LeftButton, {}, at(view, start.x, start.y));
        QCOMPARE(view.selectedRobot(), 0);
        for (int k = 1; k <= 10; ++k) moveMouse(view, at(view, start.x + 0.03 * k, start.y + 0.02 * k));
        QTest::mouseRelease(&view, Qt::LeftButton, {}, at(view, start.x + 0.3, start.y + 0.2));
        // Within a pixel or so of where it was dropped.
        const double pixel = 1.0 / (view.toWidget(1, 0).x() - view.toWidget(0, 0).x());
        QVERIFY2(waitFor(w,
                         [&](const Snapshot& s) {
                             return std::hypot(s.robots[0].x - (start.x + 0.3), s.robots[0].y - (start.y + 0.2)) <
                                    1.5 * pixel;
                         }),
                 qPrintable(QString("robot at %1, %2")
                                .arg(w.session().latest()->robots[0].x)
                                .arg(w.session().latest()->robots[0].y)));
        QCOMPARE(w.session().latest()->robots[0].theta, start.theta);
        // Undo puts it back exactly; redo moves it again.
        const RobotState dropped = w.session().latest()->robots[0];
        action(w, "action.undo")->trigger();
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.robots[0].x == start.x && s.robots[0].y == start.y; }));
        action(w, "action.redo")->trigger();
        QVERIFY(
            waitFor(w, [&](const Snapshot& s) { return s.robots[0].x == dropped.x && s.robots[0].y == dropped.y; }));
        action(w, "action.undo")->trigger();
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.robots[0].x == start.x; }));
        // The view draws (and picks robots from) the snapshot of its last refresh: wait for it too.
        QTRY_VERIFY(view.snapshot() && view.snapshot()->robots[0].x == start.x);
        // The wheel turns the robot under the cursor by 15 degrees a notch.
        const QPointF p(at(view, start.x, start.y));
        QWheelEvent wheel(p, view.mapToGlobal(p), {}, QPoint(0, 120), Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase,
                          false);
        QApplication::sendEvent(&view, &wheel);
        QVERIFY(waitFor(w, [&](const Snapshot& s) {
            return std::abs(s.robots[0].theta - (start.theta + FieldView::kRotateStep)) < 1e-12;
        }));
        // Shift-drag from the ball: a velocity of 10 (m/s)/m times the arrow.
        const BallState ball = w.session().latest()->ball;
        QTest::mousePress(&view, Qt::LeftButton, Qt::ShiftModifier, at(view, ball.x, ball.y));
        QTest::mouseRelease(&view, Qt::LeftButton, Qt::ShiftModifier, at(view, ball.x + 0.1, ball.y));
        QVERIFY(waitFor(w, [&](const Snapshot& s) {
            return std::abs(s.ball.vx - 1.0) < 20 * pixel && std::abs(s.ball.vy) < 20 * pixel;
        }));
    }

    void doubleClickPutsTheBallThere() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        FieldView& view = w.fieldView();
        QTRY_VERIFY(view.snapshot() != nullptr);
        const BallState before = w.session().latest()->ball;
        const double pixel = 1.0 / (view.toWidget(1, 0).x() - view.toWidget(0, 0).x());
        QTest::mouseDClick(&view, Qt::LeftButton, {}, at(view, 0.3, -0.2));
        QVERIFY(waitFor(w, [&](const Snapshot& s) {
            return std::hypot(s.ball.x - 0.3, s.ball.y + 0.2) < 1.5 * pixel && s.ball.vx == 0.0 && s.ball.vy == 0.0;
        }));
        // Off the floor (behind a goal's back wall): the view resets, the ball stays.
        const BallState placed = w.session().latest()->ball;
        QTest::mouseDClick(&view, Qt::LeftButton, {}, at(view, 0.95, 0.6));
        QTest::qWait(100);
        QCOMPARE(w.session().latest()->ball.x, placed.x);
        // Undo puts it back.
        action(w, "action.undo")->trigger();
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.ball.x == before.x && s.ball.y == before.y; }));
    }

    void aRobotDraggedOutOfTheFloorStaysOnIt() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        FieldView& view = w.fieldView();
        const Field field = w.session().scene().field;
        const RobotState start = w.session().latest()->robots[4];  // blue1 at (0.35, -0.25)
        const double side = w.session().scene().robots[4].params.side;
        // Into the bottom right corner triangle, then into the goal, then behind the goal's back wall.
        for (auto [x, y, inGoal] : {std::tuple{0.74, -0.64, false}, {0.80, 0.0, true}, {0.95, 0.05, true}}) {
            const RobotState before = w.session().latest()->robots[4];
            QTest::mousePress(&view, Qt::LeftButton, {}, at(view, before.x, before.y));
            moveMouse(view, at(view, x, y));
            QTest::mouseRelease(&view, Qt::LeftButton, {}, at(view, x, y));
            QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.robots[4].x != before.x; }));
            QTRY_VERIFY(view.snapshot() && view.snapshot()->robots[4].x == w.session().latest()->robots[4].x);
            const RobotState r = w.session().latest()->robots[4];
            QVERIFY2(robotInsideField(field, side, r.x, r.y, r.theta), qPrintable(QString("%1, %2").arg(r.x).arg(r.y)));
            QCOMPARE(r.x > field.length / 2, inGoal);  // its centre in the goal when dragged there
        }
        Q_UNUSED(start);
    }

    void keysDriveTheSelectedRobotAndManualOverridesTcp() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QVERIFY(w.session().listening());
        // A TCP team client drives robots 0 and 1.
        ProtocolClient team;
        QVERIFY(team.connectTo(w.session().port()));
        QVERIFY(team.hello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"images", "none"}}));
        team.send(protocol::MessageType::Voltages, protocol::encodeVoltages({{0, {2.0, 2.0}}, {1, {3.0, 1.0}}}));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.voltages[0].right == 2.0 && s.voltages[1].right == 3.0; }));
        QCOMPARE(w.session().latest()->control[0].controller, RobotController::Tcp);

        FieldView& view = w.fieldView();
        const RobotState r0 = w.session().latest()->robots[0];
        QTest::mouseClick(&view, Qt::LeftButton, {}, at(view, r0.x, r0.y));
        QCOMPARE(view.selectedRobot(), 0);
        // W: both wheels forward at 60 % of 7.4 V; the robot (heading 0) goes towards +x.
        QTest::keyPress(&view, Qt::Key_W);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.control[0].controller == RobotController::Manual; }));
        QCOMPARE(w.manualRobot(), 0);
        QVERIFY(waitFor(w, [](const Snapshot& s) {
            return std::abs(s.voltages[0].right - 0.6 * 7.4) < 1e-12 && s.voltages[0].left == s.voltages[0].right;
        }));
        const double x0 = w.session().latest()->robots[0].x;
        QTest::qWait(400);
        const Snapshot moved = *w.session().latest();
        QVERIFY2(moved.robots[0].x > x0 + 0.05, qPrintable(QString::number(moved.robots[0].x - x0)));
        QVERIFY(std::abs(moved.robots[0].y - r0.y) < 0.01);
        // TCP for robot 0 is now ignored; robot 1 still follows TCP; the UI says so.
        team.send(protocol::MessageType::Voltages, protocol::encodeVoltages({{0, {-5.0, -5.0}}, {1, {-1.0, -1.0}}}));
        QVERIFY(
            waitFor(w, [](const Snapshot& s) { return s.voltages[1].right == -1.0 && s.control[0].tcpWhileManual; }));
        QVERIFY(std::abs(w.session().latest()->voltages[0].right - 0.6 * 7.4) < 1e-12);
        QTRY_VERIFY(w.findChild<QLabel*>("drive.status")->text().contains("TCP voltages are ignored"));
        // A and W together: turning left, so the right wheel gets more.
        QTest::keyPress(&view, Qt::Key_A);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.voltages[0].right > s.voltages[0].left + 1.0; }));
        QTest::keyRelease(&view, Qt::Key_A);
        QTest::keyRelease(&view, Qt::Key_W);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.voltages[0].right == 0.0 && s.voltages[0].left == 0.0; }));
        QCOMPARE(w.session().latest()->control[0].controller, RobotController::Manual);
        // Esc lets go: robot 0 takes its last TCP voltages again.
        QTest::keyClick(&view, Qt::Key_Escape);
        QVERIFY(waitFor(w, [](const Snapshot& s) {
            return s.control[0].controller == RobotController::Tcp && s.voltages[0].right == -5.0;
        }));
        QCOMPARE(w.manualRobot(), -1);
    }

    void theDefaultSceneIsAMatchAndTheKeyboardOverridesTheBuiltinTeam() {
        // The referee and the built-in team on both sides.
        MainWindow w(kickoffMatch(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::Stop; }));
        QCOMPARE(w.session().latest()->gameSettings.yellow, TeamControl::Builtin);
        // GAME_ON without waiting the 4 s; the built-in teams play.
        w.session().post(EngineRequest::Kind::ResumeGame);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::GameOn; }));
        const Snapshot on = *w.session().latest();
        QVERIFY(waitFor(w, [&](const Snapshot& s) {
            return std::hypot(s.robots[4].x - on.robots[4].x, s.robots[4].y - on.robots[4].y) > 0.02;
        }));
        // The keyboard takes yellow2 (the built-in team's) over: W drives it at
        // 60 % of 7.4 V. (Paused, so that the click finds it where it is.)
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        FieldView& view = w.fieldView();
        // The view picks robots in the snapshot it shows: wait until it shows the paused one.
        QElapsedTimer shown;
        shown.start();
        while (!(view.snapshot() && view.snapshot()->paused) && shown.elapsed() < 5000) QTest::qWait(10);
        QVERIFY(view.snapshot() && view.snapshot()->paused);
        const RobotState r2 = view.snapshot()->robots[2];
        QTest::mouseClick(&view, Qt::LeftButton, {}, at(view, r2.x, r2.y));
        QCOMPARE(view.selectedRobot(), 2);
        // The inspector and the Let go button name the built-in team, not TCP.
        auto* drivenBy = w.findChild<QLabel*>("inspector.controller");
        auto* letGo = w.findChild<QPushButton*>("drive.release");
        QVERIFY(drivenBy && letGo);
        QTRY_COMPARE(drivenBy->text(), QStringLiteral("the built-in team"));
        QTRY_COMPARE(letGo->text(), QStringLiteral("Let go (Esc): back to the built-in team"));
        QTest::keyPress(&view, Qt::Key_W);
        QVERIFY(waitFor(w, [](const Snapshot& s) {
            return s.control[2].controller == RobotController::Manual &&
                   std::abs(s.voltages[2].right - 0.6 * 7.4) < 1e-12 && s.voltages[2].left == s.voltages[2].right;
        }));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return !s.paused; }));
        QTest::qWait(100);  // ten ticks of the built-in team later: still the person's
        QVERIFY(std::abs(w.session().latest()->voltages[2].right - 0.6 * 7.4) < 1e-12);
        QTest::keyRelease(&view, Qt::Key_W);
        QTest::keyClick(&view, Qt::Key_Escape);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.control[2].controller != RobotController::Manual; }));
    }

    void theGameDockRunsTheGame() {
        MainWindow w(kickoffMatch(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        auto* board = w.findChild<Scoreboard*>();
        QVERIFY(board && board->isVisible());
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::Stop; }));
        QTRY_COMPARE(board->scoreText(), QString("Yellow 0 : 0 Blue"));
        QTRY_VERIFY(board->lastCallText().contains("Kick-off for yellow"));
        board->findChild<QPushButton*>("scoreboard.gameOn")->click();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::GameOn; }));
        QTRY_COMPARE(board->phaseText(), QString("GAME ON"));
        // A free ball in quadrant 2, by hand: the ball on its mark.
        board->findChild<QPushButton*>("scoreboard.freeBall2")->click();
        QVERIFY(waitFor(w, [](const Snapshot& s) {
            return s.game.last.call == Call::FreeBall && s.game.last.quadrant == 2 && s.game.phase == GamePhase::Stop;
        }));
        const Eigen::Vector2d mark = freeBallMark(w.session().scene().field, 2);
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.ball.x == mark.x() && s.ball.y == mark.y(); }));
        QTRY_VERIFY(board->lastCallText().contains("Free ball, quadrant 2: by hand"));
        board->findChild<QPushButton*>("scoreboard.halt")->click();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::Halt; }));
        QTRY_COMPARE(board->phaseText(), QString("HALT"));
        // Blue played by nobody from now on.
        auto* blue = board->findChild<QComboBox*>("scoreboard.blueControl");
        blue->setCurrentIndex(blue->findData(int(TeamControl::Idle)));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.gameSettings.blue == TeamControl::Idle; }));
    }

    void pauseStepReset() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.time > 0.1; }));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        const double t = w.session().latest()->time;
        QTest::qWait(200);
        QCOMPARE(w.session().latest()->time, t);
        QTRY_VERIFY(action(w, "action.step")->isEnabled());
        action(w, "action.step")->trigger();
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return std::abs(s.time - (t + 0.03)) < 1e-9; }));
        action(w, "action.reset")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.time == 0.0 && s.frame == 0; }));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return !s.paused && s.time > 0.05; }));
        // Space on the focused field pauses too (the Play/Pause shortcut).
        w.activateWindow();
        w.fieldView().setFocus();
        QTest::keyClick(&w.fieldView(), Qt::Key_Space);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
    }

    void openSaveRoundTrip() {
        QTemporaryDir dir;
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        w.session().placeRobot(2, RobotState{0.1, -0.3, 0.7, 0.0, 0.0});
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.robots[2].x == 0.1; }));
        const QString path = dir.filePath("setup.json");
        QString error;
        QVERIFY2(w.saveScene(path, &error), qPrintable(error));
        const std::optional<Scene> saved = loadSceneFile(path, &error);
        QVERIFY2(saved, qPrintable(error));
        QCOMPARE(saved->robots[2].initial.x, 0.1);
        QCOMPARE(saved->robots[2].initial.theta, 0.7);
        QCOMPARE(saved->robots.size(), std::size_t(6));
        // Open it in a window running another scene: the engine starts from the saved poses.
        MainWindow other(*loadSceneFile(":/scenes/ball_walls.json", &error), ":/scenes/ball_walls.json", anyPort());
        QVERIFY(other.openScene(path, false));
        QVERIFY(waitFor(other, [](const Snapshot& s) { return s.robots.size() == 6 && s.robots[2].x != 0.0; }));
        QCOMPARE(sceneToJson(other.session().scene()), sceneToJson(*saved));
        QCOMPARE(other.session().latest()->scene->robots.size(), std::size_t(6));
        QVERIFY(!other.openScene(dir.filePath("missing.json"), false));
        // A scene opened from a file starts paused at t = 0.
        QTRY_VERIFY(other.session().latest()->paused && other.session().latest()->time == 0.0);
        // A name without a suffix is saved as .json (the Open dialog lists only those).
        QVERIFY2(w.saveScene(dir.filePath("nosuffix"), &error), qPrintable(error));
        QVERIFY(QFileInfo(dir.filePath("nosuffix.json")).isFile());
        QVERIFY(!QFileInfo::exists(dir.filePath("nosuffix")));
    }

    void anOpenedSceneSetsUpTheWindowFromTheSnapshots() {
        // One path for every scene change: the window follows the snapshots'
        // scene (toolbar settings, camera, undo history, selection).
        QTemporaryDir dir;
        Scene next = kickoff();
        next.robots.resize(2);
        next.simulation.integrator = Integrator::Euler;
        next.simulation.dt = 0.0005;
        const QString path = dir.filePath("two.json");
        QFile file(path);
        QVERIFY(file.open(QIODevice::WriteOnly) && file.write(sceneToJson(next)) > 0);
        file.close();

        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        auto* integrator = w.findChild<QComboBox*>("toolbar.integrator");
        auto* dt = w.findChild<QDoubleSpinBox*>("toolbar.dt");
        QVERIFY(integrator && dt);
        QCOMPARE(integrator->currentText(), integratorName(kickoff().simulation.integrator));
        // A move to undo, and robot 4 selected: neither belongs to the next scene.
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        FieldView& view = w.fieldView();
        const RobotState r4 = w.session().latest()->robots[4];
        QTest::mousePress(&view, Qt::LeftButton, {}, at(view, r4.x, r4.y));
        moveMouse(view, at(view, r4.x + 0.05, r4.y));
        QTest::mouseRelease(&view, Qt::LeftButton, {}, at(view, r4.x + 0.1, r4.y));
        QCOMPARE(view.selectedRobot(), 4);
        QVERIFY(action(w, "action.undo")->isEnabled());

        QVERIFY(w.openScene(path, false));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.robots.size() == 2; }));
        QTRY_COMPARE(integrator->currentText(), QStringLiteral("euler"));
        QCOMPARE(dt->value(), 0.0005);
        QVERIFY(!action(w, "action.undo")->isEnabled());
        QCOMPARE(view.selectedRobot(), -1);
    }

    void screenshotShowsRobotsWhereTheSnapshotSays() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        w.session().placeBall(BallState{0.2, 0.3, 0.0, 0.0});
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.ball.x == 0.2; }));
        QTest::qWait(150);  // a few refreshes
        FieldView& view = w.fieldView();
        const QImage image = view.grabFramebuffer();
        const auto snapshot = w.session().latest();
        auto colourAt = [&](double x, double y) { return image.pixelColor(view.toWidget(x, y).toPoint()); };
        auto near = [](QColor c, Bgr want) {
            return std::abs(c.red() - want.r) < 30 && std::abs(c.green() - want.g) < 30 &&
                   std::abs(c.blue() - want.b) < 30;
        };
        for (std::size_t i = 0; i < snapshot->robots.size(); ++i) {
            const RobotState& r = snapshot->robots[i];
            const double side = snapshot->scene->robots[i].params.side;
            // The team patch's centre, a quarter side behind the centre.
            const double bx = r.x - 0.25 * side * std::cos(r.theta), by = r.y - 0.25 * side * std::sin(r.theta);
            QVERIFY2(near(colourAt(bx, by), teamColour(snapshot->scene->robots[i].team)),
                     qPrintable(QString("robot %1: %2").arg(i).arg(colourAt(bx, by).name())));
        }
        QVERIFY2(near(colourAt(0.2, 0.3), kBallColour), qPrintable(colourAt(0.2, 0.3).name()));
        QVERIFY(near(colourAt(0.4, -0.4), kFloorColour));
        // The official field: floor in the goals, outside behind them and in
        // the corner triangles, walls along the back of the goals and the
        // triangles' hypotenuses, white at a free-ball mark.
        for (auto [x, y] : {std::pair{0.80, 0.1}, {-0.80, -0.1}})
            QVERIFY2(near(colourAt(x, y), kFloorColour), qPrintable(colourAt(x, y).name()));
        for (auto [x, y] : {std::pair{0.90, 0.0}, {-0.90, 0.0}, {0.80, 0.35}, {0.745, 0.645}, {-0.745, -0.645}})
            QVERIFY2(near(colourAt(x, y), kOutsideColour), qPrintable(colourAt(x, y).name()));
        for (auto [x, y] : {std::pair{0.85, 0.0}, {-0.715, 0.615}})
            QVERIFY2(near(colourAt(x, y), kWallColour), qPrintable(colourAt(x, y).name()));
        QVERIFY2(near(colourAt(-0.375, -0.25), kMarkingColour) || colourAt(-0.375, -0.25).red() > 120,
                 qPrintable(colourAt(-0.375, -0.25).name()));
        const QByteArray fieldOut = qgetenv("VSSIM_FIELD_SCREENSHOT");
        if (!fieldOut.isEmpty()) QVERIFY(image.save(QString::fromLocal8Bit(fieldOut)));
        const QByteArray out = qgetenv("VSSIM_SCREENSHOT");
        if (!out.isEmpty()) {
            // The README's picture: the kick-off as shipped, a moving robot selected.
            QString error;
            MainWindow shot(*loadSceneFile(":/scenes/kickoff_3v3.json", &error), ":/scenes/kickoff_3v3.json",
                            anyPort());
            shot.show();
            QVERIFY(QTest::qWaitForWindowExposed(&shot));
            shot.fieldView().setSelectedRobot(2);
            QTest::qWait(1800);
            QVERIFY(shot.grab().save(QString::fromLocal8Bit(out)));
        }
    }

    void fitsASmallScreen() {
        // The window fits 1024 x 768 less a taskbar: its right-hand docks
        // scroll rather than make the window taller, and keep 300 px of width.
        MainWindow w(kickoffMatch(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QVERIFY2(w.minimumSizeHint().height() <= 740 && w.minimumSizeHint().width() <= 1024,
                 qPrintable(QStringLiteral("minimum %1 x %2").arg(w.minimumSizeHint().width()).arg(w.minimumSizeHint().height())));
        w.resize(1024, 740);
        QTRY_COMPARE(w.size(), QSize(1024, 740));
        for (const char* name : {"dock.robot", "dock.drive"}) {
            const QDockWidget* d = w.findChild<QDockWidget*>(name);
            QVERIFY(d && d->isVisible());
            QVERIFY2(d->width() >= 300, name);
        }
    }

    void sidesSwapFromTheEditMenu() {
        // Edit > Blue defends the left goal: the match starts again with blue
        // placed in the left half for the kick-off, yellow in the right (seen
        // within the kick-off's 4 s stop, while the robots hold their places).
        MainWindow w(kickoffMatch(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QAction* blueLeft = w.findChild<QAction*>("action.blueOnLeft");
        QVERIFY(blueLeft && blueLeft->isCheckable());
        QCOMPARE(w.session().scene().game.rules.left_team, Team::Yellow);
        const std::vector<RobotSpec>& robots = w.session().scene().robots;
        auto inHalves = [&robots](const Snapshot& s, Team left) {
            for (std::size_t i = 0; i < robots.size(); ++i)
                if ((s.robots[i].x < 0.0) != (robots[i].team == left)) return false;
            return true;
        };
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return inHalves(s, Team::Yellow); }));
        blueLeft->trigger();
        QCOMPARE(w.session().scene().game.rules.left_team, Team::Blue);
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return s.time < 3.5 && inHalves(s, Team::Blue); }));
        blueLeft->trigger();
        QCOMPARE(w.session().scene().game.rules.left_team, Team::Yellow);
    }

    void menusShortcutsAndUndoNames() {
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        // View > Refresh rate marks the rate in force.
        QVERIFY(w.findChild<QAction*>("action.rate30")->isChecked());
        w.findChild<QAction*>("action.rate10")->trigger();
        QVERIFY(w.findChild<QAction*>("action.rate10")->isChecked());
        QVERIFY(!w.findChild<QAction*>("action.rate30")->isChecked());
        // Shortcuts: Space pauses, Ctrl+Right steps 30 ms, Ctrl+R resets, Ctrl+Up speeds up
        // (window shortcuts: the window must be the active one).
        w.activateWindow();
        QVERIFY(QTest::qWaitForWindowActive(&w));
        QTest::keyClick(&w.fieldView(), Qt::Key_Space);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        const double t0 = w.session().latest()->time;
        QTRY_VERIFY(action(w, "action.step")->isEnabled());  // at the window's next refresh
        QTest::keyClick(&w, Qt::Key_Right, Qt::ControlModifier);
        QVERIFY(waitFor(w, [&](const Snapshot& s) { return std::abs(s.time - (t0 + 0.03)) < 1e-9; }));
        QTest::keyClick(&w, Qt::Key_R, Qt::ControlModifier);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.time == 0.0; }));
        QTest::keyClick(&w, Qt::Key_Up, Qt::ControlModifier);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.speed == 2.0; }));
        // A key with Ctrl held is a shortcut's, never driving: Ctrl+D on the
        // field with a robot selected takes nothing from its client.
        FieldView& field = w.fieldView();
        field.setSelectedRobot(1);
        QTest::keyPress(&field, Qt::Key_D, Qt::ControlModifier);
        QTest::qWait(100);
        QTest::keyRelease(&field, Qt::Key_D, Qt::ControlModifier);
        QCOMPARE(w.manualRobot(), -1);
        QVERIFY(w.session().latest()->control[1].controller != RobotController::Manual);
        field.setSelectedRobot(-1);
        // Undo names what the drag changed: a Shift-drag sets the ball's velocity.
        FieldView& view = w.fieldView();
        QTRY_VERIFY(view.snapshot() && view.snapshot()->paused);
        const BallState ball = w.session().latest()->ball;
        QTest::mousePress(&view, Qt::LeftButton, Qt::ShiftModifier, at(view, ball.x, ball.y));
        moveMouse(view, at(view, ball.x + 0.05, ball.y));
        QTest::mouseRelease(&view, Qt::LeftButton, Qt::ShiftModifier, at(view, ball.x + 0.1, ball.y));
        QCOMPARE(action(w, "action.undo")->text(), QString("&Undo Set the ball's velocity"));
    }

    void nothingIsRedrawnWhileNothingChanges() {
        // Paused and idle, the window reads the same snapshot again and again:
        // the field must not be redrawn (it cost a core under software OpenGL).
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        struct PaintCounter : QObject {
            int paints = 0;
            bool eventFilter(QObject*, QEvent* e) override {
                paints += e->type() == QEvent::Paint;
                return false;
            }
        } counter;
        w.fieldView().installEventFilter(&counter);
        QTRY_VERIFY(counter.paints > 3);  // running: redrawn at the refresh rate
        action(w, "action.playPause")->trigger();
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        QTest::qWait(300);  // the last snapshots of the running engine are shown
        counter.paints = 0;
        QTest::qWait(600);  // about 18 refreshes at 30 Hz
        QCOMPARE(counter.paints, 0);
        // Something changes (a step): one more redraw.
        action(w, "action.step")->trigger();
        QTRY_VERIFY(counter.paints > 0);
    }

    void aPausedMatchRepaintsNothing() {
        // The default scene (the referee, the built-in team on both sides),
        // paused as a person pauses it: a click on the field, then Space.
        // Nothing in the window may be repainted while nothing changes: any
        // repaint has the whole window composited again (the field is a GL
        // widget), which cost most of a core under software OpenGL.
        MainWindow w(kickoffMatch(), ":/scenes/kickoff_3v3.json", anyPort());
        w.resize(1400, 1000);
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.game.phase == GamePhase::Stop; }));
        FieldView& view = w.fieldView();
        QTest::mouseClick(&view, Qt::LeftButton, {}, view.rect().center() + QPoint(0, view.height() / 3));
        QTest::keyClick(&view, Qt::Key_Space);
        QVERIFY(waitFor(w, [](const Snapshot& s) { return s.paused; }));
        struct PaintCounter : QObject {
            std::map<QString, int> paints;  // by class and object name
            bool eventFilter(QObject* o, QEvent* e) override {
                if (e->type() == QEvent::Paint || e->type() == QEvent::UpdateRequest)
                    ++paints[QStringLiteral("%1 %2").arg(o->metaObject()->className(), o->objectName())];
                return false;
            }
            QString list() const {
                QStringList out;
                for (const auto& [name, n] : paints) out << QStringLiteral("%1: %2").arg(name).arg(n);
                return out.join(", ");
            }
        } counter;
        QTest::qWait(500);  // the last snapshots of the running engine are shown
        qApp->installEventFilter(&counter);
        QTest::qWait(1000);  // about 30 refreshes at 30 Hz
        qApp->removeEventFilter(&counter);
        QVERIFY2(counter.paints.empty(), qPrintable(counter.list()));
        // The same with a robot selected (inspector and plots showing it).
        const RobotState r0 = view.snapshot()->robots[0];
        QTest::mouseClick(&view, Qt::LeftButton, {}, at(view, r0.x, r0.y));
        QCOMPARE(view.selectedRobot(), 0);
        QTest::qWait(500);
        qApp->installEventFilter(&counter);
        QTest::qWait(1000);
        qApp->removeEventFilter(&counter);
        QVERIFY2(counter.paints.empty(), qPrintable(counter.list()));
    }

    void docksStayReadableOnASmallScreen() {
        // At 1024 x 768 the right-hand docks used to shrink to a sliver; and
        // the joystick (Drive by hand) shows together with the plots.
        MainWindow w(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w.resize(1024, 768);
        w.show();
        QVERIFY(QTest::qWaitForWindowExposed(&w));
        auto* robot = w.findChild<QDockWidget*>("dock.robot");
        auto* drive = w.findChild<QDockWidget*>("dock.drive");
        QVERIFY(robot && drive);
        QTRY_VERIFY(robot->width() >= 300);
        QVERIFY(robot->isVisible() && drive->isVisible());
        QVERIFY(!w.tabifiedDockWidgets(robot).contains(drive));
        QVERIFY(w.fieldView().width() >= 400);  // the field keeps most of the window
    }

    void quitClosesEveryWindow() {
        // File > Quit ends everything, watch windows included (it used to close
        // the main window only, leaving the process and its server running).
        auto* w = new MainWindow(kickoff(), ":/scenes/kickoff_3v3.json", anyPort());
        w->setAttribute(Qt::WA_DeleteOnClose);
        w->show();
        QVERIFY(QTest::qWaitForWindowExposed(w));
        auto* watcher = new RemoteWatcher;
        QString error;
        QVERIFY2(watcher->connectTo("127.0.0.1", w->session().port(), &error), qPrintable(error));
        auto* remote = new RemoteWindow(watcher);
        remote->show();
        QVERIFY(QTest::qWaitForWindowExposed(remote));
        QPointer<MainWindow> main(w);
        QPointer<RemoteWindow> watch(remote);
        action(*w, "action.quit")->trigger();
        QTRY_VERIFY(!main);  // closed and deleted
        QVERIFY(!watch || !watch->isVisible());
        delete watch.data();
    }

    void watchingARemoteServer_data() {
        QTest::addColumn<bool>("realistic");
        QTest::newRow("ideal camera") << false;
        // The realistic camera delays, drops and blurs what the teams' clients
        // get; the watch window asks for the exact ground truth instead, and
        // its camera dock knows the server's camera.
        QTest::newRow("realistic camera") << true;
    }

    void watchingARemoteServer() {
        // A server in this process (as `vssim serve` would run it), watched
        // through the protocol: the view shows what the engine has.
        QFETCH(bool, realistic);
        Scene scene = kickoff();
        if (realistic) scene.camera = realisticCamera();
        scene.commands = {{0.0, 1, {4.0, 3.0}}};
        EngineThread engine(scene, EngineLoopSettings{});
        ServerSettings settings = anyPort();
        ControlServer server(scene, engine, settings);
        QString error;
        QVERIFY2(server.listen(&error), qPrintable(error));
        engine.start();
        auto* watcher = new RemoteWatcher;
        QVERIFY2(watcher->connectTo("127.0.0.1", server.port(), &error), qPrintable(error));
        RemoteWindow window(watcher);
        window.show();
        QVERIFY(QTest::qWaitForWindowExposed(&window));
        QTRY_VERIFY(window.fieldView().snapshot() && window.fieldView().snapshot()->time > 0.2);
        const auto seen = window.fieldView().snapshot();
        QCOMPARE(seen->robots.size(), scene.robots.size());
        QCOMPARE(seen->scene->robots[3].name, std::string("blue0"));
        // The field as the server has it (WELCOME's field: type and dimensions).
        QCOMPARE(seen->scene->field.dimensions.type, FieldType::Vsss3v3);
        QCOMPARE(seen->scene->field.walls.size(), scene.field.walls.size());
        QCOMPARE(seen->scene->field.dimensions.goal_depth, 0.10);
        QVERIFY(seen->robots[1].x > scene.robots[1].initial.x);  // robot 1 drives (4 V, 3 V)
        // The camera as WELCOME gives it for this client: the scene's image
        // (lens, light, noise, blur), the window's own exact delivery.
        CameraSettings expected = scene.camera;
        expected.latency = expected.jitter = expected.drop = 0.0;
        expected.position_noise = expected.heading_noise = expected.vanish = 0.0;
        QVERIFY(seen->scene->camera == expected);
        // Pause through the window: the server's time stops.
        window.findChild<QAction*>("remote.pause")->trigger();
        QTRY_VERIFY(engine.snapshots().latest()->paused);
        const double t = engine.snapshots().latest()->time;
        // Dragging in the window places the robot on the server.
        FieldView& view = window.fieldView();
        const RobotState r0 = seen->robots[0];
        QTest::mousePress(&view, Qt::LeftButton, {}, at(view, r0.x, r0.y));
        QTest::mouseRelease(&view, Qt::LeftButton, {}, at(view, r0.x + 0.2, r0.y - 0.1));
        QTRY_VERIFY(std::abs(engine.snapshots().latest()->robots[0].x - (r0.x + 0.2)) < 0.01);
        QCOMPARE(engine.snapshots().latest()->time, t);
        // Step works on a paused server; not while it runs. The step ends
        // with a camera instant, whose STATE is the engine's state to the bit.
        QAction* step = window.findChild<QAction*>("remote.step");
        QTRY_VERIFY(step->isEnabled());
        step->trigger();
        QTRY_VERIFY(engine.snapshots().latest()->time > t);
        const auto truth = engine.snapshots().latest();
        QTRY_VERIFY(window.fieldView().snapshot()->time == truth->time);
        const auto stepped = window.fieldView().snapshot();
        for (std::size_t i = 0; i < truth->robots.size(); ++i) {
            QCOMPARE(stepped->robots[i].x, truth->robots[i].x);
            QCOMPARE(stepped->robots[i].y, truth->robots[i].y);
            QCOMPARE(stepped->robots[i].theta, truth->robots[i].theta);
        }
        QCOMPARE(stepped->ball.x, truth->ball.x);
        window.findChild<QAction*>("remote.resume")->trigger();
        QTRY_VERIFY(!step->isEnabled());
        engine.requestStop();
        engine.wait();
    }

    void aWatchWindowReconnectsWhenTheServerComesBack() {
        Scene scene = kickoff();
        quint16 port = 0;
        auto serve = [&](std::unique_ptr<EngineThread>& engine, std::unique_ptr<ControlServer>& server) {
            engine = std::make_unique<EngineThread>(scene, EngineLoopSettings{});
            ServerSettings settings = anyPort();
            settings.port = port;
            server = std::make_unique<ControlServer>(scene, *engine, settings);
            QString error;
            if (!server->listen(&error)) return false;
            port = server->port();
            engine->start();
            return true;
        };
        std::unique_ptr<EngineThread> engine;
        std::unique_ptr<ControlServer> server;
        QVERIFY(serve(engine, server));
        auto* watcher = new RemoteWatcher;
        QString error;
        QVERIFY2(watcher->connectTo("127.0.0.1", port, &error), qPrintable(error));
        RemoteWindow window(watcher);
        window.show();
        QVERIFY(QTest::qWaitForWindowExposed(&window));
        QTRY_VERIFY(watcher->connected() && window.fieldView().snapshot());
        // The server stops...
        server.reset();
        engine->requestStop();
        engine->wait();
        QTRY_VERIFY(!watcher->connected());
        // ...and starts again on the same port: the window is watching it within a few seconds.
        QVERIFY(serve(engine, server));
        QTRY_VERIFY_WITH_TIMEOUT(watcher->connected(), 8000);
        const double before = watcher->latest()->time;
        QTRY_VERIFY(watcher->latest()->time != before);
        server.reset();
        engine->requestStop();
        engine->wait();
    }
};

QTEST_MAIN(TestGui)
#include "test_gui.moc"
