// Where the referee puts the ball and the robots after a call, and whether a
// team's own placement is legal (docs/game.md, "Placement"):
//   kick-off      ball at the centre; every robot in its own half, centres
//                 outside the centre circle, except one robot of the kicking
//                 team, which the referee puts just behind the ball;
//   free ball     ball on its quadrant's mark; one robot of each team
//                 free_ball_distance from it along x, on its own side; every
//                 robot at least free_ball_distance - 1 cm from the ball;
//   penalty kick  ball on the penalty mark; the kicker behind it, the
//                 defending goalkeeper on its goal line; every other robot
//                 in the half away from that goal;
//   goal kick     ball in the defending goal area, the goalkeeper behind it;
//                 no attacker in that goal area, every other robot in its own half.
// Each team's goalkeeper (referee.h) waits at the middle of its goal line
// unless it is the robot the call needs. Every robot lies on the floor and
// overlaps no other body. All positions in the field frame, m, rad; bodies at rest.
#pragma once

#include <string>
#include <vector>

#include "vssim/game/game_state.h"
#include "vssim/world_model.h"

namespace vssim {

struct Placement {
    std::vector<RobotState> robots;  // every robot of the scene
    BallState ball;
    // Robots off the field (WorldState::offField; empty: none): a team's
    // placement is not checked for them, nor against them.
    std::vector<char> offField;
};

// The referee's placement for `call`, starting from `state` (a robot that no
// legal spot can be found for stays where it is).
Placement automaticPlacement(const WorldModel& model, const WorldState& state, const std::vector<Team>& teams,
                             const GameState& game, const GameRules& rules, const RefereeCall& call);

// Whether `team`'s robots in `placement` are legal for `call`, with every
// other body where `placement` has it: an empty string, or why not, naming
// the robot ("yellow1 (robot 1) is in the other half").
std::string checkTeamPlacement(const WorldModel& model, const std::vector<Team>& teams,
                               const std::vector<std::string>& names, const GameRules& rules, const RefereeCall& call,
                               Team team, const Placement& placement);

}  // namespace vssim
