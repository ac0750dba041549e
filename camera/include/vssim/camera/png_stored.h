// A PNG whose image data is stored, not compressed: for camera images with
// sensor noise, which deflate cannot shrink much (zlib's fastest level saves
// about 40 % of a noisy 640 x 480 frame at some 25 ms) but which stored
// blocks write at memory speed. Any PNG decoder reads it.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace vssim {

// A CV_8UC3 BGR image as an 8-bit RGB PNG (no interlace, filter type None
// on every row) with its zlib stream in stored deflate blocks; the image
// must be non-empty (throws std::invalid_argument otherwise).
std::vector<std::uint8_t> encodePngStored(const cv::Mat& bgr);

}  // namespace vssim
