#include "delivery/camera_draws.h"

#include <cmath>

#include "vssim/split_mix.h"

namespace vssim {

namespace {

constexpr double kTwoPi = 6.283185307179586;

}  // namespace

std::uint64_t cameraBits(const CameraDrawKey& key, CameraDraw draw) {
    std::uint64_t h = splitMix64(key.seed);
    h = splitMix64(h ^ key.stream);
    h = splitMix64(h ^ static_cast<std::uint64_t>(key.frame));
    h = splitMix64(h ^ key.body);
    return splitMix64(h ^ static_cast<std::uint64_t>(draw));
}

double cameraUniform(const CameraDrawKey& key, CameraDraw draw) {
    return static_cast<double>(cameraBits(key, draw) >> 11) * 0x1.0p-53;
}

double cameraGaussian(const CameraDrawKey& key, CameraDraw draw) {
    // Two uniforms of the draw's own: the second from the first's bits mixed once more.
    const std::uint64_t bits = cameraBits(key, draw);
    const double u1 = 1.0 - static_cast<double>(bits >> 11) * 0x1.0p-53;  // (0, 1]: the log is finite
    const double u2 = static_cast<double>(splitMix64(bits) >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

std::uint64_t clientStream(int role, std::int64_t ordinal) {
    return (static_cast<std::uint64_t>(role) + 1) << 32 | (static_cast<std::uint64_t>(ordinal) & 0xffffffffULL);
}

}  // namespace vssim
