// The one clock of the real-time parts: monotonic, in nanoseconds. The server
// stamps each message with it on arrival and the engine thread maps it to
// simulated time, so both must read the same clock.
#pragma once

#include <chrono>
#include <cstdint>

namespace vssim {

inline std::int64_t monotonicNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

}  // namespace vssim
