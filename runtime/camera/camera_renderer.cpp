#include "camera/camera_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "camera/camera_layout.h"
#include "camera/field_background.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

// How far anti-aliased edges may colour pixels beyond the exact outline, px
// (OpenCV's reach about 1.5 px: 1.55 at most over 20000 random poses).
constexpr int kSpillPx = 2;

// The pixel box that holds the outline through these field points (m) plus
// the anti-aliasing spill, clipped to the image; empty when it misses the
// image (or a point is not finite).
template <std::size_t N>
cv::Rect pixelBounds(const CameraGeometry& camera, const std::array<Eigen::Vector2d, N>& points) {
    double uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
    for (const Eigen::Vector2d& p : points) {
        const Eigen::Vector2d px = toPixel(camera, p.x(), p.y());
        if (!std::isfinite(px.x()) || !std::isfinite(px.y())) return {};
        uMin = std::min(uMin, px.x()), uMax = std::max(uMax, px.x());
        vMin = std::min(vMin, px.y()), vMax = std::max(vMax, px.y());
    }
    // Clamp first so that far-away bodies cannot overflow the int conversion.
    const auto clampU = [&](double u) { return std::clamp(u, -2.0 * kSpillPx, camera.width + 2.0 * kSpillPx); };
    const auto clampV = [&](double v) { return std::clamp(v, -2.0 * kSpillPx, camera.height + 2.0 * kSpillPx); };
    const int left = static_cast<int>(std::floor(clampU(uMin))) - kSpillPx;
    const int top = static_cast<int>(std::floor(clampV(vMin))) - kSpillPx;
    const int right = static_cast<int>(std::ceil(clampU(uMax))) + kSpillPx;  // exclusive
    const int bottom = static_cast<int>(std::ceil(clampV(vMax))) + kSpillPx;
    return cv::Rect(left, top, right - left, bottom - top) & cv::Rect(0, 0, camera.width, camera.height);
}

// A rectangle of the robot frame (units of the side) as a drawing polygon.
std::array<cv::Point, 4> patchPolygon(const CameraGeometry& camera, const RobotState& pose, double side,
                                      const PatchRectangle& r) {
    std::array<cv::Point, 4> polygon;
    const std::array<Eigen::Vector2d, 4> corners{
        {{r.xMin, r.yMin}, {r.xMax, r.yMin}, {r.xMax, r.yMax}, {r.xMin, r.yMax}}};
    for (std::size_t k = 0; k < corners.size(); ++k) {
        const Eigen::Vector2d p = fromRobotFrame(pose, side * corners[k]);
        polygon[k] = drawingPoint(camera, p.x(), p.y());
    }
    return polygon;
}

void fillPolygon(cv::Mat& frame, const std::array<cv::Point, 4>& polygon, Bgr colour) {
    cv::fillConvexPoly(frame, polygon.data(), static_cast<int>(polygon.size()), toScalar(colour), cv::LINE_AA,
                       kDrawShift);
}

}  // namespace

CameraRenderer::CameraRenderer(const Scene& scene, int width, int height)
    : camera_(cameraGeometryFor(scene.field, width, height)), ballRadius_(scene.ball_params.radius) {
    int yellowCount = 0, blueCount = 0;
    for (const RobotSpec& spec : scene.robots) {
        int& indexInTeam = spec.team == Team::Yellow ? yellowCount : blueCount;
        robots_.push_back({spec.params.side, teamColour(spec.team), identityColour(indexInTeam++)});
    }
    background_ = renderFieldBackground(scene.field, camera_);
}

cv::Rect CameraRenderer::drawRobot(const RobotLook& look, const RobotState& pose, cv::Mat& frame) const {
    const std::array<Eigen::Vector2d, 4> body = robotVertices(pose, look.side);
    const cv::Rect bounds = pixelBounds(camera_, body);
    if (bounds.empty()) return bounds;
    std::array<cv::Point, 4> bodyPolygon;
    for (std::size_t k = 0; k < body.size(); ++k) bodyPolygon[k] = drawingPoint(camera_, body[k].x(), body[k].y());
    fillPolygon(frame, bodyPolygon, kRobotBodyColour);
    fillPolygon(frame, patchPolygon(camera_, pose, look.side, kTeamPatch), look.team);
    fillPolygon(frame, patchPolygon(camera_, pose, look.side, kIdentityPatch), look.identity);
    return bounds;
}

cv::Rect CameraRenderer::drawBall(const BallState& ball, cv::Mat& frame) const {
    const double r = ballRadius_;
    const cv::Rect bounds = pixelBounds<2>(camera_, {{{ball.x - r, ball.y - r}, {ball.x + r, ball.y + r}}});
    if (bounds.empty()) return bounds;
    cv::circle(frame, drawingPoint(camera_, ball.x, ball.y), drawingLength(camera_, r), toScalar(kBallColour),
               cv::FILLED, cv::LINE_AA, kDrawShift);
    return bounds;
}

void CameraRenderer::render(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches) const {
    if (state.robots.size() != robots_.size())
        throw std::invalid_argument("CameraRenderer::render: the state has " + std::to_string(state.robots.size()) +
                                    " robots, the scene " + std::to_string(robots_.size()));
    if (frame.datastart == background_.datastart) frame = cv::Mat();  // never draw into the background itself
    background_.copyTo(frame);
    patches.clear();
    for (std::size_t i = 0; i < robots_.size(); ++i) {
        // Off the field (WorldState::offField): not in the picture; an empty patch keeps the order.
        const bool off = i < state.offField.size() && state.offField[i];
        patches.push_back(off ? cv::Rect() : drawRobot(robots_[i], state.robots[i], frame));
    }
    patches.push_back(drawBall(state.ball, frame));
}

}  // namespace vssim
