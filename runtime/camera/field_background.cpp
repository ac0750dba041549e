#include "camera/field_background.h"

#include <opencv2/imgproc.hpp>
#include <vector>

#include "camera/camera_colours.h"
#include "camera/camera_layout.h"

namespace vssim {

namespace {

// The floor's outline in the field frame, m.
std::vector<Eigen::Vector2d> floorOutline(const Field& field) {
    std::vector<Eigen::Vector2d> outline;
    bool closedChain = field.walls.size() >= 3;
    for (std::size_t i = 0; i < field.walls.size() && closedChain; ++i) {
        const Wall& next = field.walls[(i + 1) % field.walls.size()];
        closedChain = (field.walls[i].b - next.a).norm() < 1e-9;
        outline.push_back(field.walls[i].a);
    }
    if (closedChain) return outline;
    const double hx = 0.5 * field.length, hy = 0.5 * field.width;
    return {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
}

}  // namespace

cv::Mat renderFieldBackground(const Field& field, const CameraGeometry& camera) {
    cv::Mat image(camera.height, camera.width, CV_8UC3, toScalar(kOutsideColour));

    std::vector<cv::Point> floor;
    for (const Eigen::Vector2d& p : floorOutline(field)) floor.push_back(drawingPoint(camera, p.x(), p.y()));
    cv::fillPoly(image, std::vector<std::vector<cv::Point>>{floor}, toScalar(kFloorColour), cv::LINE_AA, kDrawShift);

    const double hy = 0.5 * field.width;
    cv::line(image, drawingPoint(camera, 0.0, -hy), drawingPoint(camera, 0.0, hy), toScalar(kMarkingColour),
             kMarkingThicknessPx, cv::LINE_AA, kDrawShift);
    cv::circle(image, drawingPoint(camera, 0.0, 0.0), drawingLength(camera, kCentreCircleRadius),
               toScalar(kMarkingColour), kMarkingThicknessPx, cv::LINE_AA, kDrawShift);

    for (const Wall& wall : field.walls)
        cv::line(image, drawingPoint(camera, wall.a.x(), wall.a.y()), drawingPoint(camera, wall.b.x(), wall.b.y()),
                 toScalar(kWallColour), kWallThicknessPx, cv::LINE_AA, kDrawShift);
    return image;
}

}  // namespace vssim
