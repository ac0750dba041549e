#include "vssim/camera/camera_geometry.h"

#include <algorithm>
#include <cmath>

namespace vssim {

namespace {
constexpr double kMarginPx = 20.0;  // free image border around the field, px
constexpr double kShiftScale = 1 << kDrawShift;
}  // namespace

CameraGeometry cameraGeometryFor(const Field& field, int width, int height) {
    CameraGeometry camera;
    camera.width = width;
    camera.height = height;
    // The floor's bounding box; the length x width rectangle for a field without one.
    Eigen::Vector2d lower = field.lower, upper = field.upper;
    if (!(upper.x() > lower.x() && upper.y() > lower.y()))
        lower = Eigen::Vector2d(-0.5 * field.length, -0.5 * field.width), upper = -lower;
    const Eigen::Vector2d extent = upper - lower, middle = 0.5 * (lower + upper);
    camera.scale = std::min((width - 2.0 * kMarginPx) / extent.x(), (height - 2.0 * kMarginPx) / extent.y());
    camera.centreU = width / 2.0 - camera.scale * middle.x();
    camera.centreV = height / 2.0 + camera.scale * middle.y();
    return camera;
}

Eigen::Vector2d toPixel(const CameraGeometry& camera, double x, double y) {
    return {camera.centreU + camera.scale * x, camera.centreV - camera.scale * y};
}

Eigen::Vector2d toField(const CameraGeometry& camera, double u, double v) {
    return {(u - camera.centreU) / camera.scale, (camera.centreV - v) / camera.scale};
}

cv::Point drawingPoint(const CameraGeometry& camera, double x, double y) {
    const Eigen::Vector2d p = toPixel(camera, x, y);
    return {static_cast<int>(std::lround((p.x() - 0.5) * kShiftScale)),
            static_cast<int>(std::lround((p.y() - 0.5) * kShiftScale))};
}

int drawingLength(const CameraGeometry& camera, double metres) {
    return static_cast<int>(std::lround(metres * camera.scale * kShiftScale));
}

}  // namespace vssim
