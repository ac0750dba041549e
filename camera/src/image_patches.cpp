#include "vssim/camera/image_patches.h"

namespace vssim {

std::vector<cv::Mat> cropPatches(const cv::Mat& frame, const std::vector<cv::Rect>& rects) {
    std::vector<cv::Mat> patches;
    patches.reserve(rects.size());
    for (const cv::Rect& rect : rects) patches.push_back(rect.empty() ? cv::Mat() : frame(rect).clone());
    return patches;
}

bool pastePatch(cv::Mat& canvas, const cv::Rect& rect, const cv::Mat& patch) {
    if (rect.empty()) return patch.empty();
    const bool inside =
        rect.x >= 0 && rect.y >= 0 && rect.width <= canvas.cols - rect.x && rect.height <= canvas.rows - rect.y;
    if (!inside || patch.size() != rect.size() || patch.type() != canvas.type()) return false;
    patch.copyTo(canvas(rect));
    return true;
}

}  // namespace vssim
