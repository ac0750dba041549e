// The desktop app's read-only panels (robot inspector, live plots,
// connections, camera view, status line), fed hand-made snapshots.
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QLabel>
#include <QPushButton>
#include <QSignalSpy>
#include <QTableWidget>
#include <QtTest>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "camera_view.h"
#include "connections_panel.h"
#include "live_plots.h"
#include "robot_inspector.h"
#include "scoreboard.h"
#include "status_text.h"
#include "test_support.h"

using namespace vssim;

namespace {

std::shared_ptr<const Scene> twoRobotScene() {
    auto scene = std::make_shared<Scene>();
    scene->robots.push_back(test::robotAt("yellow0", -0.3, 0.1, 0.0));
    scene->robots.push_back(test::robotAt("blue0", 0.4, -0.2, M_PI));
    scene->robots[1].team = Team::Blue;
    scene->robots[1].params = test::asymmetricParams();
    return scene;
}

Snapshot makeSnapshot(double time = 1.234) {
    Snapshot s;
    s.scene = twoRobotScene();
    s.time = time;
    s.step = std::llround(time / 0.001);
    s.frame = 41;
    s.robots = {{-0.31234, 0.10987, 0.5, 0.45678, -1.2345}, {0.4, -0.2, -2.0, -0.1, 3.21}};
    s.voltages = {{3.456, -2.5}, {0.0, 7.25}};
    RobotOutputs out;
    out.wheel_speed_right = 21.37;
    out.wheel_speed_left = -8.04;
    out.current_right = 0.4321;
    out.current_left = -0.1234;
    s.outputs = {out, RobotOutputs{}};
    s.ball = {0.05, -0.02, 0.0, 0.0};
    s.control.resize(2);
    s.control[0].controller = RobotController::Tcp;
    s.control[0].client = 3;
    s.stepCost = 0.00091;
    return s;
}

// The number printed at the start of a label ("0.457 m/s" -> 0.457), checked
// against `want` to within half a unit of its last printed digit.
void expectValue(const RobotInspector& inspector, const char* key, double want, const char* unit) {
    auto* label = inspector.findChild<QLabel*>(QStringLiteral("inspector.") + key);
    QVERIFY2(label, key);
    const QString text = label->text();
    QVERIFY2(text.endsWith(QStringLiteral(" ") + unit), qPrintable(text));
    const QString number = text.section(' ', 0, 0);
    const int decimals = number.contains('.') ? number.size() - number.indexOf('.') - 1 : 0;
    bool ok = false;
    const double got = number.toDouble(&ok);
    QVERIFY2(ok, qPrintable(text));
    QVERIFY2(std::abs(got - want) <= 0.5 * std::pow(10.0, -decimals) + 1e-12,
             qPrintable(QStringLiteral("%1: %2 vs %3").arg(key, text).arg(want)));
}

QString labelText(const RobotInspector& inspector, const char* key) {
    auto* label = inspector.findChild<QLabel*>(QStringLiteral("inspector.") + key);
    return label ? label->text() : QString();
}

// Pixels of `image` inside `area` within a small distance of `colour`.
int pixelsNear(const QImage& image, const QRect& area, const QColor& colour) {
    int count = 0;
    for (int y = area.top(); y <= area.bottom(); ++y)
        for (int x = area.left(); x <= area.right(); ++x) {
            const QColor c = image.pixelColor(x, y);
            if (std::abs(c.red() - colour.red()) + std::abs(c.green() - colour.green()) +
                    std::abs(c.blue() - colour.blue()) <
                40)
                ++count;
        }
    return count;
}

ClientInfo client(int id, std::int64_t commands) {
    ClientInfo c;
    c.id = id;
    c.peer = QStringLiteral("127.0.0.1:5%1").arg(id, 4, 10, QChar('0'));
    c.greeted = true;
    c.role = QStringLiteral("yellow");
    c.name = QStringLiteral("team%1").arg(id);
    c.images = QStringLiteral("patches/png");
    c.commands = commands;
    c.framesSent = 100 + id;
    c.framesDropped = id;
    c.connectedSeconds = 12.34;
    return c;
}

}  // namespace

class TestUiPanels : public QObject {
    Q_OBJECT
private slots:
    void inspectorShowsValuesWithUnits();
    void inspectorSaysWhoDrives();
    void inspectorNamesTheBuiltInTeam();
    void plotsAccumulateAndForget();
    void plotsThinBeyondTheCap();
    void plotsDrawEveryChart();
    void connectionsShowRowsAndRates();
    void connectionsFirasimSwitch();
    void cameraViewMatchesTheRenderer();
    void cameraViewPreviewsThePresets();
    void statusLine();
    void scoreboardShowsTheGame();
    void scoreboardButtonsAskForCalls();
};

void TestUiPanels::inspectorShowsValuesWithUnits() {
    const Snapshot s = makeSnapshot();
    RobotInspector inspector;
    inspector.showRobot(s, 0);
    QCOMPARE(labelText(inspector, "name"), QStringLiteral("yellow0"));
    QCOMPARE(labelText(inspector, "team"), QStringLiteral("yellow"));
    expectValue(inspector, "x", s.robots[0].x, "m");
    expectValue(inspector, "y", s.robots[0].y, "m");
    expectValue(inspector, "theta", s.robots[0].theta * 180.0 / M_PI, "deg");
    expectValue(inspector, "v", s.robots[0].v, "m/s");
    expectValue(inspector, "omega", s.robots[0].omega, "rad/s");
    expectValue(inspector, "wheelRight", s.outputs[0].wheel_speed_right, "rad/s");
    expectValue(inspector, "wheelLeft", s.outputs[0].wheel_speed_left, "rad/s");
    expectValue(inspector, "voltageRight", s.voltages[0].right, "V");
    expectValue(inspector, "voltageLeft", s.voltages[0].left, "V");
    expectValue(inspector, "currentRight", s.outputs[0].current_right, "A");
    expectValue(inspector, "currentLeft", s.outputs[0].current_left, "A");

    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "name"), QStringLiteral("blue0"));
    QCOMPARE(labelText(inspector, "team"), QStringLiteral("blue"));
    expectValue(inspector, "omega", s.robots[1].omega, "rad/s");
    expectValue(inspector, "voltageLeft", s.voltages[1].left, "V");

    // The heading is shown wrapped (the engine counts turns), and a value that
    // rounds to zero without a minus sign.
    Snapshot turned = s;
    turned.robots[0].theta = 20 * M_PI + 0.5;
    turned.robots[0].v = -1e-9;
    inspector.showRobot(turned, 0);
    expectValue(inspector, "theta", 0.5 * 180.0 / M_PI, "deg");
    QCOMPARE(labelText(inspector, "v"), QStringLiteral("0.000 m/s"));
    turned.robots[0].theta = -3 * M_PI / 2;  // = +90 degrees
    inspector.showRobot(turned, 0);
    QCOMPARE(labelText(inspector, "theta"), QStringLiteral("90.0 deg"));

    inspector.showRobot(s, -1);
    QCOMPARE(labelText(inspector, "name"), QStringLiteral("no robot selected"));
    QVERIFY(!labelText(inspector, "v").contains("m/s"));
}

void TestUiPanels::inspectorSaysWhoDrives() {
    Snapshot s = makeSnapshot();
    RobotInspector inspector;
    inspector.showRobot(s, 0);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("TCP client 3"));
    // Nobody drives it, but it has voltages: the scene's own commands.
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("the scene's own commands"));
    s.voltages[1] = Voltages{};
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("nobody (0 V)"));
    // Watching a server: who drives is not known.
    Snapshot remote = s;
    remote.control.clear();
    inspector.showRobot(remote, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("not known (watching a server)"));
    s.control[1].controller = RobotController::Manual;
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("manual"));
    s.control[1].tcpWhileManual = true;
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("manual (TCP voltages ignored)"));
}

void TestUiPanels::inspectorNamesTheBuiltInTeam() {
    // Blue played by the built-in team: its robot is driven by that team,
    // with voltages or at rest (a stop, its first tick), and letting go of it
    // hands it back to that team, not to TCP.
    Snapshot s = makeSnapshot();
    s.gameSettings.blue = TeamControl::Builtin;
    RobotInspector inspector;
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("the built-in team"));
    s.voltages[1] = Voltages{};
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("the built-in team"));
    QCOMPARE(letGoText(s, 1), QStringLiteral("Let go (Esc): back to the built-in team"));
    // Yellow stays remote: its TCP client, and back to TCP.
    inspector.showRobot(s, 0);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("TCP client 3"));
    QCOMPARE(letGoText(s, 0), QStringLiteral("Let go (Esc): back to TCP control"));
    // A person driving it: manual, whoever plays the team.
    s.control[1].controller = RobotController::Manual;
    inspector.showRobot(s, 1);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("manual"));
    QCOMPARE(letGoText(s, 1), QStringLiteral("Let go (Esc): back to the built-in team"));
    // An idle team: nobody, even with a TCP client's commands (ignored).
    s.gameSettings.yellow = TeamControl::Idle;
    inspector.showRobot(s, 0);
    QCOMPARE(labelText(inspector, "controller"), QStringLiteral("nobody (idle team: 0 V)"));
    QCOMPARE(letGoText(s, 0), QStringLiteral("Let go (Esc): back to 0 V (idle team)"));
    // No robot: nothing to go back to yet, whatever the teams.
    QCOMPARE(letGoText(s, -1), QStringLiteral("Let go (Esc)"));
    s.gameSettings.yellow = s.gameSettings.blue = TeamControl::Builtin;
    QCOMPARE(letGoText(s, -1), QStringLiteral("Let go (Esc)"));
}

void TestUiPanels::plotsAccumulateAndForget() {
    LivePlots plots;
    QCOMPARE(plots.windowSeconds(), 5.0);
    for (int i = 0; i <= 200; ++i) plots.addSample(makeSnapshot(0.01 * i), 0);
    QCOMPARE(plots.sampleCount(), 201);
    plots.addSample(makeSnapshot(2.0), 0);  // not later: ignored
    QCOMPARE(plots.sampleCount(), 201);

    // Only the last 5 s of simulated time are kept.
    for (int i = 201; i <= 1000; ++i) plots.addSample(makeSnapshot(0.01 * i), 0);
    QVERIFY2(std::abs(plots.sampleCount() - 501) <= 1, qPrintable(QString::number(plots.sampleCount())));

    plots.addSample(makeSnapshot(0.5), 0);  // time went backwards: a reset
    QCOMPARE(plots.sampleCount(), 1);
    plots.addSample(makeSnapshot(0.6), 0);
    QCOMPARE(plots.sampleCount(), 2);
    plots.addSample(makeSnapshot(0.7), 1);  // another robot
    QCOMPARE(plots.sampleCount(), 1);
    QCOMPARE(plots.robot(), 1);
    plots.clear();
    QCOMPARE(plots.sampleCount(), 0);
}

void TestUiPanels::plotsThinBeyondTheCap() {
    LivePlots plots(nullptr, 100.0, 100);
    for (int i = 0; i <= 100; ++i) plots.addSample(makeSnapshot(0.01 * i), 0);
    QCOMPARE(plots.sampleCount(), 51);  // 101 > 100: every other one kept, the newest included
    for (int i = 101; i < 5000; ++i) {
        plots.addSample(makeSnapshot(0.01 * i), 0);
        QVERIFY(plots.sampleCount() <= 100);
    }
    QVERIFY(plots.sampleCount() >= 50);
}

void TestUiPanels::plotsDrawEveryChart() {
    LivePlots plots;
    plots.resize(420, 480);
    for (int i = 0; i <= 300; ++i) {
        Snapshot s = makeSnapshot(0.01 * i);
        const double phase = 0.05 * i;
        s.robots[0].v = 0.5 * std::sin(phase);
        s.robots[0].omega = 3.0 * std::cos(phase);
        s.voltages[0] = {6.0 * std::sin(phase), -6.0 * std::sin(phase)};
        s.outputs[0].current_right = 0.8 * std::cos(phase);
        s.outputs[0].current_left = 0.2 + 0.1 * std::sin(phase);
        plots.addSample(s, 0);
    }
    const QImage image = plots.grab().toImage().convertToFormat(QImage::Format_RGB32);
    QCOMPARE(image.size(), QSize(420, 480));
    for (int c = 0; c < LivePlots::kCharts; ++c) {
        const QRect area = plots.chartRect(c);
        QVERIFY(image.rect().contains(area));
        QVERIFY2(pixelsNear(image, area, LivePlots::firstColour()) > 50, qPrintable(QString::number(c)));
        QVERIFY2(pixelsNear(image, area, LivePlots::secondColour()) > 50, qPrintable(QString::number(c)));
    }
    // Empty plots draw too.
    LivePlots empty;
    empty.resize(300, 300);
    QVERIFY(!empty.grab().isNull());
}

void TestUiPanels::connectionsShowRowsAndRates() {
    ConnectionsPanel panel;
    panel.setListening(QStringLiteral("127.0.0.1:10030"));
    QCOMPARE(panel.listeningLabel()->text(), QStringLiteral("Listening on 127.0.0.1:10030"));

    QTableWidget* table = panel.table();
    const auto cell = [&](int row, int col) { return table->item(row, col)->text(); };
    panel.setClients({client(1, 10), client(2, 0)}, 0.5);
    QCOMPARE(table->rowCount(), 2);
    QCOMPARE(table->columnCount(), int(ConnectionsPanel::ColumnCount));
    QCOMPARE(cell(0, ConnectionsPanel::Id), QStringLiteral("1"));
    QCOMPARE(cell(0, ConnectionsPanel::Address), QStringLiteral("127.0.0.1:50001"));
    QCOMPARE(cell(1, ConnectionsPanel::Name), QStringLiteral("team2"));
    QCOMPARE(cell(1, ConnectionsPanel::Role), QStringLiteral("yellow"));
    QCOMPARE(cell(1, ConnectionsPanel::Images), QStringLiteral("patches/png"));
    QCOMPARE(cell(1, ConnectionsPanel::FramesSent), QStringLiteral("102"));
    QCOMPARE(cell(1, ConnectionsPanel::FramesDropped), QStringLiteral("2"));
    QCOMPARE(cell(1, ConnectionsPanel::ConnectedFor), QStringLiteral("12.3"));
    QCOMPARE(cell(0, ConnectionsPanel::CommandsPerSecond), QString());  // seen once: no rate yet
    QVERIFY(table->horizontalHeaderItem(ConnectionsPanel::ConnectedFor)->text().contains("(s)"));

    // 10 -> 40 commands in 0.5 s: 60 per second; 0 -> 15 in 0.5 s: 30.
    panel.setClients({client(1, 40), client(2, 15), client(3, 7)}, 0.5);
    QCOMPARE(table->rowCount(), 3);
    QCOMPARE(cell(0, ConnectionsPanel::CommandsPerSecond).toDouble(), 60.0);
    QCOMPARE(cell(1, ConnectionsPanel::CommandsPerSecond).toDouble(), 30.0);
    QCOMPARE(cell(2, ConnectionsPanel::CommandsPerSecond), QString());

    // Client 2 leaves and a new client 2 would start afresh; 3 sends 3 in 2 s.
    panel.setClients({client(3, 10)}, 2.0);
    QCOMPARE(table->rowCount(), 1);
    QCOMPARE(cell(0, ConnectionsPanel::CommandsPerSecond).toDouble(), 1.5);
    panel.setClients({client(2, 100), client(3, 10)}, 1.0);
    QCOMPARE(cell(0, ConnectionsPanel::CommandsPerSecond), QString());
    QCOMPARE(cell(1, ConnectionsPanel::CommandsPerSecond).toDouble(), 0.0);

    ClientInfo newcomer = client(4, 0);
    newcomer.greeted = false;
    panel.setClients({newcomer}, 1.0);
    QVERIFY(cell(0, ConnectionsPanel::Role).contains("HELLO"));
}

void TestUiPanels::connectionsFirasimSwitch() {
    ConnectionsPanel panel;
    QVERIFY(!panel.firasimBox()->isChecked());
    QCOMPARE(panel.firasimLabel()->text(), QStringLiteral("off"));
    QSignalSpy toggled(&panel, &ConnectionsPanel::firasimToggled);
    panel.firasimBox()->click();
    QCOMPARE(toggled.size(), 1);
    QCOMPARE(toggled.first().first().toBool(), true);
    // The owner could not start it: unchecked again, and why, without a signal.
    panel.showFirasimOff(QStringLiteral("port 20011 taken"));
    QVERIFY(!panel.firasimBox()->isChecked());
    QVERIFY(panel.firasimLabel()->text().contains("port 20011 taken"));
    QCOMPARE(toggled.size(), 1);
}

void TestUiPanels::cameraViewMatchesTheRenderer() {
    const Snapshot s = makeSnapshot();
    CameraView view;
    QVERIFY(view.image().isNull());
    view.showSnapshot(s);  // no scene yet: ignored
    QVERIFY(view.image().isNull());
    view.setScene(*s.scene);
    view.showSnapshot(s);
    const QImage image = view.image();
    QCOMPARE(image.format(), QImage::Format_RGB888);

    const CameraRenderer renderer(*s.scene);
    WorldState state = initialWorldState(*s.scene);
    state.robots = s.robots;
    state.ball = s.ball;
    cv::Mat bgr;
    std::vector<cv::Rect> patches;
    renderer.render(state, bgr, patches);
    QCOMPARE(image.size(), QSize(bgr.cols, bgr.rows));
    for (int y = 0; y < bgr.rows; ++y)
        for (int x = 0; x < bgr.cols; ++x) {
            const cv::Vec3b want = bgr.at<cv::Vec3b>(y, x);
            const QRgb got = image.pixel(x, y);
            if (qRed(got) != want[2] || qGreen(got) != want[1] || qBlue(got) != want[0])
                QFAIL(qPrintable(QStringLiteral("pixel %1,%2 differs").arg(x).arg(y)));
        }

    const Eigen::Vector2d ball = toPixel(renderer.geometry(), s.ball.x, s.ball.y);
    QCOMPARE(image.pixelColor(int(ball.x()), int(ball.y())), QColor(255, 128, 0));
    const Eigen::Vector2d robot = toPixel(renderer.geometry(), s.robots[0].x, s.robots[0].y);
    QVERIFY(image.pixelColor(int(robot.x()), int(robot.y())) != QColor(20, 20, 20));  // not the floor

    // The ball moves with the snapshot.
    Snapshot moved = s;
    moved.ball.x = -0.5;
    view.showSnapshot(moved);
    QVERIFY(view.image().pixelColor(int(ball.x()), int(ball.y())) != QColor(255, 128, 0));

    view.resize(320, 400);
    QVERIFY(!view.grab().isNull());
}

// The image a renderer with `camera` gives for the snapshot, as RGB888.
QImage renderedImage(const Snapshot& s, const CameraSettings& camera) {
    const CameraRenderer renderer(*s.scene, camera);
    WorldState state = initialWorldState(*s.scene);
    state.robots = s.robots;
    state.ball = s.ball;
    cv::Mat bgr;
    std::vector<cv::Rect> patches;
    renderer.render(state, bgr, patches, static_cast<std::uint64_t>(s.frame));
    QImage image(bgr.cols, bgr.rows, QImage::Format_RGB888);
    for (int y = 0; y < bgr.rows; ++y)
        for (int x = 0; x < bgr.cols; ++x) {
            const cv::Vec3b c = bgr.at<cv::Vec3b>(y, x);
            image.setPixel(x, y, qRgb(c[2], c[1], c[0]));
        }
    return image;
}

void TestUiPanels::cameraViewPreviewsThePresets() {
    const Snapshot s = makeSnapshot();
    CameraView view;
    view.setScene(*s.scene);
    view.showSnapshot(s);
    QCOMPARE(view.preview(), CameraView::Preview::Scene);
    QVERIFY(view.shownCamera() == s.scene->camera);
    const QImage ideal = view.image();
    QCOMPARE(ideal, renderedImage(s, idealCamera()));  // the scene has no camera key: the ideal camera

    // Choosing the realistic preview in the combo box redraws the last
    // snapshot through the realistic camera, the frame number seeding its noise.
    view.previewBox()->setCurrentIndex(2);
    QCOMPARE(view.preview(), CameraView::Preview::Realistic);
    QVERIFY(view.shownCamera() == realisticCamera());
    const QImage realistic = view.image();
    QCOMPARE(realistic, renderedImage(s, realisticCamera()));
    QVERIFY(realistic != ideal);
    // Its corners are darker than the ideal image's (vignetting), its floor noisy.
    const QColor idealCorner = ideal.pixelColor(2, 2), realCorner = realistic.pixelColor(2, 2);
    QVERIFY2(realCorner.value() < idealCorner.value(), qPrintable(realCorner.name() + " vs " + idealCorner.name()));

    // Back to the scene's camera by the API; the combo box follows.
    view.setPreview(CameraView::Preview::Scene);
    QCOMPARE(view.previewBox()->currentIndex(), 0);
    QCOMPARE(view.image(), ideal);
    // A scene with its own camera: the first item shows it.
    Scene withCamera = *s.scene;
    withCamera.camera = realisticCamera();
    withCamera.camera.noise = 0.0;
    view.setScene(withCamera);
    Snapshot t = s;
    t.scene = std::make_shared<const Scene>(withCamera);
    view.showSnapshot(t);
    QCOMPARE(view.image(), renderedImage(t, withCamera.camera));
    view.setPreview(CameraView::Preview::Ideal);
    QCOMPARE(view.image(), ideal);
}

void TestUiPanels::statusLine() {
    Snapshot s = makeSnapshot(12.3454);
    s.frame = 411;
    const QString running = statusText(s, 0.998);
    QVERIFY2(running.contains("t = 12.345 s"), qPrintable(running));
    QVERIFY(running.contains("frame 411"));
    QVERIFY(running.contains("realtime x1.00"));
    QVERIFY(running.contains("x1.00 real time"));
    QVERIFY(running.contains("engine 0.9 ms per simulated s"));
    QVERIFY(!running.contains("paused"));

    s.paused = true;
    s.mode = RunMode::Max;
    const QString paused = statusText(s, 0.0);
    QVERIFY2(paused.contains("max"), qPrintable(paused));
    QVERIFY(!paused.contains("realtime"));
    QVERIFY(paused.endsWith("paused"));
    // Paused, nothing runs: no real-time factor, no engine cost.
    s.mode = RunMode::Realtime;
    const QString pausedRealtime = statusText(s, 0.06);
    QVERIFY2(!pausedRealtime.contains("real time") && !pausedRealtime.contains("engine"), qPrintable(pausedRealtime));
    s.mode = RunMode::Max;
    s.mode = RunMode::Lockstep;
    QVERIFY(statusText(s, std::nan("")).contains("lockstep"));
    QVERIFY(!statusText(s, std::nan("")).contains("real time"));
}

void TestUiPanels::scoreboardShowsTheGame() {
    Scoreboard board;
    GameRules rules;
    rules.referee = true;
    GameState game;
    game.phase = GamePhase::Stop;
    game.stopLeft = 3.21;
    game.half = 2;
    game.clock = 133.9;
    game.goals = {2, 1};
    game.last.call = Call::FreeBall;
    game.last.quadrant = 2;
    game.last.half = 2;
    game.last.clock = 72.5;
    game.last.reason = "ball stuck";
    board.setGame(game, rules, TeamControl::Builtin, TeamControl::Remote);
    QCOMPARE(board.scoreText(), QString("Yellow 2 : 1 Blue"));
    QCOMPARE(board.clockText(), QString("Half 2 of 2 · 02:13 of 05:00"));
    QCOMPARE(board.phaseText(), QString("STOP (game on in 3.2 s)"));
    QCOMPARE(board.lastCallText(), QString("Last call: Free ball, quadrant 2: ball stuck (half 2, 01:12)"));
    QCOMPARE(board.findChild<QComboBox*>("scoreboard.yellowControl")->currentText(), QString("Built-in"));
    QCOMPARE(board.findChild<QComboBox*>("scoreboard.blueControl")->currentText(), QString("TCP / by hand"));
    QVERIFY(board.findChild<QPushButton*>("scoreboard.gameOn")->isEnabled());
    game.phase = GamePhase::Finished;
    board.setGame(game, rules, TeamControl::Builtin, TeamControl::Remote);
    QCOMPARE(board.phaseText(), QString("FULL TIME"));
    QVERIFY(!board.findChild<QPushButton*>("scoreboard.penalty")->isEnabled());
    // Referee off: no clock, no calls; the team choosers still work.
    rules.referee = false;
    board.setGame(GameState{}, rules, TeamControl::Idle, TeamControl::Idle);
    QVERIFY(board.clockText().contains("Referee off"));
    QVERIFY(!board.findChild<QPushButton*>("scoreboard.freeBall1")->isEnabled());
    QVERIFY(!board.findChild<QPushButton*>("scoreboard.halt")->isEnabled());
    QVERIFY(board.findChild<QComboBox*>("scoreboard.blueControl")->isEnabled());
    QCOMPARE(gameClockText(299.999), QString("04:59"));
    QCOMPARE(gameClockText(std::nan("")), QString("00:00"));
}

void TestUiPanels::scoreboardButtonsAskForCalls() {
    Scoreboard board;
    GameRules rules;
    rules.referee = true;
    GameState game;
    game.phase = GamePhase::GameOn;
    board.setGame(game, rules, TeamControl::Remote, TeamControl::Builtin);
    QSignalSpy calls(&board, &Scoreboard::callRequested);
    QSignalSpy halts(&board, &Scoreboard::haltRequested);
    QSignalSpy controls(&board, &Scoreboard::teamControlRequested);
    board.findChild<QPushButton*>("scoreboard.freeBall3")->click();
    QCOMPARE(calls.size(), 1);
    QCOMPARE(calls.at(0).at(0).value<Call>(), Call::FreeBall);
    QCOMPARE(calls.at(0).at(2).toInt(), 3);
    auto* team = board.findChild<QComboBox*>("scoreboard.callTeam");
    team->setCurrentIndex(team->findData(int(Team::Blue)));
    board.findChild<QPushButton*>("scoreboard.penalty")->click();
    QCOMPARE(calls.at(1).at(0).value<Call>(), Call::PenaltyKick);
    QCOMPARE(calls.at(1).at(1).value<Team>(), Team::Blue);
    board.findChild<QPushButton*>("scoreboard.halt")->click();
    QCOMPARE(halts.size(), 1);
    // Choosing asks; showing a game does not.
    auto* yellow = board.findChild<QComboBox*>("scoreboard.yellowControl");
    yellow->setCurrentIndex(yellow->findData(int(TeamControl::Idle)));
    QCOMPARE(controls.size(), 1);
    QCOMPARE(controls.at(0).at(0).value<Team>(), Team::Yellow);
    QCOMPARE(controls.at(0).at(1).value<TeamControl>(), TeamControl::Idle);
    board.setGame(game, rules, TeamControl::Builtin, TeamControl::Idle);
    QCOMPARE(controls.size(), 1);
}

QTEST_MAIN(TestUiPanels)
#include "test_ui_panels.moc"
