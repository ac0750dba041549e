// Benchmark 5: `vssim serve` in real time, seen from its clients, as a
// team's software would use it: a `vssim serve` process with the 3-vs-3
// kick-off, a team client sending new voltages to its three robots every
// 7 ms (not in step with the camera), and observers. Three scenarios of a
// minute each (--quick: 3 s): "typical", one observer taking PNG patches;
// "six subscriptions", one observer per image subscription (patches and
// full frames; raw, PNG, JPEG 90), all encoded every frame; "slow reader",
// one observer taking full PNG frames that stops reading for 1.5 s (a slow
// vision step), reads for 60 ms, and again (the server must drop its old
// frames and hand it the present: the image age at hand-over). It records when
// each frame arrives; at the end it asks the server for its own measurements
// (CONTROL stats): command latency, image period, render and encode time,
// bytes per frame.
#include <QCoreApplication>
#include <QElapsedTimer>
#include <QJsonArray>
#include <QJsonDocument>
#include <QProcess>
#include <QRandomGenerator>
#include <iomanip>
#include <memory>
#include <stdexcept>

#include "benchmarks.h"
#include "net/protocol_client.h"
#include "realtime/monotonic_clock.h"
#include "realtime/sample_stats.h"

namespace vssim::bench {

namespace {

struct Observer {
    QString name;  // "patches/png", ...
    std::unique_ptr<ProtocolClient> client;
    SampleStats periodMs;
    std::int64_t lastNs = -1;
    std::int64_t frames = 0, lastFrame = -1, gaps = 0;
    bool slow = false;  // reads 60 ms of every 1,560 ms
    bool reading = true;
};

enum class Observers { Typical, AllSubscriptions, SlowReader };

// The kick-off served with the yellow team driven over TCP (the bench's
// team client), the blue one idle and no referee: the engine, the camera and
// the server, nothing of the game.
QStringList serveArguments(const Options& options, const QStringList& extra) {
    return QStringList{"serve",  QString::fromStdString(options.sceneFile),
                       "--port", "0",
                       "--yellow", "tcp",
                       "--blue", "idle",
                       "--referee", "off"} +
           extra;
}

void row(std::ostream& out, const char* scenario, const QString& source, const QString& metric,
         const QString& subscription, const QJsonObject& s) {
    out << '"' << scenario << "\"," << source.toStdString() << ',' << metric.toStdString() << ','
        << subscription.toStdString() << ',' << s["count"].toDouble() << ',' << s["median"].toDouble() << ','
        << s["p99"].toDouble() << ',' << s["max"].toDouble() << ',' << s["mean"].toDouble() << ','
        << s["stddev"].toDouble() << '\n';
}

void runScenario(const Options& options, const char* scenario, Observers which, std::ostream& out,
                 std::ostream& log) {
    const double duration = options.quick ? 3.0 : 60.0;  // wall seconds
    QProcess server;
    server.setProcessChannelMode(QProcess::ForwardedErrorChannel);
    server.start(QStringLiteral(VSSIM_BINARY), serveArguments(options, {"--quit-after", QString::number(duration + 30)}));
    if (!server.waitForStarted(5000) || !server.waitForReadyRead(10000))
        throw std::runtime_error("vssim serve did not start");
    const QString line = QString::fromUtf8(server.readLine()).trimmed();  // "listening on 127.0.0.1:PORT"
    const quint16 port = static_cast<quint16>(line.section(':', -1).toUInt());
    if (port == 0) throw std::runtime_error("unexpected first line from vssim serve: " + line.toStdString());

    std::vector<Observer> observers;
    for (const char* images : {"patches", "full"}) {
        for (const char* encoding : {"raw", "png", "jpeg"}) {
            const bool wanted = which == Observers::AllSubscriptions ||
                                (which == Observers::Typical && QString(images) == "patches" &&
                                 QString(encoding) == "png") ||
                                (which == Observers::SlowReader && QString(images) == "full" &&
                                 QString(encoding) == "png");
            if (!wanted) continue;
            Observer o;
            o.slow = which == Observers::SlowReader;
            o.name = QStringLiteral("%1/%2%3").arg(images, encoding, QString(encoding) == "jpeg" ? "90" : "");
            o.client = std::make_unique<ProtocolClient>();
            if (!o.client->connectTo(port) || !o.client->hello(QJsonObject{{"protocol", 1},
                                                                           {"role", "observer"},
                                                                           {"images", images},
                                                                           {"encoding", encoding},
                                                                           {"jpeg_quality", 90}}))
                throw std::runtime_error("observer " + o.name.toStdString() + " could not connect");
            // A slow reader's receive buffer is fixed at 64 kB: Linux would
            // otherwise grow it with use until it held a whole pause's frames,
            // and the server would never have to drop any.
            if (o.slow) o.client->socket().setSocketOption(QAbstractSocket::ReceiveBufferSizeSocketOption, 64 << 10);
            observers.push_back(std::move(o));
        }
    }
    ProtocolClient team;
    const std::optional<QJsonObject> welcome =
        team.connectTo(port) ? team.hello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"images", "none"}})
                             : std::nullopt;
    if (!welcome) throw std::runtime_error("the team client could not connect");
    std::vector<int> robots;
    for (const QJsonValue& r : (*welcome)["robots"].toArray())
        if (r["team"].toString() == "yellow") robots.push_back(r["index"].toInt());

    QRandomGenerator random(7);
    QElapsedTimer wall;
    wall.start();
    qint64 nextCommandMs = 0;
    std::int64_t commands = 0;
    while (wall.elapsed() < duration * 1000) {
        if (wall.elapsed() >= nextCommandMs) {
            std::vector<std::pair<int, Voltages>> entries;
            for (int r : robots) entries.push_back({r, {random.bounded(14.8) - 7.4, random.bounded(14.8) - 7.4}});
            team.send(protocol::MessageType::Voltages, protocol::encodeVoltages(entries));
            ++commands;
            nextCommandMs += 7;
        }
        QCoreApplication::processEvents(QEventLoop::AllEvents, 2);
        for (Observer& o : observers) {
            if (o.slow) {
                const bool reading = wall.elapsed() % 1560 >= 1500;
                if (reading != o.reading) {
                    o.client->setReading(reading);
                    o.reading = reading;
                    o.lastNs = -1;  // the pause is not a frame period
                }
            }
            while (auto r = o.client->poll()) {
                if (r->message.type != static_cast<std::uint8_t>(protocol::MessageType::Frame)) continue;
                protocol::FrameHeader header;
                std::vector<protocol::FramePatch> patches;
                QString error;
                if (!protocol::decodeFrame(r->message.payload, &header, &patches, &error))
                    throw std::runtime_error(error.toStdString());
                if (header.kind == protocol::FrameKind::Background) continue;
                if (o.lastNs >= 0) o.periodMs.add(1e-6 * static_cast<double>(r->arrivalNs - o.lastNs));
                if (o.lastFrame >= 0 && header.frame != o.lastFrame + 1) ++o.gaps;
                o.lastNs = r->arrivalNs;
                o.lastFrame = header.frame;
                ++o.frames;
            }
        }
    }
    team.sendJson(protocol::MessageType::Control, QJsonObject{{"command", "stats"}});
    const auto reply = team.nextOf(protocol::MessageType::Reply, 10000);
    if (!reply) throw std::runtime_error("no reply to CONTROL stats");
    const QJsonObject stats = jsonPayload(reply->message)["stats"].toObject();
    server.terminate();
    server.waitForFinished(5000);

    row(out, scenario, "server", "command_latency_ms", "", stats["command_latency_ms"].toObject());
    row(out, scenario, "server", "command_delay_ms", "", stats["command_delay_ms"].toObject());
    row(out, scenario, "server", "frame_period_ms", "", stats["frame_period_ms"].toObject());
    row(out, scenario, "server", "image_age_ms", "", stats["image_age_ms"].toObject());
    row(out, scenario, "server", "render_ms", "", stats["render_ms"].toObject());
    row(out, scenario, "server", "patch_area_percent", "", stats["patch_area_percent"].toObject());
    const QJsonObject encode = stats["encode_ms"].toObject(), bytes = stats["frame_bytes"].toObject();
    for (auto it = encode.begin(); it != encode.end(); ++it)
        row(out, scenario, "server", "encode_ms", it.key(), it.value().toObject());
    for (auto it = bytes.begin(); it != bytes.end(); ++it)
        row(out, scenario, "server", "frame_bytes", it.key(), it.value().toObject());
    for (const Observer& o : observers)
        row(out, scenario, "client", "frame_period_ms", o.name, toJson(o.periodMs.summary()));

    const QJsonObject latency = stats["command_latency_ms"].toObject(), period = stats["frame_period_ms"].toObject(),
                      age = stats["image_age_ms"].toObject();
    log << "  " << scenario << ": " << duration << " s, " << commands << " commands, late "
        << stats["late_commands"].toInt() << "\n"
        << "  command latency (arrival -> applied): median " << latency["median"].toDouble() << " ms, p99 "
        << latency["p99"].toDouble() << " ms, max " << latency["max"].toDouble() << " ms\n"
        << "  image period at the engine: median " << period["median"].toDouble() << " ms, stddev "
        << period["stddev"].toDouble() << " ms, max " << period["max"].toDouble() << " ms\n"
        << "  render median " << stats["render_ms"].toObject()["median"].toDouble() << " ms; patches cover "
        << stats["patch_area_percent"].toObject()["median"].toDouble() << " % of the image (median)\n"
        << "  image age, camera instant -> handed to a socket: median " << age["median"].toDouble() << " ms, p99 "
        << age["p99"].toDouble() << " ms, max " << age["max"].toDouble() << " ms\n";
    for (const Observer& o : observers) {
        const SampleSummary s = o.periodMs.summary();
        const QJsonObject b = bytes[o.name].toObject(), e = encode[o.name].toObject();
        log << "  " << std::setw(14) << o.name.toStdString() << ": " << std::setw(8) << b["median"].toDouble()
            << " bytes/frame, encode " << std::setw(7) << e["median"].toDouble() << " ms; received " << o.frames
            << " frames, " << o.gaps << " gaps, period median " << s.median << " ms, stddev " << s.stddev << " ms, max "
            << s.max << " ms\n";
    }
}

}  // namespace

// Lockstep: one team client taking PNG patches and the ground truth, sending
// voltages and a 30 ms step, waiting for the REPLY, again and again: how
// fast a learning or testing loop can go, images included.
void runLockstep(const Options& options, const char* images, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 2.0 : 20.0;  // wall seconds
    QProcess server;
    server.setProcessChannelMode(QProcess::ForwardedErrorChannel);
    server.start(QStringLiteral(VSSIM_BINARY),
                 serveArguments(options, {"--lockstep", "--quit-after", QString::number(duration + 30)}));
    if (!server.waitForStarted(5000) || !server.waitForReadyRead(10000))
        throw std::runtime_error("vssim serve did not start");
    const quint16 port = static_cast<quint16>(QString::fromUtf8(server.readLine()).trimmed().section(':', -1).toUInt());
    ProtocolClient team;
    const std::optional<QJsonObject> welcome =
        team.connectTo(port)
            ? team.hello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"images", images}, {"state", true}})
            : std::nullopt;
    const bool withImages = QString(images) != "none";
    if (!welcome || (withImages && !team.nextOf(protocol::MessageType::Frame)))
        throw std::runtime_error("lockstep client could not connect");
    QRandomGenerator random(11);
    SampleStats roundTripMs;
    QElapsedTimer wall;
    wall.start();
    std::int64_t steps = 0, frames = 0;
    double simulated = 0;
    while (wall.elapsed() < duration * 1000) {
        std::vector<std::pair<int, Voltages>> entries;
        for (int r = 0; r < 3; ++r) entries.push_back({r, {random.bounded(14.8) - 7.4, random.bounded(14.8) - 7.4}});
        const std::int64_t startNs = monotonicNs();
        team.send(protocol::MessageType::Voltages, protocol::encodeVoltages(entries));
        team.sendJson(protocol::MessageType::Control, QJsonObject{{"command", "step"}, {"duration", 0.03}});
        for (;;) {
            const auto r = team.next(10000);
            if (!r) throw std::runtime_error("lockstep: no reply");
            if (r->message.type == static_cast<std::uint8_t>(protocol::MessageType::Frame)) ++frames;
            if (r->message.type == static_cast<std::uint8_t>(protocol::MessageType::Reply)) {
                simulated = jsonPayload(r->message)["time"].toDouble();
                break;
            }
        }
        roundTripMs.add(1e-6 * static_cast<double>(monotonicNs() - startNs));
        ++steps;
    }
    const double seconds = 1e-3 * static_cast<double>(wall.elapsed());
    server.terminate();
    server.waitForFinished(5000);
    const QString subscription = withImages ? QStringLiteral("patches/png") : QStringLiteral("none");
    row(out, "lockstep", "client", "step_round_trip_ms", subscription, toJson(roundTripMs.summary()));
    out << "\"lockstep\",client,realtime_factor," << subscription.toStdString() << ",1," << simulated / seconds
        << ",,,,\n";
    log << "  lockstep: " << steps << " steps of 30 ms with voltages, " << (withImages ? "PNG patches" : "no images")
        << " and the ground truth in " << seconds << " s: " << steps / seconds << " steps/s, " << simulated / seconds
        << "x real time; round trip median " << roundTripMs.summary().median << " ms (" << frames << " frames)\n";
}

int serveLatency(const Options& options, std::ostream& out, std::ostream& log) {
    out << "scenario,source,metric,subscription,count,median,p99,max,mean,stddev\n" << std::setprecision(6);
    runScenario(options, "typical", Observers::Typical, out, log);
    runScenario(options, "six subscriptions", Observers::AllSubscriptions, out, log);
    runScenario(options, "slow reader", Observers::SlowReader, out, log);
    runLockstep(options, "patches", out, log);
    runLockstep(options, "none", out, log);
    return 0;
}

}  // namespace vssim::bench
