// The synthetic overhead camera: draws a world state as a BGR image, and
// says which rectangles of it differ from the empty field. It renders what
// the scene's `camera` (vssim/camera_settings.h) asks for: the ideal camera
// (today's flat top view) or a realistic one, in four stages
// (docs/protocol.md, "The realistic camera"):
//   1. the scene drawn in 3-D through a pinhole (lens_warp.h's undistorted
//      canvas), averaged over the exposure's sub-frames (motion_blur.h);
//   2. the lens distortion, an image warp (lens_warp.h);
//   3. light and colour, a gain per pixel and channel (light_gain.h);
//   4. sensor noise over the whole frame (sensor_noise.h).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vssim/camera/camera_colours.h"
#include "vssim/camera/camera_geometry.h"
#include "vssim/camera/camera_lens.h"
#include "vssim/camera/lens_warp.h"
#include "vssim/camera/light_gain.h"
#include "vssim/camera/sensor_noise.h"
#include "vssim/camera_settings.h"
#include "vssim/scene.h"
#include "vssim/world.h"

namespace vssim {

class CameraRenderer {
public:
    // The look of every body comes from the scene: each robot's side, its
    // team and its index among its own team's robots in scene order; the
    // ball's radius. The camera is the scene's (scene.camera), or the one
    // given. The background and every per-pixel map (lens, light, noise) are
    // made here, once; copies share them (copying is cheap). Throws
    // std::invalid_argument, naming the setting, for a camera it cannot
    // render (a lens that folds the image, a camera not above the robots'
    // tops, a negative noise, ...).
    explicit CameraRenderer(const Scene& scene, int width = 640, int height = 480);
    CameraRenderer(const Scene& scene, const CameraSettings& camera, int width = 640, int height = 480);

    // The ideal top view's geometry (field <-> pixels without the lens).
    const CameraGeometry& geometry() const { return camera_; }
    // Where the camera sees a point (projectToImage, imageToField).
    const CameraLens& lens() const { return lens_; }
    const CameraSettings& settings() const { return settings_; }
    // The empty field through the same lens, light and colour, without
    // noise (field_background.h), CV_8UC3 BGR, height x width.
    const cv::Mat& background() const { return background_; }
    // Robots, then the ball: the length of render()'s patch list.
    int bodyCount() const { return static_cast<int>(robots_.size()) + 1; }

    // frame = the background with every robot (in scene order) and then the
    // ball drawn on top, anti-aliased at 1/256 px; its memory is reused when
    // it already has the right size and type. patches[i] = the pixel box of
    // everything drawn for body i (robots, then the ball) in the final image
    // (anti-aliasing, the lens's warp and the blur's streak included),
    // clipped to the image; empty (0 x 0) when none of the body is in the
    // image. Outside the union of the patches the frame equals the
    // background plus the sensor noise (exactly the background without
    // noise), so copying each frame(patches[i]), in order, onto a copy of
    // the background rebuilds a noise-free frame exactly. Every random draw
    // is a function of (settings().seed, frameNumber): same state and frame
    // number, same bytes. Throws std::invalid_argument when the state's
    // robot count differs from the scene's.
    void render(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches,
                std::uint64_t frameNumber = 0) const;

private:
    struct RobotLook {
        double side = 0.0;  // m
        Bgr team;
        Bgr identity;
    };
    CameraGeometry camera_;
    CameraSettings settings_;
    CameraLens lens_;
    bool ideal_ = true;  // orthographic, no light, noise or blur: the flat image, drawn straight into the frame
    std::vector<RobotLook> robots_;
    double ballRadius_ = 0.0;  // m
    cv::Mat background_;
    // Stages 1 to 4 (not ideal): the empty field on the canvas (undistorted,
    // before light), the warp, the gains, the noise.
    cv::Mat canvasBackground_;
    LensWarp warp_;
    LightGain light_;
    SensorNoise noise_;

    // The ideal top view (also the orthographic canvas).
    cv::Rect drawRobot(const RobotLook& look, const RobotState& pose, cv::Mat& frame) const;
    cv::Rect drawBall(const BallState& ball, cv::Mat& frame) const;
    // On the canvas: the box a body covers (clipped; empty when it misses)
    // and its drawing (only when that box is not empty).
    cv::Rect robotBox(const RobotLook& look, const RobotState& pose) const;
    cv::Rect ballBox(const BallState& ball) const;
    void drawRobotOnCanvas(const RobotLook& look, const RobotState& pose, cv::Mat& canvas) const;
    void drawBallOnCanvas(const BallState& ball, cv::Mat& canvas) const;
    Eigen::Vector2d canvasPixel(double x, double y, double z) const;  // px, OpenCV's convention
    void renderRealistic(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches,
                         std::uint64_t frameNumber) const;
};

// Why a renderer of `scene` with its own camera cannot be made (the message
// CameraRenderer's constructor throws: a lens that folds the image over, a
// camera below the bodies' tops, ...), or an empty string. Commands that show
// a scene's camera (vssim serve, vssim gui, the app's Open) refuse such a
// scene with this message.
std::string cameraProblem(const Scene& scene);

// The scene's camera, or the ideal one when cameraProblem(scene) is not
// empty: for threads that must not die on a scene the entry points should
// have refused.
CameraRenderer cameraRendererOrIdeal(const Scene& scene);

}  // namespace vssim
