// Light and colour of the synthetic camera: a gain per pixel and channel,
// made once per camera, that multiplies the drawn image (docs/protocol.md,
// "The realistic camera"). At pixel (u, v) (OpenCV's convention: pixel
// centres at integers) and channel c of B, G, R:
//
//   gain = max(0, 1 - vignetting (r / r_corner)^2)
//          * max(0, 1 + gradient_x (u - cx) / (w / 2))
//          * max(0, 1 + gradient_y (v - cy) / (h / 2)) * gain_c
//
// with (cx, cy) the lens's principal point, r the distance from it (px) and
// r_corner its distance to the farthest corner pixel's centre; a value
// becomes round(value * gain) saturated to 0..255, with the gain held to
// 1/4096 (12 fractional bits).
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "vssim/camera/camera_lens.h"
#include "vssim/camera_settings.h"

namespace vssim {

class LightGain {
public:
    LightGain() = default;  // all gains 1: inactive
    // For images of the lens's geometry.width x geometry.height.
    LightGain(const CameraSettings& camera, const CameraLens& lens);

    // False when every gain is exactly 1 (no vignetting, gradient or colour gain).
    bool active() const { return gains_ != nullptr; }
    // Multiplies frame(region) in place (CV_8UC3, the lens's image size;
    // region inside it). Nothing when inactive.
    void apply(cv::Mat& frame, const cv::Rect& region) const;
    // The same on `image`, a copy of frame(region) (its own memory).
    void applyAt(cv::Mat& image, const cv::Point& origin) const;

private:
    std::shared_ptr<const std::vector<std::uint16_t>> gains_;  // row-major, 3 per pixel, x 4096
    int width_ = 0, height_ = 0;
};

}  // namespace vssim
