// A FIRASim client for the tests, built on our .proto files and QUdpSocket,
// and the server it talks to: an EngineThread and a FirasimServer in
// process, its vision sent by unicast to the client's socket on 127.0.0.1,
// with the ground truth of every camera instant beside it.
#pragma once

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QThread>
#include <QUdpSocket>

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "fira_packet.pb.h"
#include "firasim/firasim_server.h"
#include "io/scene_io.h"
#include "realtime/engine_thread.h"
#include "served_server.h"  // kickoff()

namespace vssim::test {

using fira_message::sim_to_ref::Environment;
using fira_message::sim_to_ref::Packet;

constexpr double kPi = 3.14159265358979323846;


inline QByteArray bytes(const Packet& p) {
    std::string s;
    p.SerializeToString(&s);
    return QByteArray(s.data(), static_cast<qsizetype>(s.size()));
}

inline void command(Packet& p, bool yellow, unsigned id, double right, double left) {
    auto* c = p.mutable_cmd()->add_robot_commands();
    c->set_yellowteam(yellow);
    c->set_id(id);
    c->set_wheel_right(right);
    c->set_wheel_left(left);
}

inline void replaceRobot(Packet& p, bool yellow, unsigned id, double x, double y, double degrees, bool on = true) {
    auto* r = p.mutable_replace()->add_robots();
    r->set_yellowteam(yellow);
    r->set_turnon(on);
    r->mutable_position()->set_robot_id(id);
    r->mutable_position()->set_x(x);
    r->mutable_position()->set_y(y);
    r->mutable_position()->set_orientation(degrees);
}

inline void replaceBall(Packet& p, double x, double y, double vx, double vy) {
    auto* b = p.mutable_replace()->mutable_ball();
    b->set_x(x);
    b->set_y(y);
    b->set_vx(vx);
    b->set_vy(vy);
}

inline const fira_message::Robot* findRobot(const Environment& env, bool yellow, unsigned id) {
    const auto& robots = yellow ? env.frame().robots_yellow() : env.frame().robots_blue();
    for (const auto& r : robots)
        if (r.robot_id() == id) return &r;
    return nullptr;
}

// An engine, a FirasimServer on a free command port sending its vision to
// our socket, a client socket, and the ground truth at every camera instant.
struct Fira {
    std::unique_ptr<EngineThread> engine;
    std::unique_ptr<FirasimServer> server;
    QUdpSocket vision;  // receives the Environments
    QUdpSocket client;  // sends Packets
    std::mutex mutex;
    std::map<std::int64_t, WorldState> truth;  // by step
    std::int64_t lastStep = -1;
    QStringList log;

    Fira(const Scene& scene, bool sync, FirasimSettings settings = {}, bool bindVision = true) {
        EngineLoopSettings loop;
        loop.mode = sync ? RunMode::Lockstep : RunMode::Realtime;
        loop.framePeriod = 1.0 / 60.0;
        if (bindVision) {
            if (!vision.bind(QHostAddress::LocalHost, 0)) qFatal("cannot bind the vision socket");
            settings.visionAddress = QHostAddress::LocalHost;
            settings.visionPort = vision.localPort();
        }
        settings.commandPort = 0;
        settings.sync = sync;
        engine = std::make_unique<EngineThread>(scene, loop);
        engine->addInstantObserver([this](const InstantRecord& r) {
            if (!r.cameraInstant) return;
            std::lock_guard lock(mutex);
            truth[r.step] = r.world;
        });
        server = std::make_unique<FirasimServer>(scene, *engine, settings);
        QObject::connect(server.get(), &FirasimServer::logLine, [this](const QString& line) { log << line; });
        QString error;
        if (!server->listen(&error)) qFatal("%s", qPrintable(error));
        engine->start();
    }
    ~Fira() {
        server.reset();
        engine->requestStop();
        engine->wait();
    }
    void send(const QByteArray& data) { client.writeDatagram(data, QHostAddress::LocalHost, server->port()); }
    void send(const Packet& p) { send(bytes(p)); }
    // The next Environment (its bytes in `raw`), within timeoutMs.
    std::optional<Environment> next(int timeoutMs = 3000, QByteArray* raw = nullptr) {
        QElapsedTimer t;
        t.start();
        while (t.elapsed() < timeoutMs) {
            if (vision.hasPendingDatagrams()) {
                QByteArray data(static_cast<qsizetype>(std::max<qint64>(vision.pendingDatagramSize(), 1)), 0);
                data.resize(static_cast<qsizetype>(vision.readDatagram(data.data(), data.size())));
                Environment env;
                if (!env.ParseFromArray(data.constData(), static_cast<int>(data.size())))
                    qFatal("the vision is not an Environment");
                lastStep = env.step();
                if (raw) *raw = data;
                return env;
            }
            QCoreApplication::processEvents(QEventLoop::AllEvents, 2);
            QThread::usleep(200);
        }
        return std::nullopt;
    }
    // Sync mode: sends `p` (with the cmd field set) and returns the
    // Environment at the end of the step it makes.
    Environment step(Packet p = {}, QByteArray* raw = nullptr) {
        p.mutable_cmd();
        const std::int64_t before = lastStep;
        send(p);
        for (;;) {
            std::optional<Environment> env = next(3000, raw);
            if (!env) qFatal("no Environment after a step");
            if (static_cast<std::int64_t>(env->step()) > before) return *env;
        }
    }
    // Realtime: the first Environment at least `ms` from now.
    std::optional<Environment> after(int ms) {
        QElapsedTimer t;
        t.start();
        std::optional<Environment> env;
        while (t.elapsed() < ms || !env) {
            env = next(2000);
            if (!env) return env;
        }
        return env;
    }
    WorldState truthAt(std::int64_t step) {
        std::lock_guard lock(mutex);
        auto it = truth.find(step);
        if (it == truth.end()) qFatal("no ground truth at step %lld", static_cast<long long>(step));
        return it->second;
    }
};

}  // namespace vssim::test
