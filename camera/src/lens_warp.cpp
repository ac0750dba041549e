#include "vssim/camera/lens_warp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "vssim/camera/shared_by_key.h"

namespace vssim {

struct LensWarpMaps {
    cv::Mat fixed;     // CV_16SC2: integer canvas positions
    cv::Mat fraction;  // CV_16UC1: their interpolation-table indices (1/32 px)
    cv::Size canvas;
    cv::Point offset;
};

namespace {
constexpr double kMaxCanvasAreaRatio = 16.0;
}  // namespace

namespace {

// The maps of one lens and image size (throws std::invalid_argument as LensWarp's constructor).
std::shared_ptr<const LensWarpMaps> makeMaps(const CameraLens& lens) {
    const int w = lens.geometry.width, h = lens.geometry.height;
    std::vector<double> ux(static_cast<std::size_t>(w) * h), uy(ux.size());  // undistorted px, before the offset
    std::vector<int> failedAt(h, -1);  // per row: the first column Newton's method missed
    cv::parallel_for_(cv::Range(0, h), [&](const cv::Range& rows) {
        for (int v = rows.start; v < rows.end; ++v)
            for (int u = 0; u < w; ++u) {
                const Eigen::Vector2d d((u - lens.cx) / lens.fx, (v - lens.cy) / lens.fy);
                const Eigen::Vector2d n = undistort(lens, d);
                if (!((distort(lens, n) - d).norm() < 1e-9) && failedAt[v] < 0) failedAt[v] = u;
                const std::size_t i = static_cast<std::size_t>(v) * w + u;
                ux[i] = lens.fx * n.x() + lens.cx, uy[i] = lens.fy * n.y() + lens.cy;
            }
    });
    for (int v = 0; v < h; ++v)
        if (failedAt[v] >= 0)
            throw std::invalid_argument(
                "camera: the lens distortion (k1, k2, p1, p2, k3) cannot be inverted at pixel (" +
                std::to_string(failedAt[v]) + ", " + std::to_string(v) +
                "): the lens folds the image back on itself there; weaken it");
    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (std::size_t i = 0; i < ux.size(); ++i) {
        xMin = std::min(xMin, ux[i]), xMax = std::max(xMax, ux[i]);
        yMin = std::min(yMin, uy[i]), yMax = std::max(yMax, uy[i]);
    }
    // One-to-one: the map keeps the orientation between neighbouring pixels.
    for (int v = 0; v + 1 < h; ++v)
        for (int u = 0; u + 1 < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * w + u;
            const double ax = ux[i + 1] - ux[i], ay = uy[i + 1] - uy[i];
            const double bx = ux[i + w] - ux[i], by = uy[i + w] - uy[i];
            if (!(ax * by - ay * bx > 0.0))
                throw std::invalid_argument(
                    "camera: the lens distortion (k1, k2, p1, p2, k3) folds the image at pixel (" + std::to_string(u) +
                    ", " + std::to_string(v) + "); weaken it");
        }
    auto maps = std::make_shared<LensWarpMaps>();
    // Two pixels of margin around every position read (bilinear reads the next pixel too).
    maps->offset = cv::Point(2 - static_cast<int>(std::floor(xMin)), 2 - static_cast<int>(std::floor(yMin)));
    maps->canvas = cv::Size(static_cast<int>(std::ceil(xMax)) + maps->offset.x + 3,
                            static_cast<int>(std::ceil(yMax)) + maps->offset.y + 3);
    if (static_cast<double>(maps->canvas.area()) > kMaxCanvasAreaRatio * w * h)
        throw std::invalid_argument("camera: the lens distortion (k1, k2, p1, p2, k3) makes the image see " +
                                    std::to_string(maps->canvas.width) + " x " + std::to_string(maps->canvas.height) +
                                    " undistorted pixels, more than 16 times its own area; weaken it");
    cv::Mat mapX(h, w, CV_32F), mapY(h, w, CV_32F);
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * w + u;
            mapX.at<float>(v, u) = static_cast<float>(ux[i] + maps->offset.x);
            mapY.at<float>(v, u) = static_cast<float>(uy[i] + maps->offset.y);
        }
    cv::convertMaps(mapX, mapY, maps->fixed, maps->fraction, CV_16SC2);
    return maps;
}

}  // namespace

LensWarp::LensWarp(const CameraLens& lens) : lens_(lens) {
    const bool distorted = lens.k1 != 0.0 || lens.k2 != 0.0 || lens.p1 != 0.0 || lens.p2 != 0.0 || lens.k3 != 0.0;
    if (!lens.pinhole || !distorted) return;
    // Renderers of the same lens share its maps (shared_by_key.h): made once.
    using Key = std::array<double, 11>;
    static SharedByKey<Key, LensWarpMaps> made;
    const Key key{lens.fx,
                  lens.fy,
                  lens.cx,
                  lens.cy,
                  lens.k1,
                  lens.k2,
                  lens.p1,
                  lens.p2,
                  lens.k3,
                  static_cast<double>(lens.geometry.width),
                  static_cast<double>(lens.geometry.height)};
    maps_ = made.get(key, [&] { return makeMaps(lens); });
}

cv::Size LensWarp::canvasSize() const {
    return maps_ ? maps_->canvas : cv::Size(lens_.geometry.width, lens_.geometry.height);
}

cv::Point LensWarp::offset() const { return maps_ ? maps_->offset : cv::Point(0, 0); }

cv::Rect LensWarp::outputBoxOf(const cv::Rect& canvasBox) const {
    const cv::Rect image(0, 0, lens_.geometry.width, lens_.geometry.height);
    if (canvasBox.empty()) return {};
    if (!maps_) return canvasBox & image;
    // An output pixel reads canvas pixels floor(p) and floor(p) + 1 for its
    // position p: it depends on the box when p lies in (x0 - 1, x1) x (y0 - 1, y1).
    // The distortion maps that rectangle's boundary onto the boundary of its
    // image (it is one-to-one), so its samples bound the output positions;
    // one more pixel covers the curve between samples and the maps' 1/32 px.
    const double x0 = canvasBox.x - 1.0 - maps_->offset.x, x1 = canvasBox.x + canvasBox.width - maps_->offset.x;
    const double y0 = canvasBox.y - 1.0 - maps_->offset.y, y1 = canvasBox.y + canvasBox.height - maps_->offset.y;
    double uMin = INFINITY, uMax = -INFINITY, vMin = INFINITY, vMax = -INFINITY;
    const auto sample = [&](double x, double y) {
        const Eigen::Vector2d d = distort(lens_, Eigen::Vector2d((x - lens_.cx) / lens_.fx, (y - lens_.cy) / lens_.fy));
        const double u = lens_.fx * d.x() + lens_.cx, v = lens_.fy * d.y() + lens_.cy;
        uMin = std::min(uMin, u), uMax = std::max(uMax, u), vMin = std::min(vMin, v), vMax = std::max(vMax, v);
    };
    const int nx = static_cast<int>(std::ceil(x1 - x0)), ny = static_cast<int>(std::ceil(y1 - y0));
    for (int k = 0; k <= nx; ++k) {
        const double x = x0 + (x1 - x0) * k / nx;
        sample(x, y0), sample(x, y1);
    }
    for (int k = 0; k <= ny; ++k) {
        const double y = y0 + (y1 - y0) * k / ny;
        sample(x0, y), sample(x1, y);
    }
    const auto clampPx = [](double p, int size) { return std::clamp(p, -4.0, size + 4.0); };
    const int left = static_cast<int>(std::floor(clampPx(uMin, image.width))) - 1;
    const int top = static_cast<int>(std::floor(clampPx(vMin, image.height))) - 1;
    const int right = static_cast<int>(std::ceil(clampPx(uMax, image.width))) + 2;  // exclusive
    const int bottom = static_cast<int>(std::ceil(clampPx(vMax, image.height))) + 2;
    return cv::Rect(left, top, right - left, bottom - top) & image;
}

void LensWarp::warp(const cv::Mat& canvas, const cv::Rect& box, cv::Mat& region) const {
    if (box.empty()) {
        region = cv::Mat();
        return;
    }
    if (!maps_) {
        canvas(box).copyTo(region);
        return;
    }
    cv::remap(canvas, region, maps_->fixed(box), maps_->fraction(box), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
}

}  // namespace vssim
