// The vssim executable as a user runs it: help, CSV output, and every kind
// of bad input giving a clear message, a non-zero exit and no output file.
#include <QtTest>

#include <Eigen/Eigenvalues>
#include <QTemporaryDir>

#include "io/scene_io.h"
#include "run_vssim.h"
#include "vssim/robot_model.h"
#include "vssim/world.h"

using namespace vssim;

namespace {

using test::Result;
using test::runVssim;

QString sceneFile(const char* name) { return QStringLiteral(VSSIM_SOURCE_DIR "/resources/scenes/%1").arg(name); }

const char* kHeader = "t,body,x,y,theta,v,omega,e_right,e_left,omega_right,omega_left,i_right,i_left";

}  // namespace

class TestCli : public QObject {
    Q_OBJECT
private slots:
    void helpDescribesEveryOption();
    void versionAndUnknownCommand();
    void csvHasHeaderAndOneRowPerBodyPerSample();
    void csvRoundTripsTheEngineState();
    void optionsOverrideTheScene();
    void builtinSceneByName();
    void outFileWrittenOnlyOnSuccess();
    void badInput_data();
    void badInput();
    void badInputLeavesExistingFileAlone();
    void noArgumentsRunsTheDemo();
    void finalStateAlwaysWritten();
    void warnsWhenTheStepIsUnstable();
};

void TestCli::helpDescribesEveryOption() {
    const Result main = runVssim({"--help"});
    QCOMPARE(main.exitCode, 0);
    QVERIFY(main.out.contains("vssim run"));
    const Result run = runVssim({"run", "--help"});
    QCOMPARE(run.exitCode, 0);
    for (const char* option : {"--duration", "--dt", "--integrator", "--collision-model", "--sample", "--out"})
        QVERIFY2(run.out.contains(option), option);
    QVERIFY(run.out.contains(kHeader));
}

void TestCli::versionAndUnknownCommand() {
    const Result v = runVssim({"--version"});
    QCOMPARE(v.exitCode, 0);
    QVERIFY(v.out.startsWith("vssim "));
    const Result bad = runVssim({"fly"});
    QCOMPARE(bad.exitCode, 2);
    QVERIFY(bad.err.contains("unknown command \"fly\""));
}

void TestCli::csvHasHeaderAndOneRowPerBodyPerSample() {
    const Result r = runVssim({"run", sceneFile("kickoff_3v3.json"), "--duration", "0.1", "--sample", "0.01"});
    QCOMPARE(r.exitCode, 0);
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    QCOMPARE(lines[0], QByteArray(kHeader));
    // 11 sample times (0, 0.01, ..., 0.1) x (6 robots + ball).
    QCOMPARE(lines.size(), 1 + 11 * 7);
    QVERIFY(lines[1].startsWith("0,"));
    QVERIFY(lines.last().startsWith("0.10000000000000001,ball,"));  // 100 * 0.001 printed to 17 digits
    QCOMPARE(lines.last().count(','), 12);  // ball rows keep every column, robot-only ones empty
    QVERIFY(lines.last().endsWith(",,,,,,,"));
    QVERIFY(r.err.contains("100 steps"));  // the summary goes to standard error
}

void TestCli::finalStateAlwaysWritten() {
    // 0.105 s with samples every 0.01 s: rows at 0, 0.01, ..., 0.1 and the
    // final state at step 105, which is not a multiple of the sample.
    const Result r = runVssim({"run", "kickoff_3v3", "--duration", "0.105", "--sample", "0.01"});
    QCOMPARE(r.exitCode, 0);
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    QCOMPARE(lines.size(), 1 + 12 * 7);
    QCOMPARE(lines.last().split(',').first().toDouble(), 105 * 0.001);
    QCOMPARE(lines[lines.size() - 8].split(',').first().toDouble(), 100 * 0.001);
    // With the exact integrator the summary counts its long steps.
    const Result exact =
        runVssim({"run", "kickoff_3v3", "--duration", "1", "--sample", "0.5", "--integrator", "exact"});
    QCOMPARE(exact.exitCode, 0);
    QVERIFY2(exact.err.contains(" long steps (exact)"), exact.err.constData());
}

void TestCli::csvRoundTripsTheEngineState() {
    // The CSV's numbers parse back to exactly the engine's state at the same step.
    const Result r = runVssim({"run", sceneFile("robot_hits_ball.json"), "--duration", "0.5", "--sample", "0.25"});
    QCOMPARE(r.exitCode, 0);
    QString error;
    const std::optional<Scene> scene = loadSceneFile(sceneFile("robot_hits_ball.json"), &error);
    QVERIFY2(scene, qPrintable(error));
    Simulation sim(*scene);
    while (sim.state().step < 500) sim.step();
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    const QList<QByteArray> robotRow = lines[lines.size() - 1 - static_cast<int>(scene->robots.size())].split(',');
    QCOMPARE(robotRow[1], QByteArray(scene->robots[0].name.c_str()));
    QCOMPARE(robotRow[0].toDouble(), sim.state().time);
    QCOMPARE(robotRow[2].toDouble(), sim.state().robots[0].x);
    QCOMPARE(robotRow[6].toDouble(), sim.state().robots[0].omega);
    QCOMPARE(robotRow[12].toDouble(), sim.robotOutputs(0).current_left);
    const QList<QByteArray> ballRow = lines.last().split(',');
    QCOMPARE(ballRow[2].toDouble(), sim.state().ball.x);
    QCOMPARE(ballRow[5].toDouble(), std::hypot(sim.state().ball.vx, sim.state().ball.vy));
}

void TestCli::optionsOverrideTheScene() {
    const QStringList base{"run", sceneFile("robot_hits_ball.json"), "--duration", "0.3", "--sample", "0.3"};
    const Result rk4 = runVssim(base);
    const Result again = runVssim(base);
    const Result euler = runVssim(base + QStringList{"--integrator", "euler"});
    const Result coarse = runVssim(base + QStringList{"--dt", "0.002"});
    QCOMPARE(rk4.exitCode, 0);
    QCOMPARE(again.out, rk4.out);  // deterministic
    QVERIFY(euler.out != rk4.out);
    QVERIFY(coarse.out != rk4.out);
    QVERIFY(euler.err.contains("euler"));
}

void TestCli::builtinSceneByName() {
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.01"});
    QCOMPARE(r.exitCode, 0);
    QVERIFY(r.out.startsWith(kHeader));
}

void TestCli::outFileWrittenOnlyOnSuccess() {
    QTemporaryDir dir;
    const QString out = dir.filePath("run.csv");
    const Result r = runVssim({"run", sceneFile("ball_walls.json"), "--duration", "0.05", "--out", out});
    QCOMPARE(r.exitCode, 0);
    QVERIFY(r.out.isEmpty());
    QFile f(out);
    QVERIFY(f.open(QIODevice::ReadOnly));
    QVERIFY(f.readLine().startsWith(kHeader));
}

void TestCli::badInput_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("sceneText");  // written to a temporary scene file named by %SCENE%
    QTest::addColumn<QString>("message");
    const QString ok = sceneFile("ball_walls.json");
    QTest::newRow("unknown option") << QStringList{"run", ok, "--duration", "1", "--speed", "2"} << ""
                                    << "Unknown option 'speed'";
    QTest::newRow("missing duration") << QStringList{"run", ok} << ""
                                      << "--duration is required";
    QTest::newRow("negative duration") << QStringList{"run", ok, "--duration", "-1"} << ""
                                       << "--duration: must be > 0 s";
    QTest::newRow("nan duration") << QStringList{"run", ok, "--duration", "nan"} << ""
                                  << "--duration: expected a number";
    QTest::newRow("text dt") << QStringList{"run", ok, "--duration", "1", "--dt", "fast"} << ""
                             << "--dt: expected a number of seconds, got \"fast\"";
    QTest::newRow("huge dt") << QStringList{"run", ok, "--duration", "1", "--dt", "0.5"} << ""
                             << "--dt: must be <= 0.1 s";
    QTest::newRow("bad integrator") << QStringList{"run", ok, "--duration", "1", "--integrator", "rk45"} << ""
                                    << "--integrator: expected euler, rk4 or exact, got \"rk45\"";
    QTest::newRow("bad collision model") << QStringList{"run", ok, "--duration", "1", "--collision-model", "soft"} << ""
                                         << "--collision-model: expected paper or impulse";
    QTest::newRow("sample below dt") << QStringList{"run", ok, "--duration", "1", "--sample", "0.0001"} << ""
                                     << "--sample: must be >= dt";
    QTest::newRow("too many steps") << QStringList{"run", ok, "--duration", "1e9", "--dt", "0.0001"} << ""
                                    << "steps";
    QTest::newRow("no scene") << QStringList{"run", "--duration", "1"} << ""
                              << "missing the scene file";
    QTest::newRow("two scenes") << QStringList{"run", ok, ok, "--duration", "1"} << ""
                                << "expected one scene file";
    QTest::newRow("missing file") << QStringList{"run", "/nonexistent/scene.json", "--duration", "1"} << ""
                                  << "no such file";
    QTest::newRow("syntax error") << QStringList{"run", "%SCENE%", "--duration", "1"} << "{\n  \"ball\": {\"x\": 0,}\n}"
                                  << "line 2";
    QTest::newRow("bad value") << QStringList{"run", "%SCENE%", "--duration", "1"}
                               << "{\"robots\": [{\"params\": {\"right\": {\"resistance\": \"high\"}}}]}"
                               << "robots[0].params.right.resistance: expected a number";
}

void TestCli::badInput() {
    QFETCH(QStringList, args);
    QFETCH(QString, sceneText);
    QFETCH(QString, message);
    QTemporaryDir dir;
    const QString scenePath = dir.filePath("scene.json");
    if (!sceneText.isEmpty()) {
        QFile f(scenePath);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write(sceneText.toUtf8());
    }
    args.replaceInStrings("%SCENE%", scenePath);
    const QString out = dir.filePath("out.csv");
    const Result r = runVssim(args + QStringList{"--out", out});
    QCOMPARE(r.exitCode, 2);
    QVERIFY2(QString::fromUtf8(r.err).contains(message), r.err.constData());
    QVERIFY2(r.err.startsWith("vssim run: "), r.err.constData());
    QVERIFY(r.out.isEmpty());
    QVERIFY(!QFile::exists(out));
}

void TestCli::badInputLeavesExistingFileAlone() {
    QTemporaryDir dir;
    const QString out = dir.filePath("keep.csv");
    {
        QFile f(out);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write("precious\n");
    }
    const Result r = runVssim({"run", sceneFile("ball_walls.json"), "--duration", "-3", "--out", out});
    QCOMPARE(r.exitCode, 2);
    QFile f(out);
    QVERIFY(f.open(QIODevice::ReadOnly));
    QCOMPARE(f.readAll(), QByteArray("precious\n"));
}

void TestCli::noArgumentsRunsTheDemo() {
    // Without a display there is no desktop app: the headless demo, and a word why.
    const Result r = runVssim({});
    QCOMPARE(r.exitCode, 0);
    QVERIFY(r.out.contains("kickoff_3v3"));
    QVERIFY(r.out.contains("yellow0"));
    QVERIFY(r.out.contains("ball"));
    QVERIFY(r.err.contains("no display"));
    const Result demo = runVssim({"demo"});
    QCOMPARE(demo.exitCode, 0);
    QVERIFY(demo.out.contains("kickoff_3v3") && demo.out.contains("yellow0"));
    QVERIFY(!demo.err.contains("no display"));
    const Result demoHelp = runVssim({"demo", "--help"});
    QCOMPARE(demoHelp.exitCode, 0);
    QVERIFY(demoHelp.out.startsWith("Usage: vssim demo"));
    const Result demoBad = runVssim({"demo", "--bogus"});
    QCOMPARE(demoBad.exitCode, 2);
    QVERIFY(demoBad.err.contains("--bogus"));
    const Result gui = runVssim({"gui"});
    QCOMPARE(gui.exitCode, 1);
    QVERIFY2(gui.err.contains("no display") && gui.err.contains("xvfb-run"), gui.err.constData());
    // Its help and option errors need no display.
    const Result help = runVssim({"gui", "--help"});
    QCOMPARE(help.exitCode, 0);
    QVERIFY(help.out.startsWith("Usage: vssim gui") && help.out.contains("--connect"));
    const Result bad = runVssim({"gui", "--port", "99999"});
    QCOMPARE(bad.exitCode, 2);
    QVERIFY(bad.err.contains("--port"));
}

void TestCli::warnsWhenTheStepIsUnstable() {
    // The stiff robot's fastest time constant is 36 us: RK4 at 1 ms is ten
    // times past its limit (101 us) and says so; exact, or RK4 at 50 us, does not.
    const Result rk4 = runVssim({"run", "stiff_robot", "--duration", "0.01"});
    QCOMPARE(rk4.exitCode, 0);
    // The limit, from A's eigenvalues found by Eigen's solver (independent of
    // the engine's closed form): 2.785 / |lambda|max.
    QString error;
    const std::optional<Scene> scene = loadSceneFile(sceneFile("stiff_robot.json"), &error);
    QVERIFY2(scene, qPrintable(error));
    const Eigen::Vector2d rates = makeRobotModel(scene->robots[0].params).A.eigenvalues().real();
    const double fastest = rates.cwiseAbs().maxCoeff();  // 1/s
    const QString expected = QStringLiteral(
                                 "warning: robot \"stiff\" has a motor time constant of %1 ms: rk4 is unstable "
                                 "for dt > %2 ms (dt = 1 ms); use --integrator exact")
                                 .arg(1e3 / fastest, 0, 'g', 3)
                                 .arg(2.785293563405282e3 / fastest, 0, 'g', 3);
    QVERIFY2(QString::fromUtf8(rk4.err).contains(expected), qPrintable("expected: " + expected + "\ngot: " + rk4.err));
    const Result exact = runVssim({"run", "stiff_robot", "--duration", "0.01", "--integrator", "exact"});
    const Result fine = runVssim({"run", "stiff_robot", "--duration", "0.01", "--dt", "0.00005"});
    QCOMPARE(exact.exitCode, 0);
    QCOMPARE(fine.exitCode, 0);
    QVERIFY2(!exact.err.contains("warning"), exact.err.constData());
    QVERIFY2(!fine.err.contains("warning"), fine.err.constData());
    // The default robot is far from any limit.
    QVERIFY(!runVssim({"run", "kickoff_3v3", "--duration", "0.01", "--dt", "0.1"}).err.contains("warning"));
}

QTEST_GUILESS_MAIN(TestCli)
#include "test_cli.moc"
