// Motion blur of the synthetic camera: the instants an exposure samples and
// where each body was at them. A frame taken at time t with exposure T
// averages the scene over [t - T, t]; the renderer approximates that integral
// by the mean of n sub-frames at evenly spaced instants (the trapezoid rule's
// interior weights, both ends included), each body moved BACKWARDS from its
// pose at t with the velocity it has at t held constant (a robot along its
// arc of speed v and yaw rate omega, the ball in a straight line): the
// image the shutter integrates while the bodies keep their current motion.
#pragma once

#include "vssim/ball.h"
#include "vssim/camera_settings.h"
#include "vssim/robot_state.h"

namespace vssim {

// How many sub-frames a frame averages: blur_samples when exposure > 0 and
// blur_samples > 1, else 1 (the instant itself, no blur).
int blurSubFrames(const CameraSettings& camera);

// How long before the camera instant sub-frame k (0 .. blurSubFrames - 1)
// is, s: exposure * k / (n - 1); 0 without blur.
double blurDelay(const CameraSettings& camera, int k);

// The pose `delay` seconds earlier (delay >= 0, s) of a robot moving with
// constant forward speed v (m/s) and yaw rate omega (rad/s): heading
// theta - omega delay, the centre on the arc (the chord v delay
// sinc(omega delay / 2) along the mean heading), speeds unchanged.
RobotState robotBefore(const RobotState& pose, double delay);
// The ball `delay` seconds earlier at constant velocity (vx, vy), m/s.
BallState ballBefore(const BallState& ball, double delay);

}  // namespace vssim
