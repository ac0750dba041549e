// The playing field: its dimensions, its markings, and the wall segments that
// bound it (model.md §4; the official fields: shared vsss-game.md, docs/scenes.md).
//
// The walls are one closed chain of segments around the floor, listed
// counter-clockwise, so the floor is on each segment's left and its normal
// (pointing into the field) is the segment's direction turned by +90°. The
// seed's box is four segments; an official field adds, at each end, the
// goal's posts, side walls and back wall, and a triangle across each corner:
// sixteen segments, four of whose corners (the posts) point into the field.
//
// Alternatives rejected: thick wall boxes tested with the separating-axis
// test (robots catch on the seams between boxes, and the paper's vertex
// test for a robot against a wall would no longer apply); a chain of
// segments keeps the paper's tests and adds only the posts' corners.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <vector>

namespace vssim {

enum class FieldType {
    Box,      // the seed's closed rectangle: no goals, no corners
    Vsss3v3,  // IEEE VSSS 3 vs 3: 1.50 x 1.30 m with goals
    Vsss5v5,  // IEEE VSSS 5 vs 5: 2.20 x 1.80 m with goals
};

struct Wall {
    Eigen::Vector2d a;       // first end, m (field frame)
    Eigen::Vector2d b;       // second end, m
    Eigen::Vector2d normal;  // unit normal pointing into the field
};

// Every dimension of a field, m. Goal lines are x = +-length/2; the goal on
// the right (x > 0) is the one a team attacking +x shoots at.
struct FieldDimensions {
    FieldType type = FieldType::Box;
    double length = 1.50;          // playing area along x, goal line to goal line
    double width = 1.30;           // playing area along y, wall to wall
    double goal_width = 0.0;       // goal mouth, centred on each short wall (0: no goals)
    double goal_depth = 0.0;       // behind the goal line, to the back wall
    double corner_leg = 0.0;       // legs of the isosceles right triangles in the corners (0: square corners)
    double centre_radius = 0.20;   // centre circle
    double goal_area_depth = 0.0;  // goal area in front of each goal, along x (0: none)
    double goal_area_width = 0.0;  // goal area along y, centred
    double penalty_mark = 0.0;     // penalty mark's distance from the goal line, along x
    double free_ball_x = 0.0;      // free-ball marks' distance from the goal line, along x
    double free_ball_y = 0.0;      // free-ball marks' distance from the long axis, along y
};

// The official dimensions of a field type (the seed's 1.50 x 1.30 box for Box).
FieldDimensions officialDimensions(FieldType type);

// What is wrong with a set of dimensions (a goal wider than its wall between
// the corners, a goal area deeper than half the field, a negative length...),
// as a key name and a reason; empty when they make a field.
struct FieldProblem {
    const char* key = nullptr;  // "goal_width", ...; null when there is none
    const char* reason = "";
};
FieldProblem checkFieldDimensions(const FieldDimensions& d);

struct Field {
    FieldDimensions dimensions;
    double length = 1.50;     // the playing area along x (dimensions.length), m
    double width = 1.30;      // along y (dimensions.width), m
    std::vector<Wall> walls;  // the closed chain around the floor, counter-clockwise
    // Corners of the chain that point into the field (the goal posts), m:
    // bodies can touch them with a face, not only a wall with a vertex.
    std::vector<Eigen::Vector2d> posts;
    // The chain's bounding box: the floor including the goals, m.
    Eigen::Vector2d lower = Eigen::Vector2d::Zero(), upper = Eigen::Vector2d::Zero();
    // For each wall, whether its first end (a) is a post: the walls on the
    // two sides of a post meet at a corner pointing into the floor.
    std::vector<char> startsAtPost;
    // The floor no wall reaches: |x| < clearHalf.x(), |y| < clearHalf.y() and
    // |x| + |y| < clearDiagonal (the playing rectangle minus the corner
    // triangles; every wall lies on or outside its edge), m.
    Eigen::Vector2d clearHalf = Eigen::Vector2d::Zero();
    double clearDiagonal = 0.0;
};

// A field from its dimensions (which must pass checkFieldDimensions).
Field makeField(const FieldDimensions& dimensions);
// The seed's field: a closed rectangle length x width centred on the origin,
// with four walls whose normals point inwards.
Field makeRectangularField(double length, double width);

// Whether a point lies on the floor (inside the chain of walls, the goals
// included; within 1e-13 m of a wall counts as inside).
bool onFloor(const Field& field, const Eigen::Vector2d& p);
// The nearest point of the walls to p: which wall and where, and the
// distance, m.
struct NearestWall {
    int wall = -1;
    Eigen::Vector2d point = Eigen::Vector2d::Zero();
    double distance = 0.0;
};
NearestWall nearestWall(const Field& field, const Eigen::Vector2d& p);

// Whether a disc of radius r around p lies on the floor clear of every wall
// by a margin (a cheap, conservative test: false near a wall even when the
// disc does not touch it). Contact detection skips the bodies it clears.
inline bool clearOfWalls(const Field& field, const Eigen::Vector2d& p, double r) {
    // Every wall lies on the lines |x| = hx, |y| = hy or |x| + |y| = hx + hy - c,
    // or beyond them, and the corner triangles' lines are sqrt2 r away when
    // |x| + |y| is sqrt2 r short of them (1.5 r: rounding cannot matter). The
    // margin keeps the test conservative against the rounding of the exact
    // tests it lets the callers skip.
    constexpr double kMargin = 1e-9;  // m
    const double ax = std::abs(p.x()), ay = std::abs(p.y()), reach = r + kMargin;
    return ax + reach < field.clearHalf.x() && ay + reach < field.clearHalf.y() &&
           ax + ay + 1.5 * reach < field.clearDiagonal;
}

// The walls that a point off the floor is past (model.md §5, "a vertex
// beyond a wall", on a chain of walls): the nearest wall and, across a
// corner of the chain that is not a post, its neighbours, each only if p is
// beyond its line. At a post, whose two walls' lines both extend over floor,
// p is past one wall only: the one `from` (the body's centre) is in front of,
// the other being the way the body did not come; the nearest when `from`
// does not tell. Empty for a point on the floor. Up to three walls, in
// increasing index order, -1 for none.
std::array<int, 3> wallsPast(const Field& field, const Eigen::Vector2d& p, const Eigen::Vector2d& from);

// The post whose solid corner p is in (beyond both walls that meet there,
// and nearer the post than their other ends), as the index of the wall that
// starts at it; -1 for none.
int postCornerAt(const Field& field, const Eigen::Vector2d& p);

// Signed distance from p to a wall's line, positive on the floor side, m.
inline double wallSignedDistance(const Wall& w, const Eigen::Vector2d& p) { return w.normal.dot(p - w.a); }

// The distance from p to the nearest wall, for a conservative test of how far
// a body can go before touching one: the distance to each segment, measured
// along the wall's normal where p projects onto the segment (negative behind
// it), m. -infinity for a point off the floor.
double wallClearance(const Field& field, const Eigen::Vector2d& p);

// Whether a square robot of side `side` (m) centred at (x, y) with heading
// theta (rad), or a disc of radius r, lies on the floor clear of every wall
// and post (touching counts as clear). False for NaN.
bool robotInsideField(const Field& field, double side, double x, double y, double theta);
bool discInsideField(const Field& field, double r, double x, double y);

// Whether the field has goals (and so a game can be played on it).
inline bool hasGoals(const Field& field) { return field.dimensions.goal_width > 0.0; }

}  // namespace vssim
