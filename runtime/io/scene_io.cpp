#include "io/scene_io.h"

#include <sys/stat.h>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QHash>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QStringList>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "io/printable_text.h"

namespace vssim {

namespace {

constexpr int kShownCharacters = 40;  // of a name or key quoted in a message; longer ones are cut

// A name or key from the file as a message may quote it: no control characters, at most kShownCharacters.
QString shown(const QString& text) { return printableText(text, kShownCharacters); }

// Name <-> value tables, one place each.
const std::pair<const char*, Integrator> kIntegrators[] = {
    {"euler", Integrator::Euler}, {"rk4", Integrator::Rk4}, {"exact", Integrator::Exact}};
const std::pair<const char*, CollisionModel> kCollisionModels[] = {{"paper", CollisionModel::Paper},
                                                                   {"impulse", CollisionModel::Impulse}};
const std::pair<const char*, Team> kTeams[] = {{"yellow", Team::Yellow}, {"blue", Team::Blue}};
const std::pair<const char*, TeamControl> kTeamControls[] = {
    {"builtin", TeamControl::Builtin}, {"remote", TeamControl::Remote}, {"idle", TeamControl::Idle}};
const std::pair<const char*, CameraProjection> kProjections[] = {{"orthographic", CameraProjection::Orthographic},
                                                                  {"pinhole", CameraProjection::Pinhole}};
const std::pair<const char*, int> kCameraPresets[] = {{"ideal", 0}, {"realistic", 1}};
const std::pair<const char*, FieldType> kFieldTypes[] = {
    {"box", FieldType::Box}, {"vsss_3v3", FieldType::Vsss3v3}, {"vsss_5v5", FieldType::Vsss5v5}};

template <typename T, std::size_t N>
QString nameOf(const std::pair<const char*, T> (&table)[N], T value) {
    for (const auto& [name, v] : table)
        if (v == value) return QString::fromLatin1(name);
    return {};
}

template <typename T, std::size_t N>
std::optional<T> valueOf(const std::pair<const char*, T> (&table)[N], const QString& name) {
    for (const auto& [n, v] : table)
        if (name == QLatin1String(n)) return v;
    return std::nullopt;
}

template <typename T, std::size_t N>
QString choices(const std::pair<const char*, T> (&table)[N]) {
    QStringList names;
    for (const auto& entry : table) names << QStringLiteral("\"%1\"").arg(entry.first);
    return names.join(", ");
}

using namespace scene_limits;

// "between 0.01 and 100 kg", "> 0 and <= 1000 V", "between 0 and 1".
QString rangeText(const AllowedRange& r) {
    const QString unit = *r.unit ? QStringLiteral(" ") + QString::fromUtf8(r.unit) : QString();
    if (r.aboveMin) return QStringLiteral("> %1 and <= %2%3").arg(r.min).arg(r.max).arg(unit);
    return QStringLiteral("between %1 and %2%3").arg(r.min).arg(r.max).arg(unit);
}

// Reads JSON into a Scene, keeping the key path of what it reads so that
// every error says where it is. The first error stops the reading.
class SceneReader {
public:
    std::optional<Scene> read(const QJsonObject& root);
    QString error() const { return error_; }
    // A `camera` object at `path` over `c` (its preset first, then each key).
    bool camera(const QJsonObject& o, const QString& path, CameraSettings& c);

private:
    bool fail(const QString& path, const QString& message) {
        if (error_.isEmpty()) error_ = (path.isEmpty() ? QStringLiteral("(top level)") : path) + ": " + message;
        return false;
    }
    static QString join(const QString& path, const QString& key) { return path.isEmpty() ? key : path + "." + key; }

    bool objectAt(const QJsonValue& value, const QString& path, QJsonObject* out);
    bool keys(const QJsonObject& o, const QString& path, std::initializer_list<const char*> allowed);
    bool number(const QJsonObject& o, const QString& path, const char* key, const AllowedRange& range, double* out);
    bool stringAt(const QJsonObject& o, const QString& path, const char* key, QString* out);
    template <typename T, std::size_t N>
    bool choice(const QJsonObject& o, const QString& path, const char* key, const std::pair<const char*, T> (&table)[N],
                T* out);

    bool field(const QJsonObject& root, Scene& scene);
    bool simulation(const QJsonObject& root, Scene& scene);
    bool motor(const QJsonObject& o, const QString& path, MotorParams& p);
    bool robotParams(const QJsonObject& o, const QString& path, RobotParams& p, bool* inertiaGiven);
    bool ball(const QJsonObject& root, Scene& scene);
    bool robots(const QJsonObject& root, const RobotParams& defaults, bool inertiaGiven, Scene& scene);
    bool commands(const QJsonObject& root, Scene& scene);
    bool game(const QJsonObject& root, Scene& scene);
    bool camera(const QJsonObject& root, Scene& scene);
    bool insideField(const Scene& scene);
    bool bodiesFit(const Scene& scene);

    QString error_;
    QHash<QString, int> robotIndex_;  // robot name -> index in Scene::robots, for the commands
};

bool SceneReader::objectAt(const QJsonValue& value, const QString& path, QJsonObject* out) {
    if (!value.isObject()) return fail(path, QStringLiteral("expected an object"));
    *out = value.toObject();
    return true;
}

bool SceneReader::keys(const QJsonObject& o, const QString& path, std::initializer_list<const char*> allowed) {
    for (auto it = o.begin(); it != o.end(); ++it) {
        bool known = false;
        for (const char* key : allowed) known = known || it.key() == QLatin1String(key);
        if (known) continue;
        QStringList names;
        for (const char* key : allowed) names << key;
        return fail(join(path, shown(it.key())),
                    QStringLiteral("unknown key (expected one of: %1)").arg(names.join(", ")));
    }
    return true;
}

bool SceneReader::number(const QJsonObject& o, const QString& path, const char* key, const AllowedRange& range,
                         double* out) {
    if (!o.contains(QLatin1String(key))) return true;  // keep the default
    const QString where = join(path, key);
    const QJsonValue value = o.value(QLatin1String(key));
    if (!value.isDouble()) return fail(where, QStringLiteral("expected a number"));
    const double x = value.toDouble();
    if (!std::isfinite(x)) return fail(where, QStringLiteral("must be a finite number"));
    if (x < range.min || (range.aboveMin && x == range.min) || x > range.max)
        return fail(where, QStringLiteral("must be %1 (got %2)").arg(rangeText(range)).arg(x));
    *out = x;
    return true;
}

bool SceneReader::stringAt(const QJsonObject& o, const QString& path, const char* key, QString* out) {
    if (!o.contains(QLatin1String(key))) return true;
    const QJsonValue value = o.value(QLatin1String(key));
    if (!value.isString()) return fail(join(path, key), QStringLiteral("expected a string"));
    *out = value.toString();
    return true;
}

template <typename T, std::size_t N>
bool SceneReader::choice(const QJsonObject& o, const QString& path, const char* key,
                         const std::pair<const char*, T> (&table)[N], T* out) {
    QString name;
    if (!o.contains(QLatin1String(key))) return true;
    if (!stringAt(o, path, key, &name)) return false;
    const std::optional<T> value = valueOf(table, name);
    if (!value)
        return fail(join(path, key),
                    QStringLiteral("expected one of %1 (got \"%2\")").arg(choices(table), shown(name)));
    *out = *value;
    return true;
}

bool SceneReader::field(const QJsonObject& root, Scene& scene) {
    if (!root.contains("field")) return true;
    QJsonObject o;
    const QString path = "field";
    if (!objectAt(root.value(path), path, &o) ||
        !keys(o, path,
              {"type", "length", "width", "goal_width", "goal_depth", "corner_leg", "centre_radius", "goal_area_depth",
               "goal_area_width", "penalty_mark", "free_ball_x", "free_ball_y"}))
        return false;
    // The type gives every dimension its default; the keys override them one by one.
    FieldType type = FieldType::Box;
    if (!choice(o, path, "type", kFieldTypes, &type)) return false;
    FieldDimensions d = officialDimensions(type);
    const bool centreGiven = o.contains(QLatin1String("centre_radius"));
    for (const FieldDimensionKey& k : kFieldDimensionKeys) {
        if (type == FieldType::Box && !k.box && o.contains(QLatin1String(k.key)))
            return fail(join(path, k.key),
                        QStringLiteral("a box has no goals, corner triangles or goal areas (give field.type "
                                       "\"vsss_3v3\" or \"vsss_5v5\" for a field with goals)"));
        if (!number(o, path, k.key, k.range, &(d.*k.dimension))) return false;
    }
    // A box too small for the default centre circle has none (as boxDimensions).
    if (type == FieldType::Box && !centreGiven) d = boxDimensions(d.length, d.width);
    const FieldProblem problem = checkFieldDimensions(d);
    if (problem.key) {
        double value = 0.0;
        for (const FieldDimensionKey& k : kFieldDimensionKeys)
            if (std::strcmp(k.key, problem.key) == 0) value = d.*k.dimension;
        return fail(join(path, problem.key),
                    QStringLiteral("%1 (got %2 m)").arg(QString::fromUtf8(problem.reason)).arg(value));
    }
    scene.field = makeField(d);
    return true;
}

bool SceneReader::simulation(const QJsonObject& root, Scene& scene) {
    if (!root.contains("simulation")) return true;
    QJsonObject o;
    SimulationSettings& s = scene.simulation;
    const QString path = "simulation";
    if (!objectAt(root.value(path), path, &o) || !keys(o, path, {"integrator", "dt", "collision_model", "restitution"}) ||
        !choice(o, path, "integrator", kIntegrators, &s.integrator) || !number(o, path, "dt", kTimeStep, &s.dt) ||
        !choice(o, path, "collision_model", kCollisionModels, &s.collision_model) ||
        !number(o, path, "restitution", kUnitInterval, &s.restitution))
        return false;
    return true;
}

bool SceneReader::motor(const QJsonObject& o, const QString& path, MotorParams& p) {
    return keys(o, path, {"wheel_radius", "resistance", "k", "rotor_inertia", "friction"}) &&
           number(o, path, "wheel_radius", kWheelRadius, &p.wheel_radius) &&
           number(o, path, "resistance", kResistance, &p.resistance) && number(o, path, "k", kMotorConstant, &p.k) &&
           number(o, path, "rotor_inertia", kRotorInertia, &p.rotor_inertia) &&
           number(o, path, "friction", kMotorFriction, &p.friction);
}

bool SceneReader::robotParams(const QJsonObject& o, const QString& path, RobotParams& p, bool* inertiaGiven) {
    if (!keys(o, path,
              {"side", "mass", "inertia", "wheel_base", "friction_linear", "friction_angular", "max_voltage", "right",
               "left", "speed_controller"}) ||
        !number(o, path, "side", kRobotSide, &p.side) || !number(o, path, "mass", kRobotMass, &p.mass) ||
        !number(o, path, "inertia", kRobotInertia, &p.inertia) ||
        !number(o, path, "wheel_base", kWheelBase, &p.wheel_base) ||
        !number(o, path, "friction_linear", kLinearFriction, &p.friction_linear) ||
        !number(o, path, "friction_angular", kAngularFriction, &p.friction_angular) ||
        !number(o, path, "max_voltage", kMaxVoltage, &p.max_voltage))
        return false;
    *inertiaGiven = *inertiaGiven || o.contains("inertia");
    for (const auto& [key, motorParams] :
         {std::pair<const char*, MotorParams*>{"right", &p.right}, {"left", &p.left}}) {
        if (!o.contains(QLatin1String(key))) continue;
        QJsonObject m;
        if (!objectAt(o.value(QLatin1String(key)), join(path, key), &m) || !motor(m, join(path, key), *motorParams))
            return false;
    }
    if (o.contains("speed_controller")) {
        QJsonObject c;
        const QString where = join(path, "speed_controller");
        SpeedControllerParams& s = p.speed_controller;
        double counts = s.encoder_counts;
        if (!objectAt(o.value("speed_controller"), where, &c) ||
            !keys(c, where, {"rate", "kp", "ki", "encoder_counts"}) || !number(c, where, "rate", kLoopRate, &s.rate) ||
            !number(c, where, "kp", kLoopKp, &s.kp) || !number(c, where, "ki", kLoopKi, &s.ki) ||
            !number(c, where, "encoder_counts", kEncoderCounts, &counts))
            return false;
        if (counts != std::floor(counts))
            return fail(join(where, "encoder_counts"),
                        QStringLiteral("must be a whole number of counts per revolution (got %1)").arg(counts));
        s.encoder_counts = static_cast<int>(counts);
    }
    return true;
}

bool SceneReader::ball(const QJsonObject& root, Scene& scene) {
    if (!root.contains("ball")) return true;
    QJsonObject o;
    BallState& b = scene.ball;
    BallParams& p = scene.ball_params;
    if (!objectAt(root.value("ball"), "ball", &o) ||
        !keys(o, "ball", {"x", "y", "vx", "vy", "mass", "radius", "friction"}) || !number(o, "ball", "x", kAny, &b.x) ||
        !number(o, "ball", "y", kAny, &b.y) || !number(o, "ball", "vx", kBallVelocity, &b.vx) ||
        !number(o, "ball", "vy", kBallVelocity, &b.vy) || !number(o, "ball", "mass", kBallMass, &p.mass) ||
        !number(o, "ball", "radius", kBallRadius, &p.radius) ||
        !number(o, "ball", "friction", kBallFriction, &p.friction))
        return false;
    const double speed = std::hypot(b.vx, b.vy);  // m/s
    if (speed > kMaxBallSpeed)
        return fail("ball",
                    QStringLiteral("the speed |(vx, vy)| must be <= %1 m/s (got %2)").arg(kMaxBallSpeed).arg(speed));
    return true;
}

bool SceneReader::robots(const QJsonObject& root, const RobotParams& defaults, bool inertiaGiven, Scene& scene) {
    if (!root.contains("robots")) return true;
    if (!root.value("robots").isArray()) return fail("robots", QStringLiteral("expected an array"));
    const QJsonArray list = root.value("robots").toArray();
    std::map<Team, int> perTeam;
    for (int i = 0; i < list.size(); ++i) {
        const QString path = QStringLiteral("robots[%1]").arg(i);
        QJsonObject o;
        if (!objectAt(list[i], path, &o) || !keys(o, path, {"name", "team", "x", "y", "theta", "v", "omega", "params"}))
            return false;
        RobotSpec r;
        r.params = defaults;
        QString name;
        RobotState& s = r.initial;
        if (!stringAt(o, path, "name", &name) || !choice(o, path, "team", kTeams, &r.team) ||
            !number(o, path, "x", kAny, &s.x) || !number(o, path, "y", kAny, &s.y) ||
            !number(o, path, "theta", kAny, &s.theta) || !number(o, path, "v", kRobotSpeed, &s.v) ||
            !number(o, path, "omega", kRobotYawRate, &s.omega))
            return false;
        bool ownInertia = inertiaGiven;
        if (o.contains("params")) {
            QJsonObject p;
            if (!objectAt(o.value("params"), join(path, "params"), &p) ||
                !robotParams(p, join(path, "params"), r.params, &ownInertia))
                return false;
        }
        if (!ownInertia) r.params.inertia = r.params.mass * r.params.side * r.params.side / 6.0;  // uniform cube
        const int indexInTeam = perTeam[r.team]++;
        if (!o.contains("name")) name = teamName(r.team) + QString::number(indexInTeam);
        if (name.isEmpty()) return fail(join(path, "name"), QStringLiteral("must not be empty"));
        // Names are written unquoted in CSV rows (UTF-8), where "ball" names the ball.
        for (const QChar ch : name)
            if (ch == ',' || ch == '"' || ch.category() == QChar::Other_Control)
                return fail(
                    join(path, "name"),
                    QStringLiteral("\"%1\" may not contain commas, quotes or control characters (it names CSV rows)")
                        .arg(shown(name)));
        // A lone UTF-16 surrogate (JSON "\ud800") has no UTF-8 form: it would
        // become "?", and two such names the same CSV name. Valid Unicode
        // converts one to one, so distinct names stay distinct in the CSV.
        if (!name.isValidUtf16())
            return fail(join(path, "name"),
                        QStringLiteral("\"%1\" is not valid Unicode (it holds a lone UTF-16 surrogate such as \\ud800)")
                            .arg(shown(name)));
        if (name == QLatin1String("ball"))
            return fail(join(path, "name"), QStringLiteral("\"ball\" is reserved for the ball"));
        if (robotIndex_.contains(name))
            return fail(join(path, "name"), QStringLiteral("duplicate name \"%1\"").arg(shown(name)));
        robotIndex_.insert(name, static_cast<int>(scene.robots.size()));
        r.name = name.toStdString();
        scene.robots.push_back(r);
    }
    return true;
}

bool SceneReader::commands(const QJsonObject& root, Scene& scene) {
    if (!root.contains("commands")) return true;
    if (!root.value("commands").isArray()) return fail("commands", QStringLiteral("expected an array"));
    const QJsonArray list = root.value("commands").toArray();
    for (int i = 0; i < list.size(); ++i) {
        const QString path = QStringLiteral("commands[%1]").arg(i);
        QJsonObject o;
        VoltageCommand c;
        QString robot;
        if (!objectAt(list[i], path, &o) ||
            !keys(o, path, {"t", "robot", "right", "left", "right_speed", "left_speed"}) ||
            !number(o, path, "t", kCommandTime, &c.t) || !stringAt(o, path, "robot", &robot) ||
            !number(o, path, "right", kAny, &c.voltages.right) || !number(o, path, "left", kAny, &c.voltages.left) ||
            !number(o, path, "right_speed", kWheelSpeedTarget, &c.speeds.right) ||
            !number(o, path, "left_speed", kWheelSpeedTarget, &c.speeds.left))
            return false;
        // Voltages (right, left) or wheel-speed targets (right_speed, left_speed), not both.
        const bool volts = o.contains("right") || o.contains("left");
        c.wheelSpeeds = o.contains("right_speed") || o.contains("left_speed");
        if (volts && c.wheelSpeeds)
            return fail(path, QStringLiteral("gives both voltages (right, left) and wheel speeds (right_speed, "
                                             "left_speed): a command is one or the other"));
        if (!o.contains("robot")) return fail(join(path, "robot"), QStringLiteral("missing (the name of a robot)"));
        c.robot = robotIndex_.value(robot, -1);  // a hash look-up: loading stays linear in robots + commands
        if (c.robot < 0) return fail(join(path, "robot"), QStringLiteral("no robot named \"%1\"").arg(shown(robot)));
        scene.commands.push_back(c);
    }
    return true;
}

bool SceneReader::game(const QJsonObject& root, Scene& scene) {
    if (!root.contains("game")) return true;
    QJsonObject o;
    GameSettings& g = scene.game;
    GameRules& r = g.rules;
    const QString path = "game";
    double halves = r.halves;
    if (!objectAt(root.value(path), path, &o) ||
        !keys(o, path,
              {"referee", "halves", "half_duration", "stop_duration", "stuck_ball_speed", "stuck_ball_time",
               "crowded_area_time", "free_ball_distance", "tick", "left_team", "yellow", "blue"}) ||
        !number(o, path, "halves", {1.0, static_cast<double>(kMaxHalves), false, ""}, &halves) ||
        !number(o, path, "half_duration", kHalfDuration, &r.half_duration) ||
        !number(o, path, "stop_duration", kStopDuration, &r.stop_duration) ||
        !number(o, path, "stuck_ball_speed", kStuckBallSpeed, &r.stuck_ball_speed) ||
        !number(o, path, "stuck_ball_time", kRuleTime, &r.stuck_ball_time) ||
        !number(o, path, "crowded_area_time", kRuleTime, &r.crowded_area_time) ||
        !number(o, path, "free_ball_distance", kFreeBallDistance, &r.free_ball_distance) ||
        !number(o, path, "tick", kGameTick, &r.tick) || !choice(o, path, "left_team", kTeams, &r.left_team) ||
        !choice(o, path, "yellow", kTeamControls, &g.yellow) ||
        !choice(o, path, "blue", kTeamControls, &g.blue))
        return false;
    if (halves != std::floor(halves))
        return fail(join(path, "halves"), QStringLiteral("must be a whole number (got %1)").arg(halves));
    r.halves = static_cast<int>(halves);
    if (o.contains("referee")) {
        if (!o.value("referee").isBool()) return fail(join(path, "referee"), QStringLiteral("expected true or false"));
        r.referee = o.value("referee").toBool();
    }
    // The tick matters only when something acts at it: the referee or a built-in team.
    const bool ticking = r.referee || g.yellow == TeamControl::Builtin || g.blue == TeamControl::Builtin;
    const QString tickProblem = ticking ? gameTickProblem(r.tick, scene.simulation.dt) : QString();
    if (!tickProblem.isEmpty()) return fail(join(path, "tick"), tickProblem);
    if (r.referee && !fieldHasGoals(scene.field)) return fail(join(path, "referee"), refereeFieldProblem());
    return true;
}

bool SceneReader::camera(const QJsonObject& root, Scene& scene) {
    if (!root.contains("camera")) return true;
    QJsonObject o;
    return objectAt(root.value("camera"), "camera", &o) && camera(o, "camera", scene.camera);
}

bool SceneReader::camera(const QJsonObject& o, const QString& path, CameraSettings& c) {
    if (!keys(o, path, {"preset", "projection", "height", "focal_length", "k1", "k2", "p1", "p2", "k3", "vignetting",
                        "gradient_x", "gradient_y", "gain_b", "gain_g", "gain_r", "noise", "exposure", "blur_samples",
                        "latency", "jitter", "drop", "position_noise", "heading_noise", "vanish", "seed"}))
        return false;
    int preset = -1;
    if (!choice(o, path, "preset", kCameraPresets, &preset)) return false;
    if (preset >= 0) c = preset == 0 ? idealCamera() : realisticCamera();
    double samples = c.blur_samples, seed = static_cast<double>(c.seed);
    if (!choice(o, path, "projection", kProjections, &c.projection) ||
        !number(o, path, "height", kCameraHeight, &c.height) ||
        !number(o, path, "focal_length", kFocalLength, &c.focal_length) ||
        !number(o, path, "k1", kRadialDistortion, &c.k1) || !number(o, path, "k2", kRadialDistortion, &c.k2) ||
        !number(o, path, "p1", kTangentialDistortion, &c.p1) ||
        !number(o, path, "p2", kTangentialDistortion, &c.p2) || !number(o, path, "k3", kRadialDistortion, &c.k3) ||
        !number(o, path, "vignetting", kVignetting, &c.vignetting) ||
        !number(o, path, "gradient_x", kLightGradient, &c.gradient_x) ||
        !number(o, path, "gradient_y", kLightGradient, &c.gradient_y) ||
        !number(o, path, "gain_b", kColourGain, &c.gain_b) || !number(o, path, "gain_g", kColourGain, &c.gain_g) ||
        !number(o, path, "gain_r", kColourGain, &c.gain_r) || !number(o, path, "noise", kSensorNoise, &c.noise) ||
        !number(o, path, "exposure", kExposure, &c.exposure) ||
        !number(o, path, "blur_samples", kBlurSamples, &samples) ||
        !number(o, path, "latency", kCameraDelay, &c.latency) || !number(o, path, "jitter", kCameraDelay, &c.jitter) ||
        !number(o, path, "drop", kLossProbability, &c.drop) ||
        !number(o, path, "position_noise", kPositionNoise, &c.position_noise) ||
        !number(o, path, "heading_noise", kHeadingNoise, &c.heading_noise) ||
        !number(o, path, "vanish", kLossProbability, &c.vanish) || !number(o, path, "seed", kCameraSeed, &seed))
        return false;
    if (samples != std::floor(samples))
        return fail(join(path, "blur_samples"), QStringLiteral("must be a whole number (got %1)").arg(samples));
    if (seed != std::floor(seed))
        return fail(join(path, "seed"), QStringLiteral("must be a whole number (got %1)").arg(seed, 0, 'g', 17));
    c.blur_samples = static_cast<int>(samples);
    c.seed = static_cast<std::uint64_t>(seed);
    if (c.focal_length != 0.0 && c.focal_length < kMinFocalLength)
        return fail(join(path, "focal_length"),
                    QStringLiteral("must be 0 (automatic) or at least %1 px (got %2): a 640-px image at %1 px "
                                   "already sees 162 degrees across")
                        .arg(kMinFocalLength)
                        .arg(c.focal_length));
    const bool distorted = c.k1 != 0 || c.k2 != 0 || c.p1 != 0 || c.p2 != 0 || c.k3 != 0;
    if (c.projection == CameraProjection::Orthographic && distorted)
        return fail(join(path, "projection"),
                    QStringLiteral("lens distortion (k1, k2, p1, p2, k3) needs the \"pinhole\" projection"));
    return true;
}

bool SceneReader::insideField(const Scene& scene) {
    const Field& field = scene.field;
    const double hx = field.length / 2, hy = field.width / 2;
    // A box without goals or corner triangles: a body is inside when its
    // centre is within |x| and |y| bounds, which the messages can name.
    const bool plainBox = field.walls.size() == 4;
    // half: the body's half-extent along x and along y, m; inside: whether it
    // lies on the floor clear of every wall and post (robotInsideField,
    // discInsideField).
    auto check = [&](const QString& path, double x, double y, double half, const QString& note, bool inside) {
        if (half > hx || half > hy) {
            const QString body =
                path == QLatin1String("ball") ? QStringLiteral("the ball") : QStringLiteral("the robot");
            return fail(path, QStringLiteral("the field (%1 m x %2 m) is smaller than %3, which is %4 m across%5")
                                  .arg(field.length, 0, 'g', 10)
                                  .arg(field.width, 0, 'g', 10)
                                  .arg(body)
                                  .arg(2 * half, 0, 'g', 10)
                                  .arg(note));
        }
        if (inside) return true;
        if (plainBox) {
            const QString what = QStringLiteral("%1 m is outside the field (|%2| must be <= %3 m%4)");
            if (std::abs(x) > hx - half)
                return fail(join(path, "x"), what.arg(x, 0, 'g', 10).arg('x').arg(hx - half, 0, 'g', 10).arg(note));
            if (std::abs(y) > hy - half)
                return fail(join(path, "y"), what.arg(y, 0, 'g', 10).arg('y').arg(hy - half, 0, 'g', 10).arg(note));
        }
        return fail(path, QStringLiteral("at (%1, %2) m%3 it is not wholly on the field's floor: it crosses a wall, a "
                                         "corner triangle or a goal post")
                              .arg(x, 0, 'g', 10)
                              .arg(y, 0, 'g', 10)
                              .arg(note));
    };
    const double r = scene.ball_params.radius;
    if (!check("ball", scene.ball.x, scene.ball.y, r, {}, discInsideField(field, r, scene.ball.x, scene.ball.y)))
        return false;
    for (std::size_t i = 0; i < scene.robots.size(); ++i) {
        const RobotSpec& robot = scene.robots[i];
        const RobotState& s = robot.initial;
        // A square of side s at heading theta reaches (s/2)(|cos| + |sin|) along x and y.
        const double turn = std::abs(std::cos(s.theta)) + std::abs(std::sin(s.theta));
        const QString note =
            std::abs(turn - 1.0) > 1e-9 ? QStringLiteral(" at heading %1 rad").arg(s.theta, 0, 'g', 6) : QString();
        if (!check(QStringLiteral("robots[%1]").arg(i), s.x, s.y, 0.5 * robot.params.side * turn, note,
                   robotInsideField(field, robot.params.side, s.x, s.y, s.theta)))
            return false;
    }
    return true;
}

bool SceneReader::bodiesFit(const Scene& scene) {
    const double kPi = 3.14159265358979323846;
    double covered = kPi * scene.ball_params.radius * scene.ball_params.radius;  // m²
    for (const RobotSpec& robot : scene.robots) covered += robot.params.side * robot.params.side;
    const double area = floorArea(scene.field);  // m²
    if (covered <= kMaxCoveredFraction * area) return true;
    return fail(scene.robots.empty() ? QStringLiteral("ball") : QStringLiteral("robots"),
                QStringLiteral("the ball and %1 robot%2 cover %3 m², more than %4% of the field's %5 m²: they cannot "
                               "all fit (use a larger field, or fewer or smaller robots)")
                    .arg(scene.robots.size())
                    .arg(scene.robots.size() == 1 ? "" : "s")
                    .arg(covered, 0, 'g', 4)
                    .arg(100 * kMaxCoveredFraction)
                    .arg(area, 0, 'g', 4));
}

std::optional<Scene> SceneReader::read(const QJsonObject& root) {
    Scene scene;
    if (!keys(root, "", {"version", "field", "simulation", "robot_defaults", "ball", "robots", "commands", "game",
                         "camera"}))
        return std::nullopt;
    double version = 1.0;
    if (!number(root, "", "version", kAny, &version)) return std::nullopt;
    if (version != 1.0) {
        fail("version", QStringLiteral("unsupported version %1 (this vssim reads version 1)").arg(version));
        return std::nullopt;
    }
    RobotParams defaults;
    bool inertiaGiven = false;
    if (root.contains("robot_defaults")) {
        QJsonObject o;
        if (!objectAt(root.value("robot_defaults"), "robot_defaults", &o) ||
            !robotParams(o, "robot_defaults", defaults, &inertiaGiven))
            return std::nullopt;
    }
    if (!field(root, scene) || !simulation(root, scene) || !ball(root, scene) ||
        !robots(root, defaults, inertiaGiven, scene) || !commands(root, scene) || !game(root, scene) || !camera(root, scene) ||
        !insideField(scene) || !bodiesFit(scene))
        return std::nullopt;
    return scene;
}

// Line and column (1-based) of a byte offset, for syntax errors.
QString lineAndColumn(const QByteArray& text, int offset) {
    int line = 1, column = 1;
    for (int i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n')
            ++line, column = 1;
        else
            ++column;
    }
    return QStringLiteral("line %1, column %2").arg(line).arg(column);
}

QJsonObject motorJson(const MotorParams& m) {
    return {{"wheel_radius", m.wheel_radius},
            {"resistance", m.resistance},
            {"k", m.k},
            {"rotor_inertia", m.rotor_inertia},
            {"friction", m.friction}};
}

QJsonObject robotParamsJson(const RobotParams& p) {
    return {{"side", p.side},
            {"mass", p.mass},
            {"inertia", p.inertia},
            {"wheel_base", p.wheel_base},
            {"friction_linear", p.friction_linear},
            {"friction_angular", p.friction_angular},
            {"max_voltage", p.max_voltage},
            {"right", motorJson(p.right)},
            {"left", motorJson(p.left)},
            {"speed_controller", QJsonObject{{"rate", p.speed_controller.rate},
                                             {"kp", p.speed_controller.kp},
                                             {"ki", p.speed_controller.ki},
                                             {"encoder_counts", p.speed_controller.encoder_counts}}}};
}

}  // namespace

QString integratorName(Integrator integrator) { return nameOf(kIntegrators, integrator); }
std::optional<Integrator> integratorFromName(const QString& name) { return valueOf(kIntegrators, name); }
QString collisionModelName(CollisionModel model) { return nameOf(kCollisionModels, model); }
std::optional<CollisionModel> collisionModelFromName(const QString& name) { return valueOf(kCollisionModels, name); }
QString teamName(Team team) { return nameOf(kTeams, team); }
std::optional<Team> teamFromName(const QString& name) { return valueOf(kTeams, name); }
QString teamControlName(TeamControl control) { return nameOf(kTeamControls, control); }
std::optional<TeamControl> teamControlFromName(const QString& name) { return valueOf(kTeamControls, name); }

bool fieldHasGoals(const Field& field) { return field.dimensions.type != FieldType::Box; }

QString refereeFieldProblem() {
    return QStringLiteral("a referee needs a field with goals (field.type \"vsss_3v3\" or \"vsss_5v5\"), not a box");
}

QString gameTickProblem(double tick, double dt) {
    const double steps = tick / dt;
    if (tick < dt * (1.0 - 1e-9))
        return QStringLiteral("must be at least one step of simulation.dt (%1 s; got %2 s)").arg(dt).arg(tick);
    if (std::abs(steps - std::round(steps)) > 1e-9 * steps)
        return QStringLiteral("must be a whole number of steps of simulation.dt (%1 s; got %2 s, %3 steps)")
            .arg(dt)
            .arg(tick)
            .arg(steps, 0, 'g', 10);
    return {};
}

QJsonObject gameRulesToJson(const GameRules& r) {
    return {{"referee", r.referee},
            {"halves", r.halves},
            {"half_duration", r.half_duration},
            {"stop_duration", r.stop_duration},
            {"stuck_ball_speed", r.stuck_ball_speed},
            {"stuck_ball_time", r.stuck_ball_time},
            {"crowded_area_time", r.crowded_area_time},
            {"free_ball_distance", r.free_ball_distance},
            {"tick", r.tick},
            {"left_team", teamName(r.left_team)}};
}
QString fieldTypeName(FieldType type) { return nameOf(kFieldTypes, type); }
std::optional<FieldType> fieldTypeFromName(const QString& name) { return valueOf(kFieldTypes, name); }

const FieldDimensionKey kFieldDimensionKeys[11] = {
    {"length", &FieldDimensions::length, kFieldSize, true},
    {"width", &FieldDimensions::width, kFieldSize, true},
    {"goal_width", &FieldDimensions::goal_width, kFieldFeature, false},
    {"goal_depth", &FieldDimensions::goal_depth, kFieldFeature, false},
    {"corner_leg", &FieldDimensions::corner_leg, kFieldFeature, false},
    {"centre_radius", &FieldDimensions::centre_radius, kFieldFeature, true},
    {"goal_area_depth", &FieldDimensions::goal_area_depth, kFieldFeature, false},
    {"goal_area_width", &FieldDimensions::goal_area_width, kFieldFeature, false},
    {"penalty_mark", &FieldDimensions::penalty_mark, kFieldFeature, false},
    {"free_ball_x", &FieldDimensions::free_ball_x, kFieldFeature, false},
    {"free_ball_y", &FieldDimensions::free_ball_y, kFieldFeature, false},
};

FieldDimensions boxDimensions(double length, double width) {
    FieldDimensions d = officialDimensions(FieldType::Box);
    d.length = length;
    d.width = width;
    if (!(d.centre_radius < 0.5 * std::min(length, width))) d.centre_radius = 0.0;
    return d;
}

double floorArea(const Field& field) {
    // The shoelace formula over the closed counter-clockwise chain of walls;
    // the box's rectangle is length x width exactly.
    if (field.walls.size() == 4) return field.length * field.width;
    double twice = 0.0;
    for (const Wall& w : field.walls) twice += w.a.x() * w.b.y() - w.b.x() * w.a.y();
    return 0.5 * twice;
}

std::optional<Scene> parseScene(const QByteArray& json, QString* error) {
    QJsonParseError parseError;
    const QJsonDocument doc = QJsonDocument::fromJson(json, &parseError);
    if (parseError.error != QJsonParseError::NoError) {
        *error = QStringLiteral("%1: %2").arg(lineAndColumn(json, parseError.offset), parseError.errorString());
        return std::nullopt;
    }
    if (!doc.isObject()) {
        *error = QStringLiteral("(top level): expected an object");
        return std::nullopt;
    }
    SceneReader reader;
    std::optional<Scene> scene = reader.read(doc.object());
    if (!scene) *error = reader.error();
    return scene;
}

std::optional<Scene> loadSceneFile(const QString& path, QString* error) {
    QFile file(path);
    if (!file.open(QIODevice::ReadOnly)) {
        *error = QStringLiteral("%1: cannot read: %2").arg(path, file.errorString());
        return std::nullopt;
    }
    const qint64 kMaxBytes = 64 << 20;
    if (file.size() > kMaxBytes) {
        *error = QStringLiteral("%1: %2 bytes is too large for a scene (limit 64 MiB)").arg(path).arg(file.size());
        return std::nullopt;
    }
    std::optional<Scene> scene = parseScene(file.readAll(), error);
    if (!scene) *error = path + ": " + *error;
    return scene;
}

QJsonObject fieldToJson(const Field& field) {
    // The type and every dimension it takes, so that reading it back gives the same field.
    const FieldDimensions& d = field.dimensions;
    QJsonObject o{{"type", fieldTypeName(d.type)}};
    for (const FieldDimensionKey& k : kFieldDimensionKeys)
        if (d.type != FieldType::Box || k.box) o[k.key] = d.*k.dimension;
    // A box made in code with a centre circle it cannot hold (makeRectangularField
    // of a small box): left out, so the file is read as a box without one.
    if (d.type == FieldType::Box && !(d.centre_radius < 0.5 * std::min(d.length, d.width))) o.remove("centre_radius");
    return o;
}

std::optional<Field> fieldFromJson(const QJsonObject& field, QString* error) {
    QJsonObject root{{"field", field}};
    const std::optional<Scene> scene = parseScene(QJsonDocument(root).toJson(QJsonDocument::Compact), error);
    if (!scene) return std::nullopt;
    return scene->field;
}

QByteArray sceneToJson(const Scene& scene) {
    QJsonObject root;
    root["version"] = 1;
    root["field"] = fieldToJson(scene.field);
    const SimulationSettings& s = scene.simulation;
    root["simulation"] = QJsonObject{{"integrator", integratorName(s.integrator)},
                                     {"dt", s.dt},
                                     {"collision_model", collisionModelName(s.collision_model)},
                                     {"restitution", s.restitution}};
    root["ball"] = QJsonObject{{"x", scene.ball.x},
                               {"y", scene.ball.y},
                               {"vx", scene.ball.vx},
                               {"vy", scene.ball.vy},
                               {"mass", scene.ball_params.mass},
                               {"radius", scene.ball_params.radius},
                               {"friction", scene.ball_params.friction}};
    QJsonArray robots;
    for (const RobotSpec& r : scene.robots)
        robots.append(QJsonObject{{"name", QString::fromStdString(r.name)},
                                  {"team", teamName(r.team)},
                                  {"x", r.initial.x},
                                  {"y", r.initial.y},
                                  {"theta", r.initial.theta},
                                  {"v", r.initial.v},
                                  {"omega", r.initial.omega},
                                  {"params", robotParamsJson(r.params)}});
    root["robots"] = robots;
    QJsonArray commands;
    for (const VoltageCommand& c : scene.commands)
        commands.append(c.wheelSpeeds ? QJsonObject{{"t", c.t},
                                                    {"robot", QString::fromStdString(scene.robots[c.robot].name)},
                                                    {"right_speed", c.speeds.right},
                                                    {"left_speed", c.speeds.left}}
                                      : QJsonObject{{"t", c.t},
                                                    {"robot", QString::fromStdString(scene.robots[c.robot].name)},
                                                    {"right", c.voltages.right},
                                                    {"left", c.voltages.left}});
    root["commands"] = commands;
    QJsonObject game = gameRulesToJson(scene.game.rules);
    game["yellow"] = teamControlName(scene.game.yellow);
    game["blue"] = teamControlName(scene.game.blue);
    root["game"] = game;
    root["camera"] = cameraSettingsToJson(scene.camera);
    return QJsonDocument(root).toJson(QJsonDocument::Indented);
}

QJsonObject cameraSettingsToJson(const CameraSettings& c) {
    return {{"projection", nameOf(kProjections, c.projection)},
            {"height", c.height},
            {"focal_length", c.focal_length},
            {"k1", c.k1},
            {"k2", c.k2},
            {"p1", c.p1},
            {"p2", c.p2},
            {"k3", c.k3},
            {"vignetting", c.vignetting},
            {"gradient_x", c.gradient_x},
            {"gradient_y", c.gradient_y},
            {"gain_b", c.gain_b},
            {"gain_g", c.gain_g},
            {"gain_r", c.gain_r},
            {"noise", c.noise},
            {"exposure", c.exposure},
            {"blur_samples", c.blur_samples},
            {"latency", c.latency},
            {"jitter", c.jitter},
            {"drop", c.drop},
            {"position_noise", c.position_noise},
            {"heading_noise", c.heading_noise},
            {"vanish", c.vanish},
            {"seed", static_cast<double>(c.seed)}};
}

std::optional<CameraSettings> cameraSettingsFromJson(const QJsonObject& camera, const CameraSettings& base,
                                                     const QString& path, QString* error) {
    SceneReader reader;
    CameraSettings c = base;
    if (reader.camera(camera, path, c)) return c;
    if (error) *error = reader.error();
    return std::nullopt;
}

QString cameraPresetName(const CameraSettings& camera) {
    if (camera == idealCamera()) return QStringLiteral("ideal");
    if (camera == realisticCamera()) return QStringLiteral("realistic");
    return QStringLiteral("custom");
}

QString cameraProjectionName(CameraProjection projection) { return nameOf(kProjections, projection); }

bool sceneNamesLeftTeam(const QString& path) {
    QFile file(path);
    if (!file.open(QIODevice::ReadOnly)) return false;
    const QJsonDocument doc = QJsonDocument::fromJson(file.readAll());
    return doc.object().value("game").toObject().contains("left_team");
}

QStringList builtinSceneNames() {
    QStringList names;
    for (const QString& file : QDir(":/scenes").entryList({"*.json"}, QDir::Files, QDir::Name))
        names << QFileInfo(file).completeBaseName();
    return names;
}

QString resolveScenePath(const QString& argument) {
    if (QFileInfo(argument).isFile()) return argument;
    for (const QString& candidate :
         {QStringLiteral(":/scenes/%1").arg(argument), QStringLiteral(":/scenes/%1.json").arg(argument)})
        if (!argument.contains('/') && QFileInfo(candidate).isFile()) return candidate;
    return {};
}

QString sceneNotFoundMessage(const QString& argument) {
    struct stat st;
    QString what;
    if (::stat(QFile::encodeName(argument).constData(), &st) == 0) {
        if (S_ISDIR(st.st_mode))
            what = QStringLiteral("a directory");
        else if (S_ISFIFO(st.st_mode))
            what = QStringLiteral("a FIFO (named pipe)");
        else if (S_ISSOCK(st.st_mode))
            what = QStringLiteral("a socket");
        else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))
            what = QStringLiteral("a device");
    }
    if (!what.isEmpty()) return QStringLiteral("%1: is %2, not a scene file (a regular JSON file)").arg(argument, what);
    return QStringLiteral("%1: no such file or built-in scene (built-in: %2)")
        .arg(argument, builtinSceneNames().join(", "));
}

}  // namespace vssim
