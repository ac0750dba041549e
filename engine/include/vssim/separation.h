// How far apart two bodies are (model.md §5 shapes: a robot is a square, the
// ball a disc, a wall a segment), with the closest points: what the time of
// impact search (time_of_impact.h) advances on, and the contact it reports
// when the gap closes. All in the field frame, metres.
#pragma once

#include <Eigen/Core>

#include "vssim/field.h"
#include "vssim/robot_state.h"

namespace vssim {

// The gap between bodies a and b. When they are apart, `normal` is the unit
// vector from b's closest point towards a's (the direction a would move to
// separate, as in Contact) and `point` the middle of the two closest points.
// When they touch or overlap, `distance` is 0 and `overlapping` true (normal
// and point are then not set: collision detection describes overlaps).
struct Separation {
    double distance = 0.0;  // m, >= 0
    bool overlapping = false;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
};

// Robot a (side sideA) from robot b.
Separation robotRobotSeparation(const RobotState& a, double sideA, const RobotState& b, double sideB);
// The ball (a, centre and radius) from a robot (b).
Separation ballRobotSeparation(const Eigen::Vector2d& ball, double radius, const RobotState& robot, double side);
// A robot (a) from a wall segment (b); its ends are the field's corners and posts.
Separation robotWallSeparation(const RobotState& robot, double side, const Wall& wall);
// The ball (a) from a wall segment (b).
Separation ballWallSeparation(const Eigen::Vector2d& ball, double radius, const Wall& wall);

}  // namespace vssim
