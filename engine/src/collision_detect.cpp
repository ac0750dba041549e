#include "vssim/collision_detect.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "vssim/broad_phase.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {
Eigen::Vector2d centre(const RobotState& r) { return {r.x, r.y}; }

// How far past a segment's ends (in metres) a body may still count as being
// against it: a body half its size beyond an end is still at that wall.
bool projectsOntoWall(const Wall& wall, const Eigen::Vector2d& p, double reach) {
    const Eigen::Vector2d ab = wall.b - wall.a;
    const double len = ab.norm();
    const double t = (p - wall.a).dot(ab) / len;
    return t >= -reach && t <= len + reach;
}
}  // namespace

std::optional<Contact> ballWallContact(const BallState& ball, double radius, const Wall& wall, int wallIndex) {
    const Eigen::Vector2d c(ball.x, ball.y);
    const double signedDistance = wall.normal.dot(c - wall.a);
    if (signedDistance >= radius) return std::nullopt;
    Contact k;
    k.a = {BodyKind::Ball, 0};
    k.b = {BodyKind::Wall, wallIndex};
    if (signedDistance < 0.0) {  // centre behind the wall
        if (!projectsOntoWall(wall, c, radius)) return std::nullopt;
        k.normal = wall.normal;
        k.depth = radius - signedDistance;
        k.point = c - signedDistance * wall.normal;
        return k;
    }
    const SegmentClosestPoint q = closestPointOnSegment(wall.a, wall.b, c);
    if (q.distance >= radius) return std::nullopt;
    k.normal = q.distance > 1e-12 ? Eigen::Vector2d((c - q.point) / q.distance) : wall.normal;
    k.depth = radius - q.distance;
    k.point = q.point;
    return k;
}

namespace {
// A robot against one wall, from the vertices that are past it: the deepest
// gives the depth along the wall's normal, and the depth-weighted average the
// contact point, so that a face lying flat on the wall touches at its middle.
template <typename IsPast>
std::optional<Contact> vertexWallContact(const std::array<Eigen::Vector2d, 4>& vertices, int robotIndex,
                                         const Wall& wall, int wallIndex, IsPast isPast) {
    double maxDepth = 0.0, weight = 0.0;
    Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
    for (int j = 0; j < 4; ++j) {
        const Eigen::Vector2d& v = vertices[j];
        const double depth = -wall.normal.dot(v - wall.a);
        if (depth <= 0.0 || !isPast(j)) continue;
        maxDepth = std::max(maxDepth, depth);
        weighted += depth * v;
        weight += depth;
    }
    if (weight <= 0.0) return std::nullopt;
    Contact k;
    k.a = {BodyKind::Robot, robotIndex};
    k.b = {BodyKind::Wall, wallIndex};
    k.normal = wall.normal;
    k.depth = maxDepth;
    k.point = weighted / weight;
    return k;
}
}  // namespace

std::optional<Contact> robotWallContact(const RobotState& robot, double side, int robotIndex, const Wall& wall,
                                        int wallIndex) {
    // Cheap rejection: no vertex can be beyond the wall when the centre is
    // more than half a diagonal inside it.
    if (wall.normal.dot(centre(robot) - wall.a) > boundingRadius(side)) return std::nullopt;
    if (!projectsOntoWall(wall, centre(robot), side)) return std::nullopt;
    return vertexWallContact(robotVertices(robot, side), robotIndex, wall, wallIndex, [](int) { return true; });
}

std::optional<Contact> robotBallContact(const RobotState& robot, double side, int robotIndex, const BallState& ball,
                                        double radius) {
    const Eigen::Vector2d c(ball.x, ball.y);
    if ((c - centre(robot)).norm() > radius + boundingRadius(side)) return std::nullopt;  // cheap rejection

    Contact k;
    k.a = {BodyKind::Ball, 0};
    k.b = {BodyKind::Robot, robotIndex};
    const double half = 0.5 * side;
    const Eigen::Vector2d local = toRobotFrame(robot, c);
    if (std::abs(local.x()) < half && std::abs(local.y()) < half) {
        // Centre inside the square: leave through the face nearest to it.
        const bool alongX = half - std::abs(local.x()) <= half - std::abs(local.y());
        const Eigen::Vector2d axis = alongX ? Eigen::Vector2d(local.x() >= 0.0 ? 1.0 : -1.0, 0.0)
                                            : Eigen::Vector2d(0.0, local.y() >= 0.0 ? 1.0 : -1.0);
        const double inside = half - std::abs(alongX ? local.x() : local.y());
        const Eigen::Vector2d onFace =
            alongX ? Eigen::Vector2d(axis.x() * half, local.y()) : Eigen::Vector2d(local.x(), axis.y() * half);
        k.normal = fromRobotFrame(robot, axis) - centre(robot);
        k.depth = radius + inside;
        k.point = fromRobotFrame(robot, onFace);
        return k;
    }
    // Paper eqs. 10-11: distance from the ball centre to each side segment.
    const auto v = robotVertices(robot, side);
    SegmentClosestPoint best;
    best.distance = INFINITY;
    for (int j = 0; j < 4; ++j) {
        const SegmentClosestPoint q = closestPointOnSegment(v[j], v[(j + 1) % 4], c);
        if (q.distance < best.distance) best = q;
    }
    if (best.distance >= radius) return std::nullopt;
    k.normal = best.distance > 1e-12 ? Eigen::Vector2d((c - best.point) / best.distance)
                                     : Eigen::Vector2d((c - centre(robot)).normalized());
    k.depth = radius - best.distance;
    k.point = best.point;
    return k;
}

std::optional<Contact> robotRobotContact(const RobotState& a, double sideA, int indexA, const RobotState& b,
                                         double sideB, int indexB) {
    if ((centre(a) - centre(b)).norm() > boundingRadius(sideA) + boundingRadius(sideB)) return std::nullopt;
    const SquareOverlap overlap = squareOverlap(a, sideA, b, sideB);
    if (!overlap.overlapping) return std::nullopt;

    Contact k;
    k.a = {BodyKind::Robot, indexA};
    k.b = {BodyKind::Robot, indexB};
    k.normal = overlap.normal;
    k.depth = overlap.depth;
    // The paper's test, both ways: vertices of one inside the other square.
    // The tolerance (the depth) keeps vertices of a face lying flat on the
    // other robot's face.
    // (pointInRobot's test, with each heading's cosine and sine taken once.)
    const CosSin ra = cosSin(a.theta), rb = cosSin(b.theta);
    const double ca = ra.c, sa = ra.s, cb = rb.c, sb = rb.s;
    auto inside = [](const RobotState& pose, double c, double s, double side, const Eigen::Vector2d& p, double margin) {
        const Eigen::Vector2d d(p.x() - pose.x, p.y() - pose.y);
        const double h = 0.5 * side + margin;
        return std::abs(c * d.x() + s * d.y()) <= h && std::abs(-s * d.x() + c * d.y()) <= h;
    };
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (const Eigen::Vector2d& v : robotVertices(a, sideA))
        if (inside(b, cb, sb, sideB, v, 1e-9 + overlap.depth)) sum += v, ++count;
    for (const Eigen::Vector2d& v : robotVertices(b, sideB))
        if (inside(a, ca, sa, sideA, v, 1e-9 + overlap.depth)) sum += v, ++count;
    if (count > 0) {
        k.point = sum / count;
    } else {
        // No vertex inside: the middle of the overlap on the line of centres.
        const Eigen::Vector2d mid = 0.5 * (centre(a) + centre(b));
        k.point = mid;
    }
    return k;
}

std::vector<Contact> detectContacts(const Field& field, const BodiesView& bodies) {
    const std::vector<RobotState>& robots = *bodies.robots;
    const std::vector<double>& sides = *bodies.sides;
    const int n = static_cast<int>(robots.size());
    auto free = [&bodies](int i) {
        return !bodies.listedRobots && bodies.freeRobots && (*bodies.freeRobots)[i];  // (listed: none)
    };
    std::vector<Contact> contacts;
    auto testPair = [&](int i, int j) {
        if (free(i) || free(j)) return;
        if (auto k = robotRobotContact(robots[i], sides[i], i, robots[j], sides[j], j)) contacts.push_back(*k);
    };
    if (bodies.listedRobots) {
        // Among the listed robots only: their pairs come out sorted either
        // way, as from all robots.
        ListedPairsScratch scratch;
        std::vector<std::pair<int, int>> pairs;
        listedCandidatePairs(*bodies.listedRobots, robots, sides, 0.0, bodies.broadPhase, scratch, pairs);
        for (const auto& [i, j] : pairs) testPair(i, j);
    } else if (bodies.broadPhase) {
        BroadPhaseScratch fresh;
        std::vector<std::pair<int, int>> pairs;
        candidatePairs(robots, sides, 0.0, bodies.broadPhaseScratch ? *bodies.broadPhaseScratch : fresh, pairs);
        for (const auto& [i, j] : pairs) testPair(i, j);
    } else {
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) testPair(i, j);
    }
    if (bodies.ball && !bodies.freeBall) {
        auto testBall = [&](int i) {
            if (auto k = robotBallContact(robots[i], sides[i], i, *bodies.ball, bodies.ballRadius))
                contacts.push_back(*k);
        };
        if (bodies.listedRobots) {
            for (const int i : *bodies.listedRobots) testBall(i);
        } else {
            for (int i = 0; i < n; ++i)
                if (!free(i)) testBall(i);
        }
    }
    appendWallContacts(field, bodies, contacts);
    return contacts;
}

namespace {

bool contains(const std::array<int, 3>& walls, int w) {
    return std::find(walls.begin(), walls.end(), w) != walls.end();
}

// The ball against the chain of walls (model.md §5: centre within r_b of the
// wall). A wall whose line the centre is on the floor side of: the nearest
// point of the segment, a post counting for the wall that starts there only
// (a ball on a post touches it once). A wall whose line the centre is
// behind (it tunnelled, or was pressed in by a robot): a deep contact along
// the wall's normal, as in the seed's box, but only for the walls it is past
// (wallsPast), since on a chain with goals the lines of the goal lines and
// of the goals' side walls run over the floor.
void appendBallWallContacts(const Field& field, const BallState& ball, double radius, std::vector<Contact>& contacts) {
    const Eigen::Vector2d c(ball.x, ball.y);
    if (clearOfWalls(field, c, radius)) return;
    std::array<int, 3> past{-1, -1, -1};
    bool pastKnown = false;
    const int walls = static_cast<int>(field.walls.size());
    for (int w = 0; w < walls; ++w) {
        const Wall& wall = field.walls[w];
        const double signedDistance = wallSignedDistance(wall, c);
        if (signedDistance >= radius) continue;
        if (signedDistance < 0.0) {
            if (!pastKnown) past = wallsPast(field, c, c), pastKnown = true;
            if (!contains(past, w)) continue;
            if (auto k = ballWallContact(ball, radius, wall, w)) contacts.push_back(*k);
            continue;
        }
        const SegmentClosestPoint q = closestPointOnSegment(wall.a, wall.b, c);
        if (q.distance >= radius) continue;
        if (q.lambda >= 1.0 && field.startsAtPost[(w + 1) % walls]) continue;  // the next wall's post
        Contact k;
        k.a = {BodyKind::Ball, 0};
        k.b = {BodyKind::Wall, w};
        k.normal = q.distance > 1e-12 ? Eigen::Vector2d((c - q.point) / q.distance) : wall.normal;
        k.depth = radius - q.distance;
        k.point = q.point;
        contacts.push_back(k);
    }
}

// A robot against the solid corner behind a post: the quadrant beyond both
// walls that meet there, a convex set like the square, so the separating-axis
// test (model.md §5, "a robust implementation covers them") gives the least
// push that clears it: along either wall's normal (the whole square back in
// front of that wall's line) or along a face normal of the square that points
// out of the corner (the post back onto that face). A vertex meeting the post
// is then one contact, where the vertex test against one wall and a push of
// the post along a face disagreed and could leave the robot in the corner.
std::optional<Contact> robotPostContact(const Field& field, const RobotState& robot, int robotIndex,
                                        const std::array<Eigen::Vector2d, 4>& vertices, int post) {
    const int n = static_cast<int>(field.walls.size());
    const Wall &in = field.walls[(post + n - 1) % n], &out = field.walls[post];
    const Eigen::Vector2d& p = out.a;
    // The corner is p + cone{back along `in`, on along `out`}.
    const Eigen::Vector2d e1 = (in.a - in.b).normalized(), e2 = (out.b - out.a).normalized();
    double depth = INFINITY;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero(), point = p;
    for (const Wall* w : {&in, &out}) {
        // As the vertex test: the depth-weighted average of the vertices
        // beyond the line is the point, so a face flat on it touches at its middle.
        double deepest = 0.0, weight = 0.0;
        Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
        for (const Eigen::Vector2d& v : vertices) {
            const double d = -wallSignedDistance(*w, v);
            if (!(d > 0.0)) continue;
            deepest = std::max(deepest, d);
            weighted += d * v;
            weight += d;
        }
        if (!(deepest > 0.0)) return std::nullopt;  // the square is in front of this wall: separated
        if (deepest < depth) depth = deepest, normal = w->normal, point = weighted / weight;
    }
    const CosSin r = cosSin(robot.theta);
    const double c = r.c, s = r.s;
    const Eigen::Vector2d axes[4] = {{c, s}, {-c, -s}, {-s, c}, {s, -c}};
    for (const Eigen::Vector2d& u : axes) {
        if (u.dot(e1) > 0.0 || u.dot(e2) > 0.0) continue;  // the corner reaches on without end along u
        double lowest = INFINITY;
        for (const Eigen::Vector2d& v : vertices) lowest = std::min(lowest, v.dot(u));
        const double d = p.dot(u) - lowest;
        if (!(d > 0.0)) return std::nullopt;              // the post is beyond that face: separated
        if (d < depth) depth = d, normal = u, point = p;  // the post presses on the face
    }
    Contact k;
    k.a = {BodyKind::Robot, robotIndex};
    k.b = {BodyKind::Wall, post};
    k.normal = normal;
    k.depth = depth;
    k.point = point;
    return k;
}

// A robot against the chain of walls. The paper's vertex test (model.md §5):
// each vertex is past the walls wallsPast finds (in the box, every wall whose
// line it is beyond, as before). Near a post, the solid corner behind it is
// tested as a whole instead (robotPostContact): when a vertex is in it or the
// post is inside the square, which no vertex test sees (a face pressed
// against a post).
void appendRobotWallContacts(const Field& field, const RobotState& robot, double side, int robotIndex,
                             std::vector<Contact>& contacts) {
    const Eigen::Vector2d c = centre(robot);
    // Cheap rejection: nothing of the robot reaches past half a diagonal from its centre.
    if (clearOfWalls(field, c, boundingRadius(side))) return;
    const auto vertices = robotVertices(robot, side);
    std::array<std::array<int, 3>, 4> past;
    std::array<int, 12> touched;
    std::array<int, 4> corners{-1, -1, -1, -1};  // the post whose corner each vertex is in
    int count = 0;
    for (int j = 0; j < 4; ++j) {
        past[j] = {-1, -1, -1};
        if (clearOfWalls(field, vertices[j], 0.0)) continue;
        if (!field.posts.empty()) {
            // A vertex in a post's corner while the centre is in front of
            // both walls there: neither wall is the one it came through.
            const int post = postCornerAt(field, vertices[j]);
            const int walls = static_cast<int>(field.walls.size());
            if (post >= 0 && wallSignedDistance(field.walls[post], c) > 0.0 &&
                wallSignedDistance(field.walls[(post + walls - 1) % walls], c) > 0.0) {
                corners[j] = post;
                continue;
            }
        }
        past[j] = wallsPast(field, vertices[j], c);
        for (int w : past[j])
            if (w >= 0 && std::find(touched.begin(), touched.begin() + count, w) == touched.begin() + count)
                touched[count++] = w;
    }
    std::sort(touched.begin(), touched.begin() + count);  // contacts in wall order (deterministic)
    for (int t = 0; t < count; ++t) {
        const int w = touched[t];
        if (auto k = vertexWallContact(vertices, robotIndex, field.walls[w], w,
                                       [&past, w](int j) { return contains(past[j], w); }))
            contacts.push_back(*k);
    }
    if (field.posts.empty()) return;
    const double half = 0.5 * side;
    const int walls = static_cast<int>(field.walls.size());
    for (int w = 0; w < walls; ++w) {
        if (!field.startsAtPost[w]) continue;
        const bool inCorner = std::find(corners.begin(), corners.end(), w) != corners.end();
        // A post inside the square is within half a diagonal of its centre.
        if (!inCorner && (field.walls[w].a - c).squaredNorm() > 0.5 * side * side) continue;
        const Eigen::Vector2d local = toRobotFrame(robot, field.walls[w].a);
        const bool postInside = std::abs(local.x()) < half && std::abs(local.y()) < half;
        if (!postInside && !inCorner) continue;
        if (auto k = robotPostContact(field, robot, robotIndex, vertices, w)) contacts.push_back(*k);
    }
}

}  // namespace

void appendWallContacts(const Field& field, const BodiesView& bodies, std::vector<Contact>& contacts) {
    const std::vector<RobotState>& robots = *bodies.robots;
    if (bodies.listedRobots) {
        for (const int i : *bodies.listedRobots)
            appendRobotWallContacts(field, robots[i], (*bodies.sides)[i], i, contacts);
    } else {
        for (int i = 0; i < static_cast<int>(robots.size()); ++i) {
            if (bodies.freeRobots && (*bodies.freeRobots)[i]) continue;
            appendRobotWallContacts(field, robots[i], (*bodies.sides)[i], i, contacts);
        }
    }
    if (bodies.ball && !bodies.freeBall) appendBallWallContacts(field, *bodies.ball, bodies.ballRadius, contacts);
}

}  // namespace vssim
