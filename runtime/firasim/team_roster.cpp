#include "firasim/team_roster.h"

namespace vssim {

TeamRoster::TeamRoster(const Scene& scene) {
    for (std::size_t i = 0; i < scene.robots.size(); ++i) {
        std::vector<int>& team = scene.robots[i].team == Team::Yellow ? yellow_ : blue_;
        ids_.push_back(static_cast<unsigned>(team.size()));
        teams_.push_back(scene.robots[i].team);
        team.push_back(static_cast<int>(i));
    }
}

int TeamRoster::robotIndex(Team team, unsigned id) const {
    const std::vector<int>& robots = members(team);
    return id < robots.size() ? robots[id] : -1;
}

}  // namespace vssim
