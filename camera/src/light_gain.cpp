#include "vssim/camera/light_gain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vssim {

namespace {
constexpr int kGainBits = 12;  // fractional bits of the stored gains
}

LightGain::LightGain(const CameraSettings& camera, const CameraLens& lens)
    : width_(lens.geometry.width), height_(lens.geometry.height) {
    const bool light = camera.vignetting != 0.0 || camera.gradient_x != 0.0 || camera.gradient_y != 0.0;
    const bool colour = camera.gain_b != 1.0 || camera.gain_g != 1.0 || camera.gain_r != 1.0;
    if (!light && !colour) return;
    for (const double g : {camera.gain_b, camera.gain_g, camera.gain_r, camera.vignetting})
        if (!(g >= 0.0) || g > 16.0)
            throw std::invalid_argument(
                "camera: vignetting and the colour gains (gain_b, gain_g, gain_r) must be in "
                "0..16 (got " +
                std::to_string(g) + ")");
    if (!std::isfinite(camera.gradient_x) || !std::isfinite(camera.gradient_y))
        throw std::invalid_argument("camera: gradient_x and gradient_y must be finite");
    const double cx = lens.cx, cy = lens.cy, w = width_, h = height_;
    double cornerR2 = 0.0;  // px^2
    for (const double u : {0.0, w - 1.0})
        for (const double v : {0.0, h - 1.0}) cornerR2 = std::max(cornerR2, (u - cx) * (u - cx) + (v - cy) * (v - cy));
    const double channel[3] = {camera.gain_b, camera.gain_g, camera.gain_r};
    auto gains = std::make_shared<std::vector<std::uint16_t>>(static_cast<std::size_t>(width_) * height_ * 3);
    std::uint16_t* g = gains->data();
    for (int v = 0; v < height_; ++v)
        for (int u = 0; u < width_; ++u) {
            const double r2 = (u - cx) * (u - cx) + (v - cy) * (v - cy);
            const double light = std::max(0.0, 1.0 - camera.vignetting * r2 / cornerR2) *
                                 std::max(0.0, 1.0 + camera.gradient_x * (u - cx) / (0.5 * w)) *
                                 std::max(0.0, 1.0 + camera.gradient_y * (v - cy) / (0.5 * h));
            for (int c = 0; c < 3; ++c)
                *g++ = static_cast<std::uint16_t>(std::min(65535.0, std::round(light * channel[c] * (1 << kGainBits))));
        }
    gains_ = std::move(gains);
}

void LightGain::applyAt(cv::Mat& image, const cv::Point& origin) const {
    if (!gains_ || image.empty()) return;
    if (image.type() != CV_8UC3 || origin.x < 0 || origin.y < 0 || origin.x + image.cols > width_ ||
        origin.y + image.rows > height_)
        throw std::invalid_argument("LightGain: a BGR region inside the image expected");
    for (int row = 0; row < image.rows; ++row) {
        std::uint8_t* p = image.ptr<std::uint8_t>(row);
        const std::uint16_t* g = gains_->data() + (static_cast<std::size_t>(origin.y + row) * width_ + origin.x) * 3;
        const int n = image.cols * 3;
        for (int i = 0; i < n; ++i) {
            const std::uint32_t value =
                (static_cast<std::uint32_t>(p[i]) * g[i] + (1u << (kGainBits - 1))) >> kGainBits;
            p[i] = static_cast<std::uint8_t>(std::min<std::uint32_t>(value, 255u));
        }
    }
}

void LightGain::apply(cv::Mat& frame, const cv::Rect& region) const {
    if (!gains_ || region.empty()) return;
    cv::Mat view = frame(region);
    applyAt(view, region.tl());
}

}  // namespace vssim
