// The measurements a `stats` request gathers on its way to the client
// (docs/protocol.md, CONTROL stats). The request passes the engine loop, the
// engine thread, the frame encoder and the server in turn; each fills its
// own part here, and the server writes the whole as JSON once.
#pragma once

#include <QString>
#include <cstdint>
#include <map>

#include "realtime/sample_stats.h"

namespace vssim {

struct StatsReport {
    // EngineLoop: commands.
    SampleSummary commandLatencyMs;  // arrival to application, wall clock, ms
    SampleSummary commandDelayMs;    // arrival to application, simulated time, ms
    std::int64_t lateCommands = 0;   // applied after their arrival instant had passed
    std::int64_t lagResets = 0;      // times the engine fell too far behind and dropped the lag
    // EngineThread: camera instants.
    SampleSummary framePeriodMs;           // between camera instants, wall clock, ms
    SampleSummary renderMs;                // rendering one image, ms
    SampleSummary patchAreaPercent;        // patches' share of the image, %
    std::int64_t framesSkipped = 0;        // max mode: instants not rendered
    std::int64_t framesDroppedUnsent = 0;  // dropped from a full outbox (a stalled server thread)
    // FrameEncoder: per subscription ("patches/png", ...).
    std::map<QString, SampleSummary> encodeMs;    // ms
    std::map<QString, SampleSummary> frameBytes;  // bytes
    // ControlServer.
    SampleSummary imageAgeMs;  // camera instant to its FRAME's hand-over to a client's socket, wall clock, ms
    int clients = 0;
    std::int64_t framesDroppedForSlowClients = 0;
};

}  // namespace vssim
