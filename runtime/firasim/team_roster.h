// The league's way of naming robots: a team colour and an id 0, 1, 2... in
// that team (FIRASim's Command.id and Robot.robot_id, VSSReferee's
// robot_id), against vssim's robot index in the scene. A team's robots get
// their ids in scene order.
#pragma once

#include <vector>

#include "vssim/scene.h"

namespace vssim {

class TeamRoster {
public:
    explicit TeamRoster(const Scene& scene);
    // The scene's robot index of robot `id` of `team`, or -1 when the team has no such robot.
    int robotIndex(Team team, unsigned id) const;
    // The id of scene robot `robot` within its team.
    unsigned idOf(int robot) const { return ids_[robot]; }
    Team teamOf(int robot) const { return teams_[robot]; }
    // The scene indices of a team's robots, by id.
    const std::vector<int>& members(Team team) const { return team == Team::Yellow ? yellow_ : blue_; }

private:
    std::vector<int> yellow_, blue_;
    std::vector<unsigned> ids_;
    std::vector<Team> teams_;
};

}  // namespace vssim
