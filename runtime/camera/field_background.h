// The empty field as the camera sees it: what every frame is drawn on.
#pragma once

#include <opencv2/core.hpp>

#include "camera/camera_geometry.h"
#include "vssim/field.h"

namespace vssim {

// A camera.height x camera.width CV_8UC3 BGR image: the outside colour, the
// floor inside the walls, the centre line (x = 0, wall to wall) and the
// centre circle, then the walls on top (colours in camera_colours.h, sizes
// in camera_layout.h). "Inside the walls" is the polygon that the walls make
// when each one ends where the next begins (makeRectangularField's do);
// for any other set of walls it is the length x width rectangle.
cv::Mat renderFieldBackground(const Field& field, const CameraGeometry& camera);

}  // namespace vssim
