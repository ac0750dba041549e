// Collision response (model.md §6): velocity changes at a contact, by the
// paper's sphere-equivalent exchange (§6a, eq. 12) or by the energy-consistent
// impulse (§6b), and the positional separation of overlapping bodies.
//
// Both act only while the bodies approach along the normal, so a resolved
// contact does not re-trigger. Walls have infinite mass and never move.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "vssim/ball.h"
#include "vssim/collision_model.h"
#include "vssim/contact.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"

namespace vssim {

// The bodies a contact's indices refer to. `ball` may be null (no ball).
struct Bodies {
    std::vector<RobotState>* robots = nullptr;
    const std::vector<RobotModel>* models = nullptr;  // one per robot
    BallState* ball = nullptr;
    const BallParams* ballParams = nullptr;
};

// Velocity of the material point at `point` (field frame) of a body, m/s:
// for a robot v_c = v h + w z x d (model.md §6a), for the ball its velocity,
// zero for a wall.
Eigen::Vector2d contactPointVelocity(const Bodies& bodies, const BodyRef& body, const Eigen::Vector2d& point);

// §6a: recovers (v', w') from a wanted contact-point velocity v_c' = v' h + w' z x d.
// With d = (d_f, d_l) in the robot frame, w' = (v_c' . h_perp) / d_f and
// v' = v_c' . h + w' d_l. When the contact point lies on the robot's lateral
// axis (|d_f| < kLateralAxisTolerance) no finite yaw rate can produce the
// lateral part: the fallback keeps w and applies only the forward part,
// v' = v + h . (v_c' - v_c).
constexpr double kLateralAxisTolerance = 1e-3;  // m
Eigen::Vector2d decomposeContactVelocity(const RobotState& robot, const Eigen::Vector2d& d,
                                         const Eigen::Vector2d& wanted);

// Eq. 12: 1-D elastic exchange of normal speeds for masses m1, m2 (kg);
// an infinite mass is a wall. Returns (v1', v2').
Eigen::Vector2d elasticExchange(double m1, double v1, double m2, double v2);

// The paper's exchange is used as it is unless it would raise the kinetic
// energy of the two bodies by more than this fraction; then the contact is
// resolved by the elastic impulse of §6b instead (see docs/model.md).
constexpr double kPaperEnergyTolerance = 1e-9;

// Applies the chosen response to one contact. Returns true when the bodies
// were approaching and their velocities changed.
bool respondToContact(const Contact& contact, Bodies& bodies, CollisionModel model, double restitution);

// Moves the bodies apart along the normal by the full depth, shared in
// proportion to inverse mass (a wall takes none).
void separateBodies(const Contact& contact, Bodies& bodies);

// Total kinetic energy: sum of 1/2 u^T M u over robots (M includes the rotor
// inertia) plus 1/2 m_b |v_b|^2, J.
double kineticEnergy(const Bodies& bodies);

}  // namespace vssim
