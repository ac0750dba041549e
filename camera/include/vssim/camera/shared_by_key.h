// Values that are costly to make (a lens's undistortion maps, a noise bank)
// and the same for the same key, made once and shared: while any holder
// lives, every renderer of that key gets the same value. The newest value
// also stays alive after its last holder goes, so that checking a scene's
// camera (cameraProblem) and then running it makes the maps once, as does a
// scene reloaded with the same camera. Thread-safe: the engine thread, the
// server and the desktop app's camera view make renderers concurrently.
#pragma once

#include <map>
#include <memory>
#include <mutex>

namespace vssim {

template <typename Key, typename Value>
class SharedByKey {
public:
    // The value for `key`: a living one, or make() (which may throw; nothing is kept then).
    template <typename Make>
    std::shared_ptr<const Value> get(const Key& key, Make make) {
        std::lock_guard lock(mutex_);
        if (auto found = made_.find(key); found != made_.end())
            if (std::shared_ptr<const Value> value = found->second.lock()) return value;
        std::shared_ptr<const Value> value = make();
        for (auto it = made_.begin(); it != made_.end();) it = it->second.expired() ? made_.erase(it) : std::next(it);
        made_[key] = value;
        newest_ = value;
        return value;
    }

private:
    std::mutex mutex_;
    std::map<Key, std::weak_ptr<const Value>> made_;
    std::shared_ptr<const Value> newest_;  // kept alive without holders (see above)
};

}  // namespace vssim
