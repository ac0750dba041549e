#include "firasim/goal_counter.h"

#include "vssim/game/pitch.h"

namespace vssim {

bool GoalCounter::observe(const Field& field, const BallState& ball, double ballRadius) {
    const int side = goalScoredIn(field, ball, ballRadius);
    const bool entered = side != 0 && side != inGoal_;
    inGoal_ = side;
    if (!entered) return false;
    // The goal at x < 0 is yellow's: a ball there is blue's goal.
    ++goals_[teamIndex(side < 0 ? Team::Blue : Team::Yellow)];
    return true;
}

}  // namespace vssim
