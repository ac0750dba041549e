#include "net/client_requests.h"

#include <QJsonArray>
#include <QLocale>
#include <cmath>
#include <utility>

#include "io/scene_io.h"
#include "realtime/engine_loop.h"

namespace vssim {

QString roleName(ClientRole role) {
    switch (role) {
        case ClientRole::Yellow: return QStringLiteral("yellow");
        case ClientRole::Blue: return QStringLiteral("blue");
        case ClientRole::Observer: return QStringLiteral("observer");
    }
    return {};
}

namespace {

// Reads one client message's JSON object, in the scene reader's style
// (io/scene_io.cpp): each helper checks one key, returns false on failure,
// and the first failure is kept as the error, with its code and a message
// that starts with what was being read ("HELLO", "CONTROL step").
class RequestReader {
public:
    RequestReader(const QJsonObject& json, QString what) : json_(json), what_(std::move(what)) {}

    const RequestError& error() const { return error_; }

    bool fail(const QString& code, const QString& message) {
        if (error_.code.isEmpty()) error_ = {code, what_ + QStringLiteral(": ") + message};
        return false;
    }
    bool malformed(const QString& message) { return fail(QStringLiteral("malformed"), message); }

    // Only the keys listed may appear: a typo is an error, not silently ignored.
    bool keys(const QStringList& allowed) {
        for (auto it = json_.begin(); it != json_.end(); ++it)
            if (!allowed.contains(it.key()))
                return malformed(QStringLiteral("unknown key \"%1\" (expected one of: %2)")
                                     .arg(printableText(it.key(), 40), allowed.join(", ")));
        return true;
    }

    // A finite number at `key`; when absent, `fallback`, or an error if there is none.
    bool number(const QString& key, double* out, std::optional<double> fallback = std::nullopt) {
        const QJsonValue v = json_.value(key);
        if (v.isUndefined()) {
            if (!fallback) return malformed(QStringLiteral("missing \"%1\"").arg(key));
            *out = *fallback;
            return true;
        }
        if (!v.isDouble() || !std::isfinite(v.toDouble()))
            return malformed(QStringLiteral("\"%1\" must be a finite number").arg(key));
        *out = v.toDouble();
        return true;
    }

    // A whole number from `min` to `max` at `key`, or `fallback` when absent.
    bool integer(const QString& key, int min, int max, int fallback, int* out) {
        double value = 0;
        if (!number(key, &value, fallback)) return false;
        if (value != std::floor(value) || value < min || value > max)
            return malformed(QStringLiteral("\"%1\" is %2; expected a whole number from %3 to %4")
                                 .arg(key)
                                 .arg(value)
                                 .arg(min)
                                 .arg(max));
        *out = static_cast<int>(value);
        return true;
    }

    bool boolean(const QString& key, bool fallback, bool* out) {
        const QJsonValue v = json_.value(key);
        if (!v.isUndefined() && !v.isBool()) return malformed(QStringLiteral("\"%1\" must be true or false").arg(key));
        *out = v.toBool(fallback);
        return true;
    }

    // One of the names in `table` at `key` (exactly, case included), or
    // `fallback` when absent and there is one.
    template <typename T, std::size_t N>
    bool choice(const QString& key, const std::pair<const char*, T> (&table)[N], std::optional<T> fallback, T* out) {
        QStringList names;
        for (const auto& [name, value] : table) names << QStringLiteral("\"%1\"").arg(name);
        const QString expected =
            names.size() > 1 ? names.mid(0, names.size() - 1).join(", ") + " or " + names.last() : names.join("");
        const QJsonValue v = json_.value(key);
        if (v.isUndefined() && fallback) {
            *out = *fallback;
            return true;
        }
        if (!v.isString()) return malformed(QStringLiteral("\"%1\" must be %2").arg(key, expected));
        for (const auto& [name, value] : table) {
            if (v.toString() == QLatin1String(name)) {
                *out = value;
                return true;
            }
        }
        return malformed(
            QStringLiteral("\"%1\" is \"%2\"; expected %3").arg(key, printableText(v.toString(), 40), expected));
    }

    bool robotIndex(const Scene& scene, int* out) {
        double index = 0;
        if (!number(QStringLiteral("robot"), &index)) return false;
        if (index != std::floor(index) || index < 0 || index >= static_cast<double>(scene.robots.size()))
            return fail(QStringLiteral("bad_robot"), QStringLiteral("no robot %1 (the scene has robots 0 to %2)")
                                                         .arg(index)
                                                         .arg(static_cast<int>(scene.robots.size()) - 1));
        *out = static_cast<int>(index);
        return true;
    }

private:
    const QJsonObject& json_;
    QString what_;
    RequestError error_;
};

constexpr std::pair<const char*, Call> kCalls[] = {{"kickoff", Call::KickOff},
                                                   {"free_ball", Call::FreeBall},
                                                   {"penalty_kick", Call::PenaltyKick},
                                                   {"goal_kick", Call::GoalKick}};
constexpr std::pair<const char*, Team> kTeams[] = {{"yellow", Team::Yellow}, {"blue", Team::Blue}};

constexpr std::pair<const char*, ClientRole> kRoles[] = {
    {"yellow", ClientRole::Yellow}, {"blue", ClientRole::Blue}, {"observer", ClientRole::Observer}};
enum class ImagesWanted { Patches, Full, None };
constexpr std::pair<const char*, ImagesWanted> kImages[] = {
    {"patches", ImagesWanted::Patches}, {"full", ImagesWanted::Full}, {"none", ImagesWanted::None}};
constexpr std::pair<const char*, ImageEncoding> kEncodings[] = {
    {"png", ImageEncoding::Png}, {"raw", ImageEncoding::Raw}, {"jpeg", ImageEncoding::Jpeg}};

}  // namespace

const QStringList kHelloCameraKeys{"latency", "jitter", "drop", "position_noise", "heading_noise", "vanish", "seed"};

namespace {

// HELLO's `camera`: an object of per-client keys with the scene reader's
// ranges; an image-formation key is named as the scene's to set.
bool checkHelloCamera(const QJsonValue& value, RequestError* error) {
    auto malformed = [&](const QString& message) {
        *error = {QStringLiteral("malformed"), QStringLiteral("HELLO: ") + message};
        return false;
    };
    if (!value.isObject()) return malformed(QStringLiteral("camera: expected an object"));
    const QJsonObject camera = value.toObject();
    // Every key a scene's camera takes, and its preset.
    QStringList sceneKeys = cameraSettingsToJson(idealCamera()).keys();
    sceneKeys << QStringLiteral("preset");
    for (auto it = camera.begin(); it != camera.end(); ++it) {
        if (kHelloCameraKeys.contains(it.key())) continue;
        const QString where = QStringLiteral("camera.") + printableText(it.key(), 40);
        if (sceneKeys.contains(it.key()))
            return malformed(QStringLiteral("%1: the image formation (\"%2\") is per scene, the same for every "
                                            "client: set it in the scene file's camera (or vssim serve --camera); "
                                            "a HELLO's camera takes only %3")
                                 .arg(where, it.key(), kHelloCameraKeys.join(", ")));
        return malformed(
            QStringLiteral("%1: unknown key (expected one of: %2)").arg(where, kHelloCameraKeys.join(", ")));
    }
    QString message;
    if (!cameraSettingsFromJson(camera, idealCamera(), QStringLiteral("camera"), &message)) return malformed(message);
    return true;
}

}  // namespace

std::optional<Hello> parseHello(const QJsonObject& json, RequestError* error) {
    RequestReader in(json, QStringLiteral("HELLO"));
    auto failed = [&] {
        *error = in.error();
        return std::nullopt;
    };
    const QJsonValue version = json.value("protocol");
    if (!version.isDouble()) {
        in.malformed("\"protocol\" (a number, 1) is required");
        return failed();
    }
    if (version.toDouble() != 1.0) {
        in.fail("unsupported_protocol",
                QStringLiteral("protocol %1 is not supported (this server speaks 1)").arg(version.toDouble()));
        return failed();
    }
    // Keys are checked after the version: a later version's HELLO may have new ones.
    Hello hello;
    ImagesWanted images = ImagesWanted::Patches;
    ImageSubscription sub;
    if (!in.keys({"protocol", "role", "name", "images", "encoding", "jpeg_quality", "state", "camera"}) ||
        !in.choice("role", kRoles, {}, &hello.role))
        return failed();
    const QJsonValue name = json.value("name");
    if (!name.isUndefined() && (!name.isString() || name.toString().toUcs4().size() > 64)) {
        in.malformed("\"name\" must be a string of at most 64 characters");
        return failed();
    }
    hello.name = printableText(name.toString(), 64);  // printable only: the name goes into log lines
    if (!in.choice("images", kImages, std::optional(ImagesWanted::Patches), &images) ||
        !in.choice("encoding", kEncodings, std::optional(ImageEncoding::Png), &sub.encoding) ||
        !in.integer("jpeg_quality", 1, 100, 90, &sub.jpegQuality) || !in.boolean("state", false, &hello.state))
        return failed();
    sub.kind = images == ImagesWanted::Full ? protocol::FrameKind::Full : protocol::FrameKind::Patches;
    if (images != ImagesWanted::None) hello.images = sub;
    if (json.contains("camera")) {
        if (!checkHelloCamera(json.value("camera"), error)) return std::nullopt;
        hello.camera = json.value("camera").toObject();
    }
    return hello;
}

namespace {

// VOLTAGES and WHEEL_SPEEDS: `name` the message, `quantity` what its numbers are.
template <typename T>
std::optional<RequestError> checkDriveEntries(const std::vector<std::pair<int, T>>& entries, const Scene& scene,
                                              ClientRole role, const char* name, const char* quantity) {
    if (role == ClientRole::Observer)
        return RequestError{"not_your_robot",
                            QStringLiteral("%1: an observer cannot drive robots (say HELLO as \"yellow\" or \"blue\")")
                                .arg(name)};
    const Team team = role == ClientRole::Yellow ? Team::Yellow : Team::Blue;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const auto& [robot, e] = entries[i];
        // Built only for an error: a flood of good commands passes here a million times a second.
        auto where = [i, name] { return QStringLiteral("%1 entry %2").arg(name).arg(i); };
        if (robot < 0 || robot >= static_cast<int>(scene.robots.size()))
            return RequestError{"bad_robot", QStringLiteral("%1: no robot %2 (the scene has robots 0 to %3)")
                                                 .arg(where())
                                                 .arg(robot)
                                                 .arg(static_cast<int>(scene.robots.size()) - 1)};
        if (scene.robots[robot].team != team)
            return RequestError{"not_your_robot", QStringLiteral("%1: robot %2 (%3) belongs to the other team")
                                                      .arg(where())
                                                      .arg(robot)
                                                      .arg(QString::fromStdString(scene.robots[robot].name))};
        for (auto [side, value] : {std::pair{"right", e.right}, std::pair{"left", e.left}})
            if (!std::isfinite(value))
                return RequestError{"not_finite", QStringLiteral("%1: robot %2 %3 %4 is %5")
                                                      .arg(where())
                                                      .arg(robot)
                                                      .arg(side)
                                                      .arg(quantity)
                                                      .arg(std::isnan(value) ? "NaN"
                                                           : value > 0       ? "+infinity"
                                                                             : "-infinity")};
    }
    return std::nullopt;
}

}  // namespace

std::optional<RequestError> checkVoltages(const std::vector<std::pair<int, Voltages>>& entries, const Scene& scene,
                                          ClientRole role) {
    return checkDriveEntries(entries, scene, role, "VOLTAGES", "voltage");
}

std::optional<RequestError> checkWheelSpeeds(const std::vector<std::pair<int, WheelSpeeds>>& entries,
                                             const Scene& scene, ClientRole role) {
    return checkDriveEntries(entries, scene, role, "WHEEL_SPEEDS", "wheel speed");
}

std::optional<EngineRequest> parseControl(const QJsonObject& json, const Scene& scene, RequestError* error) {
    using Kind = EngineRequest::Kind;
    const QJsonValue commandValue = json.value("command");
    if (!commandValue.isString()) {
        *error = {"malformed", "CONTROL: \"command\" (a string) is required"};
        return std::nullopt;
    }
    EngineRequest r;
    r.command = commandValue.toString();
    // The name goes into messages and log lines: printable characters only.
    RequestReader in(json, QStringLiteral("CONTROL %1").arg(printableText(r.command, 40)));
    auto failed = [&] {
        *error = in.error();
        return std::nullopt;
    };
    const QStringList base{"command", "id"};
    const Field& field = scene.field;
    if (r.command == "pause" || r.command == "resume" || r.command == "reset" || r.command == "stats") {
        if (!in.keys(base)) return failed();
        r.kind = r.command == "pause"    ? Kind::Pause
                 : r.command == "resume" ? Kind::Resume
                 : r.command == "reset"  ? Kind::Reset
                                         : Kind::Stats;
    } else if (r.command == "halt" || r.command == "game_on") {
        if (!in.keys(base)) return failed();
        r.kind = r.command == "halt" ? Kind::HaltGame : Kind::ResumeGame;
    } else if (r.command == "call") {
        r.kind = Kind::CallFoul;
        if (!in.keys(base + QStringList{"call", "team", "quadrant"}) || !in.choice("call", kCalls, {}, &r.call))
            return failed();
        if (r.call == Call::FreeBall) {
            if (json.contains("team")) {
                in.malformed("a free ball is for no team: no \"team\"");
                return failed();
            }
            if (!json.contains("quadrant")) {
                in.malformed("a free ball needs \"quadrant\" (1 to 4)");
                return failed();
            }
            if (!in.integer("quadrant", 1, 4, 1, &r.quadrant)) return failed();
        } else {
            if (json.contains("quadrant")) {
                in.malformed(QStringLiteral("only a free ball has a \"quadrant\", not a %1").arg(callName(r.call)));
                return failed();
            }
            if (!in.choice("team", kTeams, {}, &r.team)) return failed();
        }
    } else if (r.command == "step") {
        r.kind = Kind::Step;
        if (!in.keys(base + QStringList{"duration"}) || !in.number("duration", &r.duration)) return failed();
        if (!(r.duration > 0 && r.duration <= kMaxStepDuration)) {
            in.malformed(QStringLiteral("\"duration\" is %1 s; expected more than 0 and at most %2 s")
                             .arg(QString::number(r.duration, 'g', QLocale::FloatingPointShortest))
                             .arg(kMaxStepDuration));
            return failed();
        }
        // In whole steps, as the engine counts them (3.6 s at 1 us is 3,600,000).
        if (static_cast<double>(Simulation::stepIndexAtOrAfter(r.duration, scene.simulation.dt)) > kMaxStepSteps) {
            in.malformed(QStringLiteral("\"duration\" is %1 s, %2 steps of dt = %3 s; at most %4 steps at once")
                             .arg(QString::number(r.duration, 'g', QLocale::FloatingPointShortest))
                             .arg(r.duration / scene.simulation.dt, 0, 'g', 6)
                             .arg(scene.simulation.dt)
                             .arg(kMaxStepSteps, 0, 'f', 0));
            return failed();
        }
    } else if (r.command == "place_robot") {
        r.kind = Kind::PlaceRobot;
        RobotState& p = r.robotPose;
        if (!in.keys(base + QStringList{"robot", "x", "y", "theta", "v", "omega"}) || !in.robotIndex(scene, &r.robot) ||
            !in.number("x", &p.x) || !in.number("y", &p.y) || !in.number("theta", &p.theta) ||
            !in.number("v", &p.v, 0.0) || !in.number("omega", &p.omega, 0.0))
            return failed();
        if (std::abs(p.v) > kMaxPlacedRobotSpeed || std::abs(p.omega) > kMaxPlacedYawRate) {
            in.malformed(QStringLiteral("|v| must be at most %1 m/s and |omega| at most %2 rad/s")
                             .arg(kMaxPlacedRobotSpeed)
                             .arg(kMaxPlacedYawRate));
            return failed();
        }
        if (!robotInsideField(field, scene.robots[r.robot].params.side, p.x, p.y, p.theta)) {
            in.fail("outside_field",
                    QStringLiteral("robot %1 at (%2, %3) m, heading %4 rad, would not lie inside the %5 x %6 m field")
                        .arg(r.robot)
                        .arg(p.x)
                        .arg(p.y)
                        .arg(p.theta)
                        .arg(field.length)
                        .arg(field.width));
            return failed();
        }
    } else if (r.command == "place_ball") {
        r.kind = Kind::PlaceBall;
        BallState& b = r.ball;
        if (!in.keys(base + QStringList{"x", "y", "vx", "vy"}) || !in.number("x", &b.x) || !in.number("y", &b.y) ||
            !in.number("vx", &b.vx, 0.0) || !in.number("vy", &b.vy, 0.0))
            return failed();
        if (std::hypot(b.vx, b.vy) > kMaxPlacedBallSpeed) {
            in.malformed(QStringLiteral("the ball's speed must be at most %1 m/s").arg(kMaxPlacedBallSpeed));
            return failed();
        }
        if (!discInsideField(field, scene.ball_params.radius, b.x, b.y)) {
            in.fail("outside_field", QStringLiteral("the ball at (%1, %2) m would not lie inside the %3 x %4 m field")
                                         .arg(b.x)
                                         .arg(b.y)
                                         .arg(field.length)
                                         .arg(field.width));
            return failed();
        }
    } else if (r.command == "speed") {
        r.kind = Kind::Speed;
        if (!in.keys(base + QStringList{"speed"})) return failed();
        const QJsonValue speed = json.value("speed");
        if (speed.isString() && speed.toString() == "max") {
            r.speed = 0.0;
        } else if (speed.isDouble() && speed.toDouble() >= kMinSpeed && speed.toDouble() <= kMaxSpeed) {
            r.speed = speed.toDouble();
        } else {
            in.malformed(QStringLiteral("\"speed\" must be a number from %1 to %2 (times real time) or \"max\"")
                             .arg(kMinSpeed)
                             .arg(kMaxSpeed));
            return failed();
        }
    } else {
        *error = {"unknown_command", QStringLiteral("CONTROL: unknown command \"%1\" (expected pause, resume, step, "
                                                    "reset, place_robot, place_ball, speed, stats, halt, game_on or "
                                                    "call)")
                                         .arg(printableText(r.command, 40))};
        return std::nullopt;
    }
    return r;
}

std::optional<EngineRequest> parsePlacement(const QJsonObject& json, const Scene& scene, ClientRole role,
                                            RequestError* error) {
    RequestReader in(json, QStringLiteral("PLACEMENT"));
    auto failed = [&] {
        *error = in.error();
        return std::nullopt;
    };
    if (role == ClientRole::Observer) {
        in.fail("not_your_robot", "an observer places no robots (say HELLO as \"yellow\" or \"blue\")");
        return failed();
    }
    EngineRequest r;
    r.kind = EngineRequest::Kind::Placement;
    r.command = QStringLiteral("placement");
    r.team = role == ClientRole::Yellow ? Team::Yellow : Team::Blue;
    if (!in.keys({"robots", "id"})) return failed();
    const QJsonValue list = json.value("robots");
    if (!list.isArray() || list.toArray().isEmpty()) {
        in.malformed("\"robots\" must be a non-empty array of {\"robot\", \"x\", \"y\", \"theta\"}");
        return failed();
    }
    const QJsonArray robots = list.toArray();
    if (robots.size() > static_cast<qsizetype>(scene.robots.size())) {
        in.malformed(QStringLiteral("%1 entries in \"robots\"; the scene has %2 robots")
                         .arg(robots.size())
                         .arg(scene.robots.size()));
        return failed();
    }
    for (qsizetype i = 0; i < robots.size(); ++i) {
        const QString where = QStringLiteral("PLACEMENT robots[%1]").arg(i);
        if (!robots[i].isObject()) {
            *error = {"malformed", where + ": expected an object {\"robot\", \"x\", \"y\", \"theta\"}"};
            return std::nullopt;
        }
        const QJsonObject entry = robots[i].toObject();
        RequestReader e(entry, where);
        int robot = -1;
        RobotState p;
        if (!e.keys({"robot", "x", "y", "theta"}) || !e.robotIndex(scene, &robot) || !e.number("x", &p.x) ||
            !e.number("y", &p.y) || !e.number("theta", &p.theta)) {
            *error = e.error();
            return std::nullopt;
        }
        const RobotSpec& spec = scene.robots[robot];
        if (spec.team != r.team) {
            *error = {"not_your_robot", QStringLiteral("%1: robot %2 (%3) belongs to the other team")
                                            .arg(where)
                                            .arg(robot)
                                            .arg(QString::fromStdString(spec.name))};
            return std::nullopt;
        }
        for (const auto& [placed, pose] : r.poses) {
            if (placed == robot) {
                *error = {"malformed", QStringLiteral("%1: robot %2 is placed twice").arg(where).arg(robot)};
                return std::nullopt;
            }
        }
        if (!robotInsideField(scene.field, spec.params.side, p.x, p.y, p.theta)) {
            *error = {"outside_field",
                      QStringLiteral("%1: robot %2 at (%3, %4) m, heading %5 rad, would not lie inside the field")
                          .arg(where)
                          .arg(robot)
                          .arg(p.x)
                          .arg(p.y)
                          .arg(p.theta)};
            return std::nullopt;
        }
        r.poses.emplace_back(robot, p);
    }
    return r;
}

bool leavesTheGameAlone(const EngineRequest& request) { return request.kind == EngineRequest::Kind::Stats; }

}  // namespace vssim
