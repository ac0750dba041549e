// The synthetic overhead camera: pixel geometry, the colours of the field and
// the bodies, heading recovery by thresholding, the patch guarantee (pasting
// the patches onto the background rebuilds the frame), determinism, and the
// image encodings.
#include <QtTest>

#include <array>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "vssim/camera/field_background.h"

#include "vssim/camera/camera_geometry.h"
#include "vssim/camera/camera_renderer.h"
#include "vssim/camera/image_codec.h"
#include "vssim/camera/image_patches.h"
#include "io/scene_io.h"
#include "camera_image_checks.h"
#include "test_support.h"

using namespace vssim;
using test::differenceMask;
using test::patchCoverage;
using test::unionMask;

namespace {

// The colours as the protocol states them, BGR (written out here, not taken
// from camera_colours.h, so that a wrong constant fails).
const cv::Vec3b kFloor(20, 20, 20), kOutside(70, 70, 70), kWall(200, 200, 200);
const cv::Vec3b kYellow(0, 255, 255), kBlue(255, 0, 0), kOrange(0, 128, 255);
const std::array<cv::Vec3b, 6> kIdentity{
    {{0, 0, 255}, {0, 255, 0}, {255, 0, 255}, {255, 255, 0}, {255, 255, 255}, {128, 0, 128}}};

constexpr double kFarAway = 5.0;  // m: a place far outside the image

// The pixel (column, row) that contains field point (x, y).
cv::Point pixelAt(const CameraGeometry& camera, double x, double y) {
    const Eigen::Vector2d p = toPixel(camera, x, y);
    return {static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y()))};
}

cv::Vec3b colourAt(const cv::Mat& image, cv::Point pixel) { return image.at<cv::Vec3b>(pixel); }

Scene sceneOf(const std::vector<Team>& teams) {
    Scene scene;
    for (std::size_t i = 0; i < teams.size(); ++i) {
        RobotSpec r = test::robotAt("r", kFarAway, kFarAway, 0.0);
        r.name = "r" + std::to_string(i);
        r.team = teams[i];
        scene.robots.push_back(r);
    }
    scene.ball.x = kFarAway;
    return scene;
}

// Centroid of a weight image in continuous pixel coordinates (pixel centres at +0.5).
Eigen::Vector2d centroid(const cv::Mat& weight) {
    const cv::Moments m = cv::moments(weight);
    return {m.m10 / m.m00 + 0.5, m.m01 / m.m00 + 0.5};
}

// A robot-frame point (x forward, y left; m) in the field frame, written out
// here rather than taken from the engine.
Eigen::Vector2d robotPoint(const RobotState& r, double forward, double left) {
    return {r.x + std::cos(r.theta) * forward - std::sin(r.theta) * left,
            r.y + std::sin(r.theta) * forward + std::cos(r.theta) * left};
}

double angleDifference(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

// A random pose: anywhere inside the field, pressed against a wall, or
// anywhere around the image (across its edge, or wholly outside it).
RobotState randomRobotPose(std::mt19937& rng, const Field& field, double side) {
    std::uniform_real_distribution<double> unit(0.0, 1.0), angle(-M_PI, M_PI);
    RobotState pose;
    pose.theta = angle(rng);
    const double hx = field.length / 2, hy = field.width / 2;
    // Half the extent of the rotated square along x (and y).
    const double extent = 0.5 * side * (std::abs(std::cos(pose.theta)) + std::abs(std::sin(pose.theta)));
    const double mode = unit(rng);
    if (mode < 0.5) {
        pose.x = (2 * unit(rng) - 1) * (hx - extent);
        pose.y = (2 * unit(rng) - 1) * (hy - extent);
    } else if (mode < 0.8) {
        const int wall = std::uniform_int_distribution<int>(0, 3)(rng);
        const double along = 2 * unit(rng) - 1;
        if (wall < 2) {
            pose.x = (wall == 0 ? -1 : 1) * (hx - extent);
            pose.y = along * (hy - extent);
        } else {
            pose.x = along * (hx - extent);
            pose.y = (wall == 2 ? -1 : 1) * (hy - extent);
        }
    } else {
        pose.x = (2 * unit(rng) - 1) * 1.05;  // the image spans about +-0.95 m in x
        pose.y = (2 * unit(rng) - 1) * 0.80;  // and +-0.71 m in y
    }
    return pose;
}

WorldState randomState(std::mt19937& rng, const Scene& scene) {
    WorldState state = initialWorldState(scene);
    for (std::size_t i = 0; i < state.robots.size(); ++i)
        state.robots[i] = randomRobotPose(rng, scene.field, scene.robots[i].params.side);
    // The ball placed like a square of side 2r: near the walls, not always touching them.
    const RobotState ballPlace = randomRobotPose(rng, scene.field, 2 * scene.ball_params.radius);
    state.ball.x = ballPlace.x;
    state.ball.y = ballPlace.y;
    return state;
}

const std::vector<Team> kThreeVersusThree{Team::Yellow, Team::Yellow, Team::Yellow, Team::Blue, Team::Blue, Team::Blue};

}  // namespace

class TestCamera : public QObject {
    Q_OBJECT
private slots:
    void geometryClosedForms();
    void backgroundColours();
    void patchColoursAtCentroids();
    void headingFromPatchCentroids();
    void ballCentreIsOrange();
    void patchesRebuildTheFrame();
    void patchOfEachBodyHoldsItsDrawing();
    void bodyOutsideTheImageHasEmptyPatch();
    void renderingIsDeterministic();
    void rawAndPngAreLossless();
    void storedPngIsLossless();
    void jpegIsClose();
    void decodeRejectsBadData();
    void encodingNames();
    void kickoffPatchFraction();
    void geometryIncludesTheGoals();
    void officialFieldBackground();
    void markingsFollowTheDimensions();
    void boxBackgroundUnchanged();
};

void TestCamera::geometryClosedForms() {
    const Field field = makeRectangularField(1.50, 1.30);
    const CameraGeometry camera = cameraGeometryFor(field);
    QCOMPARE(camera.width, 640);
    QCOMPARE(camera.height, 480);
    // min(600 / 1.5, 440 / 1.3) = min(400, 4400 / 13): the width binds.
    QVERIFY(std::abs(camera.scale - 4400.0 / 13.0) < 1e-9);
    QCOMPARE(camera.centreU, 320.0);
    QCOMPARE(camera.centreV, 240.0);
    QVERIFY((toPixel(camera, 0, 0) - Eigen::Vector2d(320, 240)).norm() < 1e-12);
    // Corners: the field's top and bottom edges sit 20 px from the image's.
    const double halfLengthPx = 0.75 * 4400.0 / 13.0;
    QVERIFY((toPixel(camera, -0.75, 0.65) - Eigen::Vector2d(320 - halfLengthPx, 20)).norm() < 1e-9);
    QVERIFY((toPixel(camera, 0.75, 0.65) - Eigen::Vector2d(320 + halfLengthPx, 20)).norm() < 1e-9);
    QVERIFY((toPixel(camera, -0.75, -0.65) - Eigen::Vector2d(320 - halfLengthPx, 460)).norm() < 1e-9);
    QVERIFY((toPixel(camera, 0.75, -0.65) - Eigen::Vector2d(320 + halfLengthPx, 460)).norm() < 1e-9);

    // A long field in a wide image: the length binds, 20 px margins left and right.
    const CameraGeometry wide = cameraGeometryFor(makeRectangularField(3.0, 0.5), 800, 600);
    QVERIFY(std::abs(wide.scale - 760.0 / 3.0) < 1e-9);
    QVERIFY(std::abs(toPixel(wide, -1.5, 0).x() - 20.0) < 1e-9);
    QVERIFY(std::abs(toPixel(wide, 1.5, 0).x() - 780.0) < 1e-9);

    std::mt19937 rng(7);
    std::uniform_real_distribution<double> any(-2.0, 2.0);
    for (int k = 0; k < 1000; ++k) {
        const Eigen::Vector2d p(any(rng), any(rng));
        const Eigen::Vector2d px = toPixel(camera, p.x(), p.y());
        QVERIFY((toField(camera, px.x(), px.y()) - p).norm() < 1e-12);
    }
}

void TestCamera::backgroundColours() {
    const Scene scene = sceneOf({});
    const CameraRenderer renderer(scene);
    const cv::Mat& bg = renderer.background();
    const CameraGeometry& camera = renderer.geometry();
    QCOMPARE(bg.type(), CV_8UC3);
    QCOMPARE(bg.rows, 480);
    QCOMPARE(bg.cols, 640);
    // Floor away from the centre line, the centre circle (r 0.2 m) and the walls.
    for (auto [x, y] : {std::pair{0.4, 0.3}, {-0.4, -0.3}, {0.05, 0.0}, {-0.6, 0.5}})
        QCOMPARE(colourAt(bg, pixelAt(camera, x, y)), kFloor);
    // Just inside and just outside the bottom wall (6.8 px either side of it).
    QCOMPARE(colourAt(bg, pixelAt(camera, 0.4, -0.65 + 0.02)), kFloor);
    QCOMPARE(colourAt(bg, pixelAt(camera, 0.4, -0.65 - 0.02)), kOutside);
    QCOMPARE(colourAt(bg, pixelAt(camera, 0.75 + 0.02, 0.3)), kOutside);
    for (cv::Point corner : {cv::Point(0, 0), cv::Point(639, 0), cv::Point(0, 479), cv::Point(639, 479)})
        QCOMPARE(colourAt(bg, corner), kOutside);
    // The bottom wall lies on v = 460: a 3 px line covers rows 459 and 460 wholly.
    const int column = pixelAt(camera, 0.4, 0.0).x;
    QCOMPARE(colourAt(bg, {column, 459}), kWall);
    QCOMPARE(colourAt(bg, {column, 460}), kWall);
    // The centre line (u = 320, between columns 319 and 320) brightens them.
    QVERIFY(cv::norm(colourAt(bg, {319, 240 - 100})) + cv::norm(colourAt(bg, {320, 240 - 100})) >
            2 * cv::norm(kFloor) + 200);
}

void TestCamera::patchColoursAtCentroids() {
    // Seven yellow robots (identity colours cycle after six) and two blue.
    std::vector<Team> teams(7, Team::Yellow);
    teams.push_back(Team::Blue);
    teams.push_back(Team::Blue);
    const Scene scene = sceneOf(teams);
    const CameraRenderer renderer(scene);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI);
    WorldState state = initialWorldState(scene);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    for (int trial = 0; trial < 20; ++trial) {
        for (std::size_t i = 0; i < state.robots.size(); ++i) {  // a 5 x 2 grid, 0.25 m apart
            state.robots[i] = RobotState{-0.5 + 0.25 * (i % 5), i < 5 ? 0.35 : -0.35, angle(rng)};
        }
        renderer.render(state, frame, patches);
        for (std::size_t i = 0; i < state.robots.size(); ++i) {
            const RobotState& r = state.robots[i];
            const double s = scene.robots[i].params.side;
            const Eigen::Vector2d team = robotPoint(r, -0.25 * s, 0.0);
            const Eigen::Vector2d id = robotPoint(r, 0.25 * s, 0.0);
            const int indexInTeam = i < 7 ? int(i) : int(i) - 7;
            QCOMPARE(colourAt(frame, pixelAt(renderer.geometry(), team.x(), team.y())), i < 7 ? kYellow : kBlue);
            QCOMPARE(colourAt(frame, pixelAt(renderer.geometry(), id.x(), id.y())), kIdentity[indexInTeam % 6]);
        }
    }
}

void TestCamera::headingFromPatchCentroids() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI), ux(0.3, 0.6), uy(-0.5, 0.5);
    std::uniform_int_distribution<int> identity(0, 5), blue(0, 1);
    double worstDegrees = 0.0, worstCentrePx = 0.0;
    for (int trial = 0; trial < 300; ++trial) {
        // Robot number k of its team, the others of the team out of sight.
        const Team team = blue(rng) ? Team::Blue : Team::Yellow;
        const int k = identity(rng);
        const Scene scene = sceneOf(std::vector<Team>(k + 1, team));
        const CameraRenderer renderer(scene);
        WorldState state = initialWorldState(scene);
        RobotState& robot = state.robots[k];
        robot = RobotState{(blue(rng) ? 1 : -1) * ux(rng), uy(rng), angle(rng)};
        cv::Mat frame;
        std::vector<cv::Rect> patches;
        renderer.render(state, frame, patches);

        // Threshold inside the robot's patch only, as a vision client would
        // (a white identity patch would match the walls elsewhere).
        const cv::Rect box = patches[k];
        const Eigen::Vector2d corner(box.x, box.y);
        const Eigen::Vector2d teamCentre =
            corner + centroid(patchCoverage(frame(box), team == Team::Blue ? kBlue : kYellow));
        const Eigen::Vector2d idCentre = corner + centroid(patchCoverage(frame(box), kIdentity[k]));
        const Eigen::Vector2d d = idCentre - teamCentre;
        const double heading = std::atan2(-d.y(), d.x());  // v points down
        worstDegrees = std::max(worstDegrees, angleDifference(heading, robot.theta) * 180.0 / M_PI);
        const Eigen::Vector2d centre = 0.5 * (teamCentre + idCentre);
        worstCentrePx = std::max(worstCentrePx, (centre - toPixel(renderer.geometry(), robot.x, robot.y)).norm());
    }
    qInfo("heading from patch centroids: worst error %.2f deg, centre %.2f px", worstDegrees, worstCentrePx);
    QVERIFY(worstDegrees < 2.0);
    QVERIFY(worstCentrePx < 0.25);
}

void TestCamera::ballCentreIsOrange() {
    const Scene scene = sceneOf({Team::Yellow});
    const CameraRenderer renderer(scene);
    WorldState state = initialWorldState(scene);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    for (auto [x, y] : {std::pair{0.0, 0.0}, {0.3, -0.2}, {-0.7, 0.6}}) {
        state.ball.x = x;
        state.ball.y = y;
        renderer.render(state, frame, patches);
        QCOMPARE(colourAt(frame, pixelAt(renderer.geometry(), x, y)), kOrange);
        // The disc's area is pi r^2 in px^2, to within its rim.
        const double r = scene.ball_params.radius * renderer.geometry().scale;
        cv::Mat orange;
        cv::inRange(frame, cv::Scalar(0, 64, 128), cv::Scalar(127, 191, 255), orange);
        QVERIFY(std::abs(cv::countNonZero(orange) - M_PI * r * r) < 2 * M_PI * r);
        QCOMPARE(patches.size(), std::size_t(2));
        QVERIFY(patches[1].contains(pixelAt(renderer.geometry(), x, y)));
    }
}

void TestCamera::patchesRebuildTheFrame() {
    const Scene scene = sceneOf(kThreeVersusThree);
    const CameraRenderer renderer(scene);
    const cv::Mat& bg = renderer.background();
    const cv::Rect image(0, 0, bg.cols, bg.rows);
    std::mt19937 rng(2024);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    const uchar* memory = nullptr;
    int emptyPatches = 0, edgePatches = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const WorldState state = randomState(rng, scene);
        renderer.render(state, frame, patches);
        if (trial == 0) memory = frame.data;
        QCOMPARE(frame.data, memory);  // the frame's memory is reused
        QCOMPARE(int(patches.size()), renderer.bodyCount());
        QCOMPARE(patches.size(), state.robots.size() + 1);
        for (const cv::Rect& r : patches) {
            QVERIFY(r.empty() ? r == cv::Rect() : (r & image) == r);
            emptyPatches += r.empty();
            edgePatches += !r.empty() && (r.x == 0 || r.y == 0 || r.br().x == bg.cols || r.br().y == bg.rows);
        }

        // Outside the union of the patches, the frame is the background.
        const cv::Mat changed = differenceMask(frame, bg);
        cv::Mat outside;
        cv::bitwise_and(changed, ~unionMask(bg.size(), patches), outside);
        QCOMPARE(cv::countNonZero(outside), 0);

        // Pasting the cropped patches in order onto the background rebuilds the frame.
        cv::Mat canvas = bg.clone();
        const std::vector<cv::Mat> crops = cropPatches(frame, patches);
        for (std::size_t i = 0; i < patches.size(); ++i) QVERIFY(pastePatch(canvas, patches[i], crops[i]));
        QCOMPARE(cv::norm(canvas, frame, cv::NORM_INF), 0.0);
    }
    qInfo("%d empty patches, %d patches at the image edge", emptyPatches, edgePatches);
    QVERIFY(emptyPatches > 0);
    QVERIFY(edgePatches > 0);

    // pastePatch refuses what does not fit, and leaves the canvas alone.
    cv::Mat canvas = bg.clone();
    QVERIFY(!pastePatch(canvas, cv::Rect(630, 470, 20, 20), cv::Mat(20, 20, CV_8UC3)));
    QVERIFY(!pastePatch(canvas, cv::Rect(-1, 0, 5, 5), cv::Mat(5, 5, CV_8UC3)));
    QVERIFY(!pastePatch(canvas, cv::Rect(10, 10, 5, 5), cv::Mat(5, 6, CV_8UC3)));
    QVERIFY(!pastePatch(canvas, cv::Rect(10, 10, 5, 5), cv::Mat(5, 5, CV_8UC1)));
    QCOMPARE(cv::norm(canvas, bg, cv::NORM_INF), 0.0);
}

void TestCamera::patchOfEachBodyHoldsItsDrawing() {
    // One body in sight at a time: everything it changes lies in its own
    // patch, and the patch is not much larger than the body.
    const Scene scene = sceneOf(kThreeVersusThree);
    const CameraRenderer renderer(scene);
    const double scale = renderer.geometry().scale;
    std::mt19937 rng(99);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    for (int trial = 0; trial < 300; ++trial) {
        WorldState state = randomState(rng, scene);
        const std::size_t body = trial % (state.robots.size() + 1);
        for (std::size_t i = 0; i < state.robots.size(); ++i)
            if (i != body) state.robots[i].x = kFarAway;
        if (body != state.robots.size()) state.ball.x = kFarAway;
        renderer.render(state, frame, patches);
        cv::Mat outside;
        cv::bitwise_and(differenceMask(frame, renderer.background()), ~unionMask(frame.size(), {patches[body]}),
                        outside);
        QCOMPARE(cv::countNonZero(outside), 0);
        const double size =
            body < state.robots.size() ? std::sqrt(2.0) * scene.robots[body].params.side : 2 * scene.ball_params.radius;
        QVERIFY(patches[body].width <= size * scale + 6 && patches[body].height <= size * scale + 6);
        for (std::size_t i = 0; i < patches.size(); ++i)
            if (i != body) QVERIFY(patches[i].empty());
    }
}

void TestCamera::bodyOutsideTheImageHasEmptyPatch() {
    const Scene scene = sceneOf(kThreeVersusThree);
    const CameraRenderer renderer(scene);
    WorldState state = initialWorldState(scene);  // everything at kFarAway but robot 2 and the ball
    state.robots[2] = RobotState{0.1, 0.2, 0.5};
    state.robots[4] = RobotState{std::nan(""), 0.0, 0.0};  // not finite: not drawn
    state.ball.x = -0.3;
    state.ball.y = 0.0;
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    renderer.render(state, frame, patches);
    QCOMPARE(patches.size(), std::size_t(7));
    for (int i : {0, 1, 3, 4, 5}) QCOMPARE(patches[i], cv::Rect());
    QVERIFY(!patches[2].empty() && !patches[6].empty());
    // A robot just beyond the image edge (its spill margin included) has an empty patch too.
    const double beyond = toField(renderer.geometry(), 640 + 3 + 10, 0).x() + 0.75 * 0.075;
    state.robots[4] = RobotState{beyond, 0.0, 0.0};
    renderer.render(state, frame, patches);
    QCOMPARE(patches[4], cv::Rect());

    WorldState wrong = state;
    wrong.robots.pop_back();
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, renderer.render(wrong, frame, patches));
}

void TestCamera::renderingIsDeterministic() {
    const Scene scene = sceneOf(kThreeVersusThree);
    const CameraRenderer first(scene), second(scene);
    QCOMPARE(cv::norm(first.background(), second.background(), cv::NORM_INF), 0.0);
    std::mt19937 rng(5);
    const WorldState a = randomState(rng, scene), b = randomState(rng, scene);
    cv::Mat frameA, frameB, again;
    std::vector<cv::Rect> patchesA, patchesB, patchesAgain;
    first.render(a, frameA, patchesA);
    second.render(b, frameB, patchesB);
    QVERIFY(cv::norm(frameA, frameB, cv::NORM_INF) > 0);
    second.render(a, frameB, patchesB);  // reusing a frame that held another state
    first.render(a, again, patchesAgain);
    QCOMPARE(cv::norm(frameA, frameB, cv::NORM_INF), 0.0);
    QCOMPARE(cv::norm(frameA, again, cv::NORM_INF), 0.0);
    QVERIFY(patchesA == patchesB && patchesA == patchesAgain);
    // A frame that shares the background's memory gets its own: the background stays empty.
    const cv::Mat emptyField = first.background().clone();
    cv::Mat shared = first.background();
    first.render(a, shared, patchesA);
    QCOMPARE(cv::norm(shared, frameA, cv::NORM_INF), 0.0);
    QCOMPARE(cv::norm(first.background(), emptyField, cv::NORM_INF), 0.0);
}

namespace {
cv::Mat someFrame(std::uint32_t seed) {
    const Scene scene = sceneOf(kThreeVersusThree);
    std::mt19937 rng(seed);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    CameraRenderer(scene).render(randomState(rng, scene), frame, patches);
    return frame;
}
}  // namespace

void TestCamera::rawAndPngAreLossless() {
    const cv::Mat frame = someFrame(1);
    const std::vector<std::uint8_t> raw = encodeImage(frame, ImageEncoding::Raw);
    QCOMPARE(raw.size(), std::size_t(640 * 480 * 3));
    // Rows top to bottom, each pixel B, G, R.
    for (cv::Point p : {cv::Point(0, 0), cv::Point(639, 0), cv::Point(17, 300), cv::Point(639, 479)})
        for (int c = 0; c < 3; ++c) QCOMPARE(raw[(std::size_t(p.y) * 640 + p.x) * 3 + c], frame.at<cv::Vec3b>(p)[c]);
    cv::Mat decoded;
    std::string error;
    QVERIFY(decodeImage(raw.data(), raw.size(), ImageEncoding::Raw, 640, 480, decoded, &error));
    QCOMPARE(cv::norm(decoded, frame, cv::NORM_INF), 0.0);

    const std::vector<std::uint8_t> png = encodeImage(frame, ImageEncoding::Png);
    QVERIFY(png.size() < raw.size() / 10);  // flat colours compress well even at level 1
    cv::Mat fromPng;
    QVERIFY(decodeImage(png.data(), png.size(), ImageEncoding::Png, 640, 480, fromPng, &error));
    QCOMPARE(fromPng.type(), CV_8UC3);
    QCOMPARE(cv::norm(fromPng, frame, cv::NORM_INF), 0.0);

    // A region of interest (non-continuous memory) encodes as its own pixels.
    const cv::Mat roi = frame(cv::Rect(100, 50, 33, 21));
    const std::vector<std::uint8_t> roiRaw = encodeImage(roi, ImageEncoding::Raw);
    QVERIFY(decodeImage(roiRaw.data(), roiRaw.size(), ImageEncoding::Raw, 33, 21, decoded, &error));
    QCOMPARE(cv::norm(decoded, roi, cv::NORM_INF), 0.0);
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, encodeImage(cv::Mat(4, 4, CV_8UC1), ImageEncoding::Png));
}

void TestCamera::storedPngIsLossless() {
    // Noise as a realistic camera's: random bytes, which deflate cannot shrink.
    std::mt19937 rng(7);
    for (const cv::Size size : {cv::Size(640, 480), cv::Size(1, 1), cv::Size(3, 200), cv::Size(300, 219)}) {
        cv::Mat frame(size, CV_8UC3);
        for (int y = 0; y < frame.rows; ++y)
            for (int x = 0; x < frame.cols * 3; ++x) frame.ptr<std::uint8_t>(y)[x] = std::uint8_t(rng());
        const std::vector<std::uint8_t> png = encodeImage(frame, ImageEncoding::Png, 90, PngDeflate::Stored);
        // Signature, IHDR (25), IDAT (12 + zlib: 2 + rows of 1 + 3 w + 5 per 65,535-byte block + 4), IEND (12).
        const std::size_t rawBytes = std::size_t(size.height) * (1 + 3 * std::size_t(size.width));
        const std::size_t blocks = (rawBytes + 65534) / 65535;
        QCOMPARE(png.size(), 8 + 25 + 12 + 2 + rawBytes + 5 * blocks + 4 + 12);
        cv::Mat decoded;
        std::string error;
        QVERIFY2(decodeImage(png.data(), png.size(), ImageEncoding::Png, size.width, size.height, decoded, &error),
                 error.c_str());
        QCOMPARE(cv::norm(decoded, frame, cv::NORM_INF), 0.0);
        // OpenCV's own decoder reads it too, to the same pixels.
        const cv::Mat viaOpenCv = cv::imdecode(png, cv::IMREAD_UNCHANGED);
        QCOMPARE(viaOpenCv.size(), size);
        QCOMPARE(cv::norm(viaOpenCv, frame, cv::NORM_INF), 0.0);
        // A flipped bit in the first pixel is refused (the IDAT chunk's CRC-32
        // no longer matches), not decoded as another image.
        std::vector<std::uint8_t> bad = png;
        bad[8 + 25 + 8 + 2 + 5 + 1] ^= 0x40;
        QVERIFY(!decodeImage(bad.data(), bad.size(), ImageEncoding::Png, size.width, size.height, decoded, &error));
    }
    // A region of interest (non-continuous memory) encodes as its own pixels.
    const cv::Mat frame = someFrame(3);
    const cv::Mat roi = frame(cv::Rect(101, 49, 37, 23));
    const std::vector<std::uint8_t> png = encodeImage(roi, ImageEncoding::Png, 90, PngDeflate::Stored);
    cv::Mat decoded;
    std::string error;
    QVERIFY(decodeImage(png.data(), png.size(), ImageEncoding::Png, 37, 23, decoded, &error));
    QCOMPARE(cv::norm(decoded, roi, cv::NORM_INF), 0.0);
}

void TestCamera::jpegIsClose() {
    const cv::Mat frame = someFrame(2);
    const std::vector<std::uint8_t> jpeg = encodeImage(frame, ImageEncoding::Jpeg, 90);
    cv::Mat decoded;
    std::string error;
    QVERIFY(decodeImage(jpeg.data(), jpeg.size(), ImageEncoding::Jpeg, 640, 480, decoded, &error));
    QCOMPARE(decoded.size(), frame.size());
    QCOMPARE(decoded.type(), CV_8UC3);
    cv::Mat diff;
    cv::absdiff(decoded, frame, diff);
    const cv::Scalar meanError = cv::mean(diff);
    QVERIFY((meanError[0] + meanError[1] + meanError[2]) / 3 < 3.0);
    // Lower quality, fewer bytes.
    QVERIFY(encodeImage(frame, ImageEncoding::Jpeg, 20).size() < jpeg.size());
}

void TestCamera::decodeRejectsBadData() {
    const cv::Mat frame = someFrame(3);
    cv::Mat out = cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3));
    const cv::Mat before = out.clone();
    std::string error;
    auto rejects = [&](const std::vector<std::uint8_t>& bytes, ImageEncoding encoding, int width, int height) {
        error.clear();
        const bool ok = decodeImage(bytes.data(), bytes.size(), encoding, width, height, out, &error);
        return !ok && !error.empty() && out.size() == before.size() && cv::norm(out, before, cv::NORM_INF) == 0;
    };
    for (ImageEncoding e : {ImageEncoding::Raw, ImageEncoding::Png, ImageEncoding::Jpeg}) {
        const std::vector<std::uint8_t> good = encodeImage(frame, e);
        QVERIFY(rejects(good, e, 641, 480));  // wrong sizes
        QVERIFY(rejects(good, e, 640, 479));
        QVERIFY(rejects(good, e, 0, 480));
        QVERIFY(rejects({}, e, 640, 480));  // no data
        std::vector<std::uint8_t> truncated(good.begin(), good.begin() + good.size() / 2);
        QVERIFY2(rejects(truncated, e, 640, 480), encodingName(e));
        truncated.assign(good.begin(), good.end() - 1);
        QVERIFY2(rejects(truncated, e, 640, 480), encodingName(e));
        QVERIFY(!decodeImage(nullptr, 0, e, 640, 480, out, nullptr));  // no error string wanted: fine
    }
    // Garbage, alone and behind a valid header.
    std::mt19937 rng(8);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<std::uint8_t> garbage(1 + trial * 251);
        for (std::uint8_t& b : garbage) b = std::uint8_t(byte(rng));
        QVERIFY(rejects(garbage, ImageEncoding::Png, 640, 480));
        QVERIFY(rejects(garbage, ImageEncoding::Jpeg, 640, 480));
        for (ImageEncoding e : {ImageEncoding::Png, ImageEncoding::Jpeg}) {
            std::vector<std::uint8_t> corrupted = encodeImage(frame, e);
            const std::size_t keep = e == ImageEncoding::Png ? 33 : 2;  // PNG signature and IHDR; JPEG SOI
            for (std::size_t i = keep; i + 2 < corrupted.size(); ++i) corrupted[i] = std::uint8_t(byte(rng));
            cv::Mat decoded;
            // Garbage may still decode (JPEG is forgiving); it must never crash and, if accepted, be the right size.
            if (decodeImage(corrupted.data(), corrupted.size(), e, 640, 480, decoded, &error))
                QCOMPARE(decoded.size(), cv::Size(640, 480));
        }
    }
    // A PNG holding the wrong encoding's data.
    QVERIFY(rejects(encodeImage(frame, ImageEncoding::Jpeg), ImageEncoding::Png, 640, 480));
    QVERIFY(rejects(encodeImage(frame, ImageEncoding::Png), ImageEncoding::Jpeg, 640, 480));
}

void TestCamera::encodingNames() {
    for (ImageEncoding e : {ImageEncoding::Raw, ImageEncoding::Png, ImageEncoding::Jpeg})
        QCOMPARE(encodingFromName(encodingName(e)), std::optional<ImageEncoding>(e));
    QCOMPARE(std::string(encodingName(ImageEncoding::Raw)), std::string("raw"));
    QCOMPARE(std::string(encodingName(ImageEncoding::Png)), std::string("png"));
    QCOMPARE(std::string(encodingName(ImageEncoding::Jpeg)), std::string("jpeg"));
    QVERIFY(!encodingFromName("jpg"));
    QVERIFY(!encodingFromName("PNG"));
    QVERIFY(!encodingFromName(""));
}

void TestCamera::kickoffPatchFraction() {
    QString error;
    const std::optional<Scene> scene =
        loadSceneFile(QStringLiteral(VSSIM_SOURCE_DIR "/resources/scenes/kickoff_3v3.json"), &error);
    QVERIFY2(scene, qPrintable(error));
    const CameraRenderer renderer(*scene);
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    renderer.render(initialWorldState(*scene), frame, patches);
    QCOMPARE(patches.size(), std::size_t(7));
    for (const cv::Rect& r : patches) QVERIFY(!r.empty());
    const double imagePixels = 640.0 * 480.0;
    const double unionFraction = cv::countNonZero(unionMask(frame.size(), patches)) / imagePixels;
    double summed = 0.0;
    for (const cv::Rect& r : patches) summed += r.area();
    qInfo("kick-off: patches cover %.2f %% of the image (%.2f %% summed); frame bytes raw %zu, png %zu, jpeg90 %zu",
          100 * unionFraction, 100 * summed / imagePixels, encodeImage(frame, ImageEncoding::Raw).size(),
          encodeImage(frame, ImageEncoding::Png).size(), encodeImage(frame, ImageEncoding::Jpeg, 90).size());
    QVERIFY(unionFraction < 0.04);
    QVERIFY(summed / imagePixels < 0.04);
}

void TestCamera::geometryIncludesTheGoals() {
    // 3 vs 3: 1.70 m from back wall to back wall, 600 / 1.7 = 352.9 px/m; the
    // width still binds, so the scale and mapping are the box's.
    const Field three = makeField(officialDimensions(FieldType::Vsss3v3));
    const CameraGeometry a = cameraGeometryFor(three);
    QVERIFY(std::abs(a.scale - 4400.0 / 13.0) < 1e-9);
    QCOMPARE(a.centreU, 320.0);
    QCOMPARE(a.centreV, 240.0);
    // 5 vs 5: 2.20 + 2 x 0.15 = 2.50 m binds: 600 / 2.5 = 240 px/m, the back walls 20 px from the image's sides.
    const Field five = makeField(officialDimensions(FieldType::Vsss5v5));
    const CameraGeometry b = cameraGeometryFor(five);
    QVERIFY(std::abs(b.scale - 240.0) < 1e-9);
    QVERIFY(std::abs(toPixel(b, -1.25, 0).x() - 20.0) < 1e-9);
    QVERIFY(std::abs(toPixel(b, 1.25, 0).x() - 620.0) < 1e-9);
    QVERIFY(std::abs(toPixel(b, 0, 0.9).y() - (240.0 - 216.0)) < 1e-9);
    // Every wall, with its 3 px line, is inside the image.
    for (const Field* field : {&three, &five}) {
        const CameraGeometry camera = cameraGeometryFor(*field);
        for (const Wall& w : field->walls)
            for (const Eigen::Vector2d& p : {w.a, w.b}) {
                const Eigen::Vector2d px = toPixel(camera, p.x(), p.y());
                QVERIFY(px.x() >= 19.99 && px.x() <= 620.01 && px.y() >= 19.99 && px.y() <= 460.01);
            }
    }
}

void TestCamera::officialFieldBackground() {
    Scene scene = sceneOf({});
    scene.field = makeField(officialDimensions(FieldType::Vsss3v3));
    const CameraRenderer renderer(scene);
    const cv::Mat& bg = renderer.background();
    const CameraGeometry& camera = renderer.geometry();
    auto at = [&](double x, double y) { return colourAt(bg, pixelAt(camera, x, y)); };
    // In the goal (mouth y in [-0.2, 0.2], back wall at |x| = 0.85): floor.
    for (auto [x, y] : {std::pair{0.80, 0.1}, {-0.80, -0.1}, {0.78, -0.15}, {-0.82, 0.15}}) QCOMPARE(at(x, y), kFloor);
    // Just behind the back walls, and beside the goals past the goal line: outside.
    for (auto [x, y] : {std::pair{0.87, 0.0}, {-0.87, 0.05}, {0.80, 0.3}, {-0.80, -0.3}, {0.80, 0.23}})
        QCOMPARE(at(x, y), kOutside);
    // The back wall and the goal's side walls are walls; so are the posts.
    QCOMPARE(at(0.85, 0.0), kWall);
    QCOMPARE(at(-0.80, 0.2), kWall);
    QCOMPARE(at(0.75, -0.2), kWall);
    // The corner triangles (legs 0.07 m: hypotenuse x + y = 1.33 at the top
    // right): wall along the hypotenuse, outside beyond it.
    QCOMPARE(at(0.715, 0.615), kWall);
    QCOMPARE(at(-0.715, -0.615), kWall);
    for (auto [x, y] : {std::pair{0.74, 0.64}, {-0.74, 0.64}, {0.74, -0.64}, {-0.74, -0.64}})
        QCOMPARE(at(x, y), kOutside);
    QCOMPARE(at(0.70, 0.60), kFloor);  // just in front of a triangle
    // The markings: white-ish (a 1 px anti-aliased line brightens a pixel or two) at every mark's cross.
    auto bright = [&](double x, double y) {
        const cv::Point c = pixelAt(camera, x, y);
        double best = 0;
        for (int dv = -1; dv <= 1; ++dv)
            for (int du = -1; du <= 1; ++du) best = std::max(best, double(colourAt(bg, c + cv::Point(du, dv))[0]));
        return best;
    };
    for (auto [x, y] : {std::pair{0.375, 0.25},
                        {0.375, -0.25},
                        {-0.375, 0.25},
                        {-0.375, -0.25},  // free-ball marks
                        {0.375, 0.0},
                        {-0.375, 0.0}})  // penalty marks
        QVERIFY2(bright(x, y) > 150, qPrintable(QString("mark at (%1, %2)").arg(x).arg(y)));
    QVERIFY(bright(0.375 + 0.01, 0.25) > 100);  // the cross's arm ends 1 cm from the mark
    QCOMPARE(at(0.375 + 0.02, 0.25), kFloor);   // and no further
    // The goal areas, 0.15 m deep and 0.70 m wide: their front lines and sides.
    QVERIFY(bright(0.60, 0.1) > 150);
    QVERIFY(bright(-0.60, -0.3) > 150);
    QVERIFY(bright(0.70, 0.35) > 150);
    QVERIFY(bright(-0.65, -0.35) > 150);
    QCOMPARE(at(0.55, 0.1), kFloor);  // in front of the goal area
    QCOMPARE(at(0.68, 0.1), kFloor);  // inside it
    // The centre circle, r = 0.20 m, at 45 degrees.
    QVERIFY(bright(0.2 * M_SQRT1_2, 0.2 * M_SQRT1_2) > 150);
}

void TestCamera::markingsFollowTheDimensions() {
    // 5 vs 5: the centre circle is 0.25 m, not 0.20 m; the free-ball marks 0.40 m off the axis.
    Scene scene = sceneOf({});
    scene.field = makeField(officialDimensions(FieldType::Vsss5v5));
    const CameraRenderer renderer(scene);
    const cv::Mat& bg = renderer.background();
    const CameraGeometry& camera = renderer.geometry();
    auto bright = [&](double x, double y) {
        const cv::Point c = pixelAt(camera, x, y);
        double best = 0;
        for (int dv = -1; dv <= 1; ++dv)
            for (int du = -1; du <= 1; ++du) best = std::max(best, double(colourAt(bg, c + cv::Point(du, dv))[0]));
        return best;
    };
    QVERIFY(bright(0.25 * M_SQRT1_2, 0.25 * M_SQRT1_2) > 150);
    QCOMPARE(bright(0.20 * M_SQRT1_2, 0.20 * M_SQRT1_2), 20.0);
    QVERIFY(bright(1.1 - 0.375, 0.40) > 150);
    QVERIFY(bright(-(1.1 - 0.375), -0.40) > 150);
    QCOMPARE(colourAt(bg, pixelAt(camera, 1.2, 0.0)), kFloor);     // in the 0.15 m deep goal
    QCOMPARE(colourAt(bg, pixelAt(camera, 1.2, 0.25)), kOutside);  // beside it
    // A field without marks or goal areas draws none: the box has only the centre line and circle.
    Scene box = sceneOf({});
    const cv::Mat plain = CameraRenderer(box).background();
    const CameraGeometry& bc = cameraGeometryFor(box.field);
    QCOMPARE(colourAt(plain, pixelAt(bc, 0.375, 0.25)), kFloor);
    QCOMPARE(colourAt(plain, pixelAt(bc, 0.60, 0.1)), kFloor);
}

void TestCamera::boxBackgroundUnchanged() {
    // The box's image as it was drawn before the official fields existed
    // (floor polygon, centre line, a 0.20 m circle, four walls), drawn here
    // with the same calls: the box's background must be the same, byte for byte.
    for (auto [length, width] : {std::pair{1.50, 1.30}, {3.0, 0.5}, {2.2, 1.8}}) {
        const Field field = makeRectangularField(length, width);
        const CameraGeometry camera = cameraGeometryFor(field);
        cv::Mat old(camera.height, camera.width, CV_8UC3, cv::Scalar(70, 70, 70));
        const double hx = length / 2, hy = width / 2;
        std::vector<cv::Point> floor;
        for (auto [x, y] : {std::pair{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}})
            floor.push_back(drawingPoint(camera, x, y));
        cv::fillPoly(old, std::vector<std::vector<cv::Point>>{floor}, cv::Scalar(20, 20, 20), cv::LINE_AA, 8);
        cv::line(old, drawingPoint(camera, 0.0, -hy), drawingPoint(camera, 0.0, hy), cv::Scalar(255, 255, 255), 1,
                 cv::LINE_AA, 8);
        cv::circle(old, drawingPoint(camera, 0.0, 0.0), drawingLength(camera, 0.20), cv::Scalar(255, 255, 255), 1,
                   cv::LINE_AA, 8);
        for (int k = 0; k < 4; ++k)
            cv::line(old, floor[k], floor[(k + 1) % 4], cv::Scalar(200, 200, 200), 3, cv::LINE_AA, 8);
        QCOMPARE(camera.centreU, 320.0);
        QCOMPARE(camera.centreV, 240.0);
        QVERIFY(std::abs(camera.scale - std::min(600 / length, 440 / width)) < 1e-12);
        QCOMPARE(cv::countNonZero(differenceMask(renderFieldBackground(field, camera), old)), 0);
    }
}

QTEST_GUILESS_MAIN(TestCamera)
#include "test_camera.moc"
