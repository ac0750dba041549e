#include "vssim/camera/camera_lens.h"

#include <Eigen/Dense>
#include <cmath>

namespace vssim {

CameraLens cameraLensFor(const CameraSettings& camera, const CameraGeometry& geometry) {
    CameraLens lens;
    lens.geometry = geometry;
    lens.pinhole = camera.projection == CameraProjection::Pinhole;
    lens.height = camera.height;
    const double f = camera.focal_length > 0.0 ? camera.focal_length : geometry.scale * camera.height;
    lens.fx = lens.fy = f;
    lens.cx = geometry.centreU - 0.5;
    lens.cy = geometry.centreV - 0.5;
    if (lens.pinhole) lens.k1 = camera.k1, lens.k2 = camera.k2, lens.p1 = camera.p1, lens.p2 = camera.p2, lens.k3 = camera.k3;
    return lens;
}

cv::Vec3d cameraRotation(const CameraLens&) { return {M_PI, 0.0, 0.0}; }
cv::Vec3d cameraTranslation(const CameraLens& lens) { return {0.0, 0.0, lens.height}; }
cv::Matx33d cameraMatrix(const CameraLens& lens) { return {lens.fx, 0.0, lens.cx, 0.0, lens.fy, lens.cy, 0.0, 0.0, 1.0}; }
cv::Vec<double, 5> distortionCoefficients(const CameraLens& lens) { return {lens.k1, lens.k2, lens.p1, lens.p2, lens.k3}; }

Eigen::Vector2d distort(const CameraLens& lens, const Eigen::Vector2d& p) {
    const double x = p.x(), y = p.y(), r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (lens.k1 + r2 * (lens.k2 + r2 * lens.k3));
    return {x * radial + 2.0 * lens.p1 * x * y + lens.p2 * (r2 + 2.0 * x * x),
            y * radial + lens.p1 * (r2 + 2.0 * y * y) + 2.0 * lens.p2 * x * y};
}

Eigen::Vector2d undistort(const CameraLens& lens, const Eigen::Vector2d& distorted) {
    Eigen::Vector2d p = distorted;
    for (int i = 0; i < 50; ++i) {
        const double x = p.x(), y = p.y(), r2 = x * x + y * y;
        const double radial = 1.0 + r2 * (lens.k1 + r2 * (lens.k2 + r2 * lens.k3));
        // d(radial)/d(r2)
        const double dRadial = lens.k1 + r2 * (2.0 * lens.k2 + 3.0 * r2 * lens.k3);
        Eigen::Matrix2d jacobian;
        jacobian(0, 0) = radial + 2.0 * x * x * dRadial + 2.0 * lens.p1 * y + 6.0 * lens.p2 * x;
        jacobian(0, 1) = 2.0 * x * y * dRadial + 2.0 * lens.p1 * x + 2.0 * lens.p2 * y;
        jacobian(1, 0) = 2.0 * x * y * dRadial + 2.0 * lens.p1 * x + 2.0 * lens.p2 * y;
        jacobian(1, 1) = radial + 2.0 * y * y * dRadial + 6.0 * lens.p1 * y + 2.0 * lens.p2 * x;
        const Eigen::Vector2d residual = distort(lens, p) - distorted;
        if (residual.norm() < 1e-15) break;
        p -= jacobian.inverse() * residual;
    }
    return p;
}

Eigen::Vector2d projectToImage(const CameraLens& lens, double x, double y, double z) {
    if (!lens.pinhole) {
        const Eigen::Vector2d continuous = toPixel(lens.geometry, x, y);
        return continuous - Eigen::Vector2d(0.5, 0.5);
    }
    // Camera frame: X right (+x), Y down (-y), Z along the view (down, -z).
    const double depth = lens.height - z;
    const Eigen::Vector2d d = distort(lens, Eigen::Vector2d(x / depth, -y / depth));
    return {lens.fx * d.x() + lens.cx, lens.fy * d.y() + lens.cy};
}

Eigen::Vector2d imageToField(const CameraLens& lens, double u, double v, double z) {
    if (!lens.pinhole) return toField(lens.geometry, u + 0.5, v + 0.5);
    const Eigen::Vector2d n = undistort(lens, Eigen::Vector2d((u - lens.cx) / lens.fx, (v - lens.cy) / lens.fy));
    const double depth = lens.height - z;
    return {n.x() * depth, -n.y() * depth};
}

}  // namespace vssim
