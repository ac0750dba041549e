// The lens distortion as an image warp: the renderer draws the scene in an
// undistorted pinhole image (straight lines stay straight there, so polygons
// and discs are drawn exactly), then every output pixel takes the value at
// its undistorted position, bilinearly interpolated (cv::remap, fixed-point
// maps at 1/32 px). The maps are made once per camera: for output pixel
// (u, v), camera_lens's undistort() of its normalised coordinates.
//
// The undistorted image ("canvas") is shifted and sized to hold every
// position the maps read: with barrel distortion (k1 < 0) the image's corners
// see beyond the undistorted image's edges. A canvas pixel (i, j) is the
// undistorted pinhole pixel (i - offset.x, j - offset.y).
#pragma once

#include <memory>
#include <opencv2/core.hpp>

#include "vssim/camera/camera_lens.h"

namespace vssim {

struct LensWarpMaps;  // lens_warp.cpp

class LensWarp {
public:
    LensWarp() = default;  // inactive
    // The warp for a pinhole lens with distortion (inactive otherwise).
    // Throws std::invalid_argument when the distortion cannot be inverted
    // over the image (it folds back or Newton's method fails) or needs a
    // canvas of more than 16 times the image's area.
    explicit LensWarp(const CameraLens& lens);

    bool active() const { return maps_ != nullptr; }
    cv::Size canvasSize() const;  // the image's size when inactive
    cv::Point offset() const;     // (0, 0) when inactive

    // The output pixels whose value can depend on the canvas pixels in
    // `canvasBox` (bilinear reads included), clipped to the image; the box
    // itself when inactive.
    cv::Rect outputBoxOf(const cv::Rect& canvasBox) const;
    // region = the output pixels in `box` (inside the image) of the canvas
    // warped: a box.height x box.width CV_8UC3 image (its memory reused when
    // it has that size and type).
    void warp(const cv::Mat& canvas, const cv::Rect& box, cv::Mat& region) const;

private:
    std::shared_ptr<const LensWarpMaps> maps_;  // shared by copies and by renderers of the same lens
    CameraLens lens_;
};

}  // namespace vssim
