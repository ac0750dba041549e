#include "vssim/camera/field_background.h"

#include <opencv2/imgproc.hpp>
#include <vector>

#include "vssim/camera/camera_colours.h"
#include "vssim/camera/camera_layout.h"

namespace vssim {

namespace {

// The floor's outline in the field frame, m: the chain of walls, goals
// included and corner triangles left out.
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

// The white markings, drawn on the floor before the walls.
void drawMarkings(cv::Mat& image, const Field& field, const CameraGeometry& camera) {
    const FieldDimensions& d = field.dimensions;
    const double hx = 0.5 * field.length, hy = 0.5 * field.width;
    const cv::Scalar white = toScalar(kMarkingColour);
    auto line = [&](double x0, double y0, double x1, double y1) {
        cv::line(image, drawingPoint(camera, x0, y0), drawingPoint(camera, x1, y1), white, kMarkingThicknessPx,
                 cv::LINE_AA, kDrawShift);
    };
    line(0.0, -hy, 0.0, hy);  // the centre line, wall to wall
    if (d.centre_radius > 0.0)
        cv::circle(image, drawingPoint(camera, 0.0, 0.0), drawingLength(camera, d.centre_radius), white,
                   kMarkingThicknessPx, cv::LINE_AA, kDrawShift);
    for (const double side : {-1.0, 1.0}) {  // the left end (x < 0), then the right
        // The goal area: its three lines in front of the goal, the wall its fourth side.
        if (d.goal_area_depth > 0.0 && d.goal_area_width > 0.0) {
            const double front = side * (hx - d.goal_area_depth), half = 0.5 * d.goal_area_width;
            line(side * hx, -half, front, -half);
            line(front, -half, front, half);
            line(front, half, side * hx, half);
        }
        // The marks: crosses at the penalty mark and the two free-ball marks of this half.
        auto cross = [&](double x, double y) {
            line(x - kMarkHalfArm, y, x + kMarkHalfArm, y);
            line(x, y - kMarkHalfArm, x, y + kMarkHalfArm);
        };
        if (d.penalty_mark > 0.0) cross(side * (hx - d.penalty_mark), 0.0);
        if (d.free_ball_x > 0.0)
            for (const double y : {-d.free_ball_y, d.free_ball_y}) cross(side * (hx - d.free_ball_x), y);
    }
}

}  // namespace

cv::Mat renderFieldBackground(const Field& field, const CameraGeometry& camera) {
    cv::Mat image(camera.height, camera.width, CV_8UC3, toScalar(kOutsideColour));

    std::vector<cv::Point> floor;
    for (const Eigen::Vector2d& p : floorOutline(field)) floor.push_back(drawingPoint(camera, p.x(), p.y()));
    cv::fillPoly(image, std::vector<std::vector<cv::Point>>{floor}, toScalar(kFloorColour), cv::LINE_AA, kDrawShift);

    drawMarkings(image, field, camera);

    for (const Wall& wall : field.walls)
        cv::line(image, drawingPoint(camera, wall.a.x(), wall.a.y()), drawingPoint(camera, wall.b.x(), wall.b.y()),
                 toScalar(kWallColour), kWallThicknessPx, cv::LINE_AA, kDrawShift);
    return image;
}

}  // namespace vssim
