#include "app_session.h"

#include "realtime/monotonic_clock.h"

namespace vssim {

AppSession::AppSession(const Scene& scene, const ServerSettings& server, QObject* parent)
    : QObject(parent), scene_(scene), serverSettings_(server) {
    engine_ = std::make_unique<EngineThread>(scene_, EngineLoopSettings{});
    feed_ = VisionFeed::attach(*engine_);
    server_ = std::make_unique<ControlServer>(scene_, *engine_, server);
    connect(server_.get(), &ControlServer::logLine, this, &AppSession::logLine);
    listening_ = server_->listen(&listenError_);
    engine_->start();
}

AppSession::~AppSession() {
    firasim_.reset();
    server_.reset();
    engine_->requestStop();
    engine_->wait();
}

void AppSession::post(EngineRequest request) {
    request.arrivalNs = monotonicNs();
    engine_->post(std::move(request));
}

void AppSession::post(EngineRequest::Kind kind) {
    EngineRequest r;
    r.kind = kind;
    post(std::move(r));
}

void AppSession::placeRobot(int robot, const RobotState& pose) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::PlaceRobot;
    r.robot = robot;
    r.robotPose = pose;
    post(std::move(r));
}

void AppSession::placeBall(const BallState& ball) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::PlaceBall;
    r.ball = ball;
    post(std::move(r));
}

void AppSession::driveManually(int robot, const Voltages& volts) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::ManualVoltages;
    r.voltages = {{robot, volts}};
    post(std::move(r));
}

void AppSession::driveManually(int robot, const WheelSpeeds& speeds) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::ManualVoltages;
    r.wheelSpeeds = {{robot, speeds}};
    post(std::move(r));
}

void AppSession::releaseManual(int robot) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::ReleaseManual;
    r.robot = robot;
    post(std::move(r));
}

void AppSession::setSpeed(double speed) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::Speed;
    r.speed = speed;
    post(std::move(r));
}

void AppSession::applySettings(const SimulationSettings& settings) {
    scene_.simulation = settings;
    server_->setSimulationSettings(settings);
    EngineRequest r;
    r.kind = EngineRequest::Kind::SetSettings;
    r.scene = std::make_shared<const Scene>(scene_);
    post(std::move(r));
}

bool AppSession::startFirasim(QString* error) {
    if (firasim_) return true;
    FirasimSettings settings;
    settings.listenAddress = serverSettings_.address;
    auto server = std::make_unique<FirasimServer>(scene_, *engine_, settings, feed_);
    connect(server.get(), &FirasimServer::logLine, this, &AppSession::logLine);
    if (!server->listen(error)) return false;
    firasim_ = std::move(server);
    if (scene_.game.rules.left_team != Team::Blue)
        emit logLine(QStringLiteral("firasim: yellow defends x < 0 in this scene; FIRASim's software and "
                                    "VSSReferee's default expect blue there (Edit > Blue defends the left goal)"));
    return true;
}

void AppSession::stopFirasim() { firasim_.reset(); }

void AppSession::loadScene(const Scene& scene, bool paused) {
    scene_ = scene;
    server_->setScene(scene_);
    if (firasim_) {
        // Its robots and field are the old scene's: start again on the new one.
        firasim_.reset();
        QString error;
        if (!startFirasim(&error)) emit logLine(QStringLiteral("firasim: not restarted: %1").arg(error));
    }
    EngineRequest r;
    r.kind = EngineRequest::Kind::LoadScene;
    r.scene = std::make_shared<const Scene>(scene_);
    r.startPaused = paused;
    post(std::move(r));
}

}  // namespace vssim
