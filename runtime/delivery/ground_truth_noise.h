// The ground truth as a camera-based vision system would report it
// (docs/protocol.md, STATE; docs/firasim.md, vision): each body's position
// with Gaussian noise of standard deviation `position_noise` (m) on x and y,
// a robot's heading with `heading_noise` (rad), and with probability
// `vanish` a body not seen at all in a frame. The draws come from
// camera_draws.h, keyed by the body, so one body's noise does not depend on
// the others'. Speeds, voltages and currents are not the camera's: callers
// leave them exact.
#pragma once

#include "delivery/camera_draws.h"
#include "vssim/camera_settings.h"

namespace vssim {

struct ObservedPose {
    bool visible = true;  // false: the body is missing from this frame (x, y, theta mean nothing)
    double x = 0.0;       // m
    double y = 0.0;       // m
    double theta = 0.0;   // rad: with heading noise, wrapped to (-pi, pi]; otherwise as given
};

// Whether `camera` changes the ground truth at all (position or heading
// noise, or vanishing bodies); when not, observePose returns its input.
bool hasGroundTruthNoise(const CameraSettings& camera);

// The pose of the body key.body (a robot's index, or kBallBody) at frame
// key.frame as the camera reports it. Zero settings leave their part exact
// (no draw): x and y untouched without position noise, theta without
// heading noise.
ObservedPose observePose(const CameraSettings& camera, const CameraDrawKey& key, double x, double y, double theta);

// An angle wrapped to (-pi, pi], rad.
double wrapToPi(double angle);

}  // namespace vssim
