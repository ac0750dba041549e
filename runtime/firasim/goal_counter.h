// Goals counted from the ball alone, for FIRASim's vision when vssim's own
// referee is off (an external referee such as VSSReferee, or none): a goal
// each time the whole ball enters a goal (game/pitch.h, goalScoredIn), once
// per entry. The ball must leave the goal (be seen outside it) before it can
// count again. Sides: yellow defends the goal at x < 0, so a ball in that
// goal is a goal by blue, and the other way round.
#pragma once

#include <array>

#include "vssim/ball.h"
#include "vssim/field.h"
#include "vssim/game/game_state.h"

namespace vssim {

class GoalCounter {
public:
    // Looks at the ball (m, field frame) at one camera instant; true when a
    // goal was counted now.
    bool observe(const Field& field, const BallState& ball, double ballRadius);
    // Goals scored by `team` so far.
    int goals(Team team) const { return goals_[teamIndex(team)]; }
    void reset() { *this = GoalCounter{}; }

private:
    std::array<int, 2> goals_{};  // by team: [Yellow], [Blue]
    int inGoal_ = 0;              // the goal the ball was last seen in: -1, +1, or 0 for none
};

}  // namespace vssim
