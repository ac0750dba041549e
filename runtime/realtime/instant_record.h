// What other interfaces than the TCP camera (FIRASim's vision, VSSReferee's
// commands) learn of each camera instant: the world and the game as they
// are at it. The engine thread hands one to each observer
// (EngineThread::addInstantObserver) on its own thread, at every camera
// instant whether or not a TCP client watches, and when a request changes
// the game between instants.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "vssim/game/game_state.h"
#include "vssim/scene.h"
#include "vssim/world_model.h"

namespace vssim {

struct InstantRecord {
    bool cameraInstant = true;  // false: only news that the game changed (a request), not a new instant
    std::int64_t frame = 0;     // camera instant number since start or reset
    std::int64_t step = 0;      // steps of dt simulated (world.step)
    double time = 0.0;          // simulated time, s
    std::int64_t instantNs = 0; // monotonicNs() when the engine reached it
    WorldState world;           // positions, velocities, voltages (SI units)
    bool referee = false;       // the built-in referee is on (then `game` is its state)
    GameState game;
};

// Called on the engine thread: must be quick and thread-safe (copy what it
// needs and hand it on).
using InstantObserver = std::function<void(const InstantRecord&)>;

}  // namespace vssim
