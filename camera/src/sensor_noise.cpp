#include "vssim/camera/sensor_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "vssim/camera/shared_by_key.h"
#include "vssim/split_mix.h"

namespace vssim {

namespace {

// Uniform in (0, 1) from 53 bits of a mixed counter.
double unitOpen(std::uint64_t bits) { return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53; }

}  // namespace

SensorNoise::SensorNoise(double sigma, std::uint64_t seed, std::size_t frameBytes)
    : frameBytes_(frameBytes), seed_(seed) {
    if (!(sigma >= 0.0) || !std::isfinite(sigma))
        throw std::invalid_argument("camera noise: the standard deviation must be >= 0 grey levels (got " +
                                    std::to_string(sigma) + ")");
    if (sigma == 0.0 || frameBytes == 0) return;
    // Cameras of the same noise share its bank (shared_by_key.h): made once.
    using Key = std::tuple<double, std::uint64_t, std::size_t>;
    static SharedByKey<Key, std::vector<std::int16_t>> made;
    bank_ = made.get(Key{sigma, seed, frameBytes}, [&] {
        // Box-Muller on a counter-based stream: the same bank on every machine.
        auto bank = std::make_shared<std::vector<std::int16_t>>(frameBytes + frameBytes / 2);
        const std::uint64_t stream = splitMix64(seed ^ 0x6e6f697365ULL);
        for (std::size_t i = 0; i < bank->size(); i += 2) {
            const double u1 = unitOpen(splitMix64(stream + 2 * i)), u2 = unitOpen(splitMix64(stream + 2 * i + 1));
            const double radius = sigma * std::sqrt(-2.0 * std::log(u1)), angle = 2.0 * M_PI * u2;
            const auto level = [](double x) {
                return static_cast<std::int16_t>(std::clamp(std::lround(x), -512L, 512L));
            };
            (*bank)[i] = level(radius * std::cos(angle));
            if (i + 1 < bank->size()) (*bank)[i + 1] = level(radius * std::sin(angle));
        }
        return std::shared_ptr<const std::vector<std::int16_t>>(std::move(bank));
    });
}

std::size_t SensorNoise::offset(std::uint64_t frameNumber) const {
    if (!bank_) return 0;
    const std::size_t choices = bank_->size() - frameBytes_ + 1;
    return static_cast<std::size_t>(splitMix64(splitMix64(seed_) ^ splitMix64(frameNumber + 0x66726d)) % choices);
}

void SensorNoise::add(cv::Mat& frame, std::uint64_t frameNumber) const {
    if (!bank_) return;
    const std::size_t rowBytes = frame.cols * frame.elemSize();
    if (frame.depth() != CV_8U || rowBytes * frame.rows != frameBytes_)
        throw std::invalid_argument("SensorNoise::add: the frame must be an 8-bit image of " +
                                    std::to_string(frameBytes_) + " bytes");
    const std::int16_t* n = bank_->data() + offset(frameNumber);
    for (int row = 0; row < frame.rows; ++row, n += rowBytes) {
        std::uint8_t* p = frame.ptr<std::uint8_t>(row);
        for (std::size_t i = 0; i < rowBytes; ++i) {
            const int v = p[i] + n[i];
            p[i] = static_cast<std::uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
        }
    }
}

}  // namespace vssim
