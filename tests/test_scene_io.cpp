// Scene files: defaults, overrides, round trip, and the error messages that
// name the key path (docs/scenes.md).
#include <QtTest>

#include <QDir>

#include "io/scene_io.h"
#include "vssim/world.h"

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
    void everyIntegratorRoundTrips();
    void badInput_data();
    void badInput();
    void surrogatePairNameIsKept();
    void rangesAcceptTheirEnds();
    void bodiesMustFit();
    void aCrowdAtTheLimitStaysInside();
    void commandsFindTheirRobotsInALargeScene();
    void unreadableFile();
    void exampleScenesLoad();
    void fieldTypesAndTheirDefaults();
    void fieldKeysOverrideOneByOne();
    void fieldWithoutTypeIsTheBox();
    void fieldRoundTripIsExact();
    void badField_data();
    void badField();
    void placementUsesTheRealFloor();
    void officialFloorArea();
    void gameDefaultsAndKeys();
    void gameRoundTripIsExact();
    void badGame_data();
    void badGame();
    void cameraPresetsAndKeys();
    void cameraRoundTripIsExact();
    void badCamera_data();
    void badCamera();
};

void TestSceneIo::emptySceneHasModelDefaults() {
    // model.md §9, written out here as the independent source.
    const Scene s = parseOk(R"({"robots": [{}]})");
    QCOMPARE(s.field.length, 1.50);
    QCOMPARE(s.field.width, 1.30);
    QCOMPARE(s.field.walls.size(), std::size_t(4));
    QCOMPARE(s.field.dimensions.type, FieldType::Box);
    QCOMPARE(s.simulation.dt, 0.001);
    QCOMPARE(s.simulation.integrator, Integrator::Exact);  // the default since it beat RK4 (docs/scenes.md)
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

void TestSceneIo::everyIntegratorRoundTrips() {
    // A written scene names its integrator, so it reads back the same whatever
    // the default: RK4 stays RK4 although a file without the key gets exact.
    QCOMPARE(parseOk(R"({"simulation": {"dt": 0.001}})").simulation.integrator, Integrator::Exact);
    for (const Integrator integrator : {Integrator::Euler, Integrator::Rk4, Integrator::Exact}) {
        Scene s;
        s.simulation.integrator = integrator;
        const QByteArray json = sceneToJson(s);
        const QJsonObject simulation = QJsonDocument::fromJson(json).object()["simulation"].toObject();
        QCOMPARE(simulation["integrator"].toString(), integratorName(integrator));
        QString error;
        const std::optional<Scene> back = parseScene(json, &error);
        QVERIFY2(back, qPrintable(error));
        QCOMPARE(back->simulation.integrator, integrator);
        const QString named = QStringLiteral(R"({"simulation": {"integrator": "%1"}})").arg(integratorName(integrator));
        QCOMPARE(parseOk(named.toUtf8()).simulation.integrator, integrator);
    }
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
                                   << "robots[0].params.mass: must be between 0.0001 and 1000 kg (got -1)";
    QTest::newRow("zero resistance") << QByteArray(R"({"robot_defaults": {"left": {"resistance": 0}}})")
                                     << "robot_defaults.left.resistance: must be between 0.001 and 1e+06 Ω (got 0)";
    QTest::newRow("negative friction") << QByteArray(R"({"ball": {"friction": -0.1}})")
                                       << "ball.friction: must be between 0 and 1000 N s/m (got -0.1)";
    QTest::newRow("restitution") << QByteArray(R"({"simulation": {"restitution": 1.5}})")
                                 << "simulation.restitution: must be between 0 and 1 (got 1.5)";
    QTest::newRow("dt too long") << QByteArray(R"({"simulation": {"dt": 0.5}})")
                                 << "simulation.dt: must be between 1e-06 and 0.1 s (got 0.5)";
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
                                   << "commands[0].t: must be between 0 and 1e+09 s (got -1)";
    QTest::newRow("robot outside") << QByteArray(R"({"robots": [{"x": 0.74}]})")
                                   << "robots[0].x: 0.74 m is outside the field";
    QTest::newRow("robot corner outside")
        << QByteArray(R"({"robots": [{"x": 0.7125, "theta": 0.7853981633974483}]})")
        << "robots[0].x: 0.7125 m is outside the field (|x| must be <= 0.6969669914 m at heading 0.785398 rad)";
    QTest::newRow("command too late") << QByteArray(
                                             R"({"robots": [{}], "commands": [{"t": 1e300, "robot": "yellow0"}]})")
                                      << "commands[0].t: must be between 0 and 1e+09 s (got 1e+300)";
    QTest::newRow("comma in name") << QByteArray(R"({"robots": [{"name": "a,b"}]})")
                                   << "robots[0].name: \"a,b\" may not contain commas";
    // Names and keys from the file are quoted printable: a control character shows as "?".
    QTest::newRow("newline in name") << QByteArray(R"({"robots": [{"name": "a\nb"}]})")
                                     << "robots[0].name: \"a?b\" may not contain commas, quotes or control characters";
    QTest::newRow("escape in command's robot")
        << QByteArray(R"({"robots": [{}], "commands": [{"robot": "a\u001b[31mb\r"}]})")
        << "commands[0].robot: no robot named \"a?[31mb?\"";
    QTest::newRow("escape in unknown key") << QByteArray(R"({"ball": {"x\u001b[2J": 1}})") << "ball.x?[2J: unknown key";
    QTest::newRow("escape in team") << QByteArray(R"({"robots": [{"team": "blue\n"}]})")
                                    << "robots[0].team: expected one of \"yellow\", \"blue\" (got \"blue?\")";
    QTest::newRow("long name cut") << QByteArray(R"({"robots": [{}], "commands": [{"robot": ")" +
                                                 QByteArray(1000, 'z') + R"("}]})")
                                   << "commands[0].robot: no robot named \"" + QString(40, 'z') + "...\"";
    // A lone UTF-16 surrogate has no UTF-8 form: the CSV would show "?" for
    // both of these names, and a command naming one would not find it.
    QTest::newRow("lone surrogate in name")
        << QByteArray(R"({"robots": [{"name": "\ud800", "x": -0.3}, {"name": "\udfff", "x": 0.3}]})")
        << "robots[0].name: \"\uFFFD\" is not valid Unicode (it holds a lone UTF-16 surrogate such as \\ud800)";
    QTest::newRow("lone surrogate after a pair")
        << QByteArray(R"({"robots": [{"name": "ok\ud83d\ude00"}, {"name": "x\ud83d", "x": 0.3}]})")
        << "robots[1].name: \"x\uFFFD\" is not valid Unicode";
    QTest::newRow("name ball") << QByteArray(R"({"robots": [{"name": "ball"}]})")
                               << "robots[0].name: \"ball\" is reserved for the ball";
    QTest::newRow("ball outside") << QByteArray(R"({"ball": {"y": -0.64}})") << "ball.y: -0.64 m is outside the field";
    QTest::newRow("version") << QByteArray(R"({"version": 2})") << "version: unsupported version 2";
    // Extreme finite values ran into NaN (exit 0) or took 0.6 s per 1 ms
    // step: each key has a physical range (scene_limits.h, docs/scenes.md).
    QTest::newRow("ball speed") << QByteArray(R"({"ball": {"vx": 1e308}})")
                                << "ball.vx: must be between -20 and 20 m/s (got 1e+308)";
    QTest::newRow("ball speed diagonal") << QByteArray(R"({"ball": {"vx": 15, "vy": -15}})")
                                         << "ball: the speed |(vx, vy)| must be <= 20 m/s (got 21.2132)";
    QTest::newRow("ball mass") << QByteArray(R"({"ball": {"mass": 1e-308}})")
                               << "ball.mass: must be between 0.0001 and 100 kg (got 1e-308)";
    QTest::newRow("robot mass subnormal")
        << QByteArray(R"({"robots": [{"params": {"mass": 5e-324}}]})")
        << "robots[0].params.mass: must be between 0.0001 and 1000 kg (got 4.94066e-324)";
    QTest::newRow("robot speed") << QByteArray(R"({"robots": [{"v": 1e10}]})")
                                 << "robots[0].v: must be between -10 and 10 m/s (got 1e+10)";
    QTest::newRow("yaw rate") << QByteArray(R"({"robots": [{"omega": -101}]})")
                              << "robots[0].omega: must be between -100 and 100 rad/s (got -101)";
    QTest::newRow("inertia") << QByteArray(R"({"robot_defaults": {"inertia": 1e300}})")
                             << "robot_defaults.inertia: must be between 1e-09 and 100 kg m² (got 1e+300)";
    QTest::newRow("side") << QByteArray(R"({"robot_defaults": {"side": 11}})")
                          << "robot_defaults.side: must be between 0.0001 and 10 m (got 11)";
    QTest::newRow("wheel base") << QByteArray(R"({"robot_defaults": {"wheel_base": 1e-200}})")
                                << "robot_defaults.wheel_base: must be between 0.0001 and 10 m";
    QTest::newRow("linear friction") << QByteArray(R"({"robot_defaults": {"friction_linear": 1e6}})")
                                     << "robot_defaults.friction_linear: must be between 0 and 1000 N s/m";
    QTest::newRow("angular friction") << QByteArray(R"({"robot_defaults": {"friction_angular": 101}})")
                                      << "robot_defaults.friction_angular: must be between 0 and 100 N m s/rad";
    QTest::newRow("max voltage") << QByteArray(R"({"robot_defaults": {"max_voltage": 0}})")
                                 << "robot_defaults.max_voltage: must be > 0 and <= 1000 V (got 0)";
    QTest::newRow("wheel radius") << QByteArray(R"({"robots": [{"params": {"left": {"wheel_radius": 2}}}]})")
                                  << "robots[0].params.left.wheel_radius: must be between 0.0001 and 1 m (got 2)";
    QTest::newRow("motor constant") << QByteArray(R"({"robot_defaults": {"right": {"k": 1e-300}}})")
                                    << "robot_defaults.right.k: must be between 1e-05 and 100 V s/rad";
    QTest::newRow("rotor inertia") << QByteArray(R"({"robot_defaults": {"right": {"rotor_inertia": 11}}})")
                                   << "robot_defaults.right.rotor_inertia: must be between 0 and 10 kg m²";
    QTest::newRow("motor friction") << QByteArray(R"({"robot_defaults": {"left": {"friction": 1e9}}})")
                                    << "robot_defaults.left.friction: must be between 0 and 100 N m s/rad";
    QTest::newRow("ball radius") << QByteArray(R"({"ball": {"radius": 0}})")
                                 << "ball.radius: must be between 1e-05 and 10 m (got 0)";
    QTest::newRow("field") << QByteArray(R"({"field": {"length": 1e9}})")
                           << "field.length: must be between 0.001 and 100 m (got 1e+09)";
    QTest::newRow("dt tiny") << QByteArray(R"({"simulation": {"dt": 1e-300}})")
                             << "simulation.dt: must be between 1e-06 and 0.1 s (got 1e-300)";
    // A field smaller than a body: said so, not "|x| must be <= -0.0125 m".
    QTest::newRow("field smaller than a robot")
        << QByteArray(R"({"field": {"length": 0.05, "width": 1}, "robots": [{}]})")
        << "robots[0]: the field (0.05 m x 1 m) is smaller than the robot, which is 0.075 m across";
    QTest::newRow("field smaller than a turned robot")
        << QByteArray(R"({"field": {"length": 1, "width": 0.1}, "robots": [{"theta": 0.7853981633974483}]})")
        << "robots[0]: the field (1 m x 0.1 m) is smaller than the robot, which is 0.1060660172 m across at "
           "heading 0.785398 rad";
    QTest::newRow("field smaller than the ball") << QByteArray(R"({"field": {"length": 0.04, "width": 1}})")
                                                 << "ball: the field (0.04 m x 1 m) is smaller than the ball, which "
                                                    "is 0.0427 m across";
}

void TestSceneIo::badInput() {
    QFETCH(QByteArray, json);
    QFETCH(QString, message);
    QString error;
    const std::optional<Scene> scene = parseScene(json, &error);
    QVERIFY(!scene);
    QVERIFY2(error.startsWith(message), qPrintable("got: " + error));
}

void TestSceneIo::rangesAcceptTheirEnds() {
    // The ends of the documented ranges are allowed (docs/scenes.md).
    const Scene s = parseOk(R"({"field": {"length": 100, "width": 100},
        "simulation": {"dt": 1e-6},
        "robot_defaults": {"mass": 1000, "side": 1, "inertia": 1e-9, "max_voltage": 1000, "friction_linear": 1000,
                           "right": {"resistance": 0.001, "k": 100, "rotor_inertia": 10}},
        "ball": {"vx": 12, "vy": -16, "mass": 1e-4, "radius": 1e-5, "friction": 1000},
        "robots": [{"x": 2, "v": -10, "omega": 100}]})");
    QCOMPARE(s.simulation.dt, 1e-6);
    QCOMPARE(s.robots[0].params.mass, 1000.0);
    QCOMPARE(s.robots[0].initial.v, -10.0);
    QCOMPARE(s.ball.vy, -16.0);  // |(12, -16)| = 20 m/s exactly
}

void TestSceneIo::bodiesMustFit() {
    // 10,000 robots on the default field (56 m² of robots on 1.95 m²) ended
    // metres outside the walls; bodies covering more than half of the field
    // are refused, at most half is accepted.
    auto crowd = [](int robots, double side) {
        QByteArray json = QStringLiteral(R"({"robot_defaults": {"side": %1}, "robots": [)").arg(side).toUtf8();
        for (int i = 0; i < robots; ++i) json += i ? ",{}" : "{}";
        return json + "]}";
    };
    QString error;
    QVERIFY(!parseScene(crowd(10000, 0.075), &error));
    QCOMPARE(error, QString("robots: the ball and 10000 robots cover 56.25 m², more than 50% of the field's 1.95 m²: "
                            "they cannot all fit (use a larger field, or fewer or smaller robots)"));
    // 0.5 * 1.95 m² less the ball's disc holds 173 default robots (0.005625 m² each), not 174.
    QVERIFY2(parseScene(crowd(173, 0.075), &error), qPrintable(error));
    QVERIFY(!parseScene(crowd(174, 0.075), &error));
    QVERIFY2(error.startsWith("robots: the ball and 174 robots cover 0.98"), qPrintable(error));
    QVERIFY(!parseScene(R"({"field": {"length": 0.05, "width": 0.05}, "ball": {"radius": 0.02}})", &error));
    QVERIFY2(error.startsWith("ball: the ball and 0 robots cover"), qPrintable(error));
}

void TestSceneIo::aCrowdAtTheLimitStaysInside() {
    // What the limit buys: 173 robots (just under half the field) dropped on
    // top of each other at random, driving, stay inside the walls for 1 s.
    std::uint32_t seed = 12345;
    auto uniform = [&](double lo, double hi) {
        seed = seed * 1664525u + 1013904223u;  // a fixed LCG: the same crowd every run
        return lo + (hi - lo) * (seed >> 8) / double(1u << 24);
    };
    QByteArray json = R"({"robots": [)";
    for (int i = 0; i < 173; ++i)
        json += QStringLiteral(R"(%1{"name": "r%2", "x": %3, "y": %4, "theta": %5, "v": %6})")
                    .arg(i ? "," : "")
                    .arg(i)
                    .arg(uniform(-0.6, 0.6))
                    .arg(uniform(-0.5, 0.5))
                    .arg(uniform(-3.0, 3.0))
                    .arg(uniform(-2.0, 2.0))
                    .toUtf8();
    json += R"(], "commands": [)";
    for (int i = 0; i < 173; ++i)
        json += QStringLiteral(R"(%1{"robot": "r%2", "right": 7, "left": %3})")
                    .arg(i ? "," : "")
                    .arg(i)
                    .arg(uniform(-7, 7))
                    .toUtf8();
    json += "]}";
    const Scene scene = parseOk(json);
    Simulation sim(scene);
    const double hx = 0.75, hy = 0.65, slack = 1e-9;  // m
    while (sim.state().step < 1000) {
        sim.advanceTo(sim.state().step + 10);
        const WorldState& s = sim.state();
        for (const RobotState& r : s.robots) {
            const double half = 0.0375 * (std::abs(std::cos(r.theta)) + std::abs(std::sin(r.theta)));
            QVERIFY2(std::abs(r.x) + half <= hx + slack && std::abs(r.y) + half <= hy + slack,
                     qPrintable(QString("robot at (%1, %2) at t = %3 s").arg(r.x).arg(r.y).arg(s.time)));
        }
        QVERIFY(std::abs(s.ball.x) + 0.02135 <= hx + slack && std::abs(s.ball.y) + 0.02135 <= hy + slack);
    }
}

void TestSceneIo::surrogatePairNameIsKept() {
    // A valid pair (U+1F600) is a fine name: it reaches the CSV as UTF-8 and commands find it.
    const Scene s = parseOk(R"({"robots": [{"name": "\ud83d\ude00"}], "commands": [{"robot": "\ud83d\ude00"}]})");
    QCOMPARE(s.robots[0].name, std::string("\xF0\x9F\x98\x80"));
    QCOMPARE(s.commands[0].robot, 0);
}

void TestSceneIo::commandsFindTheirRobotsInALargeScene() {
    // 5,000 robots and 20 commands each, listed in an order unrelated to the
    // robots': each command must land on its own robot (the reader looks
    // names up in a hash, linear in robots + commands; a scan per command
    // took 17.7 s for 5,000 robots and 100,000 commands).
    const int robots = 5000, perRobot = 20;
    QByteArray json = R"({"field": {"length": 100, "width": 100}, "robots": [)";
    for (int i = 0; i < robots; ++i)
        json += QStringLiteral(R"(%1{"name": "r%2", "x": %3, "y": %4})")
                    .arg(i ? "," : "")
                    .arg(i)
                    .arg(-45.0 + 0.5 * (i % 100))
                    .arg(-45.0 + 0.5 * (i / 100))
                    .toUtf8();
    json += R"(], "commands": [)";
    for (int k = 0; k < robots * perRobot; ++k) {
        const int robot = (k * 7919) % robots;  // 7919 is prime: every robot, out of order
        json += QStringLiteral(R"(%1{"t": %2, "robot": "r%3", "right": %4})")
                    .arg(k ? "," : "")
                    .arg(k * 1e-3)
                    .arg(robot)
                    .arg(robot % 7)
                    .toUtf8();
    }
    json += "]}";
    const Scene s = parseOk(json);
    QCOMPARE(s.robots.size(), std::size_t(robots));
    QCOMPARE(s.commands.size(), std::size_t(robots * perRobot));
    for (int k = 0; k < robots * perRobot; ++k) {
        const int robot = (k * 7919) % robots;
        QCOMPARE(s.commands[k].robot, robot);
        QCOMPARE(s.commands[k].voltages.right, double(robot % 7));
    }
    QCOMPARE(s.robots[4321].name, std::string("r4321"));
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
    // The kick-off is played on the official 3 vs 3 field; the paper's experiment stays in its box.
    QString error;
    QCOMPARE(loadSceneFile(dir.filePath("kickoff_3v3.json"), &error)->field.dimensions.type, FieldType::Vsss3v3);
    // The kick-off is a match, the built-in team on both sides, with no scripted voltages;
    // vs_builtin_3v3 leaves yellow to a client.
    const Scene kickoff = *loadSceneFile(dir.filePath("kickoff_3v3.json"), &error);
    QVERIFY(kickoff.game.rules.referee);
    QCOMPARE(kickoff.game.yellow, TeamControl::Builtin);
    QCOMPARE(kickoff.game.blue, TeamControl::Builtin);
    QVERIFY(kickoff.commands.empty());
    const Scene versus = *loadSceneFile(dir.filePath("vs_builtin_3v3.json"), &error);
    QVERIFY(versus.game.rules.referee);
    QCOMPARE(versus.game.yellow, TeamControl::Remote);
    QCOMPARE(versus.game.blue, TeamControl::Builtin);
    // The physics scenes have no game.
    QVERIFY(!loadSceneFile(dir.filePath("robot_hits_ball.json"), &error)->game.rules.referee);
    QCOMPARE(loadSceneFile(dir.filePath("paper_fig13.json"), &error)->field.dimensions.type, FieldType::Box);
    // Integrators (docs/scenes.md, "Built-in scenes"): the game scenes take the
    // default, exact; the paper's experiment keeps the paper's Euler at 1 ms;
    // the stiff robot shows RK4's stability limit.
    QCOMPARE(kickoff.simulation.integrator, Integrator::Exact);
    QCOMPARE(versus.simulation.integrator, Integrator::Exact);
    const Scene figure13 = *loadSceneFile(dir.filePath("paper_fig13.json"), &error);
    QCOMPARE(figure13.simulation.integrator, Integrator::Euler);
    QCOMPARE(figure13.simulation.dt, 0.001);
    QCOMPARE(loadSceneFile(dir.filePath("stiff_robot.json"), &error)->simulation.integrator, Integrator::Rk4);
    for (const char* name : {"ball_walls.json", "robot_hits_ball.json", "robots_collide.json", "speed_step.json"})
        QCOMPARE(loadSceneFile(dir.filePath(name), &error)->simulation.integrator, Integrator::Exact);
}

// The official dimensions, written out here from the shared rules (vsss-game.md,
// "Fields") rather than taken from the engine, m.
void TestSceneIo::fieldTypesAndTheirDefaults() {
    const Scene three = parseOk(R"({"field": {"type": "vsss_3v3"}})");
    const FieldDimensions& a = three.field.dimensions;
    QCOMPARE(a.type, FieldType::Vsss3v3);
    QCOMPARE(a.length, 1.50);
    QCOMPARE(a.width, 1.30);
    QCOMPARE(a.goal_width, 0.40);
    QCOMPARE(a.goal_depth, 0.10);
    QCOMPARE(a.corner_leg, 0.07);
    QCOMPARE(a.centre_radius, 0.20);
    QCOMPARE(a.goal_area_depth, 0.15);
    QCOMPARE(a.goal_area_width, 0.70);
    QCOMPARE(a.penalty_mark, 0.375);
    QCOMPARE(a.free_ball_x, 0.375);
    QCOMPARE(a.free_ball_y, 0.25);
    QCOMPARE(three.field.walls.size(),
             std::size_t(16));  // 2 long walls, 4 triangles, 4 short pieces, 2 x 3 in the goals
    QCOMPARE(three.field.posts.size(), std::size_t(4));
    QCOMPARE(three.field.lower, Eigen::Vector2d(-0.85, -0.65));
    QCOMPARE(three.field.upper, Eigen::Vector2d(0.85, 0.65));

    const Scene five = parseOk(R"({"field": {"type": "vsss_5v5"}})");
    const FieldDimensions& b = five.field.dimensions;
    QCOMPARE(b.type, FieldType::Vsss5v5);
    QCOMPARE(b.length, 2.20);
    QCOMPARE(b.width, 1.80);
    QCOMPARE(b.goal_width, 0.40);
    QCOMPARE(b.goal_depth, 0.15);
    QCOMPARE(b.corner_leg, 0.07);
    QCOMPARE(b.centre_radius, 0.25);
    QCOMPARE(b.goal_area_depth, 0.15);
    QCOMPARE(b.goal_area_width, 0.50);
    QCOMPARE(b.penalty_mark, 0.375);
    QCOMPARE(b.free_ball_x, 0.375);
    QCOMPARE(b.free_ball_y, 0.40);
    QCOMPARE(five.field.length, 2.20);

    const Scene box = parseOk(R"({"field": {"type": "box"}})");
    QCOMPARE(box.field.dimensions.type, FieldType::Box);
    QCOMPARE(box.field.walls.size(), std::size_t(4));
    QCOMPARE(box.field.dimensions.goal_width, 0.0);
    QCOMPARE(box.field.dimensions.centre_radius, 0.20);
}

void TestSceneIo::fieldKeysOverrideOneByOne() {
    // The rules' 7 cm corners, VSSReferee's 5 cm: one key changes, the rest stay official.
    const Scene s = parseOk(R"({"field": {"type": "vsss_3v3", "corner_leg": 0.05, "goal_depth": 0.12}})");
    QCOMPARE(s.field.dimensions.type, FieldType::Vsss3v3);
    QCOMPARE(s.field.dimensions.corner_leg, 0.05);
    QCOMPARE(s.field.dimensions.goal_depth, 0.12);
    QCOMPARE(s.field.dimensions.goal_width, 0.40);
    QCOMPARE(s.field.dimensions.free_ball_y, 0.25);
    QCOMPARE(s.field.upper, Eigen::Vector2d(0.87, 0.65));
    // A bigger field of the 3 vs 3 kind: only length and width given.
    const Scene big = parseOk(R"({"field": {"type": "vsss_3v3", "length": 1.8, "width": 1.5}})");
    QCOMPARE(big.field.length, 1.8);
    QCOMPARE(big.field.dimensions.goal_area_width, 0.70);
    // The box takes a centre radius of its own.
    QCOMPARE(parseOk(R"({"field": {"centre_radius": 0.3}})").field.dimensions.centre_radius, 0.3);
}

void TestSceneIo::fieldWithoutTypeIsTheBox() {
    // Files written before field types keep their meaning: the seed's closed box.
    const Scene s = parseOk(R"({"field": {"length": 1.7, "width": 1.2}})");
    QCOMPARE(s.field.dimensions.type, FieldType::Box);
    QCOMPARE(s.field.walls.size(), std::size_t(4));
    QVERIFY(s.field.posts.empty());
    QCOMPARE(s.field.dimensions.centre_radius, 0.20);
    QCOMPARE(s.field.lower, Eigen::Vector2d(-0.85, -0.6));
    QCOMPARE(parseOk("{}").field.dimensions.type, FieldType::Box);
    // A box too small for a 0.20 m circle has none (it used to be drawn across the walls).
    QCOMPARE(parseOk(R"({"field": {"length": 0.3, "width": 1}})").field.dimensions.centre_radius, 0.0);
}

void TestSceneIo::fieldRoundTripIsExact() {
    for (FieldType type : {FieldType::Box, FieldType::Vsss3v3, FieldType::Vsss5v5}) {
        Scene s;
        FieldDimensions d = officialDimensions(type);
        d.length += 1.0 / 3;  // digits that need every bit
        d.width += 0.1 / 7;
        d.centre_radius = 0.2 + 1e-3 / 3;
        if (type != FieldType::Box) {
            d.goal_width = 0.4 + 0.01 / 3;
            d.goal_depth = 0.1 + 0.01 / 7;
            d.corner_leg = 0.05 + 1e-4 / 3;
            d.goal_area_depth = 0.15 + 1e-3 / 7;
            d.goal_area_width = 0.6 + 1e-3 / 9;
            d.penalty_mark = 0.4 + 1e-3 / 11;
            d.free_ball_x = 0.35 + 1e-3 / 13;
            d.free_ball_y = 0.3 + 1e-3 / 17;
        }
        s.field = makeField(d);
        const QByteArray json = sceneToJson(s);
        QVERIFY(json.contains(QByteArray("\"type\": \"") + fieldTypeName(type).toUtf8() + "\""));
        QString error;
        const std::optional<Scene> back = parseScene(json, &error);
        QVERIFY2(back, qPrintable(error));
        const FieldDimensions& e = back->field.dimensions;
        QCOMPARE(e.type, type);
        for (const FieldDimensionKey& k : kFieldDimensionKeys) QCOMPARE(e.*k.dimension, d.*k.dimension);
        QCOMPARE(back->field.walls.size(), s.field.walls.size());
        for (std::size_t w = 0; w < s.field.walls.size(); ++w) {
            QCOMPARE(back->field.walls[w].a, s.field.walls[w].a);
            QCOMPARE(back->field.walls[w].b, s.field.walls[w].b);
        }
        // Written once more, the same bytes.
        QCOMPARE(sceneToJson(*back), json);
    }
}

void TestSceneIo::badField_data() {
    QTest::addColumn<QByteArray>("json");
    QTest::addColumn<QString>("message");
    QTest::newRow("type") << QByteArray(R"({"field": {"type": "vsss_4v4"}})")
                          << "field.type: expected one of \"box\", \"vsss_3v3\", \"vsss_5v5\" (got \"vsss_4v4\")";
    QTest::newRow("type not a string") << QByteArray(R"({"field": {"type": 3}})") << "field.type: expected a string";
    QTest::newRow("unknown key") << QByteArray(R"({"field": {"type": "vsss_3v3", "goal_height": 0.05}})")
                                 << "field.goal_height: unknown key (expected one of: type, length, width, goal_width, "
                                    "goal_depth, corner_leg, centre_radius, goal_area_depth, goal_area_width, "
                                    "penalty_mark, free_ball_x, free_ball_y)";
    QTest::newRow("goal without a type")
        << QByteArray(R"({"field": {"length": 1.5, "width": 1.3, "goal_width": 0.4}})")
        << "field.goal_width: a box has no goals, corner triangles or goal areas (give field.type \"vsss_3v3\" or "
           "\"vsss_5v5\" for a field with goals)";
    QTest::newRow("corner on a box") << QByteArray(R"({"field": {"type": "box", "corner_leg": 0.07}})")
                                     << "field.corner_leg: a box has no goals";
    QTest::newRow("negative goal") << QByteArray(R"({"field": {"type": "vsss_3v3", "goal_width": -0.4}})")
                                   << "field.goal_width: must be between 0 and 100 m (got -0.4)";
    QTest::newRow("huge mark") << QByteArray(R"({"field": {"type": "vsss_5v5", "free_ball_y": 1e5}})")
                               << "field.free_ball_y: must be between 0 and 100 m (got 100000)";
    QTest::newRow("length") << QByteArray(R"({"field": {"type": "vsss_3v3", "length": 0}})")
                            << "field.length: must be between 0.001 and 100 m (got 0)";
    QTest::newRow("goal wider than its wall")
        << QByteArray(R"({"field": {"type": "vsss_3v3", "goal_width": 1.2}})")
        << "field.goal_width: the goal is wider than its wall: it must be narrower than the width minus two corner "
           "legs (got 1.2 m)";
    QTest::newRow("goal without depth") << QByteArray(R"({"field": {"type": "vsss_3v3", "goal_depth": 0}})")
                                        << "field.goal_depth: a field with goals needs goals at least some depth deep "
                                           "(got 0 m)";
    QTest::newRow("corners meet") << QByteArray(R"({"field": {"type": "vsss_3v3", "corner_leg": 0.7}})")
                                  << "field.corner_leg: the corner triangles would meet";
    QTest::newRow("circle") << QByteArray(R"({"field": {"type": "vsss_3v3", "centre_radius": 0.65}})")
                            << "field.centre_radius: the centre circle must fit inside the field (got 0.65 m)";
    QTest::newRow("circle on a box") << QByteArray(R"({"field": {"length": 0.3, "width": 1, "centre_radius": 0.2}})")
                                     << "field.centre_radius: the centre circle must fit inside the field (got 0.2 m)";
    QTest::newRow("goal area") << QByteArray(R"({"field": {"type": "vsss_3v3", "goal_area_depth": 0.75}})")
                               << "field.goal_area_depth: a goal area must end before the halfway line (got 0.75 m)";
    QTest::newRow("narrow field for its goal area")
        << QByteArray(R"({"field": {"type": "vsss_3v3", "width": 0.6}})")
        << "field.goal_area_width: a goal area cannot be wider than the field (got 0.7 m)";
    QTest::newRow("free-ball marks") << QByteArray(R"({"field": {"type": "vsss_3v3", "free_ball_y": 0.65}})")
                                     << "field.free_ball_y: the free-ball marks must lie inside the field (got 0.65 m)";
    QTest::newRow("penalty mark") << QByteArray(R"({"field": {"type": "vsss_5v5", "penalty_mark": 1.2}})")
                                  << "field.penalty_mark: the penalty mark must lie in its own half (got 1.2 m)";
}

void TestSceneIo::badField() {
    QFETCH(QByteArray, json);
    QFETCH(QString, message);
    QString error;
    QVERIFY(!parseScene(json, &error));
    QVERIFY2(error.startsWith(message), qPrintable("got: " + error));
}

void TestSceneIo::placementUsesTheRealFloor() {
    QString error;
    // In the goal (it is 0.10 m deep, 0.40 m wide): on the floor.
    const Scene inGoal = parseOk(R"({"field": {"type": "vsss_3v3"}, "ball": {"x": -0.82, "y": 0.1},
        "robots": [{"x": 0.8, "y": 0.0}]})");
    QCOMPARE(inGoal.robots[0].initial.x, 0.8);
    // The same on the box: outside, said with the |x| bound as before.
    QVERIFY(!parseScene(R"({"robots": [{"x": 0.8}]})", &error));
    QCOMPARE(error, QString("robots[0].x: 0.8 m is outside the field (|x| must be <= 0.7125 m)"));
    // Behind the back wall (x = 0.85), and beside the goal, past the goal line.
    QVERIFY(!parseScene(R"({"field": {"type": "vsss_3v3"}, "ball": {"x": 0.86}})", &error));
    QCOMPARE(error, QString("ball: at (0.86, 0) m it is not wholly on the field's floor: it crosses a wall, a corner "
                            "triangle or a goal post"));
    QVERIFY(!parseScene(R"({"field": {"type": "vsss_3v3"}, "robots": [{"x": 0.77, "y": 0.4}]})", &error));
    QVERIFY2(error.startsWith("robots[0]: at (0.77, 0.4) m it is not wholly"), qPrintable(error));
    // Across a post: the square's centre in the goal mouth, a side over the post at (0.75, 0.2).
    QVERIFY(!parseScene(R"({"field": {"type": "vsss_3v3"}, "robots": [{"x": 0.75, "y": 0.19}]})", &error));
    QVERIFY2(error.startsWith("robots[0]: at (0.75, 0.19) m"), qPrintable(error));
    // Over a corner triangle (its hypotenuse is x + y = 1.33 at the top right): refused
    // there, fine on the box; a robot turned by 45 degrees fits flat against it.
    const QByteArray corner = R"({"field": {"type": "vsss_3v3"}, "robots": [{"x": 0.7, "y": 0.6}]})";
    QVERIFY(!parseScene(corner, &error));
    QVERIFY2(error.startsWith("robots[0]: at (0.7, 0.6) m it is not wholly"), qPrintable(error));
    parseOk(R"({"robots": [{"x": 0.7, "y": 0.6}]})");
    // A face on the hypotenuse, centred on its midpoint (0.715, 0.615).
    const double back = 0.0375 / std::sqrt(2.0) + 1e-9;
    parseOk(QStringLiteral(R"({"field": {"type": "vsss_3v3"}, "robots": [{"x": %1, "y": %2, "theta": %3}]})")
                .arg(0.715 - back, 0, 'g', 17)
                .arg(0.615 - back, 0, 'g', 17)
                .arg(M_PI / 4, 0, 'g', 17)
                .toUtf8());
    // Bigger than the field: said so on any type.
    QVERIFY(!parseScene(R"({"field": {"type": "vsss_3v3"}, "robot_defaults": {"side": 1.4}, "robots": [{}]})", &error));
    QVERIFY2(error.startsWith("robots[0]: the field (1.5 m x 1.3 m) is smaller than the robot"), qPrintable(error));
}

void TestSceneIo::officialFloorArea() {
    // 1.50 x 1.30 plus two 0.40 x 0.10 goals less four triangles of legs 0.07.
    const Scene s = parseOk(R"({"field": {"type": "vsss_3v3"}})");
    QVERIFY(std::abs(floorArea(s.field) - (1.95 + 2 * 0.04 - 4 * 0.5 * 0.07 * 0.07)) < 1e-12);
    QCOMPARE(floorArea(parseOk("{}").field), 1.5 * 1.3);
    // The crowd limit uses it: 179 default robots fit in half of 2.0202 m², 180 do not.
    auto crowd = [](int robots) {
        QByteArray json = R"({"field": {"type": "vsss_3v3"}, "robots": [)";
        for (int i = 0; i < robots; ++i) json += i ? ",{}" : "{}";
        return json + "]}";
    };
    QString error;
    QVERIFY2(parseScene(crowd(179), &error), qPrintable(error));
    QVERIFY(!parseScene(crowd(180), &error));
    QVERIFY2(error.contains("more than 50% of the field's 2.02 m²"), qPrintable(error));
}

void TestSceneIo::gameDefaultsAndKeys() {
    QString error;
    // Without a game section: no referee, both teams remote, the rules' defaults.
    const std::optional<Scene> plain = parseScene("{}", &error);
    QVERIFY2(plain, qPrintable(error));
    const GameRules defaults;
    QVERIFY(!plain->game.rules.referee);
    QCOMPARE(plain->game.yellow, TeamControl::Remote);
    QCOMPARE(plain->game.blue, TeamControl::Remote);
    QCOMPARE(plain->game.rules.half_duration, defaults.half_duration);
    // Each key lands in its field; the others keep their defaults.
    const std::optional<Scene> s = parseScene(R"({"field": {"type": "vsss_3v3"}, "simulation": {"dt": 0.002},
        "game": {"referee": true, "halves": 4, "half_duration": 60, "stop_duration": 0, "stuck_ball_speed": 0.05,
                 "stuck_ball_time": 2.5, "crowded_area_time": 1, "free_ball_distance": 0.25, "tick": 0.02,
                 "left_team": "blue", "yellow": "builtin", "blue": "idle"}})",
                                              &error);
    QVERIFY2(s, qPrintable(error));
    const GameRules& r = s->game.rules;
    QVERIFY(r.referee);
    QCOMPARE(r.halves, 4);
    QCOMPARE(r.half_duration, 60.0);
    QCOMPARE(r.stop_duration, 0.0);
    QCOMPARE(r.stuck_ball_speed, 0.05);
    QCOMPARE(r.stuck_ball_time, 2.5);
    QCOMPARE(r.crowded_area_time, 1.0);
    QCOMPARE(r.free_ball_distance, 0.25);
    QCOMPARE(r.tick, 0.02);
    QCOMPARE(r.left_team, Team::Blue);
    QCOMPARE(plain->game.rules.left_team, Team::Yellow);  // vssim's default
    QCOMPARE(parseScene(sceneToJson(*s), &error)->game.rules.left_team, Team::Blue);  // written back
    QCOMPARE(QJsonDocument::fromJson(sceneToJson(*s)).object()["game"].toObject()["left_team"].toString(),
             QString("blue"));
    QCOMPARE(s->game.blue, TeamControl::Idle);
    // A tick of exactly one step is fine; so is one of 0.003 s at dt 0.001 s (rounding included).
    QVERIFY2(parseScene(R"({"simulation": {"dt": 0.0005}, "game": {"tick": 0.0005, "yellow": "builtin"}})", &error),
             qPrintable(error));
    QVERIFY2(parseScene(R"({"game": {"tick": 0.003, "yellow": "builtin"}})", &error), qPrintable(error));
    // Nothing acts at the tick without a referee or a built-in team: it is not checked against dt then
    // (a physics scene written back with another dt still reads).
    QVERIFY2(parseScene(R"({"simulation": {"dt": 0.0007}, "game": {"tick": 0.01}})", &error), qPrintable(error));
}

void TestSceneIo::gameRoundTripIsExact() {
    Scene s;
    s.field = makeField(officialDimensions(FieldType::Vsss5v5));
    s.game.rules = {true, 3, 100.0 / 3, 2.5, 0.07, 4.0 / 3, 2.0, 0.18, 0.005};
    s.game.yellow = TeamControl::Idle;
    s.game.blue = TeamControl::Builtin;
    QString error;
    const std::optional<Scene> back = parseScene(sceneToJson(s), &error);
    QVERIFY2(back, qPrintable(error));
    const GameRules& a = s.game.rules;
    const GameRules& b = back->game.rules;
    QCOMPARE(b.referee, a.referee);
    QCOMPARE(b.halves, a.halves);
    QCOMPARE(b.half_duration, a.half_duration);
    QCOMPARE(b.stop_duration, a.stop_duration);
    QCOMPARE(b.stuck_ball_speed, a.stuck_ball_speed);
    QCOMPARE(b.stuck_ball_time, a.stuck_ball_time);
    QCOMPARE(b.crowded_area_time, a.crowded_area_time);
    QCOMPARE(b.free_ball_distance, a.free_ball_distance);
    QCOMPARE(b.tick, a.tick);
    QCOMPARE(back->game.yellow, TeamControl::Idle);
    QCOMPARE(back->game.blue, TeamControl::Builtin);
    // And the default game (a physics scene) comes back as it was.
    const std::optional<Scene> plain = parseScene(sceneToJson(Scene{}), &error);
    QVERIFY2(plain, qPrintable(error));
    QVERIFY(!plain->game.rules.referee);
    QCOMPARE(plain->game.yellow, TeamControl::Remote);
}

void TestSceneIo::badGame_data() {
    QTest::addColumn<QByteArray>("json");
    QTest::addColumn<QString>("message");
    const QByteArray official = R"("field": {"type": "vsss_3v3"}, )";
    QTest::newRow("not an object") << QByteArray(R"({"game": true})") << "game: expected an object";
    QTest::newRow("unknown key") << QByteArray(R"({"game": {"referees": true}})")
                                 << "game.referees: unknown key (expected one of: referee, halves,";
    QTest::newRow("referee not bool") << QByteArray(R"({"game": {"referee": 1}})")
                                      << "game.referee: expected true or false";
    QTest::newRow("referee on a box") << QByteArray(R"({"game": {"referee": true}})")
                                      << "game.referee: a referee needs a field with goals";
    QTest::newRow("no halves") << QByteArray("{" + official + R"("game": {"halves": 0}})")
                               << "game.halves: must be between 1 and 10 (got 0)";
    QTest::newRow("half a half") << QByteArray("{" + official + R"("game": {"halves": 1.5}})")
                                 << "game.halves: must be a whole number (got 1.5)";
    QTest::newRow("half duration") << QByteArray(R"({"game": {"half_duration": 0}})")
                                   << "game.half_duration: must be > 0 and <= 86400 s (got 0)";
    QTest::newRow("stop duration") << QByteArray(R"({"game": {"stop_duration": -1}})")
                                   << "game.stop_duration: must be between 0 and 600 s (got -1)";
    QTest::newRow("stuck speed") << QByteArray(R"({"game": {"stuck_ball_speed": "slow"}})")
                                 << "game.stuck_ball_speed: expected a number";
    QTest::newRow("stuck time") << QByteArray(R"({"game": {"stuck_ball_time": -1}})")
                                << "game.stuck_ball_time: must be > 0 and <= 3600 s (got -1)";
    QTest::newRow("crowded time") << QByteArray(R"({"game": {"crowded_area_time": 0}})")
                                  << "game.crowded_area_time: must be > 0 and <= 3600 s (got 0)";
    QTest::newRow("free ball distance") << QByteArray(R"({"game": {"free_ball_distance": 2}})")
                                        << "game.free_ball_distance: must be > 0 and <= 1 m (got 2)";
    QTest::newRow("tick not whole steps")
        << QByteArray(R"({"game": {"tick": 0.0105, "blue": "builtin"}})")
        << "game.tick: must be a whole number of steps of simulation.dt (0.001 s; got 0.0105 s, 10.5 steps)";
    QTest::newRow("tick below dt")
        << QByteArray("{" + official + R"("simulation": {"dt": 0.002}, "game": {"referee": true, "tick": 0.001}})")
        << "game.tick: must be at least one step of simulation.dt (0.002 s; got 0.001 s)";
    QTest::newRow("tick zero") << QByteArray(R"({"game": {"tick": 0}})") << "game.tick: must be > 0 and <= 1 s (got 0)";
    QTest::newRow("bad left team") << QByteArray(R"({"game": {"left_team": "left"}})")
                                   << R"(game.left_team: expected one of "yellow", "blue" (got "left"))";
    QTest::newRow("left team not a string") << QByteArray(R"({"game": {"left_team": true}})")
                                            << "game.left_team: expected a string";
    QTest::newRow("bad control") << QByteArray(R"({"game": {"yellow": "tcp"}})")
                                 << R"(game.yellow: expected one of "builtin", "remote", "idle" (got "tcp"))";
    QTest::newRow("control not a string") << QByteArray(R"({"game": {"blue": 1}})") << "game.blue: expected a string";
}

void TestSceneIo::badGame() {
    QFETCH(QByteArray, json);
    QFETCH(QString, message);
    QString error;
    QVERIFY(!parseScene(json, &error));
    QVERIFY2(error.startsWith(message), qPrintable(error));
}

void TestSceneIo::cameraPresetsAndKeys() {
    // No `camera`: the ideal camera, today's image.
    QVERIFY(parseOk("{}").camera == idealCamera());
    QCOMPARE(cameraPresetName(parseOk("{}").camera), QStringLiteral("ideal"));
    // A preset replaces everything, then each key overrides one value.
    const Scene realistic = parseOk(R"({"camera": {"preset": "realistic"}})");
    QVERIFY(realistic.camera == realisticCamera());
    QCOMPARE(cameraPresetName(realistic.camera), QStringLiteral("realistic"));
    QCOMPARE(realistic.camera.projection, CameraProjection::Pinhole);
    const Scene tuned = parseOk(R"({"camera": {"preset": "realistic", "noise": 0, "latency": 0.1, "seed": 7}})");
    QCOMPARE(tuned.camera.noise, 0.0);
    QCOMPARE(tuned.camera.latency, 0.1);
    QCOMPARE(tuned.camera.seed, std::uint64_t(7));
    QCOMPARE(tuned.camera.k1, realisticCamera().k1);
    QCOMPARE(cameraPresetName(tuned.camera), QStringLiteral("custom"));
    // Keys without a preset apply over the ideal camera; delivery and truth
    // noise need no lens.
    const Scene noisy = parseOk(R"({"camera": {"position_noise": 0.003, "vanish": 0.5, "blur_samples": 2}})");
    QCOMPARE(noisy.camera.projection, CameraProjection::Orthographic);
    QCOMPARE(noisy.camera.position_noise, 0.003);
    QCOMPARE(noisy.camera.vanish, 0.5);
    QCOMPARE(noisy.camera.blur_samples, 2);
    // The same function reads a HELLO's overrides over a scene's camera, naming its own path.
    QString error;
    const std::optional<CameraSettings> over =
        cameraSettingsFromJson(QJsonObject{{"drop", 0.25}}, realisticCamera(), "hello.camera", &error);
    QVERIFY2(over, qPrintable(error));
    QCOMPARE(over->drop, 0.25);
    QCOMPARE(over->k2, realisticCamera().k2);
    QVERIFY(!cameraSettingsFromJson(QJsonObject{{"drop", 1.5}}, realisticCamera(), "hello.camera", &error));
    QVERIFY2(error.startsWith("hello.camera.drop: must be between 0 and 0.9"), qPrintable(error));
}

void TestSceneIo::cameraRoundTripIsExact() {
    Scene s;
    s.camera = realisticCamera();
    s.camera.height = 1.0 + 1.0 / 3;
    s.camera.focal_length = 700.0 / 7 * 3;
    s.camera.k3 = -1.0 / 9;
    s.camera.p2 = 1.0 / 300;
    s.camera.gain_g = 2.0 / 3;
    s.camera.jitter = 0.01 / 3;
    s.camera.blur_samples = 13;
    s.camera.seed = (std::uint64_t(1) << 53) - 1;
    QString error;
    const std::optional<Scene> back = parseScene(sceneToJson(s), &error);
    QVERIFY2(back, qPrintable(error));
    QVERIFY(back->camera == s.camera);
    // Every key is written, so a written scene does not depend on today's presets.
    const QJsonObject camera = QJsonDocument::fromJson(sceneToJson(Scene{})).object()["camera"].toObject();
    QCOMPARE(camera.size(), 24);
    QCOMPARE(camera["projection"].toString(), QStringLiteral("orthographic"));
    QCOMPARE(camera.value("preset"), QJsonValue(QJsonValue::Undefined));
}

void TestSceneIo::badCamera_data() {
    QTest::addColumn<QByteArray>("json");
    QTest::addColumn<QString>("message");
    QTest::newRow("not an object") << QByteArray(R"({"camera": "realistic"})") << "camera: expected an object";
    QTest::newRow("unknown key") << QByteArray(R"({"camera": {"fov": 70}})")
                                 << "camera.fov: unknown key (expected one of: preset, projection, height,";
    QTest::newRow("unknown preset") << QByteArray(R"({"camera": {"preset": "real"}})")
                                    << R"(camera.preset: expected one of "ideal", "realistic" (got "real"))";
    QTest::newRow("unknown projection") << QByteArray(R"({"camera": {"projection": "fisheye"}})")
                                        << R"(camera.projection: expected one of "orthographic", "pinhole")";
    QTest::newRow("camera below the robots") << QByteArray(R"({"camera": {"preset": "realistic", "height": 0.05}})")
                                             << "camera.height: must be between 0.5 and 20 m (got 0.05)";
    QTest::newRow("negative focal length") << QByteArray(R"({"camera": {"focal_length": -1}})")
                                           << "camera.focal_length: must be between 0 and 100000 px (got -1)";
    QTest::newRow("tiny focal length") << QByteArray(R"({"camera": {"preset": "realistic", "focal_length": 0.001}})")
                                       << "camera.focal_length: must be 0 (automatic) or at least 50 px (got 0.001)";
    QTest::newRow("distortion without a lens") << QByteArray(R"({"camera": {"k1": -0.1}})")
                                               << "camera.projection: lens distortion (k1, k2, p1, p2, k3) needs";
    QTest::newRow("k1 too strong") << QByteArray(R"({"camera": {"preset": "realistic", "k1": -3}})")
                                   << "camera.k1: must be between -1 and 1 (got -3)";
    QTest::newRow("p2 too strong") << QByteArray(R"({"camera": {"preset": "realistic", "p2": 0.5}})")
                                   << "camera.p2: must be between -0.1 and 0.1 (got 0.5)";
    QTest::newRow("vignetting") << QByteArray(R"({"camera": {"vignetting": 1.5}})")
                                << "camera.vignetting: must be between 0 and 1 (got 1.5)";
    QTest::newRow("gain") << QByteArray(R"({"camera": {"gain_r": -1}})")
                          << "camera.gain_r: must be between 0 and 4 (got -1)";
    QTest::newRow("noise not a number") << QByteArray(R"({"camera": {"noise": "low"}})")
                                        << "camera.noise: expected a number";
    QTest::newRow("exposure") << QByteArray(R"({"camera": {"exposure": 1}})")
                              << "camera.exposure: must be between 0 and 0.1 s (got 1)";
    QTest::newRow("blur samples fractional") << QByteArray(R"({"camera": {"blur_samples": 2.5}})")
                                             << "camera.blur_samples: must be a whole number (got 2.5)";
    QTest::newRow("blur samples too few") << QByteArray(R"({"camera": {"blur_samples": 1}})")
                                          << "camera.blur_samples: must be between 2 and 64 (got 1)";
    QTest::newRow("latency") << QByteArray(R"({"camera": {"latency": -0.01}})")
                             << "camera.latency: must be between 0 and 1 s (got -0.01)";
    QTest::newRow("drop every frame") << QByteArray(R"({"camera": {"drop": 1}})")
                                      << "camera.drop: must be between 0 and 0.9 (got 1)";
    QTest::newRow("heading noise") << QByteArray(R"({"camera": {"heading_noise": 4}})")
                                   << "camera.heading_noise: must be between 0 and 3.14159";
    QTest::newRow("seed fractional") << QByteArray(R"({"camera": {"seed": 1.5}})")
                                     << "camera.seed: must be a whole number (got 1.5)";
    QTest::newRow("seed negative") << QByteArray(R"({"camera": {"seed": -1}})") << "camera.seed: must be between 0 and";
}

void TestSceneIo::badCamera() {
    QFETCH(QByteArray, json);
    QFETCH(QString, message);
    QString error;
    QVERIFY(!parseScene(json, &error));
    QVERIFY2(error.startsWith(message), qPrintable(error));
}

QTEST_GUILESS_MAIN(TestSceneIo)
#include "test_scene_io.moc"
