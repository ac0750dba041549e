// The gaps between the moving bodies of a world and everything they could
// reach within a horizon, with how fast each gap can close: the input of the
// long-step planner's conservative advancement (time_of_impact.h).
#pragma once

#include <utility>
#include <vector>

#include "vssim/broad_phase.h"
#include "vssim/contact.h"
#include "vssim/separation.h"
#include "vssim/world_model.h"

namespace vssim {

// Body a (a robot or the ball) and body b (a robot, the ball or a wall), in
// the roles Contact gives them: robot i and robot j > i; the ball and a
// robot; a robot or the ball and a wall.
struct BodyGap {
    BodyRef a;
    BodyRef b;
    double gap = 0.0;      // m, now
    double closing = 0.0;  // m/s: the fastest the gap can shrink within the horizon under the current voltages
};

struct BodyGapScratch {
    std::vector<double> speed;  // per body (robots, then the ball): the fastest any of its points moves, m/s
    std::vector<std::pair<int, int>> pairs;
    std::vector<int> moving;  // indices of the moving robots
    std::vector<RobotState> movingPoses;
    std::vector<double> movingSides;
    BroadPhaseScratch broadPhase;
};

// Appends to `out` (cleared first) the gap of every pair of a moving body
// (`movingRobots[i]` non-zero, the ball when `ballMoving`) with a moving body
// or a wall that could close within `horizon` s; pairs farther apart than
// their bodies can travel in it are left out. In a fixed order (deterministic).
void findBodyGaps(const WorldModel& model, const WorldState& state, const std::vector<char>& movingRobots,
                  bool ballMoving, double horizon, std::vector<BodyGap>& out, BodyGapScratch& scratch);

// The ball's centre as a pose (x, y; theta 0), for separationBetween.
RobotState ballPose(const BallState& ball);

// The separation of a pair's bodies at the given poses (a robot's x, y and
// theta; the ball's centre in x and y; a wall's pose is not used).
Separation separationBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                             const RobotState& poseB);

}  // namespace vssim
