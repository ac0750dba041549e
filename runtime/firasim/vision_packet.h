// FIRASim's vision message (fira_message.sim_to_ref.Environment) for one
// camera instant of vssim: the ball, the robots on the field by team and id,
// the field's dimensions and the score (shared vsss-game.md, "FIRASim's
// network interface"). vssim's field frame is FIRASim's: origin at the
// centre, x towards the goal at x > 0, metres,
// radians counter-clockwise; speeds in m/s and rad/s.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "fira_packet.pb.h"
#include "firasim/team_roster.h"
#include "vssim/camera_settings.h"
#include "vssim/field.h"
#include "vssim/world_model.h"

namespace vssim {

// The field's dimensions as FIRASim names them: width along y, length along
// x (goal line to goal line), the goal's mouth and depth, the centre circle's
// radius, the goal area as penalty_width (along y) x penalty_depth (along x),
// and penalty_point as the penalty mark's distance from the centre along x.
fira_message::Field firasimField(const Field& field);

// The Environment for the world `world`: `step` is its simulated time in
// whole milliseconds, as FIRASim fills it (wrapped to 32 bits as the wire's
// uint32; the same as vssim's step count at the default dt of 1 ms). Robots
// whose onField entry is 0 are left
// out; each robot's orientation is wrapped to [-pi, pi], its vx, vy is its
// forward speed v along its heading and vorientation its yaw rate. goals: by
// team, [Yellow] and [Blue]. The ball's z is the height of its centre,
// `ballRadius` (m; it rolls on the floor), as FIRASim sends it: a ball at rest
// at the centre is then not an all-default message, which proto3 would send
// as an empty `ball` that some clients cannot read.
//
// `camera`'s ground-truth noise (delivery/ground_truth_noise.h) applies to
// the positions and orientations, drawn for camera instant `frame` on the
// FIRASim stream (kFirasimStream): metres and radians, the packet's own
// units. A robot that vanishes is left out of its team's list; a ball that
// vanishes leaves the frame without `ball` (proto3: has_ball() false).
// Speeds stay exact. The ideal camera changes nothing.
fira_message::sim_to_ref::Environment firasimEnvironment(const fira_message::Field& field, const TeamRoster& roster,
                                                         const WorldState& world, double ballRadius,
                                                         const std::vector<char>& onField,
                                                         const std::array<int, 2>& goals,
                                                         const CameraSettings& camera = idealCamera(),
                                                         std::int64_t frame = 0);

}  // namespace vssim
