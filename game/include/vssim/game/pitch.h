// Where things are on an official field, for the rules (shared vsss-game.md,
// "Fields" and "Rules"): the goals, the goal areas and the marks. Sides are
// given as the x sign of a goal: -1 the left goal (yellow's), +1 the right
// (blue's). All in the field frame, m.
#pragma once

#include <Eigen/Core>

#include "vssim/ball.h"
#include "vssim/field.h"

namespace vssim {

// The side (-1, +1) of the goal the whole ball is in: its centre more than
// r_b past the goal line and between the posts; 0 when it is in neither.
int goalScoredIn(const Field& field, const BallState& ball, double radius);

// Whether a point is in the goal area of side `side`: the rectangle in front
// of the goal (goal_area_depth x goal_area_width), extended back through the
// goal to its back wall, edges included.
bool inGoalArea(const Field& field, int side, const Eigen::Vector2d& p);

// The middle of a goal line.
Eigen::Vector2d goalCentre(const Field& field, int side);
// The penalty mark in front of the goal on `side`.
Eigen::Vector2d penaltyMark(const Field& field, int side);
// The free-ball mark of quadrant 1-4 (counter-clockwise from x > 0, y > 0).
Eigen::Vector2d freeBallMark(const Field& field, int quadrant);

}  // namespace vssim
