#include "placement_check.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "io/scene_limits.h"
#include "vssim/field.h"

namespace vssim::python {

namespace {

// The shortest text that reads back as x (0.9, not 0.90000000000000002).
std::string number(double x) {
    char text[32];
    const auto result = std::to_chars(text, text + sizeof text, x);
    return std::string(text, result.ptr);
}

std::string fieldSize(const Field& field) { return number(field.length) + " x " + number(field.width) + " m field"; }

}  // namespace

void checkRobotPlacement(const Scene& scene, int robot, const RobotState& p, const std::string& where) {
    for (double value : {p.x, p.y, p.theta, p.v, p.omega})
        if (!std::isfinite(value)) throw std::invalid_argument(where + ": x, y, theta, v and omega must be finite numbers");
    if (std::abs(p.v) > scene_limits::kMaxRobotSpeed || std::abs(p.omega) > scene_limits::kMaxYawRate)
        throw std::invalid_argument(where + ": |v| must be at most " + number(scene_limits::kMaxRobotSpeed) +
                                    " m/s and |omega| at most " + number(scene_limits::kMaxYawRate) + " rad/s");
    if (!robotInsideField(scene.field, scene.robots[static_cast<std::size_t>(robot)].params.side, p.x, p.y, p.theta))
        throw std::invalid_argument(where + " at (" + number(p.x) + ", " + number(p.y) + ") m, heading " +
                                    number(p.theta) + " rad, would not lie inside the " + fieldSize(scene.field));
}

void checkBallPlacement(const Scene& scene, const BallState& b, const std::string& where) {
    for (double value : {b.x, b.y, b.vx, b.vy})
        if (!std::isfinite(value)) throw std::invalid_argument(where + ": x, y, vx and vy must be finite numbers");
    if (std::hypot(b.vx, b.vy) > scene_limits::kMaxBallSpeed)
        throw std::invalid_argument(where + ": its speed must be at most " + number(scene_limits::kMaxBallSpeed) +
                                    " m/s");
    if (!discInsideField(scene.field, scene.ball_params.radius, b.x, b.y))
        throw std::invalid_argument(where + " at (" + number(b.x) + ", " + number(b.y) +
                                    ") m would not lie inside the " + fieldSize(scene.field));
}

}  // namespace vssim::python
