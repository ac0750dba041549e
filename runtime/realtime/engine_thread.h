// The engine's worker thread: runs an EngineLoop (model.md §8) against the
// monotonic clock, renders camera images for the subscribers (a FrameEncoder
// thread encodes them), and publishes snapshots. Other threads talk to it through post() (requests
// stamped on arrival), takeOutbox() (frames and replies, in order) and
// snapshots(). While the server is behind (kMaxPendingFrames frames not taken
// yet; as fast as possible: one), a camera instant in real time is not
// rendered; one that ends a `step` waits for the server, since nothing else
// moves simulated time then and the client is owed that frame.
#pragma once

#include <QThread>
#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "vssim/camera/camera_renderer.h"
#include "realtime/engine_loop.h"
#include "realtime/frame_encoder.h"
#include "realtime/instant_record.h"
#include "realtime/snapshot.h"
#include "wire/frame_packet.h"

namespace vssim {

struct OutboxItem {
    std::shared_ptr<const FramePacket> frame;  // a camera instant, or
    std::optional<EngineReply> reply;          // a reply to a request
};

class EngineThread : public QThread, private EngineSink {
    Q_OBJECT
public:
    EngineThread(const Scene& scene, const EngineLoopSettings& settings, QObject* parent = nullptr);
    ~EngineThread() override;

    // Queues a request (any thread). False when the queue is full (a flood):
    // the caller answers `busy`.
    bool post(EngineRequest request);
    // Queues requests to be handled together, in order, with no simulated
    // time between them (a FIRASim replacement of several bodies). False,
    // and nothing queued, when they do not all fit.
    bool postGroup(std::vector<EngineRequest> group);
    // What the camera instants must produce (any thread; takes effect at the next instant).
    void setSubscriptions(const std::vector<ImageSubscription>& images, bool state);
    std::vector<OutboxItem> takeOutbox();
    // Adds an observer of every camera instant and game change (instant_record.h).
    // Before start() only.
    void addInstantObserver(InstantObserver observer) { observers_.push_back(std::move(observer)); }
    const SnapshotBuffer& snapshots() const { return snapshots_; }
    // Whether the loop has started (its camera instant 0 is behind it).
    bool started() const { return started_.load(); }
    // Ends the loop; returns at once (wait() joins).
    void requestStop();

    static constexpr std::size_t kMaxQueuedRequests = 10000;
    static constexpr std::size_t kMaxQueuedFrames = 64;      // in the outbox; beyond, the oldest go
    static constexpr std::size_t kMaxRequestsPerPass = 256;  // handled between two runUntil calls
    static constexpr int kMaxPendingFrames = 4;  // rendered and not yet taken; beyond, instants are not rendered
    double framePeriod() const;                  // s: the camera period (EngineLoop::framePeriod)

signals:
    // The outbox went from empty to not empty (emitted from the engine thread).
    void outboxReady();
    // The simulation's state stopped being finite and the loop halted
    // (engine_loop.h); `message` says when and which body (engine thread).
    void simulationHalted(const QString& message);

protected:
    void run() override;

private:
    void cameraInstant(const Simulation& sim, std::int64_t frame, std::int64_t nowNs) override;
    void reply(const EngineReply& reply) override;
    void halted(const SimulationFault& fault, std::int64_t nowNs) override;
    void gameChanged(const Match& match, std::int64_t frame, std::int64_t nowNs) override;
    void push(OutboxItem item);
    void tellObservers(const Simulation& sim, std::int64_t frame, std::int64_t nowNs, bool instant);

    const Scene scene_;
    const EngineLoopSettings settings_;
    CameraRenderer renderer_;                   // engine thread (after construction)
    std::shared_ptr<const Scene> sceneShared_;  // engine thread: the scene in snapshots
    std::atomic<double> framePeriod_{0.03};     // s
    SnapshotBuffer snapshots_;

    std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<EngineRequest> inbox_;
    std::atomic<bool> stop_{false};
    std::atomic<bool> started_{false};
    std::vector<ImageSubscription> images_;
    std::vector<InstantObserver> observers_;  // set before start(), then read by the engine thread only
    bool stateWanted_ = false;

    std::atomic<int> framesPending_{0};  // frames rendered and not yet taken by takeOutbox()
    std::mutex outboxMutex_;
    std::condition_variable framesTaken_;  // takeOutbox() took frames (or the thread is stopping)
    std::vector<OutboxItem> outbox_;

    // Engine-thread only.
    std::int64_t lastInstantNs_ = -1;
    SampleStats framePeriodMs_, renderMs_;
    SampleStats patchPercent_;        // the patches' total area, % of the image
    std::int64_t framesSkipped_ = 0;  // max mode: instants not rendered, the previous frame being still on its way
    std::int64_t framesDropped_ =
        0;  // dropped from a full outbox (a stalled reader); push() only, on the encoder thread
    const EngineLoop* loop_ = nullptr;       // while run() runs
    std::unique_ptr<FrameEncoder> encoder_;  // while run() runs
};

}  // namespace vssim
