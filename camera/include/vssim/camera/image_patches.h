// Patches: the rectangles of a frame that differ from the background
// (CameraRenderer::render). Sending only these, and pasting them onto a copy
// of the background at the other end, rebuilds the frame exactly.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace vssim {

// Deep copies of frame(rect) for each rect, in order (an empty rect gives an
// empty Mat). The rects must lie inside the frame.
std::vector<cv::Mat> cropPatches(const cv::Mat& frame, const std::vector<cv::Rect>& rects);

// Copies `patch` into canvas(rect). Returns false, leaving the canvas as it
// was, unless the rect lies inside the canvas and the patch has the rect's
// size and the canvas's type (an empty rect with an empty patch is fine).
bool pastePatch(cv::Mat& canvas, const cv::Rect& rect, const cv::Mat& patch);

}  // namespace vssim
