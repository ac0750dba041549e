#include "engine_thread.h"

#include <QJsonArray>
#include <chrono>

#include "image_patches.h"
#include "monotonic_clock.h"
#include "state_message.h"

namespace vssim {

QString subscriptionName(const ImageSubscription& s) {
    QString name = s.kind == protocol::FrameKind::Full ? QStringLiteral("full/") : QStringLiteral("patches/");
    name += encodingName(s.encoding);
    if (s.encoding == ImageEncoding::Jpeg) name += QString::number(s.jpegQuality);
    return name;
}

EngineThread::EngineThread(const Scene& scene, const EngineLoopSettings& settings, QObject* parent)
    : QThread(parent), scene_(scene), settings_(settings), renderer_(scene) {
    // Readers see the initial state (and the mode) from the start, before
    // the thread runs.
    EngineLoop initial(scene_, settings_, *this);
    snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(initial, 0.0, monotonicNs())));
}

EngineThread::~EngineThread() {
    requestStop();
    wait();
}

bool EngineThread::post(EngineRequest request) {
    {
        std::lock_guard lock(mutex_);
        if (inbox_.size() >= kMaxQueuedRequests) return false;
        inbox_.push_back(std::move(request));
    }
    wake_.notify_one();
    return true;
}

void EngineThread::setSubscriptions(const std::vector<ImageSubscription>& images, bool state) {
    std::lock_guard lock(mutex_);
    images_ = images;
    stateWanted_ = state;
}

void EngineThread::requestStop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
}

std::vector<OutboxItem> EngineThread::takeOutbox() {
    std::lock_guard lock(outboxMutex_);
    std::vector<OutboxItem> items;
    items.swap(outbox_);
    return items;
}

void EngineThread::push(OutboxItem item) {
    bool wasEmpty;
    {
        std::lock_guard lock(outboxMutex_);
        if (item.frame) {
            // A reader that has fallen far behind (a stalled main thread)
            // loses the oldest frames rather than the engine's memory.
            std::size_t frames = 0;
            for (const OutboxItem& queued : outbox_) frames += queued.frame ? 1 : 0;
            if (frames >= kMaxQueuedFrames) {
                for (auto it = outbox_.begin(); it != outbox_.end(); ++it) {
                    if (it->frame) {
                        outbox_.erase(it);
                        ++framesSkipped_;
                        break;
                    }
                }
            }
        }
        wasEmpty = outbox_.empty();
        outbox_.push_back(std::move(item));
    }
    if (wasEmpty) emit outboxReady();
}

void EngineThread::run() {
    EngineLoop loop(scene_, settings_, *this);
    loop_ = &loop;
    loop.start(monotonicNs());
    snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(loop, 0.0, monotonicNs())));
    std::vector<EngineRequest> batch;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            auto ready = [&] { return stop_ || !inbox_.empty(); };
            const std::int64_t wakeNs = loop.nextWakeNs();
            if (wakeNs == std::numeric_limits<std::int64_t>::max()) {
                wake_.wait(lock, ready);
            } else if (wakeNs > monotonicNs()) {
                const std::chrono::steady_clock::time_point until{std::chrono::nanoseconds(wakeNs)};
                wake_.wait_until(lock, until, ready);
            }
            if (stop_) break;
            batch.clear();
            batch.swap(inbox_);
        }
        const std::int64_t startNs = monotonicNs();
        const double simStart = loop.simulation().state().time;
        for (const EngineRequest& request : batch) loop.handle(request, monotonicNs());
        loop.runUntil(monotonicNs());
        const std::int64_t endNs = monotonicNs();
        const double simulated = loop.simulation().state().time - simStart;
        const double stepCost = simulated > 0 ? 1e-9 * static_cast<double>(endNs - startNs) / simulated : 0.0;
        snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(loop, stepCost, endNs)));
    }
    loop_ = nullptr;
}

void EngineThread::cameraInstant(const Simulation& sim, std::int64_t frame, std::int64_t nowNs) {
    std::vector<ImageSubscription> images;
    bool stateWanted;
    {
        std::lock_guard lock(mutex_);
        images = images_;
        stateWanted = stateWanted_;
    }
    if (images.empty() && !stateWanted) return;  // nobody is watching: no rendering
    if (loop_->mode() == RunMode::Realtime && !loop_->paused()) {
        if (lastInstantNs_ >= 0) framePeriodMs_.add(1e-6 * static_cast<double>(nowNs - lastInstantNs_));
        lastInstantNs_ = nowNs;
    } else {
        lastInstantNs_ = -1;
    }
    if (loop_->mode() == RunMode::Max && !loop_->paused()) {
        // As fast as possible: render only when the server has taken the
        // previous frame, instead of rendering thousands nobody can send.
        std::lock_guard lock(outboxMutex_);
        for (const OutboxItem& item : outbox_) {
            if (item.frame) {
                ++framesSkipped_;
                return;
            }
        }
    }

    auto packet = std::make_shared<FramePacket>();
    packet->frame = frame;
    packet->time = sim.state().time;
    if (!images.empty()) {
        const std::int64_t t0 = monotonicNs();
        renderer_.render(sim.state(), frameImage_, patchRects_);
        renderMs_.add(1e-6 * static_cast<double>(monotonicNs() - t0));
        for (const ImageSubscription& s : images) {
            const std::int64_t e0 = monotonicNs();
            protocol::FrameHeader header;
            header.frame = static_cast<std::uint32_t>(frame);
            header.time = sim.state().time;
            header.kind = s.kind;
            header.encoding = s.encoding;
            std::vector<protocol::FramePatch> patches;
            if (s.kind == protocol::FrameKind::Full) {
                patches.push_back({0, 0, frameImage_.cols, frameImage_.rows, encodeImage(frameImage_, s.encoding, s.jpegQuality)});
            } else {
                for (const cv::Rect& r : patchRects_) {
                    protocol::FramePatch p{r.x, r.y, r.width, r.height, {}};
                    if (!r.empty()) p.data = encodeImage(frameImage_(r), s.encoding, s.jpegQuality);
                    patches.push_back(std::move(p));
                }
            }
            QByteArray message = protocol::encodeMessage(protocol::MessageType::Frame, protocol::encodeFrame(header, patches));
            const QString name = subscriptionName(s);
            encodeMs_[name].add(1e-6 * static_cast<double>(monotonicNs() - e0));
            frameBytes_[name].add(static_cast<double>(message.size()));
            packet->images.emplace_back(s, std::move(message));
        }
    }
    if (stateWanted)
        packet->state = protocol::encodeJsonMessage(protocol::MessageType::State, stateJson(sim, frame));
    push(OutboxItem{std::move(packet), std::nullopt});
}

QJsonObject EngineThread::cameraStats() const {
    QJsonObject encode, bytes;
    for (const auto& [name, stats] : encodeMs_) encode[name] = toJson(stats.summary());
    for (const auto& [name, stats] : frameBytes_) bytes[name] = toJson(stats.summary());
    return QJsonObject{
        {"frame_period_ms", toJson(framePeriodMs_.summary())},
        {"render_ms", toJson(renderMs_.summary())},
        {"encode_ms", encode},
        {"frame_bytes", bytes},
        {"frames_skipped", static_cast<double>(framesSkipped_)},
    };
}

void EngineThread::reply(const EngineReply& reply) {
    EngineReply r = reply;
    if (r.command == QLatin1String("stats") && r.ok) {
        const QJsonObject camera = cameraStats();
        for (auto it = camera.begin(); it != camera.end(); ++it) r.extra.insert(it.key(), it.value());
    }
    push(OutboxItem{nullptr, std::move(r)});
}

}  // namespace vssim
