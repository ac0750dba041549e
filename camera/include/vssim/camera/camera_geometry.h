// Where the overhead camera sees the field: field metres <-> image pixels.
//
// Continuous pixel coordinates (u, v): u to the right, v down, origin at the
// top-left corner of the image. Pixel (column i, row j) covers u in [i, i+1),
// v in [j, j+1); its centre is (i + 0.5, j + 0.5). The camera looks straight
// down with no distortion, so the map is u = centreU + scale x,
// v = centreV - scale y (field x right, field y up).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "vssim/field.h"

namespace vssim {

struct CameraGeometry {
    int width = 640;       // image columns, px
    int height = 480;      // image rows, px
    double scale = 0.0;    // px per metre (set by cameraGeometryFor)
    double centreU = 0.0;  // u of the field origin, px
    double centreV = 0.0;  // v of the field origin, px
};

// The field, goals included (its bounding box field.lower..field.upper),
// centred in a width x height image with at least 20 px of margin on every
// side: scale = min((width - 40) / (upper.x - lower.x), (height - 40) /
// (upper.y - lower.y)), that is (width - 40) / (length + 2 goal_depth) and
// (height - 40) / width for the fields makeField builds.
CameraGeometry cameraGeometryFor(const Field& field, int width = 640, int height = 480);

// Field point (m) -> continuous pixel coordinates (px), and back.
Eigen::Vector2d toPixel(const CameraGeometry& camera, double x, double y);
Eigen::Vector2d toField(const CameraGeometry& camera, double u, double v);

// OpenCV's drawing functions take fixed-point points with kDrawShift
// fractional bits, and their integer coordinates are pixel centres: the
// point for continuous (u, v) is round((u - 0.5) 2^shift, (v - 0.5) 2^shift).
constexpr int kDrawShift = 8;  // 1/256 px
cv::Point drawingPoint(const CameraGeometry& camera, double x, double y);
// A length in metres as a fixed-point length in px (for radii).
int drawingLength(const CameraGeometry& camera, double metres);

}  // namespace vssim
