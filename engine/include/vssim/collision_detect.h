// Collision detection (model.md §5): the paper's four tests, plus the cases it
// drops (two robots overlapping with no vertex inside the other), covered by a
// separating-axis test. Each function returns a contact or nothing.
#pragma once

#include <optional>
#include <vector>

#include "vssim/ball.h"
#include "vssim/broad_phase.h"
#include "vssim/contact.h"
#include "vssim/field.h"
#include "vssim/robot_state.h"

namespace vssim {

// Ball (a) against wall `wallIndex` (b): centre within r_b of the segment, or
// behind the wall (tunnelled), which is reported as a deep contact.
std::optional<Contact> ballWallContact(const BallState& ball, double radius, const Wall& wall, int wallIndex);

// Robot `robotIndex` (a) against a wall (b): a vertex beyond the wall. The
// contact point is the penetrating vertices' average weighted by depth, so a
// face lying flat on the wall touches at its middle.
std::optional<Contact> robotWallContact(const RobotState& robot, double side, int robotIndex, const Wall& wall,
                                        int wallIndex);

// Ball (a) against robot (b): cheap rejection by centre distance, then the
// distance to each side segment (paper eqs. 10-11); a ball centre inside the
// square is pushed out through the nearest face.
std::optional<Contact> robotBallContact(const RobotState& robot, double side, int robotIndex, const BallState& ball,
                                        double radius);

// Robot a against robot b: depth and normal from the separating-axis test;
// the contact point from the paper's vertex-inside tests, or, when no vertex
// is inside (face to face, crossed squares), the middle of the overlap along
// the normal.
std::optional<Contact> robotRobotContact(const RobotState& a, double sideA, int indexA, const RobotState& b,
                                         double sideB, int indexB);

// All contacts in a world, in a fixed order (deterministic): robot-robot pairs
// (i < j), robot-ball, robot-wall, ball-wall.
struct BodiesView {
    const std::vector<RobotState>* robots = nullptr;
    const std::vector<double>* sides = nullptr;  // side of each robot, m
    const BallState* ball = nullptr;
    double ballRadius = 0.0;
    bool broadPhase = true;  // robot pairs from broad_phase.h instead of all pairs (same contacts)
    // Bodies known to be out of reach of everything (Simulation::advanceTo's
    // free bodies): no test involving them can find a contact, so none is made.
    const std::vector<char>* freeRobots = nullptr;  // non-zero entry: skip robot i
    bool freeBall = false;
    BroadPhaseScratch* broadPhaseScratch = nullptr;  // kept between calls (faster); null: a fresh one
    // When set: the only robots tested (increasing indices), every other one
    // free (freeRobots is then not read); the same contacts in the same
    // order, at a cost that grows with these robots only.
    const std::vector<int>* listedRobots = nullptr;
};
std::vector<Contact> detectContacts(const Field& field, const BodiesView& bodies);

// Only the robot-wall and ball-wall contacts, appended in the same order.
void appendWallContacts(const Field& field, const BodiesView& bodies, std::vector<Contact>& contacts);

}  // namespace vssim
