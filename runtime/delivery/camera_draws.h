// The random draws of the camera's delivery and ground-truth noise
// (docs/protocol.md, FRAME and STATE): a counter-based generator, each draw
// a pure function of (seed, stream, frame, body, what it is for), so that a
// client's drops, delays and noise at a frame do not depend on how many
// draws came before, on wall time or on thread timing, and lockstep runs
// repeat exactly. Not a std engine with state: a sequence would tie each
// client's draws to the order in which the server met its frames (a frame
// skipped in real time would shift every later one).
//
// The mixing is SplitMix64's finaliser (Steele, Lea and Flood, "Fast
// splittable pseudorandom number generators", 2014) applied to each key in
// turn; its output passes BigCrush as a counter-based generator.
#pragma once

#include <cstdint>

namespace vssim {

// What a draw is for: each purpose has draws of its own.
enum class CameraDraw : std::uint64_t {
    Drop = 1,     // whether a frame is dropped
    Jitter = 2,   // a frame's extra delay
    Vanish = 3,   // whether a body is missing from a frame's positions
    NoiseX = 4,   // Gaussian noise on x
    NoiseY = 5,   // on y
    NoiseTheta = 6,  // on a robot's heading
};

// The `body` of a draw that concerns a whole frame (Drop, Jitter).
constexpr std::uint64_t kWholeFrame = ~std::uint64_t{0};
// The ball's `body` (robots use their scene index), so that the ball's draws
// do not change with the number of robots.
constexpr std::uint64_t kBallBody = ~std::uint64_t{0} - 1;

// The stream of the FIRASim vision feed; TCP clients' streams (clientStream) differ from it.
constexpr std::uint64_t kFirasimStream = 0;

struct CameraDrawKey {
    std::uint64_t seed = 1;    // CameraSettings::seed
    std::uint64_t stream = 0;  // whose draws: a client's (clientStream), or the FIRASim feed
    std::int64_t frame = 0;    // the camera instant's number
    std::uint64_t body = kWholeFrame;
};

// 64 random bits for `key` and `draw`.
std::uint64_t cameraBits(const CameraDrawKey& key, CameraDraw draw);
// Uniform in [0, 1), with 53 random bits.
double cameraUniform(const CameraDrawKey& key, CameraDraw draw);
// Standard normal (mean 0, standard deviation 1), by Box and Muller from two
// uniform draws of its own.
double cameraGaussian(const CameraDrawKey& key, CameraDraw draw);

// A TCP client's stream: from its role (0 yellow, 1 blue, 2 observer) and
// how many clients with that role greeted the server before it (0 for the
// first), so that every client gets draws of its own and a lockstep run
// that connects the same clients in the same order repeats. Never
// kFirasimStream.
std::uint64_t clientStream(int role, std::int64_t ordinal);

}  // namespace vssim
