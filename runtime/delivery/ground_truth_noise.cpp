#include "delivery/ground_truth_noise.h"

#include <cmath>

namespace vssim {

bool hasGroundTruthNoise(const CameraSettings& camera) {
    return camera.position_noise > 0.0 || camera.heading_noise > 0.0 || camera.vanish > 0.0;
}

double wrapToPi(double angle) {
    constexpr double kPi = 3.141592653589793;
    double wrapped = std::remainder(angle, 2.0 * kPi);  // [-pi, pi]
    if (wrapped <= -kPi) wrapped += 2.0 * kPi;
    return wrapped;
}

ObservedPose observePose(const CameraSettings& camera, const CameraDrawKey& key, double x, double y, double theta) {
    ObservedPose pose{true, x, y, theta};
    if (camera.vanish > 0.0 && cameraUniform(key, CameraDraw::Vanish) < camera.vanish) {
        pose.visible = false;
        return pose;
    }
    if (camera.position_noise > 0.0) {
        pose.x += camera.position_noise * cameraGaussian(key, CameraDraw::NoiseX);
        pose.y += camera.position_noise * cameraGaussian(key, CameraDraw::NoiseY);
    }
    if (camera.heading_noise > 0.0)
        pose.theta = wrapToPi(theta + camera.heading_noise * cameraGaussian(key, CameraDraw::NoiseTheta));
    return pose;
}

}  // namespace vssim
