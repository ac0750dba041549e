// Where a camera with a lens sees a point of the world (docs/protocol.md,
// "The camera model"): the pinhole projection of a camera `height` above the
// field centre looking straight down, then OpenCV's lens distortion; or the
// ideal orthographic top view. Pixel coordinates here follow OpenCV: pixel
// (column i, row j) has its centre at (i, j), so cv::projectPoints and
// cv::undistortPoints take the same numbers (camera_geometry.h's continuous
// coordinates put that centre at (i + 0.5, j + 0.5)).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "vssim/camera/camera_geometry.h"
#include "vssim/camera_settings.h"

namespace vssim {

struct CameraLens {
    bool pinhole = false;
    CameraGeometry geometry;  // the ideal top view: the orthographic map, and the image size
    double height = 2.0;      // m, the optical centre above the floor at the field centre
    // Intrinsics, OpenCV convention: u = fx x_d + cx, v = fy y_d + cy (px).
    double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
    double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
};

// The lens of `camera` over the ideal geometry: focal_length (or, when 0,
// geometry.scale * height, so that the floor appears at the ideal scale at
// the centre), the principal point over the field centre (centreU - 0.5,
// centreV - 0.5 in OpenCV's convention).
CameraLens cameraLensFor(const CameraSettings& camera, const CameraGeometry& geometry);

// The camera pose for cv::projectPoints: the world (field x, y; z up, metres,
// origin at the field centre on the floor) seen from `height` above looking
// down, image u along +x and v along -y: rvec = (pi, 0, 0), tvec = (0, 0, height).
cv::Vec3d cameraRotation(const CameraLens& lens);
cv::Vec3d cameraTranslation(const CameraLens& lens);
cv::Matx33d cameraMatrix(const CameraLens& lens);
cv::Vec<double, 5> distortionCoefficients(const CameraLens& lens);  // k1, k2, p1, p2, k3

// Normalised image coordinates through the distortion (model.md has none of
// this: OpenCV's radial-tangential model, as cv::projectPoints applies it).
Eigen::Vector2d distort(const CameraLens& lens, const Eigen::Vector2d& undistorted);
// Its inverse by Newton's method, to 1e-14; nullopt-free: a point the model
// cannot invert (outside the range where it is one-to-one) comes back as the
// last iterate, which distort() then misses (callers check when it matters).
Eigen::Vector2d undistort(const CameraLens& lens, const Eigen::Vector2d& distorted);

// The pixel (OpenCV convention) where the world point (x, y, z) appears
// (z above the floor, m; below the camera).
Eigen::Vector2d projectToImage(const CameraLens& lens, double x, double y, double z);
// The world point at height z whose image is pixel (u, v) (OpenCV convention):
// undistort, then intersect the viewing ray with the plane at z.
Eigen::Vector2d imageToField(const CameraLens& lens, double u, double v, double z);

}  // namespace vssim
