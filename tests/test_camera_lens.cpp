// The realistic camera: the lens's projection against OpenCV's own
// (cv::projectPoints, cv::undistortPoints), where bodies appear in a rendered
// image (robot tops at z = side, the ball's centre at z = radius: the
// parallax), the sensor noise's statistics and determinism, the light's gain
// against its formula, the motion blur's streak against v * exposure, the
// patch guarantee through lens, light and blur, and the ideal camera's bytes.
#include <QtTest>

#include <array>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "vssim/camera/camera_lens.h"
#include "vssim/camera/camera_renderer.h"
#include "vssim/camera/image_patches.h"
#include "camera_image_checks.h"
#include "test_support.h"

using namespace vssim;
using test::differenceMask;
using test::patchCoverage;
using test::unionMask;

namespace {

constexpr double kFarAway = 5.0;  // m: a place far outside the image

// Robots far away (out of the picture), the ball too.
Scene sceneOf(int robots) {
    Scene scene;
    for (int i = 0; i < robots; ++i) {
        RobotSpec r = test::robotAt("r", kFarAway, kFarAway + i, 0.0);
        r.name = "r" + std::to_string(i);
        r.team = i < (robots + 1) / 2 ? Team::Yellow : Team::Blue;
        scene.robots.push_back(r);
    }
    scene.ball.x = kFarAway;
    scene.ball.y = -kFarAway;
    return scene;
}

// The realistic preset without noise, blur, or light and colour.
CameraSettings realisticLensOnly() {
    CameraSettings c = realisticCamera();
    c.noise = 0.0, c.exposure = 0.0;
    c.vignetting = 0.0, c.gradient_x = 0.0, c.gradient_y = 0.0;
    c.gain_b = c.gain_g = c.gain_r = 1.0;
    return c;
}

// Random lenses stronger than the preset (still one-to-one over the image).
CameraSettings randomLens(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    CameraSettings c = realisticLensOnly();
    c.height = 1.5 + 1.5 * u(rng);
    c.focal_length = u(rng) < 0.3 ? 0.0 : 450.0 + 500.0 * u(rng);
    c.k1 = -0.35 + 0.45 * u(rng);
    c.k2 = -0.05 + 0.1 * u(rng);
    c.k3 = -0.02 + 0.04 * u(rng);
    c.p1 = -0.003 + 0.006 * u(rng);
    c.p2 = -0.003 + 0.006 * u(rng);
    return c;
}

// Centroid of a weight image in OpenCV's pixel convention (centres at integers).
Eigen::Vector2d centroid(const cv::Mat& weight) {
    const cv::Moments m = cv::moments(weight);
    return {m.m10 / m.m00, m.m01 / m.m00};
}

// A robot-frame point (x forward, y left; m) in the field frame.
Eigen::Vector2d robotPoint(const RobotState& r, double forward, double left) {
    return {r.x + std::cos(r.theta) * forward - std::sin(r.theta) * left,
            r.y + std::sin(r.theta) * forward + std::cos(r.theta) * left};
}

// The gain of light_gain.h's formula, written out here.
double expectedGain(const CameraSettings& c, const CameraLens& lens, int w, int h, double u, double v, int channel) {
    double cornerR2 = 0.0;
    for (const double cu : {0.0, w - 1.0})
        for (const double cv_ : {0.0, h - 1.0})
            cornerR2 = std::max(cornerR2, std::pow(cu - lens.cx, 2) + std::pow(cv_ - lens.cy, 2));
    const double r2 = std::pow(u - lens.cx, 2) + std::pow(v - lens.cy, 2);
    const double gains[3] = {c.gain_b, c.gain_g, c.gain_r};
    return (1.0 - c.vignetting * r2 / cornerR2) * (1.0 + c.gradient_x * (u - lens.cx) / (w / 2.0)) *
           (1.0 + c.gradient_y * (v - lens.cy) / (h / 2.0)) * gains[channel];
}

}  // namespace

class TestCameraLens : public QObject {
    Q_OBJECT
private slots:
    void projectionMatchesOpenCv();
    void undistortionMatchesOpenCv();
    void pinholeWithoutDistortionHasTheIdealFloor();
    void robotTopsAndBallCentresInTheImage();
    void sensorNoiseStatistics();
    void lightGainFollowsItsFormula();
    void motionBlurStreak();
    void patchesRebuildTheFrame();
    void idealCameraBytesUnchanged();
    void badCamerasAreRefused();
    void cameraProblemNamesWhatCannotBeDrawn();
};

void TestCameraLens::projectionMatchesOpenCv() {
    const Scene scene;
    const CameraGeometry geometry = cameraGeometryFor(scene.field);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> x(-0.85, 0.85), y(-0.75, 0.75), z(0.0, 0.1);
    double worst = 0.0;
    for (int lensIndex = 0; lensIndex < 6; ++lensIndex) {
        const CameraSettings settings = lensIndex == 0 ? realisticCamera() : randomLens(rng);
        const CameraLens lens = cameraLensFor(settings, geometry);
        std::vector<cv::Point3d> points;
        for (int i = 0; i < 2000; ++i) points.emplace_back(x(rng), y(rng), z(rng));
        std::vector<cv::Point2d> want;
        cv::projectPoints(points, cameraRotation(lens), cameraTranslation(lens), cameraMatrix(lens),
                          distortionCoefficients(lens), want);
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Eigen::Vector2d got = projectToImage(lens, points[i].x, points[i].y, points[i].z);
            worst = std::max(worst, std::hypot(got.x() - want[i].x, got.y() - want[i].y));
        }
    }
    qInfo("projectToImage vs cv::projectPoints: worst %.2e px over 12000 points, 6 lenses", worst);
    QVERIFY(worst < 0.01);
}

void TestCameraLens::undistortionMatchesOpenCv() {
    const Scene scene;
    const CameraGeometry geometry = cameraGeometryFor(scene.field);
    std::mt19937 rng(18);
    std::uniform_real_distribution<double> x(-0.85, 0.85), y(-0.75, 0.75), z(0.0, 0.1);
    double worstPx = 0.0, worstRoundTrip = 0.0;
    for (int lensIndex = 0; lensIndex < 6; ++lensIndex) {
        const CameraSettings settings = lensIndex == 0 ? realisticCamera() : randomLens(rng);
        const CameraLens lens = cameraLensFor(settings, geometry);
        std::vector<cv::Point2d> pixels;
        std::vector<cv::Point3d> points;
        for (int i = 0; i < 2000; ++i) {
            points.emplace_back(x(rng), y(rng), z(rng));
            const Eigen::Vector2d p = projectToImage(lens, points.back().x, points.back().y, points.back().z);
            pixels.emplace_back(p.x(), p.y());
        }
        std::vector<cv::Point2d> normalised;
        cv::undistortPoints(pixels, normalised, cameraMatrix(lens), distortionCoefficients(lens), cv::noArray(),
                            cv::noArray(),
                            cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12));
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            const Eigen::Vector2d n =
                undistort(lens, Eigen::Vector2d((pixels[i].x - lens.cx) / lens.fx, (pixels[i].y - lens.cy) / lens.fy));
            // Both re-projected without distortion: px.
            worstPx = std::max(worstPx, lens.fx * std::hypot(n.x() - normalised[i].x, n.y() - normalised[i].y));
            const Eigen::Vector2d field = imageToField(lens, pixels[i].x, pixels[i].y, points[i].z);
            worstRoundTrip = std::max(worstRoundTrip, std::hypot(field.x() - points[i].x, field.y() - points[i].y));
        }
    }
    qInfo("undistort vs cv::undistortPoints: worst %.2e px; field -> pixel -> field: worst %.2e m", worstPx,
          worstRoundTrip);
    QVERIFY(worstPx < 0.01);
    QVERIFY(worstRoundTrip < 1e-6);
}

void TestCameraLens::pinholeWithoutDistortionHasTheIdealFloor() {
    // The default focal length puts the floor (z = 0) at the ideal scale:
    // without distortion or light the empty field is the ideal one, byte for byte.
    const Scene scene = sceneOf(2);
    CameraSettings pinhole = realisticLensOnly();
    pinhole.k1 = pinhole.k2 = pinhole.p1 = pinhole.p2 = pinhole.k3 = 0.0;
    const CameraRenderer ideal(scene), flat(scene, pinhole);
    QCOMPARE(cv::norm(ideal.background(), flat.background(), cv::NORM_INF), 0.0);
    // The realistic lens bends it: the wall rows move.
    const CameraRenderer bent(scene, realisticLensOnly());
    QVERIFY(cv::norm(ideal.background(), bent.background(), cv::NORM_INF) > 100.0);
}

void TestCameraLens::robotTopsAndBallCentresInTheImage() {
    Scene scene = sceneOf(1);
    const CameraSettings settings = realisticLensOnly();
    const double side = scene.robots[0].params.side, radius = scene.ball_params.radius;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    // Near the centre and near the image's corners (the largest parallax).
    const std::vector<Eigen::Vector2d> places{{0.0, 0.0}, {0.62, 0.52}, {-0.65, 0.5}, {-0.6, -0.55}, {0.3, -0.2}};
    double worst = 0.0, smallestParallax = INFINITY, smallestBallParallax = INFINITY;
    const CameraRenderer renderer(scene, settings);
    const CameraLens& lens = renderer.lens();
    for (const Eigen::Vector2d& place : places) {
        // The robot alone, then the ball alone (orange passes for yellow).
        WorldState state = initialWorldState(scene);
        state.robots[0] = RobotState{place.x(), place.y(), angle(rng), 0.0, 0.0};
        cv::Mat frame;
        std::vector<cv::Rect> patches;
        renderer.render(state, frame, patches);
        const std::array<std::pair<double, cv::Vec3b>, 2> patchColours{
            {{-0.25 * side, cv::Vec3b(0, 255, 255)}, {0.25 * side, cv::Vec3b(0, 0, 255)}}};  // yellow team, red id
        for (const auto& [forward, colour] : patchColours) {
            const Eigen::Vector2d at = robotPoint(state.robots[0], forward, 0.0);
            const Eigen::Vector2d top = projectToImage(lens, at.x(), at.y(), side);
            const Eigen::Vector2d floor = projectToImage(lens, at.x(), at.y(), 0.0);
            const Eigen::Vector2d seen = centroid(patchCoverage(frame, colour));
            worst = std::max(worst, (seen - top).norm());
            if (place.norm() > 0.5) smallestParallax = std::min(smallestParallax, (seen - floor).norm());
        }
        state.robots[0].x = kFarAway;
        state.ball.x = -place.x(), state.ball.y = -place.y();
        renderer.render(state, frame, patches);
        const Eigen::Vector2d ball = centroid(patchCoverage(frame, cv::Vec3b(0, 128, 255)));
        worst = std::max(worst, (ball - projectToImage(lens, state.ball.x, state.ball.y, radius)).norm());
        if (place.norm() > 0.5)
            smallestBallParallax =
                std::min(smallestBallParallax, (ball - projectToImage(lens, state.ball.x, state.ball.y, 0.0)).norm());
    }
    qInfo(
        "patch and ball centroids vs their projections: worst %.3f px; parallax near the corners: robot tops >= "
        "%.2f px, ball >= %.2f px",
        worst, smallestParallax, smallestBallParallax);
    QVERIFY(worst < 0.5);
    // Off the floor's projection by the parallax: the robot's top is 7.5 cm
    // up (about 7 px at 0.7 m from the centre), the ball's centre 2.1 cm
    // (about 2 px).
    QVERIFY(smallestParallax > 4.0);
    QVERIFY(smallestBallParallax > 1.0);
}

void TestCameraLens::sensorNoiseStatistics() {
    const Scene scene = sceneOf(6);  // every body out of the picture
    const WorldState state = initialWorldState(scene);
    for (const double sigma : {3.0, 12.0}) {
        CameraSettings settings = realisticCamera();
        settings.noise = sigma;
        const CameraRenderer renderer(scene, settings);
        const cv::Mat& bg = renderer.background();
        cv::Mat frame0, frame1, again;
        std::vector<cv::Rect> patches;
        renderer.render(state, frame0, patches, 0);
        for (const cv::Rect& r : patches) QVERIFY(r.empty());
        renderer.render(state, frame1, patches, 1);
        const CameraRenderer copy = renderer;
        copy.render(state, again, patches, 1);
        QCOMPARE(cv::norm(frame1, again, cv::NORM_INF), 0.0);   // same frame number, same bytes
        QVERIFY(cv::norm(frame0, frame1, cv::NORM_INF) > 0.0);  // another frame, other noise

        // Over bytes far from saturation (background 4 sigma inside 0..255).
        double sum = 0.0, sum2 = 0.0, cross = 0.0;
        std::size_t n = 0;
        const uchar *b = bg.ptr(), *f0 = frame0.ptr(), *f1 = frame1.ptr();
        for (std::size_t i = 0; i < bg.total() * 3; ++i) {
            if (b[i] < 4 * sigma || b[i] > 255 - 4 * sigma) continue;
            const double d0 = f0[i] - b[i], d1 = f1[i] - b[i];
            sum += d0, sum2 += d0 * d0, cross += d0 * d1, ++n;
        }
        const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean), correlation = cross / sum2;
        qInfo("noise %.0f: %zu bytes, mean %.4f, standard deviation %.4f, frame-to-frame correlation %.4f", sigma, n,
              mean, sd, correlation);
        QVERIFY(n > 250000);
        QVERIFY(std::abs(mean) < 0.02 * sigma);
        // Whole grey levels: sqrt(sigma^2 + 1/12), within 1 %, and sigma within 5 %.
        QVERIFY(std::abs(sd - std::sqrt(sigma * sigma + 1.0 / 12.0)) < 0.01 * sigma);
        QVERIFY(std::abs(sd - sigma) < 0.05 * sigma);
        QVERIFY(std::abs(correlation) < 0.01);
    }
}

void TestCameraLens::lightGainFollowsItsFormula() {
    const Scene scene = sceneOf(1);
    CameraSettings strong = realisticLensOnly();
    strong.vignetting = 0.6, strong.gradient_x = 0.3, strong.gradient_y = -0.2;
    strong.gain_b = 0.8, strong.gain_g = 1.0, strong.gain_r = 1.3;
    CameraSettings preset = realisticCamera();
    preset.noise = 0.0, preset.exposure = 0.0;
    for (const CameraSettings& settings : {preset, strong}) {
        const CameraRenderer renderer(scene, settings), unlit(scene, realisticLensOnly());
        const cv::Mat &bg = renderer.background(), &flat = unlit.background();
        const int w = bg.cols, h = bg.rows;
        // Every pixel of the image's border sees the outside (70), and one
        // patch of floor (20) by the centre, left of the centre line.
        std::vector<cv::Point> pixels;
        for (int u = 0; u < w; ++u) pixels.emplace_back(u, 0), pixels.emplace_back(u, h - 1);
        for (int v = 1; v + 1 < h; ++v) pixels.emplace_back(0, v), pixels.emplace_back(w - 1, v);
        for (int v = 220; v < 260; ++v)
            for (int u = 280; u < 310; ++u) pixels.emplace_back(u, v);
        int worst = 0;
        for (const cv::Point& p : pixels) {
            const cv::Vec3b before = flat.at<cv::Vec3b>(p), after = bg.at<cv::Vec3b>(p);
            QVERIFY(before == cv::Vec3b(70, 70, 70) || before == cv::Vec3b(20, 20, 20));
            for (int c = 0; c < 3; ++c) {
                const double gain = expectedGain(settings, renderer.lens(), w, h, p.x, p.y, c);
                const int want = static_cast<int>(std::min(255.0, std::round(before[c] * gain)));
                worst = std::max(worst, std::abs(after[c] - want));
            }
        }
        QVERIFY(worst <= 1);
        // The corner is darker than the centre (the vignetting), by the formula.
        const cv::Vec3b corner = bg.at<cv::Vec3b>(0, 0), centre = bg.at<cv::Vec3b>(240, 300);
        QVERIFY(corner[1] < 70 * (1.0 - 0.5 * settings.vignetting));
        QVERIFY(std::abs(centre[1] - 20 * expectedGain(settings, renderer.lens(), w, h, 300, 240, 1)) <= 1.0);
    }
}

void TestCameraLens::motionBlurStreak() {
    Scene scene = sceneOf(1);
    const double side = scene.robots[0].params.side;
    CameraSettings blurred = realisticLensOnly();
    blurred.exposure = 0.010, blurred.blur_samples = 6;
    const CameraRenderer sharp(scene, realisticLensOnly()), blurry(scene, blurred);
    const CameraLens& lens = blurry.lens();
    cv::Mat still, moving, stillBlurred;
    std::vector<cv::Rect> patches;

    // At rest, the blur changes nothing (robot and ball).
    WorldState state = initialWorldState(scene);
    state.robots[0] = RobotState{0.3, 0.2, 0.4, 0.0, 0.0};
    state.ball.x = -0.2, state.ball.y = 0.1;
    sharp.render(state, still, patches);
    blurry.render(state, stillBlurred, patches);
    QCOMPARE(cv::norm(still, stillBlurred, cv::NORM_INF), 0.0);

    // Moving along +x at 3 m/s for 10 ms: a 3 cm streak behind it. The
    // extent of what differs from the background, along the row through the
    // robot's centre, grows by the image of 3 cm at the robot's top.
    const double v = 3.0;
    const double x = 0.45;  // m, clear of the centre circle (r = 0.2 m)
    state.robots[0] = RobotState{x, 0.0, 0.0, v, 0.0};
    state.ball.x = kFarAway;
    sharp.render(state, still, patches);
    blurry.render(state, moving, patches);
    // Along the row through the robot's centre, in blue (0 on the whole
    // robot, 20 on the floor): each edge's position from the robot's
    // coverage summed over the pixels (pixel u covers [u - 0.5, u + 0.5]):
    // a rear edge at e covers sum = m + 0.5 - e of the pixels a..m, a front
    // edge sum = e - m + 0.5 of m..b. Linear in the image, so a blurred edge
    // (each a ramp) lies at the mean of its sub-frames' edges, v exposure / 2
    // behind the still one (through the lens: a rear edge on the floor,
    // z = 0, a front edge on the top, z = side, on this side of the image).
    const int row = static_cast<int>(std::lround(projectToImage(lens, x, 0.0, side).y()));
    const int middle = static_cast<int>(std::lround(projectToImage(lens, x, 0.0, side).x()));
    const auto edge = [&](const cv::Mat& frame, bool rear) {
        const auto cover = [&](int u) { return (20.0 - frame.at<cv::Vec3b>(row, u)[0]) / 20.0; };
        double sum = 0.0;
        for (int u = rear ? middle - 50 : middle; u <= (rear ? middle : middle + 50); ++u) sum += cover(u);
        return rear ? middle + 0.5 - sum : middle - 0.5 + sum;
    };
    const double rearFace = x - side / 2, frontFace = x + side / 2;  // m
    const double rearNow = projectToImage(lens, rearFace, 0.0, 0.0).x();
    const double frontNow = projectToImage(lens, frontFace, 0.0, side).x();
    double rearMean = 0.0, frontMean = 0.0;  // px, the sub-frames' mean
    for (int k = 0; k < 6; ++k) {
        const double back = v * 0.010 * k / 5;  // m
        rearMean += projectToImage(lens, rearFace - back, 0.0, 0.0).x() / 6;
        frontMean += projectToImage(lens, frontFace - back, 0.0, side).x() / 6;
    }
    const double stillRear = edge(still, true), stillFront = edge(still, false);
    const double movingRear = edge(moving, true), movingFront = edge(moving, false);
    qInfo(
        "edges: still %.2f .. %.2f px (the lens: %.2f .. %.2f); blurred, moved by %.2f and %.2f px (the sub-frames' "
        "mean: %.2f and %.2f)",
        stillRear, stillFront, rearNow, frontNow, movingRear - stillRear, movingFront - stillFront, rearMean - rearNow,
        frontMean - frontNow);
    // OpenCV's anti-aliased fill widens a polygon by about half a pixel.
    QVERIFY(std::abs(stillRear - rearNow) < 0.8 && std::abs(stillFront - frontNow) < 0.8);
    QVERIFY(std::abs((movingRear - stillRear) - (rearMean - rearNow)) < 0.2);
    QVERIFY(std::abs((movingFront - stillFront) - (frontMean - frontNow)) < 0.2);
    // What differs from the background reaches from the pose at t - exposure
    // to the pose at t: longer by v exposure (less the faint anti-aliased
    // fringe of the oldest sub-frame, a sixth of its coverage).
    const auto extent = [&](const cv::Mat& frame, const cv::Mat& bg) {
        std::vector<cv::Point> at;
        cv::findNonZero(differenceMask(frame, bg).row(row), at);
        int lo = INT32_MAX, hi = INT32_MIN;
        for (const cv::Point& p : at) lo = std::min(lo, p.x), hi = std::max(hi, p.x);
        return hi - lo + 1;
    };
    const double streak =
        projectToImage(lens, rearFace, 0.0, 0.0).x() - projectToImage(lens, rearFace - v * 0.010, 0.0, 0.0).x();
    const int longer = extent(moving, blurry.background()) - extent(still, sharp.background());
    qInfo("the changed pixels reach %d px further (v exposure through the lens: %.2f px)", longer, streak);
    QVERIFY(longer <= streak + 0.5 && longer >= streak - 2.5);
    // Half-way along the streak behind the still rear edge (covered in some
    // sub-frames only) the pixel is a blend, neither body (0) nor floor (20).
    const int halfway = static_cast<int>(std::lround(rearNow - streak / 2));
    const int blend = moving.at<cv::Vec3b>(row, halfway)[0];
    QVERIFY(blend > 3 && blend < 17);
}

void TestCameraLens::patchesRebuildTheFrame() {
    const Scene scene = sceneOf(6);
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> x(-1.0, 1.0), y(-0.8, 0.8), angle(-M_PI, M_PI), speed(-2.5, 2.5),
        turn(-15.0, 15.0);
    CameraSettings preset = realisticCamera();
    preset.noise = 0.0;
    std::vector<CameraSettings> cameras{preset};
    for (int i = 0; i < 2; ++i) {
        CameraSettings c = randomLens(rng);
        c.vignetting = 0.4, c.gradient_x = -0.2, c.gradient_y = 0.1, c.gain_r = 1.3;
        c.exposure = 0.02, c.blur_samples = 5;
        cameras.push_back(c);
    }
    CameraSettings orthographic = preset;
    orthographic.projection = CameraProjection::Orthographic;
    orthographic.k1 = orthographic.k2 = orthographic.p1 = orthographic.p2 = orthographic.k3 = 0.0;
    cameras.push_back(orthographic);
    int empty = 0, edge = 0;
    for (const CameraSettings& camera : cameras) {
        const CameraRenderer renderer(scene, camera);
        const cv::Mat& bg = renderer.background();
        const cv::Rect image(0, 0, bg.cols, bg.rows);
        cv::Mat frame;
        std::vector<cv::Rect> patches;
        for (int trial = 0; trial < 150; ++trial) {
            WorldState state = initialWorldState(scene);
            for (RobotState& r : state.robots) r = RobotState{x(rng), y(rng), angle(rng), speed(rng), turn(rng)};
            state.ball = BallState{x(rng), y(rng), speed(rng), speed(rng)};
            renderer.render(state, frame, patches, static_cast<std::uint64_t>(trial));
            QCOMPARE(int(patches.size()), renderer.bodyCount());
            for (const cv::Rect& r : patches) {
                QVERIFY(r.empty() ? r == cv::Rect() : (r & image) == r);
                empty += r.empty();
                edge += !r.empty() && (r.x == 0 || r.y == 0 || r.br().x == bg.cols || r.br().y == bg.rows);
            }
            cv::Mat outside;
            cv::bitwise_and(differenceMask(frame, bg), ~unionMask(bg.size(), patches), outside);
            QCOMPARE(cv::countNonZero(outside), 0);
            cv::Mat canvas = bg.clone();
            const std::vector<cv::Mat> crops = cropPatches(frame, patches);
            for (std::size_t i = 0; i < patches.size(); ++i) QVERIFY(pastePatch(canvas, patches[i], crops[i]));
            QCOMPARE(cv::norm(canvas, frame, cv::NORM_INF), 0.0);
        }
    }
    qInfo("%d empty patches, %d at the image's edge", empty, edge);
    QVERIFY(empty > 0 && edge > 0);
}

void TestCameraLens::idealCameraBytesUnchanged() {
    Scene scene = sceneOf(6);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> x(-0.7, 0.7), y(-0.6, 0.6), angle(-M_PI, M_PI);
    WorldState state = initialWorldState(scene);
    for (RobotState& r : state.robots) r = RobotState{x(rng), y(rng), angle(rng), 1.0, 2.0};
    state.ball = BallState{x(rng), y(rng), 1.0, 0.0};
    Scene realisticScene = scene;
    realisticScene.camera = realisticCamera();
    const CameraRenderer byScene(scene), explicitIdeal(scene, idealCamera()), overridden(realisticScene, idealCamera());
    const CameraRenderer realistic(realisticScene), explicitRealistic(scene, realisticCamera());
    cv::Mat a, b, c, d, e;
    std::vector<cv::Rect> pa, pb, pc, pd, pe;
    byScene.render(state, a, pa, 7);
    explicitIdeal.render(state, b, pb, 8);  // the ideal camera ignores the frame number
    overridden.render(state, c, pc);
    realistic.render(state, d, pd, 7);
    explicitRealistic.render(state, e, pe, 7);
    QCOMPARE(cv::norm(a, b, cv::NORM_INF), 0.0);
    QCOMPARE(cv::norm(a, c, cv::NORM_INF), 0.0);
    QVERIFY(pa == pb && pa == pc);
    QCOMPARE(cv::norm(d, e, cv::NORM_INF), 0.0);  // the scene's camera is the one given
    QVERIFY(pd == pe);
    QVERIFY(cv::norm(a, d, cv::NORM_INF) > 0.0);
    QVERIFY(byScene.settings() == idealCamera() && realistic.settings() == realisticCamera());
}

void TestCameraLens::badCamerasAreRefused() {
    const Scene scene = sceneOf(1);
    const auto refused = [&](const CameraSettings& c, const char* words) {
        try {
            CameraRenderer renderer(scene, c);
        } catch (const std::invalid_argument& e) {
            if (QString(e.what()).contains(words)) return true;
            qWarning("unexpected message: %s", e.what());
            return false;
        }
        return false;
    };
    CameraSettings folding = realisticCamera();
    folding.k1 = 1.0, folding.k2 = -1.0;  // r_d = r (1 + r^2 - r^4) turns back within the image
    folding.focal_length = 250.0;
    QVERIFY(refused(folding, "distortion"));
    CameraSettings low = realisticCamera();
    low.height = 0.05;  // below the robots' tops
    QVERIFY(refused(low, "height"));
    CameraSettings noisy = realisticCamera();
    noisy.noise = -1.0;
    QVERIFY(refused(noisy, "noise"));
    CameraSettings blur = realisticCamera();
    blur.blur_samples = 0;
    QVERIFY(refused(blur, "blur_samples"));
}

void TestCameraLens::cameraProblemNamesWhatCannotBeDrawn() {
    Scene scene = sceneOf(2);
    scene.camera = realisticCamera();
    QCOMPARE(cameraProblem(scene), std::string());
    // k1 = -1 is within the scene file's range, yet folds the image over near its corners.
    scene.camera.k1 = -1.0;
    const std::string folding = cameraProblem(scene);
    QVERIFY2(folding.find("distortion") != std::string::npos, folding.c_str());
    // A thread handed such a scene anyway draws with the ideal camera instead of dying.
    const CameraRenderer fallback = cameraRendererOrIdeal(scene);
    QVERIFY(fallback.settings() == idealCamera());
    // Robots as tall as the camera is high.
    scene.camera = realisticCamera();
    scene.camera.height = 0.5;
    for (RobotSpec& r : scene.robots) r.params.side = 0.6;
    const std::string low = cameraProblem(scene);
    QVERIFY2(low.find("height") != std::string::npos, low.c_str());
    QVERIFY(cameraRendererOrIdeal(scene).settings() == idealCamera());
    // The ideal camera has nothing to refuse.
    scene.camera = idealCamera();
    QCOMPARE(cameraProblem(scene), std::string());
}

QTEST_GUILESS_MAIN(TestCameraLens)
#include "test_camera_lens.moc"
