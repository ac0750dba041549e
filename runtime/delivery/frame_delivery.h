// One client's camera link (docs/protocol.md, FRAME, "Delivery"): a frame
// captured at simulated time t is delivered once simulated time reaches
// t + latency + j, j uniform in [0, jitter] drawn per (client, frame), and
// with probability `drop` it is never delivered; its STATE travels with it.
// Frames keep their capture order: a frame is never due before the one
// delivered ahead of it (its due time is raised to that one's). The draws
// are camera_draws.h's, keyed by (seed, the client's stream, frame number),
// so a lockstep run repeats exactly.
//
// What waits is bounded (maxBytes): beyond, the oldest frame waiting is
// dropped (overflowed()), as a camera pipeline's full buffer would.
//
// The server asks what is due whenever it learns the simulated time (a
// camera instant, a reply), so in real time a delay ends at the first such
// moment at or after it: rounded up to the next camera instant.
#pragma once

#include <QByteArray>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "delivery/camera_draws.h"
#include "vssim/camera_settings.h"

namespace vssim {

class FrameDelivery {
public:
    struct Captured {
        std::int64_t frame = 0;       // camera instant number
        double time = 0.0;            // s, simulated time of the capture
        std::int64_t instantNs = 0;   // monotonicNs() when the engine reached it (for the images' age)
        QByteArray frameMessage;      // complete FRAME message, or empty
        QByteArray stateMessage;      // complete STATE message, or empty
    };

    // Simulated time within which a frame counts as due, s: sums of dt
    // differ from their product by far less, and a delay of a whole number
    // of frame periods must end at that instant, not the next.
    static constexpr double kDueTolerance = 1e-9;

    FrameDelivery() = default;  // the ideal link: every frame due at its capture
    // `maxBytes`: the frames' bytes that may wait (at least the newest frame always does).
    FrameDelivery(const CameraSettings& camera, std::uint64_t stream, qint64 maxBytes = qint64{8} << 20);

    // No latency, no jitter, no drops: every frame is due the moment it is captured.
    bool immediate() const;

    // When the frame `frame` captured at `time` (s) would be due, from the
    // draws alone (before keeping the order), or nullopt when the link drops it.
    std::optional<double> scheduled(std::int64_t frame, double time) const;

    // A camera instant: queued until it is due, or dropped. A capture
    // earlier than the previous one (a reset took time back) first discards
    // the frames still on their way, which belong to the time before.
    void capture(Captured captured);
    // The frames due at simulated time `now` (s), oldest first, out of the queue.
    std::vector<Captured> due(double now);

    std::size_t waiting() const { return queue_.size(); }
    std::int64_t dropped() const { return dropped_; }        // frames the link dropped so far (`drop`)
    std::int64_t overflowed() const { return overflowed_; }  // frames dropped for want of room (maxBytes)
    qint64 waitingBytes() const { return bytes_; }

private:
    void rewindTo(double time);

    CameraSettings camera_;
    std::uint64_t stream_ = 0;
    qint64 maxBytes_ = qint64{8} << 20;
    std::deque<std::pair<double, Captured>> queue_;  // (due time, s; the frame), due times non-decreasing
    double lastDue_ = 0.0;      // s, the latest due time given; only meaningful while haveLast_
    double lastTime_ = 0.0;     // s, the latest capture or `now` seen
    bool haveLast_ = false;
    std::int64_t dropped_ = 0;
    std::int64_t overflowed_ = 0;
    qint64 bytes_ = 0;  // the waiting frames' FRAME and STATE bytes
};

}  // namespace vssim
