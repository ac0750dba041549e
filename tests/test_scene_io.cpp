// Scene files: defaults, overrides, round trip, and the error messages that
// name the key path (docs/scenes.md).
#include <QtTest>

#include <QDir>

#include "io/scene_io.h"

using namespace vssim;

namespace {

const char* kIssueExample = R"({
  "version": 1,
  "field": {"length": 1.5, "width": 1.3},
  "simulation": {"integrator": "rk4", "dt": 0.001, "collision_model": "paper", "restitution": 1.0},
  "robot_defaults": {"side": 0.075, "mass": 0.18, "inertia": 1.6875e-4,
      "wheel_base": 0.065, "friction_linear": 0.05, "friction_angular": 0.0002, "max_voltage": 7.4,
      "right": {"wheel_radius": 0.025, "resistance": 12, "k": 0.09, "rotor_inertia": 1e-5, "friction": 1e-4},
      "left":  {"wheel_radius": 0.025, "resistance": 12, "k": 0.09, "rotor_inertia": 1e-5, "friction": 1e-4}},
  "ball": {"x": 0, "y": 0, "vx": 0, "vy": 0, "mass": 0.046, "radius": 0.02135, "friction": 0.02},
  "robots": [{"name": "yellow0", "team": "yellow", "x": -0.3, "y": 0, "theta": 0, "v": 0, "omega": 0,
              "params": {"right": {"resistance": 11.5}}}],
  "commands": [{"t": 0.0, "robot": "yellow0", "right": 3.0, "left": 2.5}]
})";

Scene parseOk(const QByteArray& json) {
    QString error;
    const std::optional<Scene> scene = parseScene(json, &error);
    if (!scene) qFatal("unexpected error: %s", qPrintable(error));
    return *scene;
}

}  // namespace

class TestSceneIo : public QObject {
    Q_OBJECT
private slots:
    void emptySceneHasModelDefaults();
    void issueExampleLandsInTheRightFields();
    void paramsOverrideKeyByKey();
    void inertiaDefaultsToUniformCubeAfterOverrides();
    void namesDefaultPerTeam();
    void roundTripIsExact();
    void badInput_data();
    void badInput();
    void unreadableFile();
    void exampleScenesLoad();
};

void TestSceneIo::emptySceneHasModelDefaults() {
    // model.md §9, written out here as the independent source.
    const Scene s = parseOk(R"({"robots": [{}]})");
    QCOMPARE(s.field.length, 1.50);
    QCOMPARE(s.field.width, 1.30);
    QCOMPARE(s.field.walls.size(), std::size_t(4));
    QCOMPARE(s.simulation.dt, 0.001);
    QCOMPARE(s.simulation.integrator, Integrator::Rk4);
    QCOMPARE(s.simulation.collision_model, CollisionModel::Paper);
    QCOMPARE(s.ball_params.mass, 0.046);
    QCOMPARE(s.ball_params.radius, 0.02135);
    QCOMPARE(s.ball_params.friction, 0.02);
    const RobotParams& p = s.robots[0].params;
    QCOMPARE(p.side, 0.075);
    QCOMPARE(p.mass, 0.18);
    QVERIFY(qAbs(p.inertia - 0.18 * 0.075 * 0.075 / 6) < 1e-20);
    QCOMPARE(p.wheel_base, 0.065);
    QCOMPARE(p.friction_linear, 0.05);
    QCOMPARE(p.friction_angular, 0.0002);
    QCOMPARE(p.max_voltage, 7.4);
    for (const MotorParams& m : {p.right, p.left}) {
        QCOMPARE(m.wheel_radius, 0.025);
        QCOMPARE(m.resistance, 12.0);
        QCOMPARE(m.k, 0.09);
        QCOMPARE(m.rotor_inertia, 1e-5);
        QCOMPARE(m.friction, 1e-4);
    }
}

void TestSceneIo::issueExampleLandsInTheRightFields() {
    const Scene s = parseOk(kIssueExample);
    QCOMPARE(s.robots.size(), std::size_t(1));
    QCOMPARE(s.robots[0].name, std::string("yellow0"));
    QCOMPARE(s.robots[0].team, Team::Yellow);
    QCOMPARE(s.robots[0].initial.x, -0.3);
    QCOMPARE(s.robots[0].params.inertia, 1.6875e-4);
    QCOMPARE(s.commands.size(), std::size_t(1));
    QCOMPARE(s.commands[0].robot, 0);
    QCOMPARE(s.commands[0].voltages.right, 3.0);
    QCOMPARE(s.commands[0].voltages.left, 2.5);
}

void TestSceneIo::paramsOverrideKeyByKey() {
    const Scene s = parseOk(R"({"robot_defaults": {"mass": 0.2, "right": {"k": 0.1}, "left": {"k": 0.08}},
        "robots": [{"params": {"right": {"resistance": 11.5}}}, {"params": {"mass": 0.25}}]})");
    const RobotParams& a = s.robots[0].params;
    QCOMPARE(a.right.resistance, 11.5);  // overridden
    QCOMPARE(a.right.k, 0.1);            // from robot_defaults, same side object
    QCOMPARE(a.left.resistance, 12.0);   // untouched
    QCOMPARE(a.left.k, 0.08);
    QCOMPARE(a.mass, 0.2);
    QCOMPARE(s.robots[1].params.mass, 0.25);
    QCOMPARE(s.robots[1].params.right.resistance, 12.0);
}

void TestSceneIo::inertiaDefaultsToUniformCubeAfterOverrides() {
    const Scene s = parseOk(R"({"robot_defaults": {"mass": 0.3},
        "robots": [{"params": {"side": 0.07}}, {"params": {"inertia": 2e-4}}]})");
    QVERIFY(qAbs(s.robots[0].params.inertia - 0.3 * 0.07 * 0.07 / 6) < 1e-20);
    QCOMPARE(s.robots[1].params.inertia, 2e-4);
}

void TestSceneIo::namesDefaultPerTeam() {
    const Scene s = parseOk(R"({"robots": [{"team": "blue", "x": 0.1}, {}, {"team": "blue", "x": 0.3}, {"x": -0.3}]})");
    QCOMPARE(s.robots[0].name, std::string("blue0"));
    QCOMPARE(s.robots[1].name, std::string("yellow0"));
    QCOMPARE(s.robots[2].name, std::string("blue1"));
    QCOMPARE(s.robots[3].name, std::string("yellow1"));
}

void TestSceneIo::roundTripIsExact() {
    Scene s;
    s.field = makeRectangularField(1.7, 1.3);
    s.simulation = {Integrator::Euler, 0.0007, CollisionModel::Impulse, 0.3};
    s.ball = {0.1 / 3, -0.2, 1.0 / 7, 2.0 / 3};
    s.ball_params = {0.05, 0.021, 0.013};
    RobotSpec r;
    r.name = "odd";
    r.team = Team::Blue;
    r.initial = {0.1, 0.2 / 3, 1.0 / 3, -0.7, 2.0 / 9};
    r.params.right = {0.0251, 11.3, 0.0911, 1.1e-5 / 3, 1.3e-4};
    r.params.left = {0.0249, 12.7, 0.0877, 0.9e-5, 0.7e-4 / 3};
    r.params.inertia = 1.0 / 6000;
    s.robots = {r};
    s.commands = {{0.1 / 3, 0, {1.0 / 3, -2.0 / 7}}};
    QString error;
    const std::optional<Scene> back = parseScene(sceneToJson(s), &error);
    QVERIFY2(back, qPrintable(error));
    QCOMPARE(back->field.length, 1.7);
    QCOMPARE(back->simulation.integrator, Integrator::Euler);
    QCOMPARE(back->simulation.dt, 0.0007);
    QCOMPARE(back->simulation.collision_model, CollisionModel::Impulse);
    QCOMPARE(back->simulation.restitution, 0.3);
    QCOMPARE(back->ball.x, s.ball.x);
    QCOMPARE(back->ball.vy, s.ball.vy);
    QCOMPARE(back->ball_params.friction, 0.013);
    const RobotSpec& b = back->robots[0];
    QCOMPARE(b.name, std::string("odd"));
    QCOMPARE(b.team, Team::Blue);
    QCOMPARE(b.initial.y, r.initial.y);
    QCOMPARE(b.initial.theta, r.initial.theta);
    QCOMPARE(b.initial.omega, r.initial.omega);
    QCOMPARE(b.params.inertia, r.params.inertia);
    QCOMPARE(b.params.right.rotor_inertia, r.params.right.rotor_inertia);
    QCOMPARE(b.params.left.friction, r.params.left.friction);
    QCOMPARE(b.params.left.resistance, 12.7);
    QCOMPARE(back->commands[0].t, s.commands[0].t);
    QCOMPARE(back->commands[0].voltages.left, s.commands[0].voltages.left);
}

void TestSceneIo::badInput_data() {
    QTest::addColumn<QByteArray>("json");
    QTest::addColumn<QString>("message");
    QTest::newRow("syntax") << QByteArray("{\n  \"ball\": {\"x\": 0,}\n}") << "line 2, column";
    QTest::newRow("not an object") << QByteArray("[1, 2]") << "(top level): expected an object";
    QTest::newRow("unknown top key") << QByteArray(R"({"robot": []})") << "robot: unknown key";
    QTest::newRow("unknown nested key") << QByteArray(R"({"robots": [{"params": {"right": {"resistence": 12}}}]})")
                                        << "robots[0].params.right.resistence: unknown key (expected one of: "
                                           "wheel_radius, resistance, k, rotor_inertia, friction)";
    QTest::newRow("wrong type") << QByteArray(R"({"robots": [{}, {}, {"params": {"right": {"resistance": "12"}}}]})")
                                << "robots[2].params.right.resistance: expected a number";
    QTest::newRow("object expected") << QByteArray(R"({"ball": 3})") << "ball: expected an object";
    QTest::newRow("array expected") << QByteArray(R"({"robots": {}})") << "robots: expected an array";
    QTest::newRow("negative mass") << QByteArray(R"({"robots": [{"params": {"mass": -1}}]})")
                                   << "robots[0].params.mass: must be > 0 (got -1)";
    QTest::newRow("zero resistance") << QByteArray(R"({"robot_defaults": {"left": {"resistance": 0}}})")
                                     << "robot_defaults.left.resistance: must be > 0 (got 0)";
    QTest::newRow("negative friction") << QByteArray(R"({"ball": {"friction": -0.1}})")
                                       << "ball.friction: must be >= 0 (got -0.1)";
    QTest::newRow("restitution") << QByteArray(R"({"simulation": {"restitution": 1.5}})")
                                 << "simulation.restitution: must be between 0 and 1 (got 1.5)";
    QTest::newRow("dt too long") << QByteArray(R"({"simulation": {"dt": 0.5}})") << "simulation.dt: must be <= 0.1 s";
    QTest::newRow("infinite") << QByteArray(R"({"ball": {"vx": 1e999}})")
                              << "line 1, column 22: illegal number";  // Qt rejects it as it parses
    QTest::newRow("bad integrator")
        << QByteArray(R"({"simulation": {"integrator": "rk45"}})")
        << "simulation.integrator: expected one of \"euler\", \"rk4\", \"exact\" (got \"rk45\")";
    QTest::newRow("bad team") << QByteArray(R"({"robots": [{"team": "red"}]})")
                              << "robots[0].team: expected one of \"yellow\", \"blue\" (got \"red\")";
    QTest::newRow("duplicate name") << QByteArray(R"({"robots": [{"name": "a", "x": 0.1}, {"name": "a"}]})")
                                    << "robots[1].name: duplicate name \"a\"";
    QTest::newRow("unknown robot") << QByteArray(R"({"robots": [{}], "commands": [{"t": 0, "robot": "blue7"}]})")
                                   << "commands[0].robot: no robot named \"blue7\"";
    QTest::newRow("command without robot") << QByteArray(R"({"commands": [{"t": 0}]})") << "commands[0].robot: missing";
    QTest::newRow("negative time") << QByteArray(R"({"robots": [{}], "commands": [{"t": -1, "robot": "yellow0"}]})")
                                   << "commands[0].t: must be >= 0";
    QTest::newRow("robot outside") << QByteArray(R"({"robots": [{"x": 0.74}]})")
                                   << "robots[0].x: 0.74 m is outside the field";
    QTest::newRow("robot corner outside")
        << QByteArray(R"({"robots": [{"x": 0.7125, "theta": 0.7853981633974483}]})")
        << "robots[0].x: 0.7125 m is outside the field (|x| must be <= 0.6969669914 m at heading 0.785398 rad)";
    QTest::newRow("command too late") << QByteArray(
                                             R"({"robots": [{}], "commands": [{"t": 1e300, "robot": "yellow0"}]})")
                                      << "commands[0].t: must be <= 1e+09 s (got 1e+300)";
    QTest::newRow("comma in name") << QByteArray(R"({"robots": [{"name": "a,b"}]})")
                                   << "robots[0].name: \"a,b\" may not contain commas";
    QTest::newRow("newline in name") << QByteArray(R"({"robots": [{"name": "a\nb"}]})")
                                     << "robots[0].name: \"a\nb\" may not contain commas, quotes or control characters";
    QTest::newRow("name ball") << QByteArray(R"({"robots": [{"name": "ball"}]})")
                               << "robots[0].name: \"ball\" is reserved for the ball";
    QTest::newRow("ball outside") << QByteArray(R"({"ball": {"y": -0.64}})") << "ball.y: -0.64 m is outside the field";
    QTest::newRow("version") << QByteArray(R"({"version": 2})") << "version: unsupported version 2";
}

void TestSceneIo::badInput() {
    QFETCH(QByteArray, json);
    QFETCH(QString, message);
    QString error;
    const std::optional<Scene> scene = parseScene(json, &error);
    QVERIFY(!scene);
    QVERIFY2(error.startsWith(message), qPrintable("got: " + error));
}

void TestSceneIo::unreadableFile() {
    QString error;
    QVERIFY(!loadSceneFile("/nonexistent/dir/scene.json", &error));
    QVERIFY2(error.startsWith("/nonexistent/dir/scene.json: cannot read"), qPrintable(error));
}

void TestSceneIo::exampleScenesLoad() {
    const QDir dir(VSSIM_SOURCE_DIR "/resources/scenes");
    const QStringList files = dir.entryList({"*.json"}, QDir::Files);
    QVERIFY(files.size() >= 5);
    for (const QString& f : files) {
        QString error;
        QVERIFY2(loadSceneFile(dir.filePath(f), &error), qPrintable(error));
    }
}

QTEST_GUILESS_MAIN(TestSceneIo)
#include "test_scene_io.moc"
