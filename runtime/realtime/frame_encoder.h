// The camera's second stage, on a thread of its own: encodes rendered
// images (PNG, JPEG, raw) into FRAME messages for each image subscription,
// so that the engine thread, which only renders, is free to take commands
// the moment they arrive. Jobs come out in the order they went in, replies
// included, so a lockstep client still gets its FRAME before its REPLY.
#pragma once

#include <QByteArray>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <opencv2/core.hpp>
#include <optional>
#include <thread>
#include <vector>

#include "realtime/engine_request.h"
#include "realtime/sample_stats.h"
#include "wire/frame_packet.h"

namespace vssim {

struct EncodeJob {
    std::optional<EngineReply> reply;  // a reply to pass on in order, or a camera instant:
    std::int64_t frame = 0;
    double time = 0.0;              // s
    std::int64_t instantNs = 0;     // monotonicNs() when the engine reached the instant
    cv::Mat image;                  // the rendered frame (empty when only the state is wanted)
    bool noisy = false;             // the camera adds sensor noise: PNG data stored, not deflated (image_codec.h)
    std::vector<cv::Rect> patches;  // CameraRenderer::render's patches
    std::vector<ImageSubscription> subscriptions;
    QByteArray state;  // the complete STATE message, or empty
    QJsonObject stateJson;  // its JSON
};

class FrameEncoder {
public:
    // `deliver` receives each finished packet or reply, on the encoder's thread.
    explicit FrameEncoder(std::function<void(std::shared_ptr<const FramePacket>, std::optional<EngineReply>)> deliver);
    ~FrameEncoder();
    void submit(EncodeJob job);

private:
    void run();
    std::shared_ptr<const FramePacket> encode(const EncodeJob& job);

    std::function<void(std::shared_ptr<const FramePacket>, std::optional<EngineReply>)> deliver_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<EncodeJob> jobs_;
    bool stop_ = false;
    // Encoder thread only.
    std::map<QString, SampleStats> encodeMs_, frameBytes_;  // per subscription ("patches/png", ...)
    std::thread thread_;                                    // last: starts after everything above exists
};

}  // namespace vssim
