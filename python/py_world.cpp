#include "py_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "vssim/camera/camera_renderer.h"
#include "placement_check.h"
#include "realtime/simulation_fault.h"

namespace vssim::python {

namespace {

std::string number(double x) {
    std::ostringstream out;
    out.precision(17);
    out << x;
    return out.str();
}

// The most steps one call may take: beyond 2^53 step indices stop being exact doubles.
constexpr double kMaxStepsPerCall = 9007199254740992.0;

}  // namespace

World::World(Scene scene, std::uint64_t seed)
    : scene_(std::move(scene)), seed_(seed), match_(std::make_unique<Match>(scene_, seed)) {}

World::~World() = default;

void World::checkOpen() const {
    if (!match_) throw std::runtime_error("this World is closed");
}

void World::checkRobot(int robot) const {
    if (robot < 0 || robot >= robotCount())
        throw std::out_of_range("robot " + std::to_string(robot) + " does not exist: the scene has " +
                                std::to_string(robotCount()) + " robots" +
                                (robotCount() > 0 ? " (0-" + std::to_string(robotCount() - 1) + ")" : std::string()));
}

void World::checkFinite(int robot, double right, double left, const char* what, const char* unit) const {
    for (const auto& [side, value] : {std::pair<const char*, double>{"right", right}, {"left", left}})
        if (!std::isfinite(value))
            throw std::invalid_argument("robot " + std::to_string(robot) + " (" + scene_.robots[robot].name +
                                        "): the " + side + " " + what + " is " + number(value) + "; " + what +
                                        "s must be finite numbers, " + unit);
}

void World::setVoltages(const std::vector<Voltages>& e) {
    std::vector<DriveCommand> drives;
    for (const Voltages& v : e) drives.push_back(DriveCommand::ofVoltages(v));
    driveAll(drives, "voltages");
}

void World::setVoltages(int robot, const Voltages& e) { drive(robot, DriveCommand::ofVoltages(e)); }

void World::setWheelSpeeds(const std::vector<WheelSpeeds>& w) {
    std::vector<DriveCommand> drives;
    for (const WheelSpeeds& s : w) drives.push_back(DriveCommand::ofWheelSpeeds(s));
    driveAll(drives, "wheel speeds");
}

void World::setWheelSpeeds(int robot, const WheelSpeeds& w) { drive(robot, DriveCommand::ofWheelSpeeds(w)); }

void World::checkDrive(int robot, const DriveCommand& d) const {
    if (d.wheelSpeeds)
        checkFinite(robot, d.speeds.right, d.speeds.left, "wheel speed", "rad/s");
    else
        checkFinite(robot, d.voltages.right, d.voltages.left, "voltage", "V");
}

void World::driveAll(const std::vector<DriveCommand>& drives, const char* what) {
    std::lock_guard lock(mutex_);
    checkOpen();
    if (static_cast<int>(drives.size()) != robotCount())
        throw std::invalid_argument(std::string("expected ") + what + " for " + std::to_string(robotCount()) +
                                    " robots, got " + std::to_string(drives.size()));
    for (int i = 0; i < robotCount(); ++i) checkDrive(i, drives[i]);  // all checked before any applies
    for (int i = 0; i < robotCount(); ++i) match_->drive(i, drives[i]);
}

void World::drive(int robot, const DriveCommand& command) {
    std::lock_guard lock(mutex_);
    checkOpen();
    checkRobot(robot);
    checkDrive(robot, command);
    match_->drive(robot, command);
}

double World::step(double seconds) {
    std::lock_guard lock(mutex_);
    checkOpen();
    if (!std::isfinite(seconds) || seconds <= 0.0)
        throw std::invalid_argument("seconds must be a positive finite number, got " + number(seconds));
    if (seconds / dt() > kMaxStepsPerCall)
        throw std::invalid_argument("seconds = " + number(seconds) + " is too many steps of dt = " + number(dt()) +
                                    " s for one call");
    if (!fault_.empty()) throw std::runtime_error(fault_ + " (reset() starts again)");
    const std::int64_t steps = std::max<std::int64_t>(1, Simulation::stepIndexAtOrAfter(seconds, dt()));
    match_->advanceTo(match_->simulation().state().step + steps);
    if (const auto fault = findSimulationFault(match_->simulation())) {
        fault_ = "the simulation stopped: " + fault->message().toStdString();
        throw std::runtime_error(fault_);
    }
    return match_->simulation().state().time;
}

void World::placeRobot(int robot, const RobotState& p) {
    std::lock_guard lock(mutex_);
    checkOpen();
    checkRobot(robot);
    checkRobotPlacement(scene_, robot, p, "robot " + std::to_string(robot));
    match_->placeRobot(robot, p);
}

void World::placeBall(const BallState& b) {
    std::lock_guard lock(mutex_);
    checkOpen();
    checkBallPlacement(scene_, b, "the ball");
    match_->placeBall(b);
}

void World::reset() {
    std::lock_guard lock(mutex_);
    checkOpen();
    match_ = std::make_unique<Match>(scene_, seed_);
    fault_.clear();
}

void World::close() {
    std::lock_guard lock(mutex_);
    match_.reset();
    camera_.reset();
}

bool World::closed() const {
    std::lock_guard lock(mutex_);
    return !match_;
}

WorldSnapshot World::snapshot() const {
    std::lock_guard lock(mutex_);
    checkOpen();
    const Simulation& sim = match_->simulation();
    const WorldState& s = sim.state();
    WorldSnapshot out;
    out.step = s.step;
    out.time = s.time;
    out.robots = s.robots;
    out.voltages = s.voltages;
    out.onField.resize(s.robots.size());
    for (int i = 0; i < robotCount(); ++i) {
        out.outputs.push_back(sim.robotOutputs(i));
        out.onField[i] = !s.offField[i];
    }
    out.ball = s.ball;
    out.game = match_->game();
    return out;
}

cv::Mat World::cameraImage() const {
    std::lock_guard lock(mutex_);
    checkOpen();
    if (!camera_) camera_ = std::make_unique<CameraRenderer>(scene_);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    // The frame number that seeds a noisy camera's sensor noise: the state's
    // step, so that the same state gives the same bytes and each step its own noise.
    const WorldState& state = match_->simulation().state();
    camera_->render(state, frame, patches, static_cast<std::uint64_t>(std::max<std::int64_t>(0, state.step)));
    return frame;
}

}  // namespace vssim::python
