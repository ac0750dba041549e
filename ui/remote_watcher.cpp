#include "remote_watcher.h"

#include <QJsonArray>

#include "io/scene_io.h"
#include "vssim/field.h"

namespace vssim {

RemoteWatcher::RemoteWatcher(QObject* parent) : QObject(parent) {
    connect(&client_.socket(), &QTcpSocket::disconnected, this, &RemoteWatcher::disconnected);
}

RemoteWatcher::~RemoteWatcher() {
    // No signals while going away (the window listening may be half destroyed).
    client_.socket().disconnect();
    client_.disconnect();
    client_.socket().abort();
}

bool RemoteWatcher::connected() const {
    return const_cast<ProtocolClient&>(client_).socket().state() == QAbstractSocket::ConnectedState;
}

std::optional<Scene> sceneFromWelcome(const QJsonObject& welcome, QString* error) {
    // The field as a scene file has it (a server before field types sends only length and width: a box).
    const QJsonObject field = welcome["field"].toObject();
    if (!field.contains("length") || !field.contains("width")) {
        *error = QStringLiteral("WELCOME: no field size");
        return std::nullopt;
    }
    QString fieldError;
    const std::optional<Field> parsed = fieldFromJson(field, &fieldError);
    if (!parsed) {
        *error = QStringLiteral("WELCOME: %1").arg(fieldError);
        return std::nullopt;
    }
    Scene scene;
    scene.field = *parsed;
    scene.ball_params.radius = welcome["ball"].toObject()["radius"].toDouble(scene.ball_params.radius);
    scene.simulation.dt = welcome["dt"].toDouble(scene.simulation.dt);
    for (const QJsonValue& value : welcome["robots"].toArray()) {
        const QJsonObject r = value.toObject();
        RobotSpec spec;
        spec.name = r["name"].toString().toStdString();
        spec.team = r["team"].toString() == "blue" ? Team::Blue : Team::Yellow;
        spec.params.side = r["side"].toDouble(spec.params.side);
        spec.params.max_voltage = r["max_voltage"].toDouble(spec.params.max_voltage);
        scene.robots.push_back(spec);
    }
    // The server's camera, so that the camera dock draws what its clients
    // receive (servers before the realistic camera send no settings: ideal).
    const QJsonObject settings = welcome["camera"].toObject()["settings"].toObject();
    QString cameraError;
    if (const std::optional<CameraSettings> camera =
            cameraSettingsFromJson(settings, idealCamera(), "WELCOME camera.settings", &cameraError))
        scene.camera = *camera;
    return scene;
}

std::optional<Snapshot> snapshotFromState(const QJsonObject& state, std::shared_ptr<const Scene> scene) {
    const QJsonArray robots = state["robots"].toArray();
    if (!scene || robots.size() != static_cast<qsizetype>(scene->robots.size())) return std::nullopt;
    Snapshot s;
    s.time = state["time"].toDouble();
    s.frame = static_cast<std::int64_t>(state["frame"].toDouble());
    s.step = static_cast<std::int64_t>(std::llround(s.time / scene->simulation.dt));
    for (const QJsonValue& value : robots) {
        const QJsonObject r = value.toObject();
        s.robots.push_back(
            {r["x"].toDouble(), r["y"].toDouble(), r["theta"].toDouble(), r["v"].toDouble(), r["omega"].toDouble()});
        s.voltages.push_back({r["right_voltage"].toDouble(), r["left_voltage"].toDouble()});
        RobotOutputs out;
        out.current_right = r["right_current"].toDouble();
        out.current_left = r["left_current"].toDouble();
        out.wheel_speed_right = r["right_wheel_speed"].toDouble();
        out.wheel_speed_left = r["left_wheel_speed"].toDouble();
        s.outputs.push_back(out);
    }
    const QJsonObject ball = state["ball"].toObject();
    s.ball = {ball["x"].toDouble(), ball["y"].toDouble(), ball["vx"].toDouble(), ball["vy"].toDouble()};
    s.scene = std::move(scene);
    return s;
}

bool RemoteWatcher::connectTo(const QString& host, quint16 port, QString* error, int timeoutMs) {
    latest_.reset();  // nothing of a previous connection is shown as the server's present
    address_ = QStringLiteral("%1:%2").arg(host).arg(port);
    host_ = host;
    port_ = port;
    if (!client_.connectTo(port, host, timeoutMs)) {
        *error = QStringLiteral("cannot connect to %1: %2").arg(address_, client_.socket().errorString());
        return false;
    }
    // The window shows the ground truth: without the scene camera's delay,
    // drops and noise, which are for the teams' clients (a HELLO's own
    // camera, docs/protocol.md).
    const QJsonObject exact{{"latency", 0},        {"jitter", 0},        {"drop", 0},
                            {"position_noise", 0}, {"heading_noise", 0}, {"vanish", 0}};
    const std::optional<QJsonObject> welcome = client_.hello(QJsonObject{{"protocol", 1},
                                                                         {"role", "observer"},
                                                                         {"name", "vssim gui"},
                                                                         {"images", "none"},
                                                                         {"state", true},
                                                                         {"camera", exact}},
                                                             timeoutMs);
    if (!welcome) {
        const auto reply = client_.next(100);
        *error =
            QStringLiteral("%1 did not welcome us: %2")
                .arg(address_, reply ? jsonPayload(reply->message)["message"].toString() : QStringLiteral("no answer"));
        return false;
    }
    std::optional<Scene> scene = sceneFromWelcome(*welcome, error);
    if (!scene) return false;
    scene_ = std::make_shared<const Scene>(*scene);
    const QString mode = (*welcome)["mode"].toString();
    mode_ = mode == "lockstep" ? RunMode::Lockstep : mode == "max" ? RunMode::Max : RunMode::Realtime;
    paused_ = (*welcome)["paused"].toBool();
    speed_ = (*welcome)["speed"].toDouble(1.0);
    // From now on (not during the handshake, whose WELCOME hello() reads).
    connect(&client_, &ProtocolClient::messageReceived, this, &RemoteWatcher::drain, Qt::UniqueConnection);
    drain();
    return true;
}

void RemoteWatcher::drain() {
    while (auto r = client_.poll()) {
        const auto type = static_cast<protocol::MessageType>(r->message.type);
        const QJsonObject json = jsonPayload(r->message);
        if (type == protocol::MessageType::State) {
            std::optional<Snapshot> s = snapshotFromState(json, scene_);
            if (!s) continue;
            s->mode = mode_;
            s->paused = paused_;
            s->speed = speed_;
            latest_ = std::make_shared<const Snapshot>(std::move(*s));
            emit snapshotReceived();
        } else if (type == protocol::MessageType::Reply) {
            const QString command = json["command"].toString();
            if (command == "pause" || command == "resume") {
                paused_ = command == "pause";
                // A paused server sends no STATE: the snapshot shown says so now.
                if (latest_) {
                    auto s = std::make_shared<Snapshot>(*latest_);
                    s->paused = paused_;
                    latest_ = std::move(s);
                }
            }
            emit message(QStringLiteral("%1: done (t = %2 s)").arg(command).arg(json["time"].toDouble()));
        } else if (type == protocol::MessageType::Error) {
            emit message(QStringLiteral("server: %1").arg(json["message"].toString()));
        }
    }
}

void RemoteWatcher::control(const QString& command, const QJsonObject& args) {
    QJsonObject json = args;
    json["command"] = command;
    client_.sendJson(protocol::MessageType::Control, json);
}

void RemoteWatcher::placeRobot(int robot, const RobotState& pose) {
    control(
        "place_robot",
        {{"robot", robot}, {"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}, {"v", pose.v}, {"omega", pose.omega}});
}

void RemoteWatcher::placeBall(const BallState& ball) {
    control("place_ball", {{"x", ball.x}, {"y", ball.y}, {"vx", ball.vx}, {"vy", ball.vy}});
}

}  // namespace vssim
