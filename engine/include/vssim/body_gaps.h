// The gaps between the moving bodies of a world and everything they could
// reach within a horizon, with how fast each gap can close: the input of the
// long-step planner's conservative advancement (time_of_impact.h).
#pragma once

#include <utility>
#include <vector>

#include "vssim/broad_phase.h"
#include "vssim/contact.h"
#include "vssim/geometry.h"
#include "vssim/separation.h"
#include "vssim/world_model.h"

namespace vssim {

// Body a (a robot or the ball) and body b (a robot, the ball or a wall), in
// the roles Contact gives them: robot i and robot j > i; the ball and a
// robot; a robot or the ball and a wall.
//
// `closing` is a speed S such that the pair cannot touch before gap / S:
// the smaller of two bounds, each safe on its own (body_gaps.cpp):
//  - the sum of the fastest any point of either body can move (the gap is a
//    distance between sets whose points move at most that fast);
//  - the time the pair needs to close the gap along the separation's normal
//    n, held fixed: the bodies' extents along n are apart by exactly the gap
//    now (n is the direction between their nearest points), and they cannot
//    touch while those extents stay apart. A robot's centre moves towards
//    the other body at v cos(theta - angle of n), at most at the largest
//    product of v's range over the horizon and that cosine's range with
//    theta between its start plus T times w's least and greatest values
//    over the horizon (each with 0) (negative for a robot that drives
//    away all along: then the pair closes only as far as the extents grow,
//    if at all), and at most at |v| |cos|; its extent along n grows at most at |w| (s/2)
//    ||cos| - |sin|| of that angle now (0 with a corner towards the other
//    body, 1 face on) and never past s/sqrt2 (a robot spinning near a wall
//    can only reach so far). The ball
//    closes at the component of its velocity towards the other body (it
//    slides straight, slowing down); a wall not at all. Much later than the
//    first for a robot that spins or runs along a wall or past another.
struct BodyGap {
    BodyRef a;
    BodyRef b;
    double gap = 0.0;      // m, now
    double closing = 0.0;  // m/s: how fast the gap can close within the horizon under the current voltages (above)
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // the separation's normal now (zero when touching)
    Eigen::Vector2d point = Eigen::Vector2d::Zero();   // the middle of the nearest points now, m
};

// What bounds one body's motion over a horizon, for its gaps' closing speeds.
struct MotionBound {
    double pointSpeed = 0.0;  // m/s: the fastest any point of the body moves
    double linear = 0.0;      // m/s: a robot's |v|, at most
    double forwardLow = 0.0;  // m/s: a robot's v (signed) is at least this within the horizon
    double forwardHigh = 0.0; // m/s: and at most this
    double swingLow = 0.0;    // rad, <= 0: the heading turns by at least this (signed, counter-clockwise positive)
    double swingHigh = 0.0;   // rad, >= 0: and at most this (both within +-swing)
    double turning = 0.0;     // rad/s: a robot's |w|, at most
    double swing = 0.0;       // rad: the most a robot's heading can turn
    CosSin heading;           // a robot's heading now
    double side = 0.0;        // m: a robot's side
    bool ball = false;        // the ball: it goes straight at `velocity`, slowing down
    Eigen::Vector2d velocity = Eigen::Vector2d::Zero();  // m/s: the ball's
};
// A robot's over progress.T seconds (progress.fits(model, progress.T)).
MotionBound robotMotionBound(const RobotModel& model, const RobotState& state, const Voltages& e, double side,
                             const ModeProgress& progress);
MotionBound ballMotionBound(const BallState& ball);
// The closing speed of a gap (BodyGap) with separation `s` between body a
// and body b (nullptr: a wall), from their bounds over the same horizon;
// `pointSpeeds` is their point speeds' sum (the first bound), returned when
// the second is no better or `s` is within rounding of touching.
double closingSpeed(const Separation& s, const MotionBound& a, const MotionBound* b, double pointSpeeds);

struct BodyGapScratch {
    std::vector<MotionBound> bounds;  // per body (robots, then the ball), over the horizon
    std::vector<std::pair<int, int>> pairs;
    ListedPairsScratch listed;  // the moving robots' broad phase
    ModeProgressCache progress;
    std::vector<char> bounded;  // remeasureBodyGaps': per body, its entry of `bounds` is set
};

// Appends to `out` (cleared first) the gap of every pair of a moving body
// (the robots `movingRobots`, increasing indices, and the ball when
// `ballMoving`; its cost grows with those only) with a moving body
// or a wall that could close within `horizon` s; pairs farther apart than
// their bodies can travel in it are left out. In a fixed order (deterministic).
void findBodyGaps(const WorldModel& model, const WorldState& state, const std::vector<int>& movingRobots,
                  bool ballMoving, double horizon, std::vector<BodyGap>& out, BodyGapScratch& scratch);

// Each of `gaps` (found by findBodyGaps for a longer horizon, in a state
// these bodies have since reached under the same voltages, with no contact
// on the way) measured again in `state`, with the bounds over `horizon` s:
// the same values findBodyGaps would give those pairs. It finds no new
// pair: the caller keeps the ones that may still come within kContactSkin.
void remeasureBodyGaps(const WorldModel& model, const WorldState& state, double horizon, std::vector<BodyGap>& gaps,
                       BodyGapScratch& scratch);

// The ball's centre as a pose (x, y; theta 0), for separationBetween.
RobotState ballPose(const BallState& ball);

// The separation of a pair's bodies at the given poses (a robot's x, y and
// theta; the ball's centre in x and y; a wall's pose is not used).
Separation separationBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                             const RobotState& poseB);

// How deep a pair's bodies overlap at the given poses (as separationBetween
// takes them), m: the collision test's depth along its normal, 0 when they
// do not touch.
double overlapDepthBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                           const RobotState& poseB);

}  // namespace vssim
