#include "vssim/camera/camera_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "vssim/camera/camera_layout.h"
#include "vssim/camera/field_background.h"
#include "vssim/camera/motion_blur.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

// How far anti-aliased edges may colour pixels beyond the exact outline, px
// (OpenCV's reach about 1.5 px: 1.55 at most over 20000 random poses).
constexpr int kSpillPx = 2;

// The pixel box (in an image of width x height) that holds the outline
// spanning continuous pixel coordinates (camera_geometry.h: pixel centres at
// +0.5) uMin..uMax, vMin..vMax plus the anti-aliasing spill, clipped to the
// image; empty when it misses the image (or a bound is not finite).
cv::Rect spilledBox(double uMin, double uMax, double vMin, double vMax, int width, int height) {
    if (!std::isfinite(uMin) || !std::isfinite(uMax) || !std::isfinite(vMin) || !std::isfinite(vMax)) return {};
    // Clamp first so that far-away bodies cannot overflow the int conversion.
    const auto clampU = [&](double u) { return std::clamp(u, -2.0 * kSpillPx, width + 2.0 * kSpillPx); };
    const auto clampV = [&](double v) { return std::clamp(v, -2.0 * kSpillPx, height + 2.0 * kSpillPx); };
    const int left = static_cast<int>(std::floor(clampU(uMin))) - kSpillPx;
    const int top = static_cast<int>(std::floor(clampV(vMin))) - kSpillPx;
    const int right = static_cast<int>(std::ceil(clampU(uMax))) + kSpillPx;  // exclusive
    const int bottom = static_cast<int>(std::ceil(clampV(vMax))) + kSpillPx;
    return cv::Rect(left, top, right - left, bottom - top) & cv::Rect(0, 0, width, height);
}

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
    return spilledBox(uMin, uMax, vMin, vMax, camera.width, camera.height);
}

// A point in OpenCV's pixel convention (px) as a fixed-point drawing point.
cv::Point fixedPoint(const Eigen::Vector2d& p) {
    constexpr double kShiftScale = 1 << kDrawShift;
    // Far beyond any canvas but inside int once scaled: a body just below a
    // long lens can project millions of pixels away (and a NaN goes to the edge).
    constexpr double kFar = 1 << 20;  // px
    const auto scaled = [&](double v) {
        return static_cast<int>(std::lround(std::clamp(std::isnan(v) ? kFar : v, -kFar, kFar) * kShiftScale));
    };
    return {scaled(p.x()), scaled(p.y())};
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
    : CameraRenderer(scene, scene.camera, width, height) {}

CameraRenderer::CameraRenderer(const Scene& scene, const CameraSettings& camera, int width, int height)
    : camera_(cameraGeometryFor(scene.field, width, height)),
      settings_(camera),
      lens_(cameraLensFor(camera, camera_)),
      ballRadius_(scene.ball_params.radius) {
    int yellowCount = 0, blueCount = 0;
    double tallest = 2.0 * ballRadius_;  // m, the highest point of any body
    for (const RobotSpec& spec : scene.robots) {
        int& indexInTeam = spec.team == Team::Yellow ? yellowCount : blueCount;
        robots_.push_back({spec.params.side, teamColour(spec.team), identityColour(indexInTeam++)});
        tallest = std::max(tallest, spec.params.side);
    }
    if (lens_.pinhole) {
        if (!(camera.height > tallest) || !std::isfinite(camera.height))
            throw std::invalid_argument("camera: height " + std::to_string(camera.height) +
                                        " m must be above the bodies' tops (" + std::to_string(tallest) + " m)");
        if (!(lens_.fx > 0.0) || !std::isfinite(lens_.fx))
            throw std::invalid_argument("camera: focal_length must be > 0 px or 0 for the default (got " +
                                        std::to_string(camera.focal_length) + ")");
    }
    if (!(camera.exposure >= 0.0) || !std::isfinite(camera.exposure))
        throw std::invalid_argument("camera: exposure must be >= 0 s (got " + std::to_string(camera.exposure) + ")");
    if (camera.exposure > 0.0 && (camera.blur_samples < 1 || camera.blur_samples > 257))
        throw std::invalid_argument("camera: blur_samples must be 1..257 (got " + std::to_string(camera.blur_samples) +
                                    ")");
    warp_ = LensWarp(lens_);
    light_ = LightGain(camera, lens_);
    noise_ = SensorNoise(camera.noise, camera.seed, static_cast<std::size_t>(width) * height * 3);
    ideal_ = !lens_.pinhole && !light_.active() && !noise_.active() && blurSubFrames(camera) == 1;
    if (ideal_) {
        background_ = renderFieldBackground(scene.field, camera_);
        return;
    }
    // The canvas: the ideal top view itself (orthographic), or the undistorted
    // pinhole image, in which the floor (z = 0) is the ideal map at scale
    // f / height about the principal point. The walls are drawn there too, at
    // floor level (their height is not modelled).
    CameraGeometry canvas = camera_;
    if (lens_.pinhole) {
        const cv::Size size = warp_.canvasSize();
        const cv::Point offset = warp_.offset();
        canvas.width = size.width, canvas.height = size.height;
        canvas.scale = lens_.fx / lens_.height;
        canvas.centreU = lens_.cx + 0.5 + offset.x;
        canvas.centreV = lens_.cy + 0.5 + offset.y;
    }
    canvasBackground_ = renderFieldBackground(scene.field, canvas);
    warp_.warp(canvasBackground_, cv::Rect(0, 0, width, height), background_);
    light_.applyAt(background_, cv::Point(0, 0));
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

Eigen::Vector2d CameraRenderer::canvasPixel(double x, double y, double z) const {
    if (!lens_.pinhole) return toPixel(camera_, x, y) - Eigen::Vector2d(0.5, 0.5);
    const double depth = lens_.height - z;  // m, along the optical axis
    const cv::Point offset = warp_.offset();
    return {lens_.fx * x / depth + lens_.cx + offset.x, -lens_.fy * y / depth + lens_.cy + offset.y};
}

cv::Rect CameraRenderer::robotBox(const RobotLook& look, const RobotState& pose) const {
    const std::array<Eigen::Vector2d, 4> body = robotVertices(pose, look.side);
    if (!lens_.pinhole) return pixelBounds(camera_, body);
    double uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
    for (const double z : {0.0, look.side})  // the bottom and top squares
        for (const Eigen::Vector2d& p : body) {
            const Eigen::Vector2d px = canvasPixel(p.x(), p.y(), z) + Eigen::Vector2d(0.5, 0.5);
            uMin = std::min(uMin, px.x()), uMax = std::max(uMax, px.x());
            vMin = std::min(vMin, px.y()), vMax = std::max(vMax, px.y());
        }
    const cv::Size size = canvasBackground_.size();
    return spilledBox(uMin, uMax, vMin, vMax, size.width, size.height);
}

cv::Rect CameraRenderer::ballBox(const BallState& ball) const {
    const double r = ballRadius_;
    if (!lens_.pinhole) return pixelBounds<2>(camera_, {{{ball.x - r, ball.y - r}, {ball.x + r, ball.y + r}}});
    const Eigen::Vector2d centre = canvasPixel(ball.x, ball.y, r) + Eigen::Vector2d(0.5, 0.5);
    const double radius = lens_.fx * r / (lens_.height - r);  // px
    const cv::Size size = canvasBackground_.size();
    return spilledBox(centre.x() - radius, centre.x() + radius, centre.y() - radius, centre.y() + radius, size.width,
                      size.height);
}

void CameraRenderer::drawRobotOnCanvas(const RobotLook& look, const RobotState& pose, cv::Mat& canvas) const {
    if (!lens_.pinhole) {
        drawRobot(look, pose, canvas);
        return;
    }
    // The cube: the hull of its bottom (z = 0) and top (z = side) squares in
    // the body colour (its sides are black too), the patches on the top.
    const std::array<Eigen::Vector2d, 4> body = robotVertices(pose, look.side);
    std::vector<cv::Point> corners, hull;
    for (const double z : {0.0, look.side})
        for (const Eigen::Vector2d& p : body) corners.push_back(fixedPoint(canvasPixel(p.x(), p.y(), z)));
    cv::convexHull(corners, hull);
    cv::fillConvexPoly(canvas, hull.data(), static_cast<int>(hull.size()), toScalar(kRobotBodyColour), cv::LINE_AA,
                       kDrawShift);
    for (const auto& [patch, colour] : {std::pair{kTeamPatch, look.team}, std::pair{kIdentityPatch, look.identity}}) {
        const std::array<Eigen::Vector2d, 4> local{
            {{patch.xMin, patch.yMin}, {patch.xMax, patch.yMin}, {patch.xMax, patch.yMax}, {patch.xMin, patch.yMax}}};
        std::array<cv::Point, 4> polygon;
        for (std::size_t k = 0; k < local.size(); ++k) {
            const Eigen::Vector2d p = fromRobotFrame(pose, look.side * local[k]);
            polygon[k] = fixedPoint(canvasPixel(p.x(), p.y(), look.side));
        }
        fillPolygon(canvas, polygon, colour);
    }
}

void CameraRenderer::drawBallOnCanvas(const BallState& ball, cv::Mat& canvas) const {
    if (!lens_.pinhole) {
        drawBall(ball, canvas);
        return;
    }
    // A disc about the image of the ball's centre (z = radius), of the
    // radius a sphere's outline has on the optical axis, f r / (height - r).
    const double r = ballRadius_;
    const double radius = lens_.fx * r / (lens_.height - r);  // px
    cv::circle(canvas, fixedPoint(canvasPixel(ball.x, ball.y, r)),
               static_cast<int>(std::lround(radius * (1 << kDrawShift))), toScalar(kBallColour), cv::FILLED,
               cv::LINE_AA, kDrawShift);
}

void CameraRenderer::render(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches,
                            std::uint64_t frameNumber) const {
    if (state.robots.size() != robots_.size())
        throw std::invalid_argument("CameraRenderer::render: the state has " + std::to_string(state.robots.size()) +
                                    " robots, the scene " + std::to_string(robots_.size()));
    if (frame.datastart == background_.datastart) frame = cv::Mat();  // never draw into the background itself
    if (!ideal_) {
        renderRealistic(state, frame, patches, frameNumber);
        return;
    }
    background_.copyTo(frame);
    patches.clear();
    for (std::size_t i = 0; i < robots_.size(); ++i) {
        // Off the field (WorldState::offField): not in the picture; an empty patch keeps the order.
        const bool off = i < state.offField.size() && state.offField[i];
        patches.push_back(off ? cv::Rect() : drawRobot(robots_[i], state.robots[i], frame));
    }
    patches.push_back(drawBall(state.ball, frame));
}

void CameraRenderer::renderRealistic(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches,
                                     std::uint64_t frameNumber) const {
    const std::size_t robots = robots_.size(), bodies = robots + 1;
    const int subFrames = blurSubFrames(settings_);
    // Every body's pose and canvas box at every sub-frame (k = 0: the instant
    // itself), and each body's box over them all.
    std::vector<RobotState> robotPoses(robots * subFrames);
    std::vector<BallState> ballPoses(subFrames);
    std::vector<cv::Rect> subBoxes(bodies * subFrames), boxes(bodies);
    for (int k = 0; k < subFrames; ++k) {
        const double delay = blurDelay(settings_, k);  // s before the camera instant
        for (std::size_t i = 0; i < robots; ++i) {
            // Off the field (WorldState::offField): not in the picture.
            if (i < state.offField.size() && state.offField[i]) continue;
            robotPoses[k * robots + i] = robotBefore(state.robots[i], delay);
            subBoxes[k * bodies + i] = robotBox(robots_[i], robotPoses[k * robots + i]);
        }
        ballPoses[k] = ballBefore(state.ball, delay);
        subBoxes[k * bodies + robots] = ballBox(ballPoses[k]);
        for (std::size_t i = 0; i < bodies; ++i) boxes[i] |= subBoxes[k * bodies + i];
    }
    const auto drawSubFrame = [&](int k, cv::Mat& canvas) {
        for (std::size_t i = 0; i < robots; ++i)
            if (!subBoxes[k * bodies + i].empty()) drawRobotOnCanvas(robots_[i], robotPoses[k * robots + i], canvas);
        if (!subBoxes[k * bodies + robots].empty()) drawBallOnCanvas(ballPoses[k], canvas);
    };

    // Stage 1: the canvas, every body's box the mean of its sub-frames (each
    // sub-frame drawn on the empty field, summed exactly in 16 bits, the mean
    // rounded to the nearest level).
    cv::Mat canvas = canvasBackground_.clone();
    if (subFrames == 1) {
        drawSubFrame(0, canvas);
    } else {
        std::vector<cv::Mat> sums(bodies);
        for (std::size_t i = 0; i < bodies; ++i)
            if (!boxes[i].empty()) sums[i] = cv::Mat::zeros(boxes[i].size(), CV_16UC3);
        for (int k = 0; k < subFrames; ++k) {
            if (k > 0)
                for (const cv::Rect& box : boxes)
                    if (!box.empty()) canvasBackground_(box).copyTo(canvas(box));
            drawSubFrame(k, canvas);
            for (std::size_t i = 0; i < bodies; ++i)
                if (!boxes[i].empty()) cv::add(sums[i], canvas(boxes[i]), sums[i], cv::noArray(), CV_16U);
        }
        for (std::size_t i = 0; i < bodies; ++i) {
            if (boxes[i].empty()) continue;
            cv::Mat target = canvas(boxes[i]);
            sums[i].convertTo(target, CV_8U, 1.0 / subFrames);
        }
    }

    // Stages 2 and 3 on each body's output box (overlapping boxes compute
    // the same pixels), onto the background; then stage 4 everywhere.
    background_.copyTo(frame);
    patches.assign(bodies, cv::Rect());
    cv::Mat region;
    for (std::size_t i = 0; i < bodies; ++i) {
        const cv::Rect box = warp_.outputBoxOf(boxes[i]);
        if (box.empty()) continue;
        warp_.warp(canvas, box, region);
        light_.applyAt(region, box.tl());
        region.copyTo(frame(box));
        patches[i] = box;
    }
    noise_.add(frame, frameNumber);
}

std::string cameraProblem(const Scene& scene) {
    try {
        const CameraRenderer renderer(scene);
    } catch (const std::exception& e) {
        return e.what();
    }
    return {};
}

CameraRenderer cameraRendererOrIdeal(const Scene& scene) {
    try {
        return CameraRenderer(scene);
    } catch (const std::exception&) {
        return CameraRenderer(scene, idealCamera());
    }
}

}  // namespace vssim
