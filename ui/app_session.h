// What the desktop app runs: an engine thread and its TCP server, in real
// time, on a scene that can be replaced. The widgets read snapshots
// (latest()) and send requests (post()); none of them steps the engine.
#pragma once

#include <QObject>
#include <memory>

#include "firasim/firasim_server.h"
#include "firasim/vision_feed.h"
#include "net/control_server.h"
#include "realtime/engine_thread.h"
#include "realtime/snapshot.h"

namespace vssim {

class AppSession : public QObject {
    Q_OBJECT
public:
    // Starts the engine (real time, x1) on `scene` and tries to listen on
    // `server` (listening() says whether it could, listenError() why not).
    AppSession(const Scene& scene, const ServerSettings& server, QObject* parent = nullptr);
    ~AppSession() override;

    std::shared_ptr<const Snapshot> latest() const { return engine_->snapshots().latest(); }
    // The scene being run (the last one loaded).
    const Scene& scene() const { return scene_; }
    // Posts a request stamped now (arrivalNs) from the app itself.
    void post(EngineRequest request);
    // Convenience requests.
    void post(EngineRequest::Kind kind);
    void placeRobot(int robot, const RobotState& pose);
    void placeBall(const BallState& ball);
    void driveManually(int robot, const Voltages& volts);
    // The same as wheel-speed targets through the robot's speed loop (rad/s).
    void driveManually(int robot, const WheelSpeeds& speeds);
    void releaseManual(int robot);
    void setSpeed(double speed);  // x real time; 0: as fast as possible
    // New integrator, step, collision model or restitution: the bodies stay
    // where they are, the clock restarts at 0 (EngineRequest::SetSettings).
    void applySettings(const SimulationSettings& settings);
    // Replaces the scene (engine and server; TCP clients must reconnect);
    // `paused`: it waits at t = 0 (otherwise it runs if the engine was running).
    void loadScene(const Scene& scene, bool paused = false);

    bool listening() const { return listening_; }
    QString listenError() const { return listenError_; }
    quint16 port() const { return server_->port(); }
    const ControlServer& server() const { return *server_; }

    // FIRASim's interface (docs/firasim.md) beside the TCP server, on its
    // defaults (commands on the TCP server's address, port 20011; vision to
    // 224.0.0.1:10002 at every camera instant). Started and stopped at will;
    // a new scene restarts it on that scene.
    bool startFirasim(QString* error);
    void stopFirasim();
    const FirasimServer* firasim() const { return firasim_.get(); }

signals:
    void logLine(const QString& line);

private:
    Scene scene_;
    std::unique_ptr<EngineThread> engine_;
    std::unique_ptr<ControlServer> server_;
    ServerSettings serverSettings_;
    std::shared_ptr<VisionFeed> feed_;  // attached before the engine starts, fed while FIRASim runs
    std::unique_ptr<FirasimServer> firasim_;
    bool listening_ = false;
    QString listenError_;
};

}  // namespace vssim
