// The synthetic overhead camera: draws a world state as a BGR image, and
// says which rectangles of it differ from the empty field.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "camera/camera_colours.h"
#include "camera/camera_geometry.h"
#include "vssim/scene.h"
#include "vssim/world.h"

namespace vssim {

class CameraRenderer {
public:
    // The look of every body comes from the scene: each robot's side, its
    // team and its index among its own team's robots in scene order; the
    // ball's radius. The background is drawn here, once.
    explicit CameraRenderer(const Scene& scene, int width = 640, int height = 480);

    const CameraGeometry& geometry() const { return camera_; }
    // The empty field (field_background.h), CV_8UC3 BGR, height x width.
    const cv::Mat& background() const { return background_; }
    // Robots, then the ball: the length of render()'s patch list.
    int bodyCount() const { return static_cast<int>(robots_.size()) + 1; }

    // frame = the background with every robot (in scene order) and then the
    // ball drawn on top, anti-aliased at 1/256 px; its memory is reused when
    // it already has the right size and type. patches[i] = the pixel box of
    // everything drawn for body i (robots, then the ball), anti-aliasing
    // included, clipped to the image; empty (0 x 0) when none of the body is
    // in the image. Outside the union of the patches the frame equals the
    // background, so copying each frame(patches[i]), in order, onto a copy
    // of the background rebuilds the frame exactly. Same state, same bytes.
    // Throws std::invalid_argument when the state's robot count differs
    // from the scene's.
    void render(const WorldState& state, cv::Mat& frame, std::vector<cv::Rect>& patches) const;

private:
    struct RobotLook {
        double side = 0.0;  // m
        Bgr team;
        Bgr identity;
    };
    CameraGeometry camera_;
    std::vector<RobotLook> robots_;
    double ballRadius_ = 0.0;  // m
    cv::Mat background_;

    cv::Rect drawRobot(const RobotLook& look, const RobotState& pose, cv::Mat& frame) const;
    cv::Rect drawBall(const BallState& ball, cv::Mat& frame) const;
};

}  // namespace vssim
