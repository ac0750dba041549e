// The empty field as the camera sees it: what every frame is drawn on.
#pragma once

#include <opencv2/core.hpp>

#include "vssim/camera/camera_geometry.h"
#include "vssim/field.h"

namespace vssim {

// A camera.height x camera.width CV_8UC3 BGR image: the outside colour, the
// floor inside the walls (the goals included, the corner triangles left
// out), the white markings (the centre line, wall to wall; the centre circle
// of the field's centre_radius; each goal area's three lines; a cross at each
// penalty and free-ball mark; each only where the field's dimensions have
// it), then the walls on top, along every segment (colours in
// camera_colours.h, sizes in camera_layout.h). "Inside the walls" is the
// polygon that the walls make when each one ends where the next begins
// (makeField's chain); for any other set of walls it is the length x width
// rectangle.
cv::Mat renderFieldBackground(const Field& field, const CameraGeometry& camera);

}  // namespace vssim
