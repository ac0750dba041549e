#include "vssim/field.h"

#include <algorithm>
#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

namespace {

// Points this close to a wall (m) count as on it: far below any body's size,
// far above the rounding of coordinates of order 1 m.
constexpr double kOnWall = 1e-13;

Eigen::Vector2d leftNormal(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d d = (b - a).normalized();
    return {-d.y(), d.x()};
}

}  // namespace

FieldDimensions officialDimensions(FieldType type) {
    FieldDimensions d;
    d.type = type;
    switch (type) {
        case FieldType::Box: break;  // the defaults: the seed's closed 1.50 x 1.30 box
        case FieldType::Vsss3v3:
            d.length = 1.50, d.width = 1.30;
            d.goal_width = 0.40, d.goal_depth = 0.10, d.corner_leg = 0.07, d.centre_radius = 0.20;
            d.goal_area_depth = 0.15, d.goal_area_width = 0.70;
            d.penalty_mark = 0.375, d.free_ball_x = 0.375, d.free_ball_y = 0.25;
            break;
        case FieldType::Vsss5v5:
            d.length = 2.20, d.width = 1.80;
            d.goal_width = 0.40, d.goal_depth = 0.15, d.corner_leg = 0.07, d.centre_radius = 0.25;
            d.goal_area_depth = 0.15, d.goal_area_width = 0.50;
            d.penalty_mark = 0.375, d.free_ball_x = 0.375, d.free_ball_y = 0.40;
            break;
    }
    return d;
}

FieldProblem checkFieldDimensions(const FieldDimensions& d) {
    auto finiteAtLeast = [](double v, double min) { return std::isfinite(v) && v >= min; };
    if (!(finiteAtLeast(d.length, 0.0) && d.length > 0.0)) return {"length", "must be a positive length"};
    if (!(finiteAtLeast(d.width, 0.0) && d.width > 0.0)) return {"width", "must be a positive length"};
    const char* nonNegative = "must be zero or a positive length";
    const std::pair<const char*, double> lengths[] = {
        {"goal_width", d.goal_width},           {"goal_depth", d.goal_depth},
        {"corner_leg", d.corner_leg},           {"centre_radius", d.centre_radius},
        {"goal_area_depth", d.goal_area_depth}, {"goal_area_width", d.goal_area_width},
        {"penalty_mark", d.penalty_mark},       {"free_ball_x", d.free_ball_x},
        {"free_ball_y", d.free_ball_y},
    };
    for (const auto& [key, value] : lengths)
        if (!finiteAtLeast(value, 0.0)) return {key, nonNegative};
    const double shorter = std::min(d.length, d.width);
    if (!(2.0 * d.corner_leg < shorter))
        return {"corner_leg", "the corner triangles would meet: twice the leg must be under the field's shorter side"};
    if (!(d.goal_width < d.width - 2.0 * d.corner_leg))
        return {"goal_width",
                "the goal is wider than its wall: it must be narrower than the width minus two corner legs"};
    if (d.goal_width > 0.0 && !(d.goal_depth > 0.0))
        return {"goal_depth", "a field with goals needs goals at least some depth deep"};
    if (!(d.centre_radius < 0.5 * shorter)) return {"centre_radius", "the centre circle must fit inside the field"};
    if (!(d.goal_area_depth < 0.5 * d.length))
        return {"goal_area_depth", "a goal area must end before the halfway line"};
    if (!(d.goal_area_width <= d.width)) return {"goal_area_width", "a goal area cannot be wider than the field"};
    if (!(d.penalty_mark <= 0.5 * d.length)) return {"penalty_mark", "the penalty mark must lie in its own half"};
    if (!(d.free_ball_x <= 0.5 * d.length)) return {"free_ball_x", "the free-ball marks must lie in their own half"};
    if (!(d.free_ball_y < 0.5 * d.width)) return {"free_ball_y", "the free-ball marks must lie inside the field"};
    return {};
}

Field makeField(const FieldDimensions& dimensions) {
    Field field;
    field.dimensions = dimensions;
    field.length = dimensions.length;
    field.width = dimensions.width;
    const double hx = 0.5 * dimensions.length, hy = 0.5 * dimensions.width;
    const double g = 0.5 * dimensions.goal_width, depth = dimensions.goal_depth, c = dimensions.corner_leg;
    using V = Eigen::Vector2d;
    // The chain's corners, counter-clockwise from the bottom wall's left end.
    std::vector<V> corners;
    auto add = [&corners](double x, double y) { corners.emplace_back(x, y); };
    add(-hx + c, -hy);
    if (c > 0.0) add(hx - c, -hy);
    add(hx, -hy + c);
    if (g > 0.0) add(hx, -g), add(hx + depth, -g), add(hx + depth, g), add(hx, g);
    add(hx, hy - c);
    if (c > 0.0) add(hx - c, hy);
    add(-hx + c, hy);
    if (c > 0.0) add(-hx, hy - c);
    if (g > 0.0) add(-hx, g), add(-hx - depth, g), add(-hx - depth, -g), add(-hx, -g);
    if (c > 0.0) add(-hx, -hy + c);  // without corners it is the first point again
    const std::size_t n = corners.size();
    for (std::size_t i = 0; i < n; ++i) {
        const V& a = corners[i];
        const V& b = corners[(i + 1) % n];
        field.walls.push_back({a, b, leftNormal(a, b)});
    }
    // A corner where the chain turns clockwise points into the floor.
    field.startsAtPost.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const V in = corners[i] - corners[(i + n - 1) % n];
        const V out = corners[(i + 1) % n] - corners[i];
        if (in.x() * out.y() - in.y() * out.x() < 0.0) {
            field.posts.push_back(corners[i]);
            field.startsAtPost[i] = 1;  // wall i starts at corner i
        }
    }
    field.lower = V(-hx - depth, -hy);
    field.upper = V(hx + depth, hy);
    field.clearHalf = V(hx, hy);
    field.clearDiagonal = hx + hy - c;
    return field;
}

Field makeRectangularField(double length, double width) {
    FieldDimensions d;
    d.length = length;
    d.width = width;
    return makeField(d);
}

NearestWall nearestWall(const Field& field, const Eigen::Vector2d& p) {
    NearestWall best;
    best.distance = INFINITY;
    for (std::size_t w = 0; w < field.walls.size(); ++w) {
        const Wall& wall = field.walls[w];
        // Skip a wall whose bounding box is already no nearer than the best:
        // its distance cannot be smaller (the margin covers rounding), so
        // the answer is the one the full test gives.
        const double dx =
            std::max({0.0, std::min(wall.a.x(), wall.b.x()) - p.x(), p.x() - std::max(wall.a.x(), wall.b.x())});
        const double dy =
            std::max({0.0, std::min(wall.a.y(), wall.b.y()) - p.y(), p.y() - std::max(wall.a.y(), wall.b.y())});
        if (std::sqrt(dx * dx + dy * dy) * (1.0 - 1e-12) >= best.distance) continue;
        const SegmentClosestPoint q = closestPointOnSegment(wall.a, wall.b, p);
        if (q.distance < best.distance) {
            best.wall = static_cast<int>(w);
            best.point = q.point;
            best.distance = q.distance;
        }
    }
    return best;
}

int postCornerAt(const Field& field, const Eigen::Vector2d& p) {
    const int n = static_cast<int>(field.walls.size());
    for (int out = 0; out < n; ++out) {
        if (!field.startsAtPost[out]) continue;
        const int in = (out + n - 1) % n;
        const Wall &a = field.walls[in], &b = field.walls[out];
        if (!(wallSignedDistance(a, p) < 0.0 && wallSignedDistance(b, p) < 0.0)) continue;
        // Only near the post: the lines run on over the floor and the solid
        // beyond it, so a point beyond both may be at the far end of a goal's
        // side wall, in the back corner.
        const double d = (p - b.a).squaredNorm();
        if (d < (p - a.a).squaredNorm() && d < (p - b.b).squaredNorm()) return out;
    }
    return -1;
}

std::array<int, 3> wallsPast(const Field& field, const Eigen::Vector2d& p, const Eigen::Vector2d& from) {
    std::array<int, 3> past{-1, -1, -1};
    const int n = static_cast<int>(field.walls.size());
    const NearestWall nearest = nearestWall(field, p);
    if (nearest.wall < 0) return past;
    const int w = nearest.wall, prev = (w + n - 1) % n, next = (w + 1) % n;
    auto beyond = [&](int k) { return wallSignedDistance(field.walls[k], p) < 0.0; };
    // Inside a post's solid corner, which a body enters through one wall or
    // the other: the nearest wall would push a robot sliding along the goal
    // line into the goal, or one inside the goal out through the post; the
    // body's centre tells which way it came.
    const int post = postCornerAt(field, p);
    if (post >= 0) {
        const int in = (post + n - 1) % n;
        const bool fromIn = wallSignedDistance(field.walls[in], from) > 0.0;
        const bool fromOut = wallSignedDistance(field.walls[post], from) > 0.0;
        past[0] = fromIn && !fromOut ? in : fromOut && !fromIn ? post : w;
        return past;
    }
    // Elsewhere (a corner of the chain pointing away from the floor: the
    // box's corners, the corner triangles' ends, the back of the goal), p is
    // past each wall whose line it is beyond, as in the paper's box; not
    // across a post, whose neighbour's line runs over the floor.
    const bool postAtA = field.startsAtPost[w] != 0, postAtB = field.startsAtPost[next] != 0;
    int order[3] = {prev, w, next};
    std::sort(order, order + 3);  // in increasing index order (prev is the highest when w is 0)
    int count = 0;
    for (int k : order) {
        if ((k == prev && postAtA) || (k == next && postAtB)) continue;
        if (beyond(k)) past[count++] = k;
    }
    return past;
}

double wallClearance(const Field& field, const Eigen::Vector2d& p) {
    if (!clearOfWalls(field, p, 0.0) && !onFloor(field, p)) return -INFINITY;
    double best = INFINITY;
    for (const Wall& w : field.walls) {
        const Eigen::Vector2d ab = w.b - w.a;
        const double t = (p - w.a).dot(ab);
        // The line distance where p projects onto the segment: written as
        // the box's test always was, so the box's results do not change.
        const double d = t >= 0.0 && t <= ab.squaredNorm()
                             ? w.normal.x() * (p.x() - w.a.x()) + w.normal.y() * (p.y() - w.a.y())
                             : (t < 0.0 ? p - w.a : p - w.b).norm();
        best = std::min(best, d);
    }
    return best;
}

bool onFloor(const Field& field, const Eigen::Vector2d& p) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return false;
    if (clearOfWalls(field, p, 0.0)) return true;  // the open field: most points
    if (p.x() < field.lower.x() - kOnWall || p.x() > field.upper.x() + kOnWall || p.y() < field.lower.y() - kOnWall ||
        p.y() > field.upper.y() + kOnWall)
        return false;
    // Crossing number of a ray towards +x; points on a wall count as inside.
    bool inside = false;
    for (const Wall& w : field.walls) {
        if ((w.a.y() > p.y()) != (w.b.y() > p.y())) {
            const double x = w.a.x() + (p.y() - w.a.y()) * (w.b.x() - w.a.x()) / (w.b.y() - w.a.y());
            if (x > p.x()) inside = !inside;
        }
    }
    return inside || nearestWall(field, p).distance <= kOnWall;
}

bool robotInsideField(const Field& field, double side, double x, double y, double theta) {
    if (!std::isfinite(side) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(theta)) return false;
    const RobotState pose{x, y, theta, 0.0, 0.0};
    for (const Eigen::Vector2d& v : robotVertices(pose, side))
        if (!onFloor(field, v)) return false;
    // Every vertex on the floor, and no corner of the chain inside the square
    // (a post poking into its face): then the whole square is on the floor.
    for (const Wall& w : field.walls)
        if (pointInRobot(pose, side, w.a, -kOnWall)) return false;
    return true;
}

bool discInsideField(const Field& field, double r, double x, double y) {
    const Eigen::Vector2d c(x, y);
    if (!std::isfinite(r) || !onFloor(field, c)) return false;
    return nearestWall(field, c).distance >= r - kOnWall;
}

}  // namespace vssim
