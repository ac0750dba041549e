#include "py_batch_world.h"

namespace vssim::python {

double BatchWorld::dt() const {
    std::lock_guard lock(mutex_);
    return batch_.match(0).simulation().dt();
}

void BatchWorld::setVoltagesAll(const double* rightLeft) {
    std::lock_guard lock(mutex_);
    batch_.setVoltagesAll(rightLeft);
}

void BatchWorld::setWheelSpeedsAll(const double* rightLeft) {
    std::lock_guard lock(mutex_);
    batch_.setWheelSpeedsAll(rightLeft);
}

std::int64_t BatchWorld::step(double seconds) {
    std::lock_guard lock(mutex_);
    return batch_.step(seconds);
}

void BatchWorld::placeRobot(int world, int robot, const RobotState& pose) {
    std::lock_guard lock(mutex_);
    batch_.placeRobot(world, robot, pose);
}

void BatchWorld::placeBall(int world, const BallState& ball) {
    std::lock_guard lock(mutex_);
    batch_.placeBall(world, ball);
}

void BatchWorld::reset(int world) {
    std::lock_guard lock(mutex_);
    batch_.reset(world);
}

void BatchWorld::resetAll() {
    std::lock_guard lock(mutex_);
    batch_.resetAll();
}

void BatchWorld::copyRobots(double* out) const {
    std::lock_guard lock(mutex_);
    batch_.copyRobots(out);
}

void BatchWorld::copyWheelSpeeds(double* out) const {
    std::lock_guard lock(mutex_);
    batch_.copyWheelSpeeds(out);
}

void BatchWorld::copyBalls(double* out) const {
    std::lock_guard lock(mutex_);
    batch_.copyBalls(out);
}

void BatchWorld::copyScores(int* out) const {
    std::lock_guard lock(mutex_);
    batch_.copyScores(out);
}

void BatchWorld::copySteps(std::int64_t* out) const {
    std::lock_guard lock(mutex_);
    batch_.copySteps(out);
}

void BatchWorld::copyTimes(double* out) const {
    std::lock_guard lock(mutex_);
    for (int i = 0; i < batch_.size(); ++i) out[i] = batch_.match(i).simulation().state().time;
}

}  // namespace vssim::python
