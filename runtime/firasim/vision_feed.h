// The bridge from the engine thread to FIRASim's vision: an instant observer
// (realtime/instant_record.h) that, at every camera instant, turns the world
// into an Environment (vision_packet.h), serialises it, and queues the bytes
// for the FirasimServer in the main thread, which sends them. Registered with
// the engine before it starts (attach), so that the desktop app can start
// and stop a FirasimServer while its engine runs: while no server listens
// (inactive), an instant costs one lock and nothing else.
//
// The score: the built-in referee's when it is on; otherwise 0:0, as
// FIRASim always sends it (its own goal counting is switched off in its
// source; an external referee such as VSSReferee keeps the score itself).
//
// The scene's camera adds its ground-truth noise to the positions (and
// leaves vanished bodies out), drawn per camera instant (vision_packet.h).
//
// Which robots are on the field: the server says (setOnField) when it takes
// a robot off (FIRASim's turnon false) or brings it back; those off are left
// out of the vision.
#pragma once

#include <QByteArray>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "fira_packet.pb.h"
#include "firasim/team_roster.h"
#include "realtime/instant_record.h"

namespace vssim {

class EngineThread;

// One vision message, serialised, and what it shows.
struct VisionItem {
    QByteArray bytes;          // a serialised fira_message.sim_to_ref.Environment
    std::int64_t step = 0;     // simulation step
    std::int64_t frame = 0;    // camera instant number
};

class VisionFeed {
public:
    // At most this many messages wait for the server; beyond, the oldest go (counted).
    static constexpr std::size_t kMaxQueued = 256;

    // A feed observing `engine`'s camera instants. Before engine.start() only.
    static std::shared_ptr<VisionFeed> attach(EngineThread& engine);

    // Starts feeding for `scene` (its field, robots and ball): every robot on
    // the field, the queue emptied. `wake` is
    // called (on the engine thread) when the queue goes from empty to not
    // empty, under the feed's lock; it must only schedule work (a queued call)
    // and not call the feed.
    void activate(const Scene& scene, std::function<void()> wake);
    // Stops feeding; no `wake` call happens after this returns.
    void deactivate();

    // Robot `robot` (scene index) on the field or not, from the next instant on.
    void setOnField(int robot, bool onField);
    std::vector<char> onField() const;
    // The world at the last camera instant (nothing before the first one seen while active).
    std::optional<WorldState> latestWorld() const;

    std::vector<VisionItem> take();
    std::int64_t dropped() const;  // messages dropped from a full queue

    // The observer's work (public for tests): one instant or game change.
    void observe(const InstantRecord& record);

private:
    mutable std::mutex mutex_;
    bool active_ = false;
    std::function<void()> wake_;
    std::optional<TeamRoster> roster_;
    double ballRadius_ = 0.0;
    CameraSettings camera_;  // the scene's: its ground-truth noise shows in the vision
    fira_message::Field fieldMessage_;
    std::vector<char> onField_;
    std::optional<WorldState> latest_;
    std::deque<VisionItem> queue_;
    std::int64_t dropped_ = 0;
};

}  // namespace vssim
