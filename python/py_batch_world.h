// n worlds of one scene stepped together for Python (docs/python.md): the C++
// BatchWorld (batch/) behind one lock. Plain C++, no pybind11:
// batch_binding.cpp turns it into vssim.BatchWorld.
//
// The C++ BatchWorld is for one thread at a time; Python releases the GIL
// while step() and resetAll() run, so two Python threads could otherwise be
// inside it at once (a reset freeing a world a step is advancing). Every
// method touching the worlds takes the lock, so that a Python thread calling
// in while another one steps waits for the step instead of racing it, as
// vssim.World does (py_world.h).
#pragma once

#include <cstdint>
#include <mutex>

#include "vssim/batch/batch_world.h"

namespace vssim::python {

class BatchWorld {
public:
    // As vssim::BatchWorld's constructor (and its exceptions).
    BatchWorld(const Scene& scene, int worlds, int threads, std::uint64_t seed)
        : batch_(scene, worlds, threads, seed) {}

    // Constant from construction on: no lock.
    int size() const { return batch_.size(); }
    int robots() const { return batch_.robots(); }
    int threads() const { return batch_.threads(); }
    const Scene& scene() const { return batch_.scene(); }

    double dt() const;  // s

    // As vssim::BatchWorld's (batch_world.h), each under the lock.
    void setVoltagesAll(const double* rightLeft);
    void setWheelSpeedsAll(const double* rightLeft);
    std::int64_t step(double seconds);
    void placeRobot(int world, int robot, const RobotState& pose);
    void placeBall(int world, const BallState& ball);
    void reset(int world);
    void resetAll();

    // Copies of the state, all worlds in one consistent read (batch_world.h
    // for the layouts).
    void copyRobots(double* out) const;
    void copyWheelSpeeds(double* out) const;
    void copyBalls(double* out) const;
    void copyScores(int* out) const;
    void copySteps(std::int64_t* out) const;
    // size() times: each world's simulated time, s.
    void copyTimes(double* out) const;

private:
    vssim::BatchWorld batch_;
    mutable std::mutex mutex_;
};

}  // namespace vssim::python
