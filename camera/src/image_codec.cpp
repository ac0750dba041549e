#include "vssim/camera/image_codec.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "vssim/camera/png_stored.h"

namespace vssim {

namespace {

constexpr std::uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr int kPngCompressionLevel = 1;  // zlib 0..9: 1 is fast and still small on flat images

std::uint32_t bigEndian32(const std::uint8_t* p) {
    return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

bool fail(std::string* error, std::string message) {
    if (error) *error = std::move(message);
    return false;
}

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// Checks what can be checked before decoding: the signature, and for PNG the
// size in its header (so that a wrong size is refused before any allocation).
bool checkHeader(const std::uint8_t* data, std::size_t n, ImageEncoding encoding, int width, int height,
                 std::string* error) {
    if (encoding == ImageEncoding::Png) {
        // Signature (8 bytes), IHDR length and type (8), width and height (4 + 4).
        if (n < 24 || std::memcmp(data, kPngSignature, sizeof kPngSignature) != 0)
            return fail(error, "png: not PNG data (" + std::to_string(n) + " bytes)");
        const std::uint32_t w = bigEndian32(data + 16), h = bigEndian32(data + 20);
        if (w != std::uint32_t(width) || h != std::uint32_t(height))
            return fail(error, "png: image is " + std::to_string(w) + "x" + std::to_string(h) + ", expected " +
                                   sizeText(width, height));
        return true;
    }
    // JPEG: start-of-image marker first, end-of-image marker last.
    if (n < 4 || data[0] != 0xff || data[1] != 0xd8)
        return fail(error, "jpeg: not JPEG data (" + std::to_string(n) + " bytes)");
    if (data[n - 2] != 0xff || data[n - 1] != 0xd9) return fail(error, "jpeg: truncated (no end-of-image marker)");
    return true;
}

}  // namespace

const char* encodingName(ImageEncoding encoding) {
    switch (encoding) {
        case ImageEncoding::Raw: return "raw";
        case ImageEncoding::Png: return "png";
        case ImageEncoding::Jpeg: return "jpeg";
    }
    return "?";
}

std::optional<ImageEncoding> encodingFromName(std::string_view name) {
    for (ImageEncoding e : {ImageEncoding::Raw, ImageEncoding::Png, ImageEncoding::Jpeg})
        if (name == encodingName(e)) return e;
    return std::nullopt;
}

std::vector<std::uint8_t> encodeImage(const cv::Mat& bgr, ImageEncoding encoding, int jpegQuality, PngDeflate png) {
    if (bgr.type() != CV_8UC3) throw std::invalid_argument("encodeImage: expected a CV_8UC3 BGR image");
    std::vector<std::uint8_t> bytes;
    switch (encoding) {
        case ImageEncoding::Raw: {
            const std::size_t rowBytes = std::size_t(bgr.cols) * 3;
            bytes.resize(rowBytes * std::size_t(bgr.rows));
            for (int row = 0; row < bgr.rows; ++row) std::memcpy(bytes.data() + row * rowBytes, bgr.ptr(row), rowBytes);
            break;
        }
        case ImageEncoding::Png:
            if (png == PngDeflate::Stored && !bgr.empty()) return encodePngStored(bgr);
            cv::imencode(".png", bgr, bytes, {cv::IMWRITE_PNG_COMPRESSION, kPngCompressionLevel});
            break;
        case ImageEncoding::Jpeg:
            cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, std::clamp(jpegQuality, 1, 100)});
            break;
    }
    return bytes;
}

bool decodeImage(const std::uint8_t* data, std::size_t n, ImageEncoding encoding, int width, int height, cv::Mat& out,
                 std::string* error) {
    const char* name = encodingName(encoding);
    if (width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16))
        return fail(error, std::string(name) + ": bad image size " + sizeText(width, height));
    if (data == nullptr && n > 0) return fail(error, std::string(name) + ": no data");

    if (encoding == ImageEncoding::Raw) {
        const std::size_t expected = std::size_t(width) * std::size_t(height) * 3;
        if (n != expected)
            return fail(error, "raw: " + std::to_string(n) + " bytes, expected " + std::to_string(expected) + " for " +
                                   sizeText(width, height) + " BGR");
        cv::Mat image(height, width, CV_8UC3);
        std::memcpy(image.data, data, n);
        out = image;
        return true;
    }

    if (n > std::size_t(std::numeric_limits<int>::max())) return fail(error, std::string(name) + ": data too large");
    if (!checkHeader(data, n, encoding, width, height, error)) return false;
    cv::Mat image;
    try {
        // imdecode only reads the buffer; the Mat header needs a non-const pointer.
        const cv::Mat buffer(1, static_cast<int>(n), CV_8UC1, const_cast<std::uint8_t*>(data));
        image = cv::imdecode(buffer, cv::IMREAD_COLOR);
    } catch (const std::exception& e) {
        return fail(error, std::string(name) + ": corrupt data (" + e.what() + ")");
    }
    if (image.empty()) return fail(error, std::string(name) + ": corrupt data (cannot decode)");
    if (image.cols != width || image.rows != height)
        return fail(error, std::string(name) + ": image is " + sizeText(image.cols, image.rows) + ", expected " +
                               sizeText(width, height));
    out = image;
    return true;
}

}  // namespace vssim
