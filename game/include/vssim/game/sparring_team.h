// vssim's built-in team: a simple, deterministic controller that plays
// either side through the motor model (it outputs voltages, as a team's own
// software would). Roles by the team's robots: its goalkeeper (referee.h)
// guards the goal line, the robot after it defends between the ball and the
// goal, and the others attack: get behind the ball on the line to the
// other goal and drive through it. docs/game.md describes each role.
//
// It sees the true state (no camera) and decides once per game tick; the
// same state gives the same voltages.
#pragma once

#include <vector>

#include "vssim/game/game_state.h"
#include "vssim/world_model.h"

namespace vssim {

// Voltages for every robot of `team` (entries of other robots are left as
// they are), V. The team defends the goal rules.left_team says it does.
void sparringVoltages(const WorldModel& model, const WorldState& state, const std::vector<Team>& teams,
                      const GameRules& rules, const GameState& game, Team team, std::vector<Voltages>& voltages);

// The voltages that drive a robot towards body velocity (v, w) (m/s, rad/s):
// the steady-state inverse of the motor model (model.md eq. 7) plus a
// proportional correction on the velocity error, clamped to +-max_voltage.
Voltages voltagesFor(const RobotModel& robot, const RobotState& state, double v, double w);

}  // namespace vssim
