#include "net/control_server.h"

#include <QJsonArray>
#include <QTcpSocket>
#include <QTimer>
#include <deque>

#include "vssim/camera/camera_lens.h"
#include "delivery/frame_delivery.h"
#include "delivery/ground_truth_noise.h"
#include "io/scene_io.h"
#include "realtime/monotonic_clock.h"
#include "wire/game_message.h"
#include "wire/state_message.h"

namespace vssim {

namespace {

QJsonObject summariesJson(const std::map<QString, SampleSummary>& byName) {
    QJsonObject json;
    for (const auto& [name, summary] : byName) json[name] = toJson(summary);
    return json;
}

// The REPLY's "stats" object (docs/protocol.md, CONTROL stats).
QJsonObject statsJson(const StatsReport& s) {
    return QJsonObject{
        {"command_latency_ms", toJson(s.commandLatencyMs)},
        {"command_delay_ms", toJson(s.commandDelayMs)},
        {"late_commands", static_cast<double>(s.lateCommands)},
        {"lag_resets", static_cast<double>(s.lagResets)},
        {"frame_period_ms", toJson(s.framePeriodMs)},
        {"render_ms", toJson(s.renderMs)},
        {"patch_area_percent", toJson(s.patchAreaPercent)},
        {"frames_skipped", static_cast<double>(s.framesSkipped)},
        {"frames_dropped_unsent", static_cast<double>(s.framesDroppedUnsent)},
        {"encode_ms", summariesJson(s.encodeMs)},
        {"frame_bytes", summariesJson(s.frameBytes)},
        {"clients", s.clients},
        {"frames_dropped_for_slow_clients", static_cast<double>(s.framesDroppedForSlowClients)},
        {"image_age_ms", toJson(s.imageAgeMs)},
    };
}

}  // namespace

struct ControlServer::Client {
    int id = 0;
    QTcpSocket* socket = nullptr;
    QString peer;
    protocol::MessageReader reader{protocol::kMaxClientMessage};
    bool greeted = false;
    bool closing = false;                            // dropped or disconnected: nothing more is read or sent
    bool turnQueued = false;                         // a turn to handle the rest of its input is queued
    std::vector<std::pair<int, DriveCommand>> drives;  // this turn's VOLTAGES and WHEEL_SPEEDS, the newest per robot
    Hello hello;
    QTimer* helloTimer = nullptr;
    QByteArray pendingFrame, pendingState;  // newest unsent, waiting for the socket to drain
    // Other messages (REPLY, ERROR) queued while a frame waits, in order: the
    // ones produced before it (whose own frames were dropped) and after it.
    QByteArray heldBefore, heldAfter;
    std::int64_t pendingInstantNs = 0;
    std::int64_t framesDropped = 0;
    int errorsLogged = 0;
    std::int64_t errorWindowStartNs = 0;  // monotonicNs() of the current error window's first error
    int errorsInWindow = 0;
    std::int64_t errorsNotSent = 0;
    std::shared_ptr<std::atomic<int>> queued = std::make_shared<std::atomic<int>>(0);  // requests in the engine's queue
    bool statsPending = false;   // one `stats` at a time per client (each sorts thousands of samples)
    std::deque<double> steps;    // durations of its `step` requests not answered yet, s, oldest first
    double stepSeconds = 0.0;    // their sum, s
    bool robotsStopped = false;  // its team's robots got 0 V when it was dropped
    std::int64_t commands = 0;   // VOLTAGES accepted
    std::int64_t framesSent = 0;
    std::int64_t connectedNs = 0;  // monotonicNs() at connection
    // Its camera (docs/protocol.md, FRAME and STATE): the scene's, with its
    // HELLO's overrides; the stream of its draws; its link's frames on their way.
    CameraSettings camera;
    std::uint64_t stream = 0;
    FrameDelivery delivery;
};

std::vector<ClientInfo> ControlServer::clients() const {
    std::vector<ClientInfo> out;
    for (const auto& [id, c] : clients_) {
        ClientInfo info;
        info.id = id;
        info.peer = c->peer;
        info.greeted = c->greeted;
        info.role = c->greeted ? roleName(c->hello.role) : QStringLiteral("(no HELLO yet)");
        info.name = c->hello.name;
        info.images = c->hello.images ? subscriptionName(*c->hello.images) : QStringLiteral("none");
        info.state = c->hello.state;
        info.commands = c->commands;
        info.framesSent = c->framesSent;
        info.framesDropped = c->framesDropped + c->delivery.overflowed();
        info.unsentBytes =
            unsent(*c) + c->pendingFrame.size() + c->pendingState.size() + c->delivery.waitingBytes();
        info.errorsNotSent = c->errorsNotSent;
        info.unreadBytes = c->socket->bytesAvailable() + static_cast<qint64>(c->reader.buffered());
        info.connectedSeconds = 1e-9 * static_cast<double>(monotonicNs() - c->connectedNs);
        out.push_back(info);
    }
    return out;
}

void ControlServer::setScene(const Scene& scene) {
    // The clients go first, while scene_ is still the one the engine runs:
    // their robots are stopped by index in that scene, not in the new one.
    for (auto& [id, client] : clients_)
        sendError(*client, {"scene_changed", "the server loaded another scene: connect again"}, true);
    scene_ = scene;
    lastReferee_ = {};
    greetedByRole_.clear();
    background_ = cameraRendererOrIdeal(scene);
}

ControlServer::ControlServer(const Scene& scene, EngineThread& engine, const ServerSettings& settings, QObject* parent)
    : QObject(parent), scene_(scene), engine_(engine), settings_(settings), background_(cameraRendererOrIdeal(scene)) {
    connect(&server_, &QTcpServer::newConnection, this, &ControlServer::accept);
    connect(&engine_, &EngineThread::outboxReady, this, &ControlServer::drainEngine, Qt::QueuedConnection);
    // A halted simulation is the server's news too: its log says why.
    connect(
        &engine_, &EngineThread::simulationHalted, this,
        [this](const QString& message) {
            emit logLine(QStringLiteral("the simulation halted: %1; clients get ERROR non_finite for step and resume "
                                        "until a reset")
                             .arg(printableText(message, 400)));
        },
        Qt::QueuedConnection);
}

ControlServer::~ControlServer() {
    for (auto& [id, client] : clients_) {
        client->socket->disconnect(this);
        client->socket->abort();
        client->socket->deleteLater();
    }
}

bool ControlServer::listen(QString* error) {
    if (!server_.listen(settings_.address, settings_.port)) {
        *error = QStringLiteral("cannot listen on %1:%2: %3")
                     .arg(settings_.address.toString())
                     .arg(settings_.port)
                     .arg(server_.errorString());
        return false;
    }
    return true;
}

void ControlServer::log(const Client& client, const QString& text) {
    const QString who = client.greeted
                            ? QStringLiteral(", ") + roleName(client.hello.role) +
                                  (client.hello.name.isEmpty() ? QString() : " \"" + client.hello.name + "\"")
                            : QString();
    // In one pass (a "%1" in a client's name stays as it is), and printable
    // as a whole: the parts are checked where they come from (names, keys
    // and commands are made printable when parsed), and whatever a later
    // message may carry, a client cannot start a line of its own in the log.
    emit logLine(
        printableText(QStringLiteral("client %1 (%2%3): %4").arg(QString::number(client.id), client.peer, who, text),
                      kMaxLogLineCharacters));
}

void ControlServer::accept() {
    while (QTcpSocket* socket = server_.nextPendingConnection()) {
        auto client = std::make_unique<Client>();
        client->id = nextId_++;
        client->socket = socket;
        // Small messages (replies, STATE) go out at once: no Nagle delay.
        socket->setSocketOption(QAbstractSocket::LowDelayOption, 1);
        // Qt reads no further ahead than this: a client that sends faster than
        // its turns take is slowed down by TCP instead of filling our memory.
        socket->setReadBufferSize(kReadAheadBytes);
        client->peer = QStringLiteral("%1:%2").arg(socket->peerAddress().toString()).arg(socket->peerPort());
        client->connectedNs = monotonicNs();
        Client& c = *client;
        const int id = c.id;
        clients_.emplace(id, std::move(client));
        log(c, "connected");
        connect(socket, &QTcpSocket::readyRead, this, [this, id] {
            auto it = clients_.find(id);
            if (it != clients_.end() && !it->second->turnQueued) serveTurn(*it->second);
        });
        connect(socket, &QTcpSocket::bytesWritten, this, [this, id] {
            auto it = clients_.find(id);
            if (it != clients_.end()) flushPending(*it->second);
        });
        // The client goes from the event loop, never from inside a loop over
        // the clients (a failed write can close a socket there); until then
        // nothing more is read from it or sent to it.
        connect(socket, &QTcpSocket::disconnected, this, [this, id] {
            auto it = clients_.find(id);
            if (it != clients_.end()) {
                // Its robots stop now, before a successor of the same team can say HELLO.
                stopRobots(*it->second);
                it->second->closing = true;
            }
            QMetaObject::invokeMethod(
                this, [this, id] { forget(id); }, Qt::QueuedConnection);
        });
        c.helloTimer = new QTimer(socket);
        c.helloTimer->setSingleShot(true);
        connect(c.helloTimer, &QTimer::timeout, this, [this, id] {
            auto it = clients_.find(id);
            if (it != clients_.end() && !it->second->greeted)
                sendError(*it->second,
                          {"hello_timeout",
                           QStringLiteral("no HELLO within %1 s of connecting").arg(settings_.helloTimeoutMs / 1000.0)},
                          true);
        });
        c.helloTimer->start(settings_.helloTimeoutMs);
        makeRoomFor(c);
    }
}

void ControlServer::makeRoomFor(Client& newcomer) {
    int open = 0;
    for (const auto& [id, client] : clients_) open += client->closing ? 0 : 1;
    if (open <= settings_.maxClients) return;
    // Connections that never say HELLO must not lock real clients out: the
    // oldest of them goes, preferably one that has sent nothing at all (a
    // client whose HELLO is on its way has). Only when every connection has
    // said HELLO is the newcomer refused.
    Client* silent = nullptr;
    Client* ungreeted = nullptr;
    for (const auto& [id, client] : clients_) {
        if (client.get() == &newcomer || client->greeted || client->closing) continue;
        if (!ungreeted) ungreeted = client.get();
        if (!silent && client->socket->bytesAvailable() == 0 && client->reader.buffered() == 0) silent = client.get();
    }
    if (Client* oldest = silent ? silent : ungreeted)
        return sendError(
            *oldest,
            {"too_many_clients", QStringLiteral("the server is full (%1 connections) and this one has not said HELLO: "
                                                "closed to make room for a new one")
                                     .arg(settings_.maxClients)},
            true);
    sendError(newcomer,
              {"too_many_clients", QStringLiteral("the server takes at most %1 clients").arg(settings_.maxClients)},
              true);
}

void ControlServer::serveTurn(Client& client) {
    // One stamp per turn: a message that waited for its turn arrives, for the
    // engine, when the server gets to it.
    const std::int64_t arrivalNs = monotonicNs();
    protocol::Message message;
    std::uint32_t length = 0;
    int messages = 0;
    qint64 bytes = 0;
    bool more = false;  // the turn ended with its budget spent, maybe with input left
    while (!client.closing) {
        if (messages == kMaxMessagesPerTurn || bytes >= kMaxBytesPerTurn) {
            more = true;
            break;
        }
        const protocol::MessageReader::Status status = client.reader.next(&message, &length);
        if (status == protocol::MessageReader::Status::NeedMore) {
            if (client.socket->bytesAvailable() == 0) break;  // the next readyRead starts a turn
            client.reader.append(client.socket->read(kReadAheadBytes));
            continue;
        }
        if (status == protocol::MessageReader::Status::Oversize) {
            sendError(client,
                      {"oversize", QStringLiteral("message length %1 exceeds the limit of %2 bytes")
                                       .arg(length)
                                       .arg(protocol::kMaxClientMessage)},
                      true);
            break;
        }
        if (status == protocol::MessageReader::Status::Empty) {
            sendError(client, {"malformed", "message length 0 (a message has at least its type byte)"}, true);
            break;
        }
        ++messages;
        bytes += 4 + static_cast<qint64>(length);
        handle(client, message, arrivalNs);
    }
    flushVoltages(client, arrivalNs);
    if (!more || client.closing) return;
    // The rest waits behind what is queued now: other clients' turns and the engine's frames.
    client.turnQueued = true;
    QMetaObject::invokeMethod(
        this,
        [this, id = client.id] {
            auto it = clients_.find(id);
            if (it == clients_.end()) return;
            it->second->turnQueued = false;
            serveTurn(*it->second);
        },
        Qt::QueuedConnection);
}

void ControlServer::flushVoltages(Client& client, std::int64_t arrivalNs) {
    if (client.drives.empty()) return;
    EngineRequest request;
    request.kind = EngineRequest::Kind::Voltages;  // with wheel speeds too: each robot appears once
    request.arrivalNs = arrivalNs;
    request.client = client.id;
    for (const auto& [robot, drive] : client.drives) {
        if (drive.wheelSpeeds)
            request.wheelSpeeds.emplace_back(robot, drive.speeds);
        else
            request.voltages.emplace_back(robot, drive.voltages);
    }
    client.drives.clear();
    // A dropped team client's robots have been stopped: its last voltages must not restart them.
    if (client.closing) return;
    if (!post(client, std::move(request)))
        sendError(client,
                  {"busy",
                   QStringLiteral("more than %1 of this client's requests are waiting for the engine; VOLTAGES and WHEEL_SPEEDS dropped")
                       .arg(kMaxQueuedPerClient)},
                  false);
}

void ControlServer::handle(Client& client, const protocol::Message& message, std::int64_t arrivalNs) {
    using protocol::MessageType;
    const auto type = static_cast<MessageType>(message.type);
    if (!client.greeted) {
        if (type != MessageType::Hello) {
            sendError(client,
                      {"hello_required", QStringLiteral("the first message must be HELLO (type 0x01), got type 0x%1")
                                             .arg(message.type, 2, 16, QChar('0'))},
                      true);
            return;
        }
        QString jsonError;
        const std::optional<QJsonObject> json = protocol::parseJsonObject(message.payload, &jsonError);
        if (!json) {
            sendError(client, {"malformed", "HELLO: " + jsonError}, true);
            return;
        }
        greet(client, *json);
        return;
    }
    switch (type) {
        case MessageType::Hello:
            sendError(client, {"malformed", "HELLO again: a client says HELLO once"}, false);
            return;
        case MessageType::Voltages: return handleVoltages(client, message);
        case MessageType::WheelSpeeds: return handleWheelSpeeds(client, message);
        case MessageType::Placement: {
            QString jsonError;
            const std::optional<QJsonObject> json = protocol::parseJsonObject(message.payload, &jsonError);
            if (!json) return sendError(client, {"malformed", "PLACEMENT: " + jsonError}, false);
            RequestError error;
            std::optional<EngineRequest> request = parsePlacement(*json, scene_, client.hello.role, &error);
            if (!request) return sendError(client, error, false, json->value("id"));
            flushVoltages(client, arrivalNs);  // the turn's VOLTAGES before it, as they came
            request->arrivalNs = arrivalNs;
            request->client = client.id;
            request->id = json->value("id");
            if (!post(client, std::move(*request)))
                return sendError(
                    client,
                    {"busy", QStringLiteral(
                                 "more than %1 of this client's requests are waiting for the engine; PLACEMENT dropped")
                                 .arg(kMaxQueuedPerClient)},
                    false, json->value("id"));
            return;
        }
        case MessageType::Control: {
            QString jsonError;
            const std::optional<QJsonObject> json = protocol::parseJsonObject(message.payload, &jsonError);
            if (!json) return sendError(client, {"malformed", "CONTROL: " + jsonError}, false);
            RequestError error;
            std::optional<EngineRequest> request = parseControl(*json, scene_, &error);
            if (!request) return sendError(client, error, false, json->value("id"));
            if (settings_.readOnlyObservers && client.hello.role == ClientRole::Observer &&
                !leavesTheGameAlone(*request))
                return sendError(client,
                                 {"read_only", QStringLiteral("CONTROL %1: observers are read-only on this server; an "
                                                              "observer may only ask for stats")
                                                   .arg(request->command)},
                                 false, json->value("id"));
            flushVoltages(client, arrivalNs);  // the turn's VOLTAGES before it, as they came
            request->arrivalNs = arrivalNs;
            request->client = client.id;
            request->id = json->value("id");
            const bool stats = request->kind == EngineRequest::Kind::Stats;
            if (stats && client.statsPending)
                return sendError(client, {"busy", "CONTROL stats: the previous stats request is not answered yet"},
                                 false, request->id);
            // Engine time is shared: a client's steps waiting are bounded (ServerSettings).
            const bool isStep = request->kind == EngineRequest::Kind::Step;
            const double duration = request->duration;
            // In seconds and in steps of dt (a tiny dt makes a second millions of steps).
            const double budget = std::min(settings_.maxQueuedStepSeconds, kMaxStepSteps * scene_.simulation.dt);
            if (isStep && client.stepSeconds + duration > budget)
                return sendError(client,
                                 {"busy", QStringLiteral("CONTROL step: this client's steps waiting for the engine "
                                                         "would add up to more than %1 s of simulated time")
                                              .arg(budget)},
                                 false, request->id);
            if (!post(client, std::move(*request)))
                return sendError(
                    client,
                    {"busy", QStringLiteral(
                                 "more than %1 of this client's requests are waiting for the engine; CONTROL dropped")
                                 .arg(kMaxQueuedPerClient)},
                    false, json->value("id"));
            if (stats) client.statsPending = true;
            if (isStep) {
                client.steps.push_back(duration);
                client.stepSeconds += duration;
            }
            return;
        }
        default:
            sendError(client,
                      {"unknown_type", QStringLiteral("unknown message type 0x%1 (%2 payload bytes skipped)")
                                           .arg(message.type, 2, 16, QChar('0'))
                                           .arg(message.payload.size())},
                      false);
    }
}

void ControlServer::handleVoltages(Client& client, const protocol::Message& message) {
    QString layoutError;
    const auto entries = protocol::decodeVoltages(message.payload, &layoutError);
    if (!entries) return sendError(client, {"malformed", layoutError}, false);
    if (const auto error = checkVoltages(*entries, scene_, client.hello.role)) return sendError(client, *error, false);
    ++client.commands;
    for (const auto& [robot, volts] : *entries) keepNewest(client, robot, DriveCommand::ofVoltages(volts));
}

void ControlServer::handleWheelSpeeds(Client& client, const protocol::Message& message) {
    QString layoutError;
    const auto entries = protocol::decodeWheelSpeeds(message.payload, &layoutError);
    if (!entries) return sendError(client, {"malformed", layoutError}, false);
    if (const auto error = checkWheelSpeeds(*entries, scene_, client.hello.role))
        return sendError(client, *error, false);
    ++client.commands;
    for (const auto& [robot, speeds] : *entries) keepNewest(client, robot, DriveCommand::ofWheelSpeeds(speeds));
}

void ControlServer::keepNewest(Client& client, int robot, const DriveCommand& drive) {
    // Merged into the turn's one request: the turn's messages share one
    // arrival instant, at which the engine would apply them one after the
    // other, so each robot's newest command is all that counts.
    auto it = std::find_if(client.drives.begin(), client.drives.end(),
                           [robot](const auto& entry) { return entry.first == robot; });
    if (it != client.drives.end())
        it->second = drive;
    else
        client.drives.emplace_back(robot, drive);
}

bool ControlServer::post(Client& client, EngineRequest request) {
    if (client.queued->load() >= kMaxQueuedPerClient) return false;
    request.queued = client.queued;
    client.queued->fetch_add(1);
    if (engine_.post(std::move(request))) return true;
    client.queued->fetch_sub(1);
    return false;
}

void ControlServer::greet(Client& client, const QJsonObject& json) {
    RequestError error;
    const std::optional<Hello> hello = parseHello(json, &error);
    if (!hello) return sendError(client, error, true);
    if (hello->role != ClientRole::Observer) {
        // Only a remote team is a client's to drive (vssim serve --yellow, --blue; the scene's game).
        const Team team = hello->role == ClientRole::Yellow ? Team::Yellow : Team::Blue;
        const std::shared_ptr<const Snapshot> snapshot = engine_.snapshots().latest();
        const GameSettings& game = snapshot ? snapshot->gameSettings : scene_.game;
        const TeamControl control = team == Team::Yellow ? game.yellow : game.blue;
        if (control != TeamControl::Remote)
            return sendError(client,
                             {"role_not_remote",
                              QStringLiteral("the %1 team is %2 on this server, not driven by a client (vssim serve "
                                             "--%1 tcp lets a client drive it)")
                                  .arg(roleName(hello->role), control == TeamControl::Builtin
                                                                  ? QStringLiteral("played by the built-in team")
                                                                  : QStringLiteral("idle"))},
                             true);
        for (const auto& [id, other] : clients_) {
            if (other.get() != &client && other->greeted && !other->closing && other->hello.role == hello->role)
                return sendError(
                    client,
                    {"role_taken",
                     QStringLiteral("client %1 already drives the %2 team").arg(id).arg(roleName(hello->role))},
                    true);
        }
    }
    // Its camera: the scene's, with the HELLO's delivery and noise over it
    // (already checked against every range: parseHello).
    CameraSettings camera = scene_.camera;
    if (!hello->camera.isEmpty()) {
        QString message;
        const std::optional<CameraSettings> own =
            cameraSettingsFromJson(hello->camera, scene_.camera, QStringLiteral("camera"), &message);
        if (!own) return sendError(client, {"malformed", QStringLiteral("HELLO: ") + message}, true);
        camera = *own;
    }
    // Draws of its own, the same in every run that greets the same roles in
    // the same order; a client that gives its seed gets its role's first stream.
    const std::int64_t ordinal = greetedByRole_[hello->role]++;
    client.camera = camera;
    client.stream = clientStream(static_cast<int>(hello->role), hello->camera.contains("seed") ? 0 : ordinal);
    client.delivery = FrameDelivery(camera, client.stream, settings_.maxUnsentBytes);
    client.hello = *hello;
    client.greeted = true;
    client.helloTimer->stop();
    // In real time a short kernel queue keeps the frames a slow reader gets
    // recent (it is behind by what the queue holds); lockstep keeps the default.
    if ((hello->images || hello->state) && !lockstep())
        client.socket->setSocketOption(QAbstractSocket::SendBufferSizeSocketOption, settings_.realtimeSendBufferBytes);
    log(client, QStringLiteral("HELLO: images %1, state %2")
                    .arg(hello->images ? subscriptionName(*hello->images) : QStringLiteral("none"))
                    .arg(hello->state ? "yes" : "no"));
    send(client, protocol::encodeJsonMessage(protocol::MessageType::Welcome, welcome(client)));
    if (hello->images) {
        const std::shared_ptr<const Snapshot> snapshot = engine_.snapshots().latest();
        protocol::FrameHeader header;
        header.frame = snapshot ? static_cast<std::uint32_t>(snapshot->frame) : 0;
        header.time = snapshot ? snapshot->time : 0.0;
        header.kind = protocol::FrameKind::Background;
        header.encoding = hello->images->encoding;
        const cv::Mat& image = background_.background();
        std::vector<protocol::FramePatch> patches{
            {0, 0, image.cols, image.rows, encodeImage(image, hello->images->encoding, hello->images->jpegQuality)}};
        send(client, protocol::encodeMessage(protocol::MessageType::Frame, protocol::encodeFrame(header, patches)));
    }
    updateSubscriptions();
}

QJsonObject ControlServer::welcome(const Client& client) const {
    const std::shared_ptr<const Snapshot> snapshot = engine_.snapshots().latest();
    QJsonArray robots;
    std::map<Team, int> perTeam;
    for (std::size_t i = 0; i < scene_.robots.size(); ++i) {
        const RobotSpec& r = scene_.robots[i];
        robots.append(QJsonObject{{"index", static_cast<int>(i)},
                                  {"name", QString::fromStdString(r.name)},
                                  {"team", teamName(r.team)},
                                  {"id", perTeam[r.team]++},
                                  {"side", r.params.side},
                                  {"max_voltage", r.params.max_voltage}});
    }
    const CameraGeometry& camera = background_.geometry();
    QJsonObject cameraJson{{"width", camera.width},
                           {"height", camera.height},
                           {"scale", camera.scale},
                           {"centre_u", camera.centreU},
                           {"centre_v", camera.centreV}};
    cameraJson["images"] =
        client.hello.images ? (client.hello.images->kind == protocol::FrameKind::Full ? "full" : "patches") : "none";
    if (client.hello.images) cameraJson["encoding"] = encodingName(client.hello.images->encoding);
    // The lens, OpenCV's convention (pixel centres at whole numbers), and this client's settings.
    const CameraLens lens = cameraLensFor(scene_.camera, camera);
    const cv::Matx33d k = cameraMatrix(lens);
    const cv::Vec<double, 5> d = distortionCoefficients(lens);
    cameraJson["projection"] = cameraProjectionName(scene_.camera.projection);
    cameraJson["mount_height"] = scene_.camera.height;
    cameraJson["matrix"] = QJsonArray{QJsonArray{k(0, 0), k(0, 1), k(0, 2)}, QJsonArray{k(1, 0), k(1, 1), k(1, 2)},
                                      QJsonArray{k(2, 0), k(2, 1), k(2, 2)}};
    cameraJson["distortion"] = QJsonArray{d[0], d[1], d[2], d[3], d[4]};
    cameraJson["settings"] = cameraSettingsToJson(client.camera);
    const double dt = scene_.simulation.dt;
    const double framePeriod = engine_.framePeriod();
    return QJsonObject{
        {"protocol", protocol::kVersion},
        {"server", QStringLiteral("vssim %1").arg(VSSIM_VERSION)},
        {"client", client.id},
        {"role", roleName(client.hello.role)},
        {"mode", snapshot ? runModeName(snapshot->mode) : "realtime"},
        {"speed", snapshot ? snapshot->speed : 1.0},
        {"paused", snapshot ? snapshot->paused : false},
        {"time", snapshot ? snapshot->time : 0.0},
        {"frame", snapshot ? static_cast<double>(snapshot->frame) : 0.0},
        {"dt", dt},
        {"frame_period", framePeriod},
        {"field", fieldToJson(scene_.field)},
        {"ball", QJsonObject{{"radius", scene_.ball_params.radius}}},
        {"camera", cameraJson},
        {"robots", robots},
        {"game", gameJson()},
    };
}

QJsonObject ControlServer::gameJson() const {
    const std::shared_ptr<const Snapshot> snapshot = engine_.snapshots().latest();
    const GameSettings& game = snapshot ? snapshot->gameSettings : scene_.game;
    QJsonObject json = gameSettingsJson(game.rules, game.yellow, game.blue);
    // The newest state the clients were told (REFEREE), or the engine's.
    QJsonObject state = lastReferee_;
    if (state.isEmpty()) state = gameStateJson(snapshot ? snapshot->game : GameState{});
    state.remove("frame");
    state.remove("time");
    json["state"] = state;
    return json;
}

void ControlServer::sendError(Client& client, const RequestError& error, bool fatal, const QJsonValue& id) {
    if (client.closing) return;
    // A fatal error always goes (the connection closes after it).
    if (fatal || errorAllowed(client)) writeError(client, error, fatal, id);
}

bool ControlServer::errorAllowed(Client& client) {
    const std::int64_t nowNs = monotonicNs();
    if (client.errorsInWindow == 0 || nowNs - client.errorWindowStartNs >= kErrorWindowNs) {
        client.errorWindowStartNs = nowNs;
        client.errorsInWindow = 0;
    }
    if (++client.errorsInWindow <= kMaxErrorsPerWindow) return true;
    ++client.errorsNotSent;
    if (client.errorsInWindow == kMaxErrorsPerWindow + 1) {
        const double secondsLeft = 1e-9 * static_cast<double>(client.errorWindowStartNs + kErrorWindowNs - nowNs);
        writeError(client,
                   {"too_many_errors",
                    QStringLiteral("too many errors (%1 in %2 s): further ones are not reported for the next %3 s")
                        .arg(kMaxErrorsPerWindow)
                        .arg(kErrorWindowNs / 1'000'000'000)
                        .arg(secondsLeft, 0, 'f', 1)},
                   false, QJsonValue());
    }
    return false;
}

void ControlServer::writeError(Client& client, const RequestError& error, bool fatal, const QJsonValue& id) {
    if (client.errorsLogged < 20) {
        log(client,
            QStringLiteral("%1 error %2: %3").arg(fatal ? "fatal" : "").arg(error.code, error.message).trimmed());
        if (++client.errorsLogged == 20) log(client, "further errors from this client are not logged");
    }
    QJsonObject json{{"error", error.code},
                     {"message", error.message},
                     {"fatal", fatal},
                     {"id", id.isUndefined() ? QJsonValue() : id}};
    send(client, protocol::encodeJsonMessage(protocol::MessageType::Error, json));
    if (fatal) drop(client, QStringLiteral("closed after a fatal %1 error").arg(error.code));
}

void ControlServer::send(Client& client, const QByteArray& bytes) {
    if (client.closing) return;
    // Messages keep their order: behind a frame that waits, they wait too
    // (protocol.md: a step's FRAME comes before its REPLY).
    if (waiting(client)) {
        if (fits(client, bytes.size())) client.heldAfter += bytes;
        return;
    }
    if (fits(client, bytes.size())) client.socket->write(bytes);
}

bool ControlServer::waiting(const Client& client) {
    return !client.pendingFrame.isEmpty() || !client.pendingState.isEmpty();
}

bool ControlServer::fits(Client& client, qint64 bytes) {
    if (unsent(client) + bytes > settings_.maxUnsentBytes) {
        drop(client,
             QStringLiteral("disconnected: more than %1 MiB unsent (the client is not reading)")
                 .arg(static_cast<double>(settings_.maxUnsentBytes) / (1 << 20)),
             true);
        return false;
    }
    return makeRoom(client, bytes);
}

qint64 ControlServer::unsent(const Client& client) const {
    // Not the frame waiting: it is the newest, which the server holds anyway,
    // shared by every client with the same subscription.
    return client.socket->bytesToWrite() + client.heldBefore.size() + client.heldAfter.size();
}

qint64 ControlServer::totalUnsent() const {
    qint64 total = 0;
    for (const auto& [id, client] : clients_) total += unsent(*client);
    return total;
}

bool ControlServer::makeRoom(Client& writer, qint64 bytes) {
    for (;;) {
        // Clients closing are counted (their bytes are still held) but cannot
        // be dropped again; they hold at most kGraceBytes, for 2 s at most
        // (one dropped here holds nothing: its bytes are discarded).
        qint64 total = bytes, most = 0;  // a client with nothing unsent is never the one dropped
        Client* furthestBehind = nullptr;
        for (auto& [id, client] : clients_) {
            const qint64 n = unsent(*client);
            total += n;
            if (!client->closing && n > most) {
                most = n;
                furthestBehind = client.get();
            }
        }
        if (total <= settings_.maxTotalUnsentBytes || !furthestBehind) return true;
        drop(*furthestBehind,
             QStringLiteral("disconnected: the server holds more than %1 MiB unsent for all its clients, the most "
                            "(%2 bytes) for this one (it is not reading)")
                 .arg(static_cast<double>(settings_.maxTotalUnsentBytes) / (1 << 20))
                 .arg(most),
             true);
        if (furthestBehind == &writer) return false;
    }
}

bool ControlServer::lockstep() const {
    const std::shared_ptr<const Snapshot> snapshot = engine_.snapshots().latest();
    return snapshot && snapshot->mode == RunMode::Lockstep;
}

bool ControlServer::holdsFrames(Client& client) {
    // Lockstep: the client sets the pace and should get every frame, unless
    // the server as a whole is short of room.
    if (lockstep() && totalUnsent() <= settings_.maxTotalUnsentBytes / 2)
        return client.socket->bytesToWrite() > settings_.lockstepBacklogBytes;
    // Real time: the kernel takes what it can now; whatever it cannot take
    // means the client is behind, and a newer frame would only wait behind it.
    if (client.socket->bytesToWrite() > 0) client.socket->flush();
    return client.socket->bytesToWrite() > 0;
}

void ControlServer::sendNewest(Client& client, QByteArray frame, QByteArray state, std::int64_t instantNs) {
    if (client.closing || (frame.isEmpty() && state.isEmpty())) return;
    if (waiting(client)) {
        // The older frame is dropped; what was queued behind it now goes before the newer one.
        ++client.framesDropped;
        client.heldBefore += client.heldAfter;
        client.heldAfter.clear();
    }
    client.pendingFrame = std::move(frame);
    client.pendingState = std::move(state);
    client.pendingInstantNs = instantNs;
    flushPending(client);
}

void ControlServer::flushPending(Client& client) {
    if (client.closing || !waiting(client) || holdsFrames(client)) return;
    // holdsFrames() may have flushed the socket: a failed write (the client
    // reset the connection) makes Qt abort it, whose disconnected() marked the
    // client closing, and with its buffer gone it holds nothing. The socket is
    // closed then: nothing more may be written to it.
    if (client.closing) return;
    const QByteArray before = std::exchange(client.heldBefore, {}), frame = std::exchange(client.pendingFrame, {}),
                     state = std::exchange(client.pendingState, {}), after = std::exchange(client.heldAfter, {});
    if (!fits(client, before.size() + frame.size() + state.size() + after.size())) return;
    // One by one: Qt keeps a large QByteArray written whole as it is, shared
    // with the other clients that get the same frame.
    for (const QByteArray* bytes : {&before, &frame, &state, &after})
        if (!bytes->isEmpty()) client.socket->write(*bytes);
    if (!frame.isEmpty()) {
        ++client.framesSent;
        imageAgeMs_.add(1e-6 * static_cast<double>(monotonicNs() - client.pendingInstantNs));
    }
}

void ControlServer::drainEngine() {
    for (OutboxItem& item : engine_.takeOutbox()) {
        if (item.frame) {
            for (auto& [id, client] : clients_) {
                if (!client->greeted || client->closing) continue;
                QByteArray frame, state;
                if (client->hello.images)
                    for (const auto& [sub, bytes] : item.frame->images)
                        if (sub == *client->hello.images) frame = bytes;
                if (client->hello.state) state = item.frame->state;
                if (frame.isEmpty() && state.isEmpty()) continue;
                // Its camera's noise on the ground truth, drawn for it alone.
                if (!state.isEmpty() && hasGroundTruthNoise(client->camera))
                    state = protocol::encodeJsonMessage(
                        protocol::MessageType::State,
                        observedStateJson(item.frame->stateJson, client->camera, client->stream));
                if (client->delivery.immediate()) {
                    sendNewest(*client, frame, state, item.frame->instantNs);
                    continue;
                }
                client->delivery.capture({item.frame->frame, item.frame->time, item.frame->instantNs, frame, state});
                deliverDue(*client, item.frame->time);
            }
        } else if (item.reply && item.reply->referee) {
            // The game's state changed: every client is told.
            lastReferee_ = *item.reply->referee;
            const QByteArray bytes = protocol::encodeJsonMessage(protocol::MessageType::Referee, lastReferee_);
            const double time = lastReferee_.value("time").toDouble();
            for (auto& [id, client] : clients_) {
                if (!client->greeted || client->closing) continue;
                deliverDue(*client, time);  // the frames its camera delivered by then go first
                send(*client, bytes);
            }
        } else if (item.reply) {
            const EngineReply& r = *item.reply;
            auto it = clients_.find(r.client);
            if (it == clients_.end()) continue;
            Client& client = *it->second;
            if (r.stats) client.statsPending = false;
            // The frames its camera delivered by the reply's instant go before it; later ones after.
            deliverDue(client, r.time);
            if (r.kind == EngineRequest::Kind::Step && !client.steps.empty()) {
                const double done = client.steps.front();
                client.steps.pop_front();
                // Zero when none is left, so that rounding cannot build up.
                client.stepSeconds = client.steps.empty() ? 0.0 : client.stepSeconds - done;
            }
            if (!r.ok) {
                const QString what = r.kind == EngineRequest::Kind::Placement ? QStringLiteral("PLACEMENT")
                                                                              : QStringLiteral("CONTROL ") + r.command;
                sendError(client, {r.error, QStringLiteral("%1: %2").arg(what, r.message)}, false, r.id);
                continue;
            }
            QJsonObject json{{"id", r.id.isUndefined() ? QJsonValue() : r.id},
                             {"command", r.command},
                             {"ok", true},
                             {"time", r.time},
                             {"frame", static_cast<double>(r.frame)}};
            if (r.stats) {
                StatsReport stats = *r.stats;
                stats.clients = clientCount();
                stats.imageAgeMs = imageAgeMs_.summary();
                for (const auto& [id, c] : clients_) stats.framesDroppedForSlowClients += c->framesDropped;
                json["stats"] = statsJson(stats);
            }
            send(client, protocol::encodeJsonMessage(protocol::MessageType::Reply, json));
        }
    }
}

void ControlServer::deliverDue(Client& client, double now) {
    if (client.closing || client.delivery.immediate()) return;
    for (FrameDelivery::Captured& due : client.delivery.due(now))
        sendNewest(client, std::move(due.frameMessage), std::move(due.stateMessage), due.instantNs);
}

void ControlServer::updateSubscriptions() {
    std::vector<ImageSubscription> images;
    bool state = false;
    for (const auto& [id, client] : clients_) {
        if (!client->greeted || client->closing) continue;
        state = state || client->hello.state;
        if (client->hello.images && std::find(images.begin(), images.end(), *client->hello.images) == images.end())
            images.push_back(*client->hello.images);
    }
    engine_.setSubscriptions(images, state);
}

void ControlServer::drop(Client& client, const QString& why, bool now) {
    if (client.closing) return;
    log(client, why);
    client.closing = true;
    // What waited behind a frame (its last ERROR among it) is written, the frame not.
    if (!now && !client.heldBefore.isEmpty()) client.socket->write(client.heldBefore);
    if (!now && !client.heldAfter.isEmpty()) client.socket->write(client.heldAfter);
    client.pendingFrame.clear();
    client.pendingState.clear();
    client.heldBefore.clear();
    client.heldAfter.clear();
    stopRobots(client);  // now, as its role is free from now on
    updateSubscriptions();
    // One that does not read would never take its last ERROR: its memory goes now.
    if (now || client.socket->bytesToWrite() > kGraceBytes) return client.socket->abort();
    client.socket->disconnectFromHost();  // after the unsent bytes (the error reply) are written
    // A client that never reads would keep the connection open: close hard
    // after a grace period.
    QTimer::singleShot(2000, client.socket, [socket = client.socket] { socket->abort(); });
}

void ControlServer::stopRobots(Client& client) {
    if (client.robotsStopped || !client.greeted || client.hello.role == ClientRole::Observer) return;
    client.robotsStopped = true;
    // Its robots stop, as real robots would when their radio link dies.
    const Team team = client.hello.role == ClientRole::Yellow ? Team::Yellow : Team::Blue;
    EngineRequest stop;
    stop.kind = EngineRequest::Kind::Voltages;
    stop.arrivalNs = monotonicNs();
    for (std::size_t i = 0; i < scene_.robots.size(); ++i)
        if (scene_.robots[i].team == team) stop.voltages.emplace_back(static_cast<int>(i), Voltages{});
    if (!stop.voltages.empty()) engine_.post(std::move(stop));
}

void ControlServer::forget(int id) {
    auto it = clients_.find(id);
    if (it == clients_.end()) return;
    Client& client = *it->second;
    log(client,
        client.framesDropped > 0
            ? QStringLiteral("disconnected (%1 frames dropped: it did not read fast enough)").arg(client.framesDropped)
            : QStringLiteral("disconnected"));
    stopRobots(client);
    client.socket->deleteLater();
    clients_.erase(it);
    updateSubscriptions();
}

}  // namespace vssim
