#include "vssim/batch/batch_world.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "vssim/world_model.h"

namespace vssim {

namespace {

// The most steps one step() may take (about 31,700 years at dt = 1 ms): far
// beyond any use, far below int64 overflow.
constexpr double kMaxSteps = 1e15;

int poolSize(int worlds, int threads) {
    if (worlds < 1)
        throw std::invalid_argument("BatchWorld: the number of worlds must be at least 1, not " +
                                    std::to_string(worlds));
    if (threads < 0)
        throw std::invalid_argument("BatchWorld: the thread count must be 0 (all cores) or more, not " +
                                    std::to_string(threads));
    if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return std::min(threads, worlds);
}

// The shortest text that reads back as x (1e+300, not 300 digits).
std::string shortest(double x) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, x);
    return std::string(text, result.ptr);
}

void checkPointer(const void* p, std::size_t count, const char* what) {
    if (!p && count > 0) throw std::invalid_argument(std::string("BatchWorld::") + what + ": null pointer");
}

// A command's number: finite (a NaN or an infinity is refused, as a lone
// World refuses it). `side` 0 is the right wheel, 1 the left; `what` names the call.
void checkNumber(double value, const char* what, int world, int robot, int side, bool wheelSpeeds) {
    if (!std::isfinite(value))
        throw std::invalid_argument(std::string("BatchWorld::") + what + ": world " + std::to_string(world) +
                                    ", robot " + std::to_string(robot) + ": the " + (side == 0 ? "right" : "left") +
                                    (wheelSpeeds ? " wheel speed" : " voltage") + " is " +
                                    (std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf") +
                                    " (expected a finite number)");
}

}  // namespace

BatchWorld::BatchWorld(const Scene& scene, int worlds, int threads, std::uint64_t seed)
    : scene_(scene), seed_(seed), pool_(poolSize(worlds, threads)), tableCaches_(pool_.size()) {
    matches_.resize(static_cast<std::size_t>(worlds));
    pool_.parallelFor(matches_.size(), [this](std::size_t i) {
        matches_[i] = std::make_unique<Match>(scene_, seedOf(static_cast<int>(i)));
    });
}

BatchWorld::~BatchWorld() = default;

std::uint64_t BatchWorld::seedOf(int world) const {
    if (world < 0 || world >= static_cast<int>(matches_.size()))
        throw std::out_of_range("BatchWorld::seedOf: world " + std::to_string(world) + " out of range (" +
                                std::to_string(matches_.size()) + " worlds)");
    return seed_ == 0 ? 0 : seed_ + static_cast<std::uint64_t>(world);
}

Match& BatchWorld::at(int world, const char* what) {
    return const_cast<Match&>(static_cast<const BatchWorld*>(this)->at(world, what));
}

const Match& BatchWorld::at(int world, const char* what) const {
    if (world < 0 || world >= size())
        throw std::out_of_range(std::string("BatchWorld::") + what + ": world " + std::to_string(world) +
                                " out of range (" + std::to_string(size()) + " worlds)");
    return *matches_[static_cast<std::size_t>(world)];
}

void BatchWorld::checkRobot(int robot, const char* what) const {
    if (robot < 0 || robot >= robots())
        throw std::out_of_range(std::string("BatchWorld::") + what + ": robot " + std::to_string(robot) +
                                " out of range (" + std::to_string(robots()) + " robots)");
}

void BatchWorld::setVoltages(int world, int robot, const Voltages& e) {
    setOne(world, robot, DriveCommand::ofVoltages(e), e.right, e.left, "setVoltages");
}

void BatchWorld::setWheelSpeeds(int world, int robot, const WheelSpeeds& w) {
    setOne(world, robot, DriveCommand::ofWheelSpeeds(w), w.right, w.left, "setWheelSpeeds");
}

void BatchWorld::setOne(int world, int robot, const DriveCommand& command, double right, double left,
                        const char* what) {
    Match& m = at(world, what);
    checkRobot(robot, what);
    checkNumber(right, what, world, robot, 0, command.wheelSpeeds);
    checkNumber(left, what, world, robot, 1, command.wheelSpeeds);
    m.drive(robot, command);
}

void BatchWorld::setVoltagesAll(const double* rightLeft) { setAll(rightLeft, false, "setVoltagesAll"); }

void BatchWorld::setWheelSpeedsAll(const double* rightLeft) { setAll(rightLeft, true, "setWheelSpeedsAll"); }

void BatchWorld::setAll(const double* rightLeft, bool wheelSpeeds, const char* what) {
    const std::size_t n = matches_.size() * scene_.robots.size();
    checkPointer(rightLeft, n, what);
    for (std::size_t k = 0; k < 2 * n; ++k)
        checkNumber(rightLeft[k], what, static_cast<int>(k / 2 / scene_.robots.size()),
                    static_cast<int>(k / 2 % scene_.robots.size()), static_cast<int>(k % 2), wheelSpeeds);
    const int r = robots();
    for (int w = 0; w < size(); ++w)
        for (int i = 0; i < r; ++i) {
            const double* p = rightLeft + 2 * (static_cast<std::size_t>(w) * r + i);
            matches_[w]->drive(i, wheelSpeeds ? DriveCommand::ofWheelSpeeds({p[0], p[1]})
                                              : DriveCommand::ofVoltages({p[0], p[1]}));
        }
}

std::int64_t BatchWorld::stepsFor(double seconds) const {
    if (std::isnan(seconds)) throw std::invalid_argument("BatchWorld::step: seconds is NaN");
    if (!(seconds > 0.0))
        throw std::invalid_argument("BatchWorld::step: seconds must be positive, not " + shortest(seconds));
    const Match& first = *matches_.front();
    const double dt = first.simulation().dt();
    if (!(seconds / dt <= kMaxSteps))
        throw std::invalid_argument("BatchWorld::step: " + shortest(seconds) + " s is too long (at most " +
                                    shortest(kMaxSteps * dt) + " s, 10^15 steps, at a time)");
    return std::max<std::int64_t>(1, Simulation::stepIndexAtOrAfter(seconds, dt));
}

std::int64_t BatchWorld::step(double seconds) {
    const std::int64_t steps = stepsFor(seconds);
    pool_.parallelFor(matches_.size(), [this, steps](std::size_t i) {
        Match& m = *matches_[i];
        m.lendTableCache(&tableCaches_[static_cast<std::size_t>(ThreadPool::threadIndex())]);
        m.advanceTo(m.simulation().state().step + steps);
    });
    return steps;
}

void BatchWorld::placeRobot(int world, int robot, const RobotState& pose) {
    Match& m = at(world, "placeRobot");
    checkRobot(robot, "placeRobot");
    for (double value : {pose.x, pose.y, pose.theta, pose.v, pose.omega})
        if (!std::isfinite(value))
            throw std::invalid_argument("BatchWorld::placeRobot: world " + std::to_string(world) + ", robot " +
                                        std::to_string(robot) + ": x, y, theta, v and omega must be finite");
    m.placeRobot(robot, pose);
}

void BatchWorld::placeBall(int world, const BallState& ball) {
    Match& m = at(world, "placeBall");
    for (double value : {ball.x, ball.y, ball.vx, ball.vy})
        if (!std::isfinite(value))
            throw std::invalid_argument("BatchWorld::placeBall: world " + std::to_string(world) +
                                        ": x, y, vx and vy must be finite");
    m.placeBall(ball);
}

void BatchWorld::reset(int world) {
    at(world, "reset");
    matches_[static_cast<std::size_t>(world)] = std::make_unique<Match>(scene_, seedOf(world));
}

void BatchWorld::resetAll() {
    pool_.parallelFor(matches_.size(), [this](std::size_t i) {
        matches_[i] = std::make_unique<Match>(scene_, seedOf(static_cast<int>(i)));
    });
}

const Match& BatchWorld::match(int world) const { return at(world, "match"); }

bool BatchWorld::finite(int world) const {
    return firstNonFiniteBody(at(world, "finite").simulation().state()) < 0;
}

void BatchWorld::copyRobots(double* out) const {
    const std::size_t r = scene_.robots.size();
    checkPointer(out, matches_.size() * r, "copyRobots");
    for (const auto& m : matches_)
        for (const RobotState& s : m->simulation().state().robots) {
            out[0] = s.x, out[1] = s.y, out[2] = s.theta, out[3] = s.v, out[4] = s.omega;
            out += 5;
        }
}

void BatchWorld::copyWheelSpeeds(double* out) const {
    const int r = robots();
    checkPointer(out, matches_.size() * static_cast<std::size_t>(r), "copyWheelSpeeds");
    for (const auto& m : matches_)
        for (int i = 0; i < r; ++i) {
            const RobotOutputs o = m->simulation().robotOutputs(i);
            out[0] = o.wheel_speed_right, out[1] = o.wheel_speed_left;
            out += 2;
        }
}

void BatchWorld::copyBalls(double* out) const {
    checkPointer(out, matches_.size(), "copyBalls");
    for (const auto& m : matches_) {
        const BallState& b = m->simulation().state().ball;
        out[0] = b.x, out[1] = b.y, out[2] = b.vx, out[3] = b.vy;
        out += 4;
    }
}

void BatchWorld::copyScores(int* out) const {
    checkPointer(out, matches_.size(), "copyScores");
    for (const auto& m : matches_) {
        out[0] = m->game().goals[0], out[1] = m->game().goals[1];
        out += 2;
    }
}

void BatchWorld::copySteps(std::int64_t* out) const {
    checkPointer(out, matches_.size(), "copySteps");
    for (const auto& m : matches_) *out++ = m->simulation().state().step;
}

}  // namespace vssim
