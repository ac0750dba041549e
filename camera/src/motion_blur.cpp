#include "vssim/camera/motion_blur.h"

#include <cmath>

namespace vssim {

int blurSubFrames(const CameraSettings& camera) {
    return camera.exposure > 0.0 && camera.blur_samples > 1 ? camera.blur_samples : 1;
}

double blurDelay(const CameraSettings& camera, int k) {
    const int n = blurSubFrames(camera);
    return n > 1 ? camera.exposure * k / (n - 1) : 0.0;
}

RobotState robotBefore(const RobotState& pose, double delay) {
    const double s = -delay;             // signed time from the pose, s
    const double turn = pose.omega * s;  // rad
    const double half = 0.5 * turn;
    // sin(h)/h, its series near 0 (exact to rounding for |h| < 1e-4).
    const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
    const double chord = pose.v * s * sinc;  // m, signed along the mean heading
    RobotState before = pose;
    before.x = pose.x + chord * std::cos(pose.theta + half);
    before.y = pose.y + chord * std::sin(pose.theta + half);
    before.theta = pose.theta + turn;
    return before;
}

BallState ballBefore(const BallState& ball, double delay) {
    BallState before = ball;
    before.x = ball.x - ball.vx * delay;
    before.y = ball.y - ball.vy * delay;
    return before;
}

}  // namespace vssim
