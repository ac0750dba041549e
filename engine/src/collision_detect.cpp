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
std::optional<Contact> vertexWallContact(const RobotState& robot, double side, int robotIndex, const Wall& wall,
                                         int wallIndex, IsPast isPast) {
    double maxDepth = 0.0, weight = 0.0;
    Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
    const auto vertices = robotVertices(robot, side);
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
    return vertexWallContact(robot, side, robotIndex, wall, wallIndex, [](int) { return true; });
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
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (const Eigen::Vector2d& v : robotVertices(a, sideA))
        if (pointInRobot(b, sideB, v, 1e-9 + overlap.depth)) sum += v, ++count;
    for (const Eigen::Vector2d& v : robotVertices(b, sideB))
        if (pointInRobot(a, sideA, v, 1e-9 + overlap.depth)) sum += v, ++count;
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
    auto free = [&bodies](int i) { return bodies.freeRobots && (*bodies.freeRobots)[i]; };
    std::vector<Contact> contacts;
    auto testPair = [&](int i, int j) {
        if (free(i) || free(j)) return;
        if (auto k = robotRobotContact(robots[i], sides[i], i, robots[j], sides[j], j)) contacts.push_back(*k);
    };
    if (bodies.broadPhase) {
        BroadPhaseScratch fresh;
        std::vector<std::pair<int, int>> pairs;
        candidatePairs(robots, sides, 0.0, bodies.broadPhaseScratch ? *bodies.broadPhaseScratch : fresh, pairs);
        for (const auto& [i, j] : pairs) testPair(i, j);
    } else {
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j) testPair(i, j);
    }
    if (bodies.ball && !bodies.freeBall) {
        for (int i = 0; i < n; ++i)
            if (!free(i))
                if (auto k = robotBallContact(robots[i], sides[i], i, *bodies.ball, bodies.ballRadius))
                    contacts.push_back(*k);
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

// A robot against the chain of walls. The paper's vertex test (model.md §5):
// each vertex is past the walls wallsPast finds (in the box, every wall whose
// line it is beyond, as before; near a post, the one wall the robot came
// through). Then each post (a corner of the chain pointing into the floor)
// inside the square, which no vertex test sees (a face pressed against a
// post), pushes the robot back out through the face nearest to it.
void appendRobotWallContacts(const Field& field, const RobotState& robot, double side, int robotIndex,
                             std::vector<Contact>& contacts) {
    const Eigen::Vector2d c = centre(robot);
    // Cheap rejection: nothing of the robot reaches past half a diagonal from its centre.
    if (clearOfWalls(field, c, boundingRadius(side))) return;
    const auto vertices = robotVertices(robot, side);
    std::array<std::array<int, 3>, 4> past;
    std::array<int, 12> touched;
    int count = 0;
    for (int j = 0; j < 4; ++j) {
        past[j] = {-1, -1, -1};
        if (clearOfWalls(field, vertices[j], 0.0)) continue;
        past[j] = wallsPast(field, vertices[j], c);
        for (int w : past[j])
            if (w >= 0 && std::find(touched.begin(), touched.begin() + count, w) == touched.begin() + count)
                touched[count++] = w;
    }
    std::sort(touched.begin(), touched.begin() + count);  // contacts in wall order (deterministic)
    for (int t = 0; t < count; ++t) {
        const int w = touched[t];
        if (auto k = vertexWallContact(robot, side, robotIndex, field.walls[w], w,
                                       [&past, w](int j) { return contains(past[j], w); }))
            contacts.push_back(*k);
    }
    const double half = 0.5 * side;
    const int walls = static_cast<int>(field.walls.size());
    for (int w = 0; w < walls; ++w) {
        if (!field.startsAtPost[w]) continue;
        const Eigen::Vector2d& post = field.walls[w].a;
        const Eigen::Vector2d local = toRobotFrame(robot, post);
        const double alongX = half - std::abs(local.x()), alongY = half - std::abs(local.y());
        if (!(alongX > 0.0 && alongY > 0.0)) continue;  // the post is not inside the square
        const bool xFace = alongX <= alongY;
        const Eigen::Vector2d face = xFace ? Eigen::Vector2d(local.x() >= 0.0 ? 1.0 : -1.0, 0.0)
                                           : Eigen::Vector2d(0.0, local.y() >= 0.0 ? 1.0 : -1.0);
        Contact k;
        k.a = {BodyKind::Robot, robotIndex};
        k.b = {BodyKind::Wall, w};
        k.normal = (c - fromRobotFrame(robot, face)).normalized();  // away from the face the post presses into
        k.depth = xFace ? alongX : alongY;
        k.point = post;
        contacts.push_back(k);
    }
}

}  // namespace

void appendWallContacts(const Field& field, const BodiesView& bodies, std::vector<Contact>& contacts) {
    const std::vector<RobotState>& robots = *bodies.robots;
    for (int i = 0; i < static_cast<int>(robots.size()); ++i) {
        if (bodies.freeRobots && (*bodies.freeRobots)[i]) continue;
        appendRobotWallContacts(field, robots[i], (*bodies.sides)[i], i, contacts);
    }
    if (bodies.ball && !bodies.freeBall) appendBallWallContacts(field, *bodies.ball, bodies.ballRadius, contacts);
}

}  // namespace vssim
