// One scene run in-process for Python (docs/python.md): the Match (the world,
// the referee, the built-in teams) with every input checked first, so that no
// call can leave the world in a state the engine would not reach itself.
// Plain C++, no pybind11: world_binding.cpp turns it into vssim.World.
//
// Errors are exceptions the binding maps onto Python's: std::invalid_argument
// -> ValueError, std::out_of_range -> IndexError, std::runtime_error ->
// RuntimeError. Every public method takes the world's lock, so that a
// Python thread calling in while another one steps (the GIL released)
// waits for the step instead of racing it.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vssim/game/match.h"
#include "vssim/scene.h"

namespace vssim {
class CameraRenderer;
}

namespace vssim::python {

// A consistent copy of everything observable, taken under the lock.
struct WorldSnapshot {
    std::int64_t step = 0;
    double time = 0.0;                // s
    std::vector<RobotState> robots;   // x, y, theta, v, omega
    std::vector<Voltages> voltages;   // applied (clamped), V
    std::vector<RobotOutputs> outputs;  // wheel speeds, currents
    std::vector<char> onField;
    BallState ball;
    GameState game;
};

class World {
public:
    explicit World(Scene scene, std::uint64_t seed = 0);
    ~World();

    const Scene& scene() const { return scene_; }  // constant
    int robotCount() const { return static_cast<int>(scene_.robots.size()); }
    double dt() const { return scene_.simulation.dt; }
    std::uint64_t seed() const { return seed_; }

    // Every robot's command at once (size robotCount()), or one robot's,
    // through the Match: a remote team's robots take them at once while the
    // game is on (kept for later while it is stopped); a built-in or idle
    // team's robots ignore them. Non-finite values are refused (nothing is
    // applied), naming the robot and the side.
    void setVoltages(const std::vector<Voltages>& e);
    void setVoltages(int robot, const Voltages& e);
    void setWheelSpeeds(const std::vector<WheelSpeeds>& w);
    void setWheelSpeeds(int robot, const WheelSpeeds& w);

    // Advances by `seconds` rounded up to whole steps of dt (at least one),
    // with the referee and the built-in teams at every game tick on the way.
    // Returns the new time (s). Throws std::runtime_error when the state
    // stops being finite (and on every later step until reset()).
    double step(double seconds);

    // Moves a body, checked like a client's placement (inside the field,
    // finite, speeds within the scene files' limits).
    void placeRobot(int robot, const RobotState& pose);
    void placeBall(const BallState& ball);

    // Back to the scene's start (a new Match with the same seed).
    void reset();
    // Frees the world; every later call but closed() throws std::runtime_error.
    void close();
    bool closed() const;

    WorldSnapshot snapshot() const;
    // The synthetic camera's image of the current state: BGR, 480 x 640, CV_8UC3.
    cv::Mat cameraImage() const;

private:
    const Scene scene_;
    const std::uint64_t seed_;
    std::unique_ptr<Match> match_;
    mutable std::unique_ptr<CameraRenderer> camera_;  // made at the first image
    std::string fault_;                               // why stepping stopped, or empty
    mutable std::mutex mutex_;

    void checkOpen() const;
    void checkRobot(int robot) const;
    void checkFinite(int robot, double right, double left, const char* what, const char* unit) const;
    void checkDrive(int robot, const DriveCommand& command) const;
    // One per robot (`what`: "voltages" or "wheel speeds", for errors), every one checked first.
    void driveAll(const std::vector<DriveCommand>& drives, const char* what);
    void drive(int robot, const DriveCommand& command);
};

}  // namespace vssim::python
