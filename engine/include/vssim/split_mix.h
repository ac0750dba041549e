// SplitMix64's output function (Steele, Lea and Flood 2014): a bijective mix
// of a 64-bit integer whose outputs pass as independent uniform draws. Every
// seeded stream in vssim is built on it, so that a draw depends only on its
// key (seed, counter, ...): the match's jittered placements, the camera's
// sensor noise and its per-client delivery and ground-truth noise.
#pragma once

#include <cstdint>

namespace vssim {

constexpr std::uint64_t splitMix64(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

}  // namespace vssim
