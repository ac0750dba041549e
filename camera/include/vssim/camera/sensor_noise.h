// Gaussian sensor noise of the synthetic camera, cheap enough for every
// frame: a bank of Gaussian draws made once (1.5 frames' worth of bytes,
// shared by every camera of the same noise, seed and size: shared_by_key.h;
// rounded to whole grey levels), of which each frame adds the window that
// starts at an offset drawn from (seed, frame number). Same seed and frame
// number, same noise; frames differ by where their window starts.
//
// What the bank implies: a frame's noise is independent from pixel to pixel
// and channel to channel, with standard deviation sqrt(sigma^2 + 1/12) grey
// levels before saturation (the rounding adds 1/12) and mean 0; two frames'
// noise fields are the same values shifted by the difference of their offsets
// (one of half a frame's bytes of offsets): uncorrelated pixel by pixel, but
// drawn from the same 1.5 frames' worth of values.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace vssim {

class SensorNoise {
public:
    SensorNoise() = default;  // none
    // Noise of standard deviation `sigma` grey levels (>= 0) for frames of
    // `frameBytes` bytes. sigma = 0: none (no bank).
    SensorNoise(double sigma, std::uint64_t seed, std::size_t frameBytes);

    bool active() const { return bank_ != nullptr; }
    // Adds the noise of frame `frameNumber` to every byte of `frame` (an
    // 8-bit image of frameBytes bytes, rows in order; throws
    // std::invalid_argument otherwise), saturating to 0..255. Nothing when
    // inactive.
    void add(cv::Mat& frame, std::uint64_t frameNumber) const;
    // Where frame `frameNumber`'s window starts in the bank (tests).
    std::size_t offset(std::uint64_t frameNumber) const;

private:
    std::shared_ptr<const std::vector<std::int16_t>> bank_;  // grey levels; shared (see above)
    std::size_t frameBytes_ = 0;
    std::uint64_t seed_ = 0;
};

}  // namespace vssim
