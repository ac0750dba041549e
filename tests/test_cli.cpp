// The vssim executable as a user runs it: help, CSV output, and every kind
// of bad input giving a clear message, a non-zero exit and no output file.
#include <QtTest>

#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>
#include <Eigen/Eigenvalues>
#include <QTemporaryDir>
#include <cerrno>
#include <climits>

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

QByteArray readAll(const QString& path) {
    QFile f(path);
    return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray("(unreadable)");
}

void writeFile(const QString& path, const QByteArray& content) {
    QFile f(path);
    QVERIFY(f.open(QIODevice::WriteOnly));
    QCOMPARE(f.write(content), content.size());
}

struct stat statOf(const QString& path) {
    struct stat st {};
    if (::lstat(QFile::encodeName(path).constData(), &st) != 0) st.st_mode = 0;
    return st;
}

// A robot within every documented range whose motors are far too stiff for
// RK4 at 10 ms (time constant 3e-15 s): its state overflows within two steps.
// (RK4 named: the default, exact, is stable for it.)
const char* kRunawayScene = R"({"simulation": {"integrator": "rk4", "dt": 0.01}, "ball": {"x": 0.5},
    "robots": [{"name": "wild", "params": {"mass": 0.01, "inertia": 1e-7,
        "right": {"resistance": 0.001, "k": 100, "rotor_inertia": 0},
        "left": {"resistance": 0.001, "k": 100, "rotor_inertia": 0}}}],
    "commands": [{"robot": "wild", "right": 7, "left": 7}]})";

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
    void warnsWhenTheBallIsUnstable();
    void outWritesADeviceInPlace();
    void outWritesAFifoInPlace();
    void outKeepsHardLinks();
    void outFollowsSymbolicLinks();
    void writeFailuresExitOne();
    void outToStandardOutputByName();
    void outLeavesNoTemporaryWhenKilled();
    void outRemovesTemporariesOfDeadRuns();
    void stopsOnANonFiniteState();
    void sceneThatIsNotAFile();
    void runPlaysTheScenesGame();
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
    // The summary goes to standard error (the kick-off's exact integrator
    // takes long steps: while the game is stopped, a tick of 10 ms each).
    QVERIFY2(r.err.contains("vssim run: 0.1 s simulated in ") && r.err.contains(" long steps (exact)"),
             r.err.constData());
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
    // Advanced as vssim run does, one advanceTo per sample: the scene's
    // integrator (exact, the default) takes long steps, which agree with
    // step() only to rounding.
    Simulation sim(*scene);
    sim.advanceTo(250);
    sim.advanceTo(500);
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
    const Result scenes = runVssim(base);  // the scene's integrator: the default, exact
    const Result again = runVssim(base);
    const Result euler = runVssim(base + QStringList{"--integrator", "euler"});
    const Result rk4 = runVssim(base + QStringList{"--integrator", "rk4"});
    const Result coarse = runVssim(base + QStringList{"--dt", "0.002"});
    const Result coarseRk4 = runVssim(base + QStringList{"--integrator", "rk4", "--dt", "0.002"});
    QCOMPARE(scenes.exitCode, 0);
    QCOMPARE(again.out, scenes.out);  // deterministic
    QVERIFY(euler.out != scenes.out);
    QVERIFY(rk4.out != scenes.out);
    // Before the robot reaches the ball exact's result does not depend on dt
    // (the point of it): the summary shows the new step; RK4's result changes.
    QVERIFY2(coarse.err.contains("steps of 0.002 s"), coarse.err.constData());
    QVERIFY(coarseRk4.out != rk4.out);
    QVERIFY(scenes.err.contains("exact"));
    QVERIFY(euler.err.contains("euler"));
    QVERIFY(rk4.err.contains("rk4"));
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
    QTest::newRow("bad referee") << QStringList{"run", ok, "--duration", "1", "--referee", "maybe"} << ""
                                 << "--referee: expected on or off, got \"maybe\"";
    QTest::newRow("referee on a box") << QStringList{"run", ok, "--duration", "1", "--referee", "on"} << ""
                                      << "--referee on: ";
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
    QVERIFY(help.out.contains("--read-only-observers"));
    const Result bad = runVssim({"gui", "--port", "99999"});
    QCOMPARE(bad.exitCode, 2);
    QVERIFY(bad.err.contains("--port"));
    // A scene whose camera cannot be drawn (its lens folds the image over)
    // is refused by vssim serve before it listens (vssim gui refuses it
    // too, once it has a display; the app's Open with a message).
    QTemporaryDir dir;
    const QString folding = dir.filePath("folding.json");
    writeFile(folding, R"({"camera": {"preset": "realistic", "k1": -1}})");
    const Result refused = runVssim({"serve", folding, "--port", "0"});
    QCOMPARE(refused.exitCode, 2);
    QVERIFY2(refused.err.contains("folding.json") && refused.err.contains("distortion"), refused.err.constData());
}

void TestCli::warnsWhenTheStepIsUnstable() {
    // The stiff robot's fastest time constant is 36 us: RK4 at 1 ms (its scene's
    // integrator) is ten times past its limit (101 us) and says so; exact, or
    // RK4 at 50 us, does not.
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

void TestCli::warnsWhenTheBallIsUnstable() {
    // Friction 200 N s/m on the 46 g ball: lambda = -200/0.046 = -4348 /s, and
    // RK4 is stable for h |lambda| <= 2.785 (0.641 ms), Euler for <= 2 (0.46
    // ms). At 1 ms the ball went from 1 m/s to 1,100 m/s without a word.
    QTemporaryDir dir;
    const QString scene = dir.filePath("sticky.json");
    writeFile(scene, R"({"simulation": {"integrator": "rk4"}, "ball": {"vx": 1, "friction": 200}})");
    const double rate = 200 / 0.046;  // 1/s
    const Result rk4 = runVssim({"run", scene, "--duration", "0.01"});
    QCOMPARE(rk4.exitCode, 0);
    const QString expected = QStringLiteral(
                                 "vssim run: warning: the ball has a friction time constant (mass/friction) of %1 ms: "
                                 "rk4 is unstable for dt > %2 ms (dt = 1 ms); use --integrator exact or a --dt below "
                                 "%2 ms\n")
                                 .arg(1e3 / rate, 0, 'g', 3)
                                 .arg(2.785293563405282e3 / rate, 0, 'g', 3);
    QVERIFY2(QString::fromUtf8(rk4.err).contains(expected), qPrintable("expected: " + expected + "got: " + rk4.err));
    QVERIFY(expected.contains("of 0.23 ms") && expected.contains("dt > 0.641 ms"));
    const Result euler = runVssim({"run", scene, "--duration", "0.01", "--integrator", "euler", "--dt", "0.0005"});
    QVERIFY2(euler.err.contains("euler is unstable for dt > 0.46 ms (dt = 0.5 ms)"), euler.err.constData());
    // Within the limits, or exact: no warning.
    for (const QStringList& options : {QStringList{"--dt", "0.0006"}, QStringList{"--integrator", "exact"}}) {
        const Result quiet = runVssim(QStringList{"run", scene, "--duration", "0.01"} + options);
        QCOMPARE(quiet.exitCode, 0);
        QVERIFY2(!quiet.err.contains("warning"), quiet.err.constData());
    }
    // The same ball in a scene that names no integrator gets the default, exact: no warning.
    const QString byDefault = dir.filePath("sticky_default.json");
    writeFile(byDefault, R"({"ball": {"vx": 1, "friction": 200}})");
    const Result quiet = runVssim({"run", byDefault, "--duration", "0.01"});
    QCOMPARE(quiet.exitCode, 0);
    QVERIFY2(!quiet.err.contains("warning") && quiet.err.contains("(exact)"), quiet.err.constData());
}

void TestCli::outWritesADeviceInPlace() {
    // --out used to write a temporary file and rename it over the target: as
    // root, `--out /dev/null` made /dev/null a regular file. Here on device
    // nodes made in a temporary folder (never the system's own): the null
    // device takes the CSV and stays a device; the full device fails with the
    // system's reason and exit 1.
    QTemporaryDir dir;
    const QString null = dir.filePath("null"), full = dir.filePath("full");
    const bool root = ::geteuid() == 0;
    const int madeNull = ::mknod(QFile::encodeName(null).constData(), S_IFCHR | 0666, makedev(1, 3));
    const int madeFull = ::mknod(QFile::encodeName(full).constData(), S_IFCHR | 0666, makedev(1, 7));
    if (!root) {
        // Without root no device can be made (and none replaced): the full
        // device case runs on the system's /dev/full, which an ordinary user
        // cannot replace, and writing to it is harmless.
        QCOMPARE(madeNull, -1);
        QCOMPARE(errno, EPERM);
        const Result r = runVssim({"run", "ball_walls", "--duration", "0.01", "--out", "/dev/full"});
        QCOMPARE(r.exitCode, 1);
        QVERIFY2(r.err.contains("vssim run: failed to write /dev/full: No space left on device"), r.err.constData());
        QVERIFY(S_ISCHR(statOf("/dev/full").st_mode));
        return;
    }
    QCOMPARE(madeNull, 0);
    QCOMPARE(madeFull, 0);
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.01", "--out", null});
    QCOMPARE(r.exitCode, 0);
    QVERIFY2(S_ISCHR(statOf(null).st_mode), "the null device was replaced");
    QCOMPARE(statOf(null).st_rdev, makedev(1, 3));
    QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::System | QDir::NoDotAndDotDot).size(), 2);
    const Result f = runVssim({"run", "ball_walls", "--duration", "0.01", "--out", full});
    QCOMPARE(f.exitCode, 1);
    QVERIFY2(
        f.err.contains(QStringLiteral("vssim run: failed to write %1: No space left on device").arg(full).toUtf8()),
        f.err.constData());
    QVERIFY(S_ISCHR(statOf(full).st_mode));
    QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::System | QDir::NoDotAndDotDot).size(), 2);
}

void TestCli::outWritesAFifoInPlace() {
    // A FIFO gets the CSV through itself (a reader process reads it) and
    // stays a FIFO; renamed over, the reader would wait for ever.
    QTemporaryDir dir;
    const QString fifo = dir.filePath("pipe");
    QCOMPARE(::mkfifo(QFile::encodeName(fifo).constData(), 0600), 0);
    QProcess reader;
    reader.start("cat", {fifo});
    QVERIFY(reader.waitForStarted());
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.05", "--out", fifo});
    const bool readerDone = reader.waitForFinished(20000);
    if (!readerDone) reader.kill();
    QCOMPARE(r.exitCode, 0);
    QVERIFY2(readerDone, "the reader of the FIFO got no end of file");
    const Result plain = runVssim({"run", "ball_walls", "--duration", "0.05"});
    QCOMPARE(reader.readAllStandardOutput(), plain.out);
    QVERIFY(S_ISFIFO(statOf(fifo).st_mode));
}

void TestCli::outKeepsHardLinks() {
    // A file with two names: both see the new CSV, still one file.
    QTemporaryDir dir;
    const QString a = dir.filePath("a.csv"), b = dir.filePath("b.csv");
    writeFile(a, "old\n");
    QCOMPARE(::link(QFile::encodeName(a).constData(), QFile::encodeName(b).constData()), 0);
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.05", "--out", a});
    QCOMPARE(r.exitCode, 0);
    const Result plain = runVssim({"run", "ball_walls", "--duration", "0.05"});
    QCOMPARE(readAll(a), plain.out);
    QCOMPARE(readAll(b), plain.out);
    QCOMPARE(statOf(a).st_ino, statOf(b).st_ino);
    QCOMPARE(statOf(a).st_nlink, nlink_t(2));
}

void TestCli::outFollowsSymbolicLinks() {
    // The link's target gets the CSV (through a relative link and a chain of
    // two); the links stay links. A single-link regular file is still
    // replaced only when the run succeeds.
    QTemporaryDir dir;
    QVERIFY(QDir(dir.path()).mkdir("sub"));
    const QString target = dir.filePath("sub/target.csv"), link = dir.filePath("link.csv"),
                  link2 = dir.filePath("sub/link2.csv");
    writeFile(target, "old\n");
    QCOMPARE(::symlink("target.csv", QFile::encodeName(link2).constData()), 0);
    QCOMPARE(::symlink("sub/link2.csv", QFile::encodeName(link).constData()), 0);
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.05", "--out", link});
    QCOMPARE(r.exitCode, 0);
    QVERIFY(S_ISLNK(statOf(link).st_mode));
    QVERIFY(S_ISLNK(statOf(link2).st_mode));
    QVERIFY(S_ISREG(statOf(target).st_mode));
    QCOMPARE(readAll(link), runVssim({"run", "ball_walls", "--duration", "0.05"}).out);
    QCOMPARE(QDir(dir.filePath("sub")).entryList(QDir::AllEntries | QDir::System | QDir::NoDotAndDotDot).size(), 2);
    // A dangling link: the file is created where it points.
    const QString dangling = dir.filePath("dangling.csv");
    QCOMPARE(::symlink("sub/new.csv", QFile::encodeName(dangling).constData()), 0);
    QCOMPARE(runVssim({"run", "ball_walls", "--duration", "0.01", "--out", dangling}).exitCode, 0);
    QVERIFY(S_ISLNK(statOf(dangling).st_mode));
    QVERIFY(readAll(dir.filePath("sub/new.csv")).startsWith(kHeader));
    // A directory is refused as it is.
    const Result d = runVssim({"run", "ball_walls", "--duration", "0.01", "--out", dir.filePath("sub")});
    QCOMPARE(d.exitCode, 2);
    QVERIFY2(d.err.contains("vssim run: cannot write " + QFile::encodeName(dir.filePath("sub")) + ": Is a directory"),
             d.err.constData());
}

// /dev/stdout is a link whose text ("pipe:[123]") is no path: it is written
// in place, through the name, like any other non-regular file.
void TestCli::outToStandardOutputByName() {
    const Result r = runVssim({"run", "robot_hits_ball", "--duration", "0.01", "--out", "/dev/stdout"});
    QVERIFY2(r.exitCode == 0, r.err.constData());
    QVERIFY(r.out.startsWith("t,body,x,y,theta"));
    QVERIFY(r.out.count('\n') > 10);
}

// The bytes a process has written so far to a file it holds open in `dir`
// (through /proc: the file may have no name), or -1 when it holds none.
qint64 bytesWrittenInto(qint64 pid, const QString& dir) {
    const QString fds = QStringLiteral("/proc/%1/fd").arg(pid);
    for (const QString& fd : QDir(fds).entryList(QDir::AllEntries | QDir::System | QDir::NoDotAndDotDot)) {
        const QByteArray path = QFile::encodeName(fds + "/" + fd);
        char target[PATH_MAX];
        const ssize_t n = ::readlink(path.constData(), target, sizeof target);
        if (n <= 0 || !QByteArray(target, static_cast<int>(n)).startsWith(QFile::encodeName(dir) + "/")) continue;
        struct stat st {};
        if (::stat(path.constData(), &st) == 0 && S_ISREG(st.st_mode)) return st.st_size;
    }
    return -1;
}

void TestCli::outLeavesNoTemporaryWhenKilled() {
    // A run killed with SIGKILL (no clean-up runs) while it writes: the old
    // file is as it was, and nothing else is left in its folder (its partial
    // CSV used to stay for ever as run.csv.vssim-PID-0).
    QTemporaryDir dir;
    const QString out = dir.filePath("run.csv");
    writeFile(out, "old\n");
    QProcess p;
    p.start(VSSIM_BINARY, {"run", "kickoff_3v3", "--duration", "100000", "--out", out});
    QVERIFY(p.waitForStarted());
    const qint64 pid = p.processId();
    const auto stop = qScopeGuard([&] {
        p.kill();
        p.waitForFinished();
    });
    // Until some of the CSV is in the file being written.
    QVERIFY2(QTest::qWaitFor([&] { return bytesWrittenInto(pid, QDir(dir.path()).canonicalPath()) > 0; }, 60000),
             "the run wrote nothing");
    QCOMPARE(::kill(static_cast<pid_t>(pid), SIGKILL), 0);
    QVERIFY(p.waitForFinished(10000));
    QCOMPARE(p.exitStatus(), QProcess::CrashExit);
    QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::System | QDir::Hidden | QDir::NoDotAndDotDot),
             QStringList{"run.csv"});
    QCOMPARE(readAll(out), QByteArray("old\n"));
}

void TestCli::outRemovesTemporariesOfDeadRuns() {
    // Temporaries that runs killed before this change left beside the
    // target (or that a run killed while it renames leaves): the next run
    // into the same file removes those of processes that no longer exist,
    // and never one of a living process (which may be about to rename it).
    QProcess gone;
    gone.start("true", QStringList());
    QVERIFY(gone.waitForStarted());
    const QString dead = QString::number(gone.processId());
    QVERIFY(gone.waitForFinished());
    const QString alive = QString::number(::getpid());
    QTemporaryDir dir;
    const QString out = dir.filePath("run.csv");
    const QStringList removed = {"run.csv.vssim-" + dead + "-0", "run.csv.vssim-" + dead + "-12"};
    const QStringList kept = {"run.csv.vssim-" + alive + "-0",        // a living process's
                              "other.csv.vssim-" + dead + "-0",       // another file's
                              "run.csv.vssim-" + dead + "-0.keep",    // not a temporary's name
                              "run.csv.vssim-" + dead + "-",          // nor this
                              "run.csv.vssim-x" + dead + "-0",        // nor this
                              "run.csv.vssim-99999999999-0",         // no process id
                              "run.csv"};
    for (const QString& name : removed + kept) writeFile(dir.filePath(name), "partial\n");
    const Result r = runVssim({"run", "ball_walls", "--duration", "0.01", "--out", out});
    QCOMPARE(r.exitCode, 0);
    QStringList expected = kept, left = QDir(dir.path()).entryList(QDir::AllEntries | QDir::System | QDir::Hidden |
                                                                    QDir::NoDotAndDotDot);
    expected.sort();
    left.sort();
    QCOMPARE(left, expected);
    QVERIFY(readAll(out).startsWith(kHeader));
    // A temporary of a living process stays even when it is the target's only company.
    QCOMPARE(readAll(dir.filePath("run.csv.vssim-" + alive + "-0")), QByteArray("partial\n"));
}

void TestCli::writeFailuresExitOne() {
    // Standard output on a full device, and closed: both ended with exit 0
    // and the CSV lost. /dev/full is opened here as the child's standard
    // output (as `> /dev/full` does), which only writes to it.
    const Result full = runVssim({"run", "kickoff_3v3", "--duration", "0.01"},
                                 [](QProcess& p) { p.setStandardOutputFile("/dev/full"); });
    QCOMPARE(full.exitCode, 1);
    QVERIFY2(full.err.contains("vssim run: failed to write standard output: No space left on device\n"),
             full.err.constData());
    const Result closed = runVssim({"run", "kickoff_3v3", "--duration", "0.01"},
                                   [](QProcess& p) { p.setChildProcessModifier([] { ::close(STDOUT_FILENO); }); });
    QCOMPARE(closed.exitCode, 1);
    QVERIFY2(closed.err.contains("vssim run: failed to write standard output: Bad file descriptor (it is closed)\n"),
             closed.err.constData());
    // A closed standard error: nothing else may take its descriptor (the CSV
    // file would get the messages).
    QTemporaryDir dir;
    const QString out = dir.filePath("out.csv");
    const Result quiet = runVssim({"run", "kickoff_3v3", "--duration", "0.01", "--out", out},
                                  [](QProcess& p) { p.setChildProcessModifier([] { ::close(STDERR_FILENO); }); });
    QCOMPARE(quiet.exitCode, 0);
    QCOMPARE(readAll(out), runVssim({"run", "kickoff_3v3", "--duration", "0.01"}).out);
}

void TestCli::stopsOnANonFiniteState() {
    // A NaN state used to be written as 2,000 rows of "nan" with exit 0. The
    // run stops at the first non-finite state, says when and which body, and
    // writes the rows before it.
    QTemporaryDir dir;
    const QString scene = dir.filePath("runaway.json");
    writeFile(scene, kRunawayScene);
    const Result r = runVssim({"run", scene, "--duration", "1"});
    QCOMPARE(r.exitCode, 1);
    QVERIFY2(r.err.contains("vssim run: stopped: at t = 0.02 s, robot \"wild\" (x = nan m, y = nan m, theta = nan rad, "
                            "v = nan m/s, omega = nan rad/s) has a non-finite state"),
             r.err.constData());
    QVERIFY(!r.out.toLower().contains("nan"));
    const QList<QByteArray> lines = r.out.trimmed().split('\n');
    QCOMPARE(lines.size(), 1 + 2 * 2);  // header, samples at 0 and 0.01 s (robot and ball)
    QVERIFY(lines.last().startsWith("0.01,ball,"));
    // With sparse samples the message says since when it was finite.
    const Result sparse = runVssim({"run", scene, "--duration", "1", "--sample", "0.5"});
    QCOMPARE(sparse.exitCode, 1);
    QVERIFY2(sparse.err.contains("at t = 0.5 s, robot \"wild\"") && sparse.err.contains("(it was finite at t = 0 s)"),
             sparse.err.constData());
    // With --out, a failed run leaves no file.
    const QString out = dir.filePath("out.csv");
    QCOMPARE(runVssim({"run", scene, "--duration", "1", "--out", out}).exitCode, 1);
    QVERIFY(!QFile::exists(out));
}

void TestCli::sceneThatIsNotAFile() {
    // A directory or a FIFO given as the scene was "no such file or built-in scene".
    QTemporaryDir dir;
    const QString fifo = dir.filePath("scene.json");
    QCOMPARE(::mkfifo(QFile::encodeName(fifo).constData(), 0600), 0);
    const Result d = runVssim({"run", dir.path(), "--duration", "1"});
    QCOMPARE(d.exitCode, 2);
    QVERIFY2(d.err.contains(dir.path().toUtf8() + ": is a directory, not a scene file"), d.err.constData());
    const Result f = runVssim({"run", fifo, "--duration", "1"});
    QCOMPARE(f.exitCode, 2);
    QVERIFY2(f.err.contains(fifo.toUtf8() + ": is a FIFO (named pipe), not a scene file"), f.err.constData());
    const Result missing = runVssim({"run", dir.filePath("nothing.json"), "--duration", "1"});
    QVERIFY2(missing.err.contains("nothing.json: no such file or built-in scene (built-in: ball_walls,"),
             missing.err.constData());
}

void TestCli::runPlaysTheScenesGame() {
    // The kick-off is a match: after its 4 s STOP the built-in teams play,
    // and the score and calls go to standard error.
    const Result game = runVssim({"run", "kickoff_3v3", "--duration", "8", "--sample", "0.5"});
    QCOMPARE(game.exitCode, 0);
    QVERIFY2(game.err.contains("vssim run: game: yellow "), game.err.constData());
    const QList<QByteArray> rows = game.out.trimmed().split('\n');
    // yellow2 at t = 0 (placed for the kick-off) and at the end: it moved.
    QByteArray first, last;
    for (const QByteArray& row : rows)
        if (row.contains(",yellow2,")) (first.isEmpty() ? first : last) = row;
    QVERIFY(!first.isEmpty() && !last.isEmpty() && first.split(',')[2] != last.split(',')[2]);
    // The same final state whatever the sampling (RK4: fixed steps; the game
    // acts at its ticks only). RK4 named: the kick-off's own integrator, exact,
    // takes long steps that depend on the samples and agrees only to rounding.
    const Result fine = runVssim({"run", "kickoff_3v3", "--duration", "8", "--sample", "0.5", "--integrator", "rk4"});
    const QList<QByteArray> fineRows = fine.out.trimmed().split('\n');
    const Result coarse = runVssim({"run", "kickoff_3v3", "--duration", "8", "--sample", "2", "--integrator", "rk4"});
    const QList<QByteArray> coarseRows = coarse.out.trimmed().split('\n');
    QCOMPARE(coarseRows.mid(coarseRows.size() - 7), fineRows.mid(fineRows.size() - 7));
    // Without the referee: no game line.
    const Result off = runVssim({"run", "kickoff_3v3", "--duration", "1", "--referee", "off"});
    QCOMPARE(off.exitCode, 0);
    QVERIFY(!off.err.contains("game:"));
}

QTEST_GUILESS_MAIN(TestCli)
#include "test_cli.moc"
