// A fingerprint of a world state for determinism checks: FNV-1a (64 bit)
// over the bytes of every double of the state. Equal hashes mean
// bit-identical states (to the odds of a 64-bit collision); a one-ulp change
// anywhere changes the hash.
#pragma once

#include <cstdint>
#include <cstring>

#include "vssim/world.h"

namespace vssim {

inline std::uint64_t hashState(const WorldState& s) {
    std::uint64_t h = 1469598103934665603ull;  // FNV-1a 64-bit offset basis
    auto mix = [&h](double value) {
        unsigned char bytes[sizeof value];
        std::memcpy(bytes, &value, sizeof value);
        for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;  // FNV-1a 64-bit prime
    };
    for (const RobotState& r : s.robots)
        for (double v : {r.x, r.y, r.theta, r.v, r.omega}) mix(v);
    for (const Voltages& e : s.voltages) mix(e.right), mix(e.left);
    for (double v : {s.ball.x, s.ball.y, s.ball.vx, s.ball.vy}) mix(v);
    return h;
}

}  // namespace vssim
