#include "firasim/vision_feed.h"

#include "firasim/vision_packet.h"
#include "realtime/engine_thread.h"

namespace vssim {

std::shared_ptr<VisionFeed> VisionFeed::attach(EngineThread& engine) {
    auto feed = std::make_shared<VisionFeed>();
    // The engine keeps the feed alive as long as it may call it.
    engine.addInstantObserver([feed](const InstantRecord& record) { feed->observe(record); });
    return feed;
}

void VisionFeed::activate(const Scene& scene, std::function<void()> wake) {
    std::lock_guard lock(mutex_);
    active_ = true;
    wake_ = std::move(wake);
    roster_.emplace(scene);
    ballRadius_ = scene.ball_params.radius;
    camera_ = scene.camera;
    fieldMessage_ = firasimField(scene.field);
    onField_.assign(scene.robots.size(), 1);
    latest_.reset();
    queue_.clear();
}

void VisionFeed::deactivate() {
    std::lock_guard lock(mutex_);
    active_ = false;
    wake_ = nullptr;
    queue_.clear();
}

void VisionFeed::setOnField(int robot, bool onField) {
    std::lock_guard lock(mutex_);
    if (robot >= 0 && robot < static_cast<int>(onField_.size())) onField_[robot] = onField ? 1 : 0;
}

std::vector<char> VisionFeed::onField() const {
    std::lock_guard lock(mutex_);
    return onField_;
}

std::optional<WorldState> VisionFeed::latestWorld() const {
    std::lock_guard lock(mutex_);
    return latest_;
}

std::vector<VisionItem> VisionFeed::take() {
    std::lock_guard lock(mutex_);
    std::vector<VisionItem> items(std::make_move_iterator(queue_.begin()), std::make_move_iterator(queue_.end()));
    queue_.clear();
    return items;
}

std::int64_t VisionFeed::dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
}

void VisionFeed::observe(const InstantRecord& record) {
    if (!record.cameraInstant) return;  // news of the game only: the next instant shows it
    {
        // `wake` is called under the lock, so that none comes after deactivate().
        std::lock_guard lock(mutex_);
        if (!active_ || !roster_) return;
        // A scene of another size (the app loaded one before restarting the
        // server) is not ours to describe.
        if (record.world.robots.size() != onField_.size()) return;
        // The engine's word on who is on the field (WorldState::offField):
        // a turnon the engine has not handled yet does not show.
        for (std::size_t i = 0; i < onField_.size(); ++i)
            onField_[i] = i < record.world.offField.size() && record.world.offField[i] ? 0 : 1;
        latest_ = record.world;
        const std::array<int, 2> goals = record.referee ? record.game.goals : std::array<int, 2>{};
        const fira_message::sim_to_ref::Environment env =
            firasimEnvironment(fieldMessage_, *roster_, record.world, ballRadius_, onField_, goals, camera_,
                               record.frame);
        VisionItem item;
        item.bytes.resize(static_cast<qsizetype>(env.ByteSizeLong()));
        env.SerializeToArray(item.bytes.data(), static_cast<int>(item.bytes.size()));
        item.step = record.step;
        item.frame = record.frame;
        if (queue_.size() >= kMaxQueued) {
            queue_.pop_front();
            ++dropped_;
        }
        const bool wasEmpty = queue_.empty();
        queue_.push_back(std::move(item));
        if (wasEmpty && wake_) wake_();
    }
}

}  // namespace vssim
