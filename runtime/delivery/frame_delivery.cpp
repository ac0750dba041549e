#include "delivery/frame_delivery.h"

#include <algorithm>

namespace vssim {

FrameDelivery::FrameDelivery(const CameraSettings& camera, std::uint64_t stream, qint64 maxBytes)
    : camera_(camera), stream_(stream), maxBytes_(maxBytes) {}

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
        bytes_ = 0;
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
    bytes_ += captured.frameMessage.size() + captured.stateMessage.size();
    queue_.emplace_back(lastDue_, std::move(captured));
    while (bytes_ > maxBytes_ && queue_.size() > 1) {
        const Captured& oldest = queue_.front().second;
        bytes_ -= oldest.frameMessage.size() + oldest.stateMessage.size();
        queue_.pop_front();
        ++overflowed_;
    }
}

std::vector<FrameDelivery::Captured> FrameDelivery::due(double now) {
    rewindTo(now);
    if (haveLast_) lastTime_ = std::max(lastTime_, now);
    std::vector<Captured> out;
    while (!queue_.empty() && queue_.front().first <= now + kDueTolerance) {
        Captured& front = queue_.front().second;
        bytes_ -= front.frameMessage.size() + front.stateMessage.size();
        out.push_back(std::move(front));
        queue_.pop_front();
    }
    return out;
}

}  // namespace vssim
