#include "delivery/frame_delivery.h"

#include <algorithm>

namespace vssim {

FrameDelivery::FrameDelivery(const CameraSettings& camera, std::uint64_t stream) : camera_(camera), stream_(stream) {}

bool FrameDelivery::immediate() const { return camera_.latency == 0.0 && camera_.jitter == 0.0 && camera_.drop == 0.0; }

std::optional<double> FrameDelivery::scheduled(std::int64_t frame, double time) const {
    const CameraDrawKey key{camera_.seed, stream_, frame, kWholeFrame};
    if (camera_.drop > 0.0 && cameraUniform(key, CameraDraw::Drop) < camera_.drop) return std::nullopt;
    double delay = camera_.latency;
    if (camera_.jitter > 0.0) delay += camera_.jitter * cameraUniform(key, CameraDraw::Jitter);
    return time + delay;
}

void FrameDelivery::rewindTo(double time) {
    if (haveLast_ && time < lastTime_ - kDueTolerance) {
        queue_.clear();
        haveLast_ = false;
    }
}

void FrameDelivery::capture(Captured captured) {
    rewindTo(captured.time);
    const std::optional<double> at = scheduled(captured.frame, captured.time);
    if (!haveLast_) {
        lastDue_ = lastTime_ = captured.time;
        haveLast_ = true;
    }
    lastTime_ = std::max(lastTime_, captured.time);
    if (!at) {
        ++dropped_;
        return;
    }
    // Never ahead of the frame before it.
    lastDue_ = std::max(lastDue_, *at);
    queue_.emplace_back(lastDue_, std::move(captured));
}

std::vector<FrameDelivery::Captured> FrameDelivery::due(double now) {
    rewindTo(now);
    if (haveLast_) lastTime_ = std::max(lastTime_, now);
    std::vector<Captured> out;
    while (!queue_.empty() && queue_.front().first <= now + kDueTolerance) {
        out.push_back(std::move(queue_.front().second));
        queue_.pop_front();
    }
    return out;
}

}  // namespace vssim
