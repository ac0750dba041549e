#include "vssim/camera/png_stored.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace vssim {

namespace {

constexpr std::size_t kMaxStoredBlock = 65535;  // bytes: a stored deflate block's LEN is 16 bits

void put32(std::vector<std::uint8_t>& out, std::uint32_t value) {  // big-endian, as PNG and zlib want
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(value >> shift));
}

// Appends a chunk: length, type, data, and the CRC-32 of type and data.
template <typename Fill>
void chunk(std::vector<std::uint8_t>& out, const char (&type)[5], std::size_t length, Fill fill) {
    put32(out, static_cast<std::uint32_t>(length));
    const std::size_t typeAt = out.size();
    out.insert(out.end(), type, type + 4);
    fill(out);
    const uLong crc = crc32(0L, out.data() + typeAt, static_cast<uInt>(out.size() - typeAt));
    put32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::vector<std::uint8_t> encodePngStored(const cv::Mat& bgr) {
    if (bgr.type() != CV_8UC3 || bgr.empty())
        throw std::invalid_argument("encodePngStored: expected a non-empty CV_8UC3 BGR image");
    const std::size_t w = static_cast<std::size_t>(bgr.cols), h = static_cast<std::size_t>(bgr.rows);
    const std::size_t rowBytes = 1 + 3 * w;  // the filter type byte, then R, G, B per pixel
    const std::size_t raw = rowBytes * h;
    const std::size_t blocks = std::max<std::size_t>(1, (raw + kMaxStoredBlock - 1) / kMaxStoredBlock);
    const std::size_t idat = 2 + raw + 5 * blocks + 4;  // zlib header, data, block headers, Adler-32

    // The scanlines, filter type 0 (None): the zlib stream's payload.
    std::vector<std::uint8_t> lines(raw);
    for (std::size_t row = 0; row < h; ++row) {
        const std::uint8_t* in = bgr.ptr<std::uint8_t>(static_cast<int>(row));
        std::uint8_t* line = lines.data() + row * rowBytes;
        line[0] = 0;
        for (std::size_t x = 0; x < w; ++x) {
            line[1 + 3 * x] = in[3 * x + 2];
            line[2 + 3 * x] = in[3 * x + 1];
            line[3 + 3 * x] = in[3 * x];
        }
    }
    const uLong adler = adler32(adler32(0L, Z_NULL, 0), lines.data(), static_cast<uInt>(raw));

    std::vector<std::uint8_t> out;
    out.reserve(8 + 25 + 12 + idat + 12);
    const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    out.insert(out.end(), signature, signature + 8);
    chunk(out, "IHDR", 13, [&](std::vector<std::uint8_t>& o) {
        put32(o, static_cast<std::uint32_t>(w));
        put32(o, static_cast<std::uint32_t>(h));
        const std::uint8_t rest[5] = {8, 2, 0, 0, 0};  // bit depth 8, RGB, deflate, adaptive filtering, no interlace
        o.insert(o.end(), rest, rest + 5);
    });
    chunk(out, "IDAT", idat, [&](std::vector<std::uint8_t>& o) {
        o.push_back(0x78);  // deflate, 32 KiB window
        o.push_back(0x01);  // no dictionary, fastest; (0x78 * 256 + 0x01) % 31 == 0
        for (std::size_t at = 0, b = 0; b < blocks; ++b) {
            const std::size_t n = std::min(kMaxStoredBlock, raw - at);
            const bool last = b + 1 == blocks;
            o.push_back(last ? 1 : 0);  // BFINAL, BTYPE 00 (stored)
            o.push_back(static_cast<std::uint8_t>(n & 0xff));
            o.push_back(static_cast<std::uint8_t>(n >> 8));
            o.push_back(static_cast<std::uint8_t>(~n & 0xff));
            o.push_back(static_cast<std::uint8_t>((~n >> 8) & 0xff));
            o.insert(o.end(), lines.begin() + static_cast<std::ptrdiff_t>(at),
                     lines.begin() + static_cast<std::ptrdiff_t>(at + n));
            at += n;
        }
        put32(o, static_cast<std::uint32_t>(adler));
    });
    chunk(out, "IEND", 0, [](std::vector<std::uint8_t>&) {});
    return out;
}

}  // namespace vssim
