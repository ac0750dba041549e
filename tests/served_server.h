// For the server suites: the kick-off as plain physics, and an engine thread
// with its TCP server on a free port, torn down in order.
#pragma once

#include <QElapsedTimer>
#include <QStringList>
#include <QThread>
#include <memory>
#include <optional>

#include "io/scene_io.h"
#include "net/control_server.h"
#include "realtime/engine_thread.h"

namespace vssim::test {

// The kick-off's bodies as plain physics: no referee, both teams remote, no
// scene commands (only the clients drive).
inline Scene kickoff() {
    QString error;
    std::optional<Scene> scene = loadSceneFile(":/scenes/kickoff_3v3.json", &error);
    if (!scene) qFatal("%s", qPrintable(error));
    scene->commands.clear();
    scene->game = GameSettings{};
    return *scene;
}

struct Served {
    std::unique_ptr<EngineThread> engine;
    std::unique_ptr<ControlServer> server;
    QStringList log;  // the server's log lines
    Served(const Scene& scene, RunMode mode, int helloTimeoutMs = 5000)
        : Served(scene, mode, withHelloTimeout(helloTimeoutMs)) {}
    Served(const Scene& scene, RunMode mode, ServerSettings settings) {
        EngineLoopSettings loop;
        loop.mode = mode;
        settings.port = 0;
        engine = std::make_unique<EngineThread>(scene, loop);
        server = std::make_unique<ControlServer>(scene, *engine, settings);
        QObject::connect(server.get(), &ControlServer::logLine, [this](const QString& line) { log << line; });
        QString error;
        if (!server->listen(&error)) qFatal("%s", qPrintable(error));
        engine->start();
        // Clients join after instant 0, so that none sees it (the tests count frames).
        QElapsedTimer t;
        t.start();
        while (!engine->started() && t.elapsed() < 5000) QThread::msleep(1);
    }
    ~Served() {
        server.reset();
        engine->requestStop();
        engine->wait();
    }
    Served(const Served&) = delete;
    Served& operator=(const Served&) = delete;
    quint16 port() const { return server->port(); }
    static ServerSettings withHelloTimeout(int ms) {
        ServerSettings settings;
        settings.helloTimeoutMs = ms;
        return settings;
    }
};

}  // namespace vssim::test
