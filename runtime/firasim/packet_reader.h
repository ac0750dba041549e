// What a FIRASim Packet (fira_message.sim_to_ref.Packet, from team software
// or VSSReferee) asks of vssim, checked against the scene before anything
// reaches the engine: the bad-input policy of docs/firasim.md.
//
// Commands: robot (yellowteam, id) through the TeamRoster; an unknown one is
// skipped (counted). Wheel speeds in rad/s: NaN becomes 0 rad/s, anything
// else is clamped to +-kMaxWheelSpeed (counted when it had to be). A robot
// commanded twice in one packet keeps the last command. Either team may be
// commanded; the result keeps the teams apart.
//
// Replacement: the ball at (x, y) m with (vx, vy) m/s; a robot at (x, y) m
// with its orientation in DEGREES (as FIRASim reads it), placed at rest (the
// replacement's speeds are ignored); turnon false takes the robot off the
// field (its pose is ignored), turnon true on a robot off the field brings it
// back at the pose. Refused (counted): non-finite numbers, a ball faster than
// kMaxPlacedBallSpeed, a body that would not lie wholly inside the field, and
// a body whose final pose, once the whole packet's replacements are applied,
// overlaps another body on the field (for the ball: a robot where it ends
// up). A robot replaced twice in one packet keeps the last replacement.
#pragma once

#include <QString>
#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "firasim/team_roster.h"
#include "vssim/scene.h"
#include "vssim/speed_controller.h"
#include "vssim/world_model.h"

namespace vssim {

// The largest wheel speed accepted, rad/s (about 25 m/s at the rim of a
// 2.5 cm wheel: far beyond any VSSS motor, so it only catches garbage).
constexpr double kMaxWheelSpeed = kMaxWheelSpeedTarget;
// How far into a wall a replaced body may reach and still be accepted, m:
// referees compute in float (VSSReferee puts a ball resting on a wall a few
// 1e-8 m into it); the engine's next contact pass puts it back on the field.
constexpr double kReplacementWallSlack = 5e-4;  // the engine's limit (speed_controller.h)

// A wheel-speed target as accepted: NaN -> 0, otherwise clamped to
// +-kMaxWheelSpeed (infinities included). `changed` tells whether it had to be.
double acceptWheelSpeed(double w, bool* changed);

// A robot replacement with turnon true: placed at `pose`, and on the field
// (brought back if it was off).
struct FirasimPlacement {
    int robot = -1;   // scene index
    RobotState pose;  // m, rad; v = omega = 0
};

// What one datagram asks for, and what was wrong with it.
struct FirasimPacket {
    bool parsed = false;       // false: not a Packet (malformed protobuf); nothing else is set
    bool hasCommands = false;  // the `cmd` field was present (even empty): a tick in sync mode
    // Wheel speeds by team ([Yellow], [Blue]): (robot index, rad/s), one per robot.
    std::array<std::vector<std::pair<int, WheelSpeeds>>, 2> wheelSpeeds;
    std::optional<BallState> ball;         // an accepted ball replacement
    std::vector<FirasimPlacement> robots;  // accepted robot replacements
    // Replacements onto another body (on the final poses of the packet):
    // blocked, with the log line that refuses them. The server retries them
    // briefly (a referee moves the bodies in its next datagrams) before it
    // refuses them.
    std::vector<std::pair<FirasimPlacement, QString>> blocked;
    std::optional<BallState> blockedBall;
    QString blockedBallWhy;
    std::vector<int> turnOff;              // robots to take off the field
    // Problems, counted by kind.
    int unknownRobots = 0;          // commands and replacements for robots the scene does not have
    int clampedSpeeds = 0;          // wheel speeds that were NaN, infinite or beyond the limit
    int refusedOutside = 0;         // replacements outside the field
    int refusedBad = 0;             // replacements with non-finite numbers or too fast a ball
    std::vector<QString> problems;  // one line each, for the log (bounded)
};

// What robot `robot` at poses[robot] would overlap among the robots present
// at `poses` and the ball: a robot's name, "the ball", or empty.
QString firasimRobotOverlap(const Scene& scene, int robot, const std::vector<RobotState>& poses,
                            const std::vector<char>& present, const BallState& ball);
// What the ball would overlap among the robots present: a name or empty.
QString firasimBallOverlap(const Scene& scene, const BallState& ball, const std::vector<RobotState>& poses,
                           const std::vector<char>& present);

// Reads `size` bytes. `current`: the bodies now (for the overlap test);
// `onField`: per scene robot, whether it is on the field now.
FirasimPacket readFirasimPacket(const char* data, int size, const Scene& scene, const TeamRoster& roster,
                                const WorldState& current, const std::vector<char>& onField);

}  // namespace vssim
