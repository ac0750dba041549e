#include "net/client_requests.h"

#include <QJsonArray>

#include "realtime/engine_loop.h"
#include <cmath>

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

bool fail(RequestError* error, const QString& code, const QString& message) {
    *error = {code, message};
    return false;
}

// Only the keys listed may appear: a typo is an error, not silently ignored.
bool onlyKeys(const QJsonObject& json, const QString& what, const QStringList& allowed, RequestError* error) {
    for (auto it = json.begin(); it != json.end(); ++it)
        if (!allowed.contains(it.key()))
            return fail(error, "malformed",
                        QStringLiteral("%1: unknown key \"%2\" (expected one of: %3)").arg(what, it.key(), allowed.join(", ")));
    return true;
}

// A finite number at `key`; `required` or else `fallback`.
bool number(const QJsonObject& json, const QString& what, const QString& key, bool required, double fallback,
            double* out, RequestError* error) {
    const QJsonValue v = json.value(key);
    if (v.isUndefined()) {
        if (required) return fail(error, "malformed", QStringLiteral("%1: missing \"%2\"").arg(what, key));
        *out = fallback;
        return true;
    }
    if (!v.isDouble() || !std::isfinite(v.toDouble()))
        return fail(error, "malformed", QStringLiteral("%1: \"%2\" must be a finite number").arg(what, key));
    *out = v.toDouble();
    return true;
}

bool robotIndex(const QJsonObject& json, const QString& what, const Scene& scene, int* out, RequestError* error) {
    double index = 0;
    if (!number(json, what, "robot", true, 0, &index, error)) return false;
    if (index != std::floor(index) || index < 0 || index >= static_cast<double>(scene.robots.size()))
        return fail(error, "bad_robot",
                    QStringLiteral("%1: no robot %2 (the scene has robots 0 to %3)")
                        .arg(what).arg(index).arg(static_cast<int>(scene.robots.size()) - 1));
    *out = static_cast<int>(index);
    return true;
}

}  // namespace

std::optional<Hello> parseHello(const QJsonObject& json, RequestError* error) {
    const QString what = QStringLiteral("HELLO");
    const QJsonValue version = json.value("protocol");
    if (!version.isDouble()) {
        fail(error, "malformed", "HELLO: \"protocol\" (a number, 1) is required");
        return std::nullopt;
    }
    if (version.toDouble() != 1.0) {
        fail(error, "unsupported_protocol",
             QStringLiteral("HELLO: protocol %1 is not supported (this server speaks 1)").arg(version.toDouble()));
        return std::nullopt;
    }
    // Keys are checked after the version: a later version's HELLO may have new ones.
    if (!onlyKeys(json, what, {"protocol", "role", "name", "images", "encoding", "jpeg_quality", "state"}, error))
        return std::nullopt;
    Hello hello;
    const QString role = json.value("role").toString();
    if (role == "yellow") hello.role = ClientRole::Yellow;
    else if (role == "blue") hello.role = ClientRole::Blue;
    else if (role == "observer") hello.role = ClientRole::Observer;
    else {
        fail(error, "malformed", "HELLO: \"role\" must be \"yellow\", \"blue\" or \"observer\"");
        return std::nullopt;
    }
    const QJsonValue name = json.value("name");
    const QList<uint> codePoints = name.toString().toUcs4();
    if (!name.isUndefined() && (!name.isString() || codePoints.size() > 64)) {
        fail(error, "malformed", "HELLO: \"name\" must be a string of at most 64 characters");
        return std::nullopt;
    }
    // Printable only: the name goes into log lines.
    for (uint c : codePoints) {
        const char32_t cp = static_cast<char32_t>(c);
        hello.name += QChar::isPrint(cp) ? QString::fromUcs4(&cp, 1) : QStringLiteral("?");
    }

    const QString images = json.value("images").toString("patches");
    if (!json.value("images").isUndefined() && !json.value("images").isString()) {
        fail(error, "malformed", "HELLO: \"images\" must be \"patches\", \"full\" or \"none\"");
        return std::nullopt;
    }
    ImageSubscription sub;
    if (images == "patches") sub.kind = protocol::FrameKind::Patches;
    else if (images == "full") sub.kind = protocol::FrameKind::Full;
    else if (images != "none") {
        fail(error, "malformed",
             QStringLiteral("HELLO: \"images\" is \"%1\"; expected \"patches\", \"full\" or \"none\"").arg(images));
        return std::nullopt;
    }
    const QJsonValue encoding = json.value("encoding");
    const std::optional<ImageEncoding> enc =
        encoding.isUndefined() ? std::optional(ImageEncoding::Png)
                               : (encoding.isString() ? encodingFromName(encoding.toString().toStdString()) : std::nullopt);
    if (!enc) {
        fail(error, "malformed", "HELLO: \"encoding\" must be \"png\", \"raw\" or \"jpeg\"");
        return std::nullopt;
    }
    sub.encoding = *enc;
    double quality = 90;
    if (!number(json, what, "jpeg_quality", false, 90, &quality, error)) return std::nullopt;
    if (quality != std::floor(quality) || quality < 1 || quality > 100) {
        fail(error, "malformed", QStringLiteral("HELLO: \"jpeg_quality\" is %1; expected a whole number from 1 to 100").arg(quality));
        return std::nullopt;
    }
    sub.jpegQuality = static_cast<int>(quality);
    if (images != "none") hello.images = sub;
    const QJsonValue state = json.value("state");
    if (!state.isUndefined() && !state.isBool()) {
        fail(error, "malformed", "HELLO: \"state\" must be true or false");
        return std::nullopt;
    }
    hello.state = state.toBool(false);
    return hello;
}

std::optional<RequestError> checkVoltages(const std::vector<std::pair<int, Voltages>>& entries, const Scene& scene,
                                          ClientRole role) {
    if (role == ClientRole::Observer)
        return RequestError{"not_your_robot", "VOLTAGES: an observer cannot drive robots (say HELLO as \"yellow\" or \"blue\")"};
    const Team team = role == ClientRole::Yellow ? Team::Yellow : Team::Blue;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const auto& [robot, e] = entries[i];
        const QString where = QStringLiteral("VOLTAGES entry %1").arg(i);
        if (robot < 0 || robot >= static_cast<int>(scene.robots.size()))
            return RequestError{"bad_robot", QStringLiteral("%1: no robot %2 (the scene has robots 0 to %3)")
                                                 .arg(where).arg(robot).arg(static_cast<int>(scene.robots.size()) - 1)};
        if (scene.robots[robot].team != team)
            return RequestError{"not_your_robot", QStringLiteral("%1: robot %2 (%3) belongs to the other team")
                                                      .arg(where).arg(robot).arg(QString::fromStdString(scene.robots[robot].name))};
        for (auto [side, volts] : {std::pair{"right", e.right}, std::pair{"left", e.left}})
            if (!std::isfinite(volts))
                return RequestError{"not_finite", QStringLiteral("%1: robot %2 %3 voltage is %4")
                                                      .arg(where).arg(robot).arg(side)
                                                      .arg(std::isnan(volts) ? "NaN" : volts > 0 ? "+infinity" : "-infinity")};
    }
    return std::nullopt;
}

std::optional<EngineRequest> parseControl(const QJsonObject& json, const Scene& scene, RequestError* error) {
    using Kind = EngineRequest::Kind;
    const QJsonValue commandValue = json.value("command");
    if (!commandValue.isString()) {
        fail(error, "malformed", "CONTROL: \"command\" (a string) is required");
        return std::nullopt;
    }
    EngineRequest r;
    r.command = commandValue.toString();
    const QString what = QStringLiteral("CONTROL %1").arg(r.command);
    const QStringList base{"command", "id"};
    auto keys = [&](QStringList more) { return onlyKeys(json, what, base + more, error); };
    const Field& field = scene.field;
    if (r.command == "pause" || r.command == "resume" || r.command == "reset" || r.command == "stats") {
        if (!keys({})) return std::nullopt;
        r.kind = r.command == "pause" ? Kind::Pause : r.command == "resume" ? Kind::Resume
               : r.command == "reset" ? Kind::Reset : Kind::Stats;
    } else if (r.command == "step") {
        r.kind = Kind::Step;
        if (!keys({"duration"}) || !number(json, what, "duration", true, 0, &r.duration, error)) return std::nullopt;
        if (!(r.duration > 0 && r.duration <= 3600)) {
            fail(error, "malformed", QStringLiteral("%1: \"duration\" is %2 s; expected more than 0 and at most 3600 s").arg(what).arg(r.duration));
            return std::nullopt;
        }
    } else if (r.command == "place_robot") {
        r.kind = Kind::PlaceRobot;
        RobotState& p = r.robotPose;
        if (!keys({"robot", "x", "y", "theta", "v", "omega"}) || !robotIndex(json, what, scene, &r.robot, error) ||
            !number(json, what, "x", true, 0, &p.x, error) || !number(json, what, "y", true, 0, &p.y, error) ||
            !number(json, what, "theta", true, 0, &p.theta, error) || !number(json, what, "v", false, 0, &p.v, error) ||
            !number(json, what, "omega", false, 0, &p.omega, error))
            return std::nullopt;
        if (std::abs(p.v) > kMaxPlacedRobotSpeed || std::abs(p.omega) > kMaxPlacedYawRate) {
            fail(error, "malformed", QStringLiteral("%1: |v| must be at most %2 m/s and |omega| at most %3 rad/s")
                                         .arg(what).arg(kMaxPlacedRobotSpeed).arg(kMaxPlacedYawRate));
            return std::nullopt;
        }
        if (!robotInsideField(field, scene.robots[r.robot].params.side, p.x, p.y, p.theta)) {
            fail(error, "outside_field", QStringLiteral("%1: robot %2 at (%3, %4) m, heading %5 rad, would not lie inside the %6 x %7 m field")
                                             .arg(what).arg(r.robot).arg(p.x).arg(p.y).arg(p.theta).arg(field.length).arg(field.width));
            return std::nullopt;
        }
    } else if (r.command == "place_ball") {
        r.kind = Kind::PlaceBall;
        BallState& b = r.ball;
        if (!keys({"x", "y", "vx", "vy"}) || !number(json, what, "x", true, 0, &b.x, error) ||
            !number(json, what, "y", true, 0, &b.y, error) || !number(json, what, "vx", false, 0, &b.vx, error) ||
            !number(json, what, "vy", false, 0, &b.vy, error))
            return std::nullopt;
        if (std::hypot(b.vx, b.vy) > kMaxPlacedBallSpeed) {
            fail(error, "malformed", QStringLiteral("%1: the ball's speed must be at most %2 m/s").arg(what).arg(kMaxPlacedBallSpeed));
            return std::nullopt;
        }
        if (!discInsideField(field, scene.ball_params.radius, b.x, b.y)) {
            fail(error, "outside_field", QStringLiteral("%1: the ball at (%2, %3) m would not lie inside the %4 x %5 m field")
                                             .arg(what).arg(b.x).arg(b.y).arg(field.length).arg(field.width));
            return std::nullopt;
        }
    } else if (r.command == "speed") {
        r.kind = Kind::Speed;
        if (!keys({"speed"})) return std::nullopt;
        const QJsonValue speed = json.value("speed");
        if (speed.isString() && speed.toString() == "max") {
            r.speed = 0.0;
        } else if (speed.isDouble() && speed.toDouble() >= kMinSpeed && speed.toDouble() <= kMaxSpeed) {
            r.speed = speed.toDouble();
        } else {
            fail(error, "malformed", QStringLiteral("%1: \"speed\" must be a number from %2 to %3 (times real time) or \"max\"").arg(what).arg(kMinSpeed).arg(kMaxSpeed));
            return std::nullopt;
        }
    } else {
        fail(error, "unknown_command",
             QStringLiteral("CONTROL: unknown command \"%1\" (expected pause, resume, step, reset, place_robot, place_ball, speed or stats)")
                 .arg(r.command.left(40)));
        return std::nullopt;
    }
    return r;
}

}  // namespace vssim
