#include "realtime/engine_thread.h"

#include <QJsonArray>
#include <chrono>

#include "vssim/camera/image_patches.h"
#include "realtime/monotonic_clock.h"
#include "wire/game_message.h"
#include "wire/state_message.h"

namespace vssim {

EngineThread::EngineThread(const Scene& scene, const EngineLoopSettings& settings, QObject* parent)
    : QThread(parent), scene_(scene), settings_(settings), renderer_(cameraRendererOrIdeal(scene)) {
    // Readers see the initial state (and the mode) from the start, before
    // the thread runs.
    EngineLoop initial(scene_, settings_, *this);
    sceneShared_ = std::make_shared<const Scene>(scene_);
    framePeriod_ = initial.framePeriod();
    snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(initial, sceneShared_, 0.0, monotonicNs())));
}

double EngineThread::framePeriod() const { return framePeriod_.load(); }

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

bool EngineThread::postGroup(std::vector<EngineRequest> group) {
    if (group.empty()) return true;
    for (std::size_t i = 0; i + 1 < group.size(); ++i) group[i].groupedWithNext = true;
    group.back().groupedWithNext = false;
    {
        std::lock_guard lock(mutex_);
        if (inbox_.size() + group.size() > kMaxQueuedRequests) return false;
        for (EngineRequest& r : group) inbox_.push_back(std::move(r));
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
    { std::lock_guard lock(outboxMutex_); }
    framesTaken_.notify_all();
}

std::vector<OutboxItem> EngineThread::takeOutbox() {
    std::lock_guard lock(outboxMutex_);
    std::vector<OutboxItem> items;
    items.swap(outbox_);
    for (const OutboxItem& item : items)
        if (item.frame) framesPending_.fetch_sub(1);
    framesTaken_.notify_all();
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
                        framesPending_.fetch_sub(1);
                        ++framesDropped_;
                        break;
                    }
                }
            }
        }
        if (item.reply && item.reply->stats) item.reply->stats->framesDroppedUnsent = framesDropped_;
        wasEmpty = outbox_.empty();
        outbox_.push_back(std::move(item));
    }
    if (wasEmpty) emit outboxReady();
}

void EngineThread::run() {
    encoder_ = std::make_unique<FrameEncoder>(
        [this](std::shared_ptr<const FramePacket> frame, std::optional<EngineReply> reply) {
            push(OutboxItem{std::move(frame), std::move(reply)});
        });
    EngineLoop loop(scene_, settings_, *this);
    loop_ = &loop;
    loop.start(monotonicNs());
    started_ = true;
    snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(loop, sceneShared_, 0.0, monotonicNs())));
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
            // A slice at a time, so that a flood cannot hold simulated time still.
            std::size_t n = std::min(inbox_.size(), kMaxRequestsPerPass);
            while (n < inbox_.size() && inbox_[n - 1].groupedWithNext) ++n;  // a group stays whole
            batch.assign(std::make_move_iterator(inbox_.begin()), std::make_move_iterator(inbox_.begin() + n));
            inbox_.erase(inbox_.begin(), inbox_.begin() + n);
        }
        const std::int64_t startNs = monotonicNs();
        const double simStart = loop.simulation().state().time;
        for (const EngineRequest& request : batch) {
            if (request.kind == EngineRequest::Kind::LoadScene) {
                // The camera draws the new robots; readers see the new scene.
                renderer_ = cameraRendererOrIdeal(*request.scene);
                sceneShared_ = request.scene;
            }
            loop.handle(request, monotonicNs());
            if (request.kind == EngineRequest::Kind::LoadScene || request.kind == EngineRequest::Kind::SetSettings)
                framePeriod_ = loop.framePeriod();
            if (request.queued) request.queued->fetch_sub(1);
        }
        loop.runUntil(monotonicNs());
        const std::int64_t endNs = monotonicNs();
        const double simulated = loop.simulation().state().time - simStart;
        const double stepCost = simulated > 0 ? 1e-9 * static_cast<double>(endNs - startNs) / simulated : 0.0;
        snapshots_.publish(std::make_shared<Snapshot>(takeSnapshot(loop, sceneShared_, stepCost, endNs)));
    }
    loop_ = nullptr;
    encoder_.reset();  // finishes the jobs queued
}

void EngineThread::tellObservers(const Simulation& sim, std::int64_t frame, std::int64_t nowNs, bool instant) {
    if (observers_.empty()) return;
    InstantRecord record;
    record.cameraInstant = instant;
    record.frame = frame;
    record.step = sim.state().step;
    record.time = sim.state().time;
    record.instantNs = nowNs;
    record.world = sim.state();
    if (loop_) {
        record.referee = loop_->match().scene().game.rules.referee;
        record.game = loop_->match().game();
    }
    for (const InstantObserver& observer : observers_) observer(record);
}

void EngineThread::cameraInstant(const Simulation& sim, std::int64_t frame, std::int64_t nowNs) {
    tellObservers(sim, frame, nowNs, true);
    EncodeJob job;
    bool stateWanted;
    {
        std::lock_guard lock(mutex_);
        job.subscriptions = images_;
        stateWanted = stateWanted_;
    }
    if (job.subscriptions.empty() && !stateWanted) return;  // nobody is watching: no rendering
    const bool running = loop_->mode() != RunMode::Lockstep && !loop_->paused();
    if (loop_->mode() == RunMode::Realtime && running) {
        if (lastInstantNs_ >= 0) framePeriodMs_.add(1e-6 * static_cast<double>(nowNs - lastInstantNs_));
        lastInstantNs_ = nowNs;
    } else {
        lastInstantNs_ = -1;
    }
    // Render only when the server keeps up: as fast as possible, once it
    // has taken the previous frame (instead of rendering thousands nobody
    // could send); otherwise while fewer than kMaxPendingFrames wait to be
    // encoded or taken, which bounds the memory they hold.
    const int pendingLimit = loop_->mode() == RunMode::Max && running ? 1 : kMaxPendingFrames;
    if (!running) {
        // The instant that ends a step: wait for the server to take frames.
        std::unique_lock lock(outboxMutex_);
        framesTaken_.wait(lock, [&] { return framesPending_.load() < pendingLimit || stop_.load(); });
    } else if (framesPending_.load() >= pendingLimit) {
        ++framesSkipped_;
        return;
    }
    framesPending_.fetch_add(1);
    job.frame = frame;
    job.time = sim.state().time;
    job.instantNs = nowNs;
    if (!job.subscriptions.empty()) {
        const std::int64_t startNs = monotonicNs();
        // A new image each time (the encoder owns it); the frame number seeds its noise.
        renderer_.render(sim.state(), job.image, job.patches, static_cast<std::uint64_t>(job.frame));
        job.noisy = renderer_.settings().noise > 0.0;
        renderMs_.add(1e-6 * static_cast<double>(monotonicNs() - startNs));
        double area = 0.0;
        for (const cv::Rect& r : job.patches) area += r.area();
        patchPercent_.add(100.0 * area / (static_cast<double>(job.image.cols) * job.image.rows));
    }
    if (stateWanted) {
        const Match& match = loop_->match();
        const GameState* game = match.scene().game.rules.referee ? &match.game() : nullptr;
        job.stateJson = stateJson(sim, frame, game);
        job.state = protocol::encodeJsonMessage(protocol::MessageType::State, job.stateJson);
    }
    encoder_->submit(std::move(job));
}

void EngineThread::reply(const EngineReply& reply) {
    EncodeJob job;
    job.reply = reply;
    if (StatsReport* stats = job.reply->stats ? &*job.reply->stats : nullptr) {
        stats->framePeriodMs = framePeriodMs_.summary();
        stats->renderMs = renderMs_.summary();
        stats->patchAreaPercent = patchPercent_.summary();
        stats->framesSkipped = framesSkipped_;
    }
    // Through the encoder, to stay in order with the frames before it.
    encoder_->submit(std::move(job));
}

void EngineThread::halted(const SimulationFault& fault, std::int64_t) { emit simulationHalted(fault.message()); }

void EngineThread::gameChanged(const Match& match, std::int64_t frame, std::int64_t nowNs) {
    tellObservers(match.simulation(), frame, nowNs, false);
    EncodeJob job;
    job.reply = EngineReply{};
    QJsonObject json = gameStateJson(match.game());
    json["frame"] = static_cast<double>(frame);
    json["time"] = match.simulation().state().time;
    job.reply->referee = json;
    // Through the encoder, to stay in order with the frames around it.
    if (encoder_) encoder_->submit(std::move(job));
}

}  // namespace vssim
