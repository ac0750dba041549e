// Planar geometry of the bodies (model.md §5): a robot is a square of side s
// centred on its pose; the ball is a disc. All in the field frame, metres.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "vssim/robot_state.h"

namespace vssim {

// The cosine and sine of an angle (rad). With glibc, one sincos() call: it
// gives exactly the values of std::cos and std::sin (checked on 2e7 random
// angles), in about the time of one of them; headings are rotated at every
// integration stage and contact test, so this is a good part of a step.
struct CosSin {
    double c = 1.0;
    double s = 0.0;
};
inline CosSin cosSin(double angle) {
    CosSin r;
#if defined(__GLIBC__)
    ::sincos(angle, &r.s, &r.c);
#else
    r.c = std::cos(angle);
    r.s = std::sin(angle);
#endif
    return r;
}

// The radius of the disc around a robot's centre that holds the square at any
// heading: half its diagonal, s / sqrt2, m (model.md §5).
inline double boundingRadius(double side) { return side / std::sqrt(2.0); }

// Half the side of the axis-aligned box around a robot of side `side` at
// heading theta: (s/2)(|cos theta| + |sin theta|), m.
inline double robotHalfExtent(double side, double theta) {
    const CosSin r = cosSin(theta);
    return 0.5 * side * (std::abs(r.c) + std::abs(r.s));
}

// Vertex j = 0..3 at (s/sqrt2)(cos, sin)(theta + 45deg + 90deg j) from the centre.
std::array<Eigen::Vector2d, 4> robotVertices(const RobotState& pose, double side);

// The closest point of segment [a, b] to p (paper eqs. 10-11): lambda of the
// projection clamped to [0, 1].
struct SegmentClosestPoint {
    double lambda = 0.0;                              // clamped parameter along a -> b
    Eigen::Vector2d point = Eigen::Vector2d::Zero();  // a + lambda (b - a), m
    double distance = 0.0;                            // |p - point|, m
};
SegmentClosestPoint closestPointOnSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p);

// p expressed in the robot's frame (x forward, y to the left), m.
Eigen::Vector2d toRobotFrame(const RobotState& pose, const Eigen::Vector2d& p);
Eigen::Vector2d fromRobotFrame(const RobotState& pose, const Eigen::Vector2d& local);

// The paper's test: |x_r| <= s/2 + margin and |y_r| <= s/2 + margin in the robot's frame.
bool pointInRobot(const RobotState& pose, double side, const Eigen::Vector2d& p, double margin = 0.0);

// Separating-axis test of two squares. When they overlap, `normal` is the
// unit axis of least penetration, oriented from B towards A (the direction A
// must move to separate), and `depth` the penetration along it (m).
struct SquareOverlap {
    bool overlapping = false;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();
    double depth = 0.0;
};
SquareOverlap squareOverlap(const RobotState& a, double sideA, const RobotState& b, double sideB);

}  // namespace vssim
