#include "vssim/geometry.h"

#include <algorithm>
#include <cmath>

namespace vssim {

namespace {

// Half-extent of a square (half side h, axes u, u_perp) projected on a unit axis.
double projectedHalfExtent(double half, const Eigen::Vector2d& u, const Eigen::Vector2d& axis) {
    const Eigen::Vector2d perp(-u.y(), u.x());
    return half * (std::abs(u.dot(axis)) + std::abs(perp.dot(axis)));
}
}  // namespace

std::array<Eigen::Vector2d, 4> robotVertices(const RobotState& pose, double side) {
    // Vertex j at angle theta + 45deg + 90deg j: rotate (s/2)(1, 1) by theta,
    // then by quarter turns (one sin/cos pair instead of four).
    const double h = 0.5 * side;
    const CosSin r = cosSin(pose.theta);
    const double c = r.c, s = r.s;
    const Eigen::Vector2d first(h * (c - s), h * (s + c));  // (s/sqrt2)(cos, sin)(theta + 45deg)
    const Eigen::Vector2d centre(pose.x, pose.y);
    return {centre + first, centre + Eigen::Vector2d(-first.y(), first.x()), centre - first,
            centre + Eigen::Vector2d(first.y(), -first.x())};
}

Eigen::Vector2d toRobotFrame(const RobotState& pose, const Eigen::Vector2d& p) {
    const CosSin r = cosSin(pose.theta);
    const double c = r.c, s = r.s;
    const Eigen::Vector2d d(p.x() - pose.x, p.y() - pose.y);
    return {c * d.x() + s * d.y(), -s * d.x() + c * d.y()};
}

Eigen::Vector2d fromRobotFrame(const RobotState& pose, const Eigen::Vector2d& local) {
    const CosSin r = cosSin(pose.theta);
    const double c = r.c, s = r.s;
    return {pose.x + c * local.x() - s * local.y(), pose.y + s * local.x() + c * local.y()};
}

bool pointInRobot(const RobotState& pose, double side, const Eigen::Vector2d& p, double margin) {
    const Eigen::Vector2d r = toRobotFrame(pose, p);
    const double h = 0.5 * side + margin;
    return std::abs(r.x()) <= h && std::abs(r.y()) <= h;
}

SquareOverlap squareOverlap(const RobotState& a, double sideA, const RobotState& b, double sideB) {
    return squareOverlap(a, cosSin(a.theta), sideA, b, cosSin(b.theta), sideB);
}

SquareOverlap squareOverlap(const RobotState& a, const CosSin& headingA, double sideA, const RobotState& b,
                            const CosSin& headingB, double sideB) {
    const Eigen::Vector2d ua(headingA.c, headingA.s), ub(headingB.c, headingB.s);
    const Eigen::Vector2d axes[4] = {ua, Eigen::Vector2d(-ua.y(), ua.x()), ub, Eigen::Vector2d(-ub.y(), ub.x())};
    const Eigen::Vector2d centres(a.x - b.x, a.y - b.y);  // from B to A
    SquareOverlap best;
    best.depth = INFINITY;
    for (const Eigen::Vector2d& axis : axes) {
        const double reach = projectedHalfExtent(0.5 * sideA, ua, axis) + projectedHalfExtent(0.5 * sideB, ub, axis);
        const double along = centres.dot(axis);
        const double depth = reach - std::abs(along);
        if (depth <= 0.0) return {};  // a separating axis: no overlap
        if (depth < best.depth) {
            best.depth = depth;
            best.normal = along >= 0.0 ? axis : Eigen::Vector2d(-axis);
        }
    }
    best.overlapping = true;
    return best;
}

}  // namespace vssim
