// n independent worlds of one scene, stepped together on a pool of threads
// (batch/README.md). Each world is a Match (game/match.h) with its own
// inputs; step() advances every world by the same whole number of steps, one
// world per task, so each world's results are bit-identical to a lone Match
// given the same inputs and advanced by the same steps, whatever the thread
// count. The worlds share nothing mutable.
//
// Arrays are flat and row-major: world-major, then robot, then the fields
// (the shapes a Python binding hands over as (worlds, robots, k) arrays).
// A BatchWorld is not itself thread-safe: call it from one thread at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vssim/batch/thread_pool.h"
#include "vssim/game/match.h"

namespace vssim {

class BatchWorld {
public:
    // `worlds` >= 1 copies of `scene`; `threads` workers (0: all cores; never
    // more than there are worlds). World i plays Match(scene, seed == 0 ? 0 :
    // seed + i) (the seed moves the referee's placements; match.h).
    // Throws std::invalid_argument for worlds < 1 or threads < 0.
    BatchWorld(const Scene& scene, int worlds, int threads = 0, std::uint64_t seed = 0);
    ~BatchWorld();
    BatchWorld(const BatchWorld&) = delete;
    BatchWorld& operator=(const BatchWorld&) = delete;

    int size() const { return static_cast<int>(matches_.size()); }
    int robots() const { return static_cast<int>(scene_.robots.size()); }
    int threads() const { return pool_.size(); }
    const Scene& scene() const { return scene_; }
    // The Match seed of world i.
    std::uint64_t seedOf(int world) const;

    // One robot's command, as Match::setVoltages / setWheelSpeeds: applied now
    // to a remote team's robot while the game is on, remembered otherwise,
    // ignored for a built-in or idle team's robot. Throws std::out_of_range
    // for a world or robot out of range, std::invalid_argument for a NaN or an
    // infinity (naming the world, robot and side).
    void setVoltages(int world, int robot, const Voltages& e);
    void setWheelSpeeds(int world, int robot, const WheelSpeeds& w);
    // Every robot of every world at once from worlds * robots * 2 doubles
    // (right, left), row-major. The whole array is checked (finite numbers only) before
    // any world changes. Throws std::invalid_argument for a null pointer
    // (unless there are no robots) or a number that is not finite.
    void setVoltagesAll(const double* rightLeft);
    void setWheelSpeedsAll(const double* rightLeft);

    // The whole number of steps of dt that step(seconds) advances every world
    // by: seconds rounded up to steps (Simulation::stepIndexAtOrAfter, so
    // 0.03 s at dt = 1 ms is 30 steps), at least 1 -- as a lone World's step
    // does, so that a world of the batch and a lone World given the same
    // calls stay on the same steps. (Match::advanceTo runs the referee and
    // the built-in teams at every game tick on the way, wherever a call ends.)
    // Throws std::invalid_argument for NaN, infinite, zero or negative
    // seconds, or more steps than an int64 holds.
    std::int64_t stepsFor(double seconds) const;
    // Advances every world by stepsFor(seconds) steps from where it is, the
    // worlds in parallel; returns the steps. A world whose bodies went
    // non-finite stops where Match::advanceTo stops it (see finite()).
    std::int64_t step(double seconds);

    // Moves a body of world `world` at once, as Match::placeRobot /
    // placeBall (a client's placement; an overlap is resolved by the next
    // step's contacts). Whether it lies inside the field is the caller's
    // check (the Python binding makes it). Throws std::out_of_range for a
    // world or robot out of range, std::invalid_argument for a value that is
    // not finite.
    void placeRobot(int world, int robot, const RobotState& pose);
    void placeBall(int world, const BallState& ball);

    // World `world` afresh: a new Match of the scene with its seed (its
    // inputs forgotten, the clock at 0). Throws std::out_of_range.
    void reset(int world);
    void resetAll();  // in parallel

    // World i's Match, read-only. Throws std::out_of_range.
    const Match& match(int world) const;
    // Whether every body of world i is finite (a world that blew up is
    // frozen by Match::advanceTo; reset it).
    bool finite(int world) const;

    // The state, into caller-owned arrays (each throws std::invalid_argument
    // for a null pointer unless the array would be empty):
    // worlds * robots * 5: x, y (m), theta (rad), v (m/s), omega (rad/s);
    void copyRobots(double* out) const;
    // worlds * robots * 2: wheel speeds, right, left (rad/s);
    void copyWheelSpeeds(double* out) const;
    // worlds * 4: ball x, y (m), vx, vy (m/s);
    void copyBalls(double* out) const;
    // worlds * 2: goals of yellow, blue;
    void copyScores(int* out) const;
    // worlds: the step index (simulated time = step * dt).
    void copySteps(std::int64_t* out) const;

private:
    // One robot's command (right, left: its two numbers, checked); `what` names the call in errors.
    void setOne(int world, int robot, const DriveCommand& command, double right, double left, const char* what);
    // Both of the above: rightLeft as voltages or as wheel speeds; `what` names the call in errors.
    void setAll(const double* rightLeft, bool wheelSpeeds, const char* what);
    Scene scene_;
    std::uint64_t seed_;
    std::vector<std::unique_ptr<Match>> matches_;
    ThreadPool pool_;
    // The exact integrator's step tables, one cache per pool thread, lent to
    // each world for its step (Simulation::lendTableCache): every world of the
    // batch has the same robots and step lengths, so a few tables serve them
    // all and stay in the processor's cache, instead of a copy per world.
    std::vector<ExactTableCache> tableCaches_;

    Match& at(int world, const char* what);
    const Match& at(int world, const char* what) const;
    void checkRobot(int robot, const char* what) const;
};

}  // namespace vssim
