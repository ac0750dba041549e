// How a camera image travels as bytes: raw BGR, PNG or JPEG. Width and height
// travel separately (in the message that carries the bytes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vssim {

enum class ImageEncoding {
    Raw,   // rows top to bottom, each pixel's B, G, R bytes; no header; width * height * 3 bytes
    Png,   // lossless; zlib level 1 (IMWRITE_PNG_COMPRESSION 1: fast, a little larger)
    Jpeg,  // lossy, quality 1..100
};

// "raw", "png", "jpeg", and back (exact, lower case; nullopt otherwise).
const char* encodingName(ImageEncoding encoding);
std::optional<ImageEncoding> encodingFromName(std::string_view name);

// How a PNG's data is deflated: by zlib at level 1 (small for the ideal
// camera's flat colours), or stored uncompressed (png_stored.h: a camera
// image with sensor noise, where deflate saves little at 20 times the time).
enum class PngDeflate { Fast, Stored };

// Encodes a CV_8UC3 BGR image (throws std::invalid_argument for any other
// type). jpegQuality is clamped to 1..100 and used for Jpeg only; png for
// Png only. Every PNG decodes to the same pixels whichever `png`.
std::vector<std::uint8_t> encodeImage(const cv::Mat& bgr, ImageEncoding encoding, int jpegQuality = 90,
                                      PngDeflate png = PngDeflate::Fast);

// Decodes n bytes into a height x width CV_8UC3 BGR image (width and height
// 1..65536; a grey PNG or JPEG comes out as BGR too). Raw needs exactly
// width * height * 3 bytes; PNG and JPEG must decode (a JPEG must also end
// with its end-of-image marker, as libjpeg fills a truncated one with grey)
// to exactly width x height. On failure returns false, leaves `out` as it
// was and, when error is not null, sets it to a one-line reason. Never
// throws on bad data.
bool decodeImage(const std::uint8_t* data, std::size_t n, ImageEncoding encoding, int width, int height, cv::Mat& out,
                 std::string* error);

}  // namespace vssim
