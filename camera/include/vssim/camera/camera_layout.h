// The sizes of what the synthetic camera draws (the colours are in
// camera_colours.h). Part of the image protocol, like the colours.
#pragma once

namespace vssim {

// The thickness OpenCV draws wall lines with, centred on each Wall segment;
// anti-aliased, a wall shows as 4 to 5 px of kWallColour plus blended edges
// (docs/protocol.md, Camera).
constexpr int kWallThicknessPx = 3;  // px, cv::line thickness
// The white markings (centre line and circle, goal areas, the marks' crosses):
// 1 px, about 3 mm of a 1.50 x 1.30 m field at 338 px/m, as the rules' lines.
constexpr int kMarkingThicknessPx = 1;  // px, cv::line thickness
// A penalty or free-ball mark: a cross of two lines along x and y, each
// reaching this far either side of the mark.
constexpr double kMarkHalfArm = 0.01;  // m

// A robot seen from above: a black square of side s, rotated by theta, with
// two rectangular patches. In the robot frame (x forward along the heading,
// y to the left), in units of s:
//   team patch (rear)      x in [-0.45, -0.05], y in [-0.40, 0.40]
//   identity patch (front) x in [ 0.05,  0.45], y in [-0.40, 0.40]
// Their centroids are (-0.25 s, 0) and (0.25 s, 0): the robot's centre is
// their midpoint and its heading the direction from team to identity patch.
struct PatchRectangle {
    double xMin, xMax, yMin, yMax;  // robot frame, units of the robot's side
};
constexpr PatchRectangle kTeamPatch{-0.45, -0.05, -0.40, 0.40};
constexpr PatchRectangle kIdentityPatch{0.05, 0.45, -0.40, 0.40};

}  // namespace vssim
