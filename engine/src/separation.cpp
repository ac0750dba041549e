#include "vssim/separation.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

namespace {

// The nearest pair found so far: a point of body a, the nearest point of body b.
struct Nearest {
    double squared = INFINITY;  // m^2
    Eigen::Vector2d onA = Eigen::Vector2d::Zero(), onB = Eigen::Vector2d::Zero();
    void offer(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
        const double d2 = (a - b).squaredNorm();
        if (d2 < squared) squared = d2, onA = a, onB = b;
    }
    Separation separation(double radiusA = 0.0) const {
        Separation s;
        const double gap = std::sqrt(squared);
        s.distance = gap - radiusA;
        if (!(s.distance > 0.0) || !(gap > 0.0)) {
            s.distance = 0.0;
            s.overlapping = true;
            return s;
        }
        s.normal = (onA - onB) / gap;
        // The middle of the gap between the surfaces (a disc's surface is radiusA short of its centre).
        s.point = onB + 0.5 * s.distance * s.normal;
        return s;
    }
};

// A robot's square with its heading's cosine and sine computed once.
struct Square {
    Eigen::Vector2d centre;
    double c, s, half;  // cos and sin of the heading; half the side, m
    Square(const RobotState& robot, double side) : Square(robot, cosSin(robot.theta), side) {}
    Square(const RobotState& robot, const CosSin& heading, double side)
        : centre(robot.x, robot.y), c(heading.c), s(heading.s), half(0.5 * side) {}
    Eigen::Vector2d toLocal(const Eigen::Vector2d& p) const {
        const Eigen::Vector2d d = p - centre;
        return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
    }
    Eigen::Vector2d toField(const Eigen::Vector2d& local) const {
        return centre + Eigen::Vector2d(c * local.x() - s * local.y(), s * local.x() + c * local.y());
    }
    // The point of the square nearest to p (p itself when inside), m.
    Eigen::Vector2d nearest(const Eigen::Vector2d& p) const {
        const Eigen::Vector2d l = toLocal(p);
        return toField({std::clamp(l.x(), -half, half), std::clamp(l.y(), -half, half)});
    }
    std::array<Eigen::Vector2d, 4> vertices() const {
        const Eigen::Vector2d first(half * (c - s), half * (s + c));  // (half, half) turned by the heading
        const Eigen::Vector2d quarter(-first.y(), first.x());
        return {centre + first, centre + quarter, centre - first, centre - quarter};
    }
};

// Whether the segment [a, b] and the square overlap: no separating axis among
// the square's two axes and the segment's normal.
bool segmentOverlapsSquare(const Square& square, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double half = square.half;
    const Eigen::Vector2d la = square.toLocal(a), lb = square.toLocal(b);
    if (std::max(la.x(), lb.x()) < -half || std::min(la.x(), lb.x()) > half) return false;
    if (std::max(la.y(), lb.y()) < -half || std::min(la.y(), lb.y()) > half) return false;
    const Eigen::Vector2d d = lb - la;
    const Eigen::Vector2d n(-d.y(), d.x());  // the segment's normal (not unit: only signs matter)
    const double offset = n.dot(la);
    const double reach = half * (std::abs(n.x()) + std::abs(n.y()));
    return std::abs(offset) <= reach;
}

}  // namespace

Separation robotRobotSeparation(const RobotState& a, double sideA, const RobotState& b, double sideB) {
    const CosSin headingA = cosSin(a.theta), headingB = cosSin(b.theta);
    if (squareOverlap(a, headingA, sideA, b, headingB, sideB).overlapping) return Separation{0.0, true};
    // Apart: two convex polygons are nearest at a vertex of one and a point
    // of the other's boundary, so the nearest of each vertex to the other square.
    const Square qa(a, headingA, sideA), qb(b, headingB, sideB);
    Nearest n;
    for (const Eigen::Vector2d& v : qa.vertices()) n.offer(v, qb.nearest(v));
    for (const Eigen::Vector2d& v : qb.vertices()) n.offer(qa.nearest(v), v);
    return n.separation();
}

Separation ballRobotSeparation(const Eigen::Vector2d& ball, double radius, const RobotState& robot, double side) {
    Nearest n;
    n.offer(ball, Square(robot, side).nearest(ball));
    return n.separation(radius);
}

Separation robotWallSeparation(const RobotState& robot, double side, const Wall& wall) {
    const Square square(robot, side);
    if (segmentOverlapsSquare(square, wall.a, wall.b)) return Separation{0.0, true};
    // Apart: nearest at a vertex of the square, or at an end of the segment.
    Nearest n;
    for (const Eigen::Vector2d& v : square.vertices()) n.offer(v, closestPointOnSegment(wall.a, wall.b, v).point);
    n.offer(square.nearest(wall.a), wall.a);
    n.offer(square.nearest(wall.b), wall.b);
    return n.separation();
}

Separation ballWallSeparation(const Eigen::Vector2d& ball, double radius, const Wall& wall) {
    Nearest n;
    n.offer(ball, closestPointOnSegment(wall.a, wall.b, ball).point);
    return n.separation(radius);
}

}  // namespace vssim
