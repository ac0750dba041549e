// A contact between two bodies, as found by collision detection (model.md §5)
// and consumed by collision response (§6).
#pragma once

#include <Eigen/Core>

namespace vssim {

enum class BodyKind { Robot, Ball, Wall };

struct BodyRef {
    BodyKind kind = BodyKind::Wall;
    int index = 0;  // robot index, wall index, or 0 for the ball
};

// Body `a` touches body `b`. `normal` is a unit vector pointing from b
// towards a: the direction in which a must move to separate.
struct Contact {
    BodyRef a;
    BodyRef b;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();
    Eigen::Vector2d point = Eigen::Vector2d::Zero();  // contact point, field frame, m
    double depth = 0.0;                               // penetration along normal, m (>= 0)
};

}  // namespace vssim
