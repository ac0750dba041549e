// VSSReferee's messages against vssim's game, both ways, as pure functions
// (no sockets): the command the league's referee would send for vssim's
// GameState, and a team's VSSRef_Placement as vssim's own placement request
// (docs/firasim.md, "VSSReferee's protocol"; shared vsss-game.md, "VSSReferee's network interface").
//
// Command, for GameState::phase:
//   Stop      the call being played: KickOff -> KICKOFF, FreeBall -> FREE_BALL,
//             PenaltyKick -> PENALTY_KICK, GoalKick -> GOAL_KICK (no call
//             yet: STOP); teamcolor the team the call favours (NONE for a
//             free ball), foulQuadrant the free ball's quadrant (NO_QUADRANT
//             otherwise)
//   GameOn    GAME_ON, teamcolor NONE, NO_QUADRANT
//   Halt      HALT, teamcolor NONE, NO_QUADRANT
//   Finished  HALT (VSSReferee has no "match over"; nothing moves after it)
// gameHalf: half 1 FIRST_HALF, 2 SECOND_HALF, 3 OVERTIME_FIRST_HALF,
// 4 OVERTIME_SECOND_HALF (vssim plays further halves as normal ones; the
// numbers are VSSReferee's), any other NO_HALF.
// timestamp: the simulated time of the state, s (VSSReferee stamps wall
// time; vssim's game runs on simulated time, at any speed).
//
// Placement: VSSRef.Frame's robots in the field frame (m; origin at the
// centre, x towards the goal blue defends, y up) with orientation in
// DEGREES (VSSReferee forwards it into FIRASim's replacement, which reads
// degrees), counter-clockwise from +x; vssim's poses in radians, wrapped to
// (-pi, pi].
#pragma once

#include <QString>
#include <optional>
#include <utility>
#include <vector>

#include "firasim/team_roster.h"
#include "vssim/game/game_state.h"
#include "vssim/robot_state.h"
#include "vssim/scene.h"
#include "vssref_command.pb.h"
#include "vssref_placement.pb.h"

namespace vssim {

// The command for `game` at simulated time `time` (s).
VSSRef::ref_to_team::VSSRef_Command vssRefCommand(const GameState& game, double time);

// The parts of a state that a command carries: when they change, the
// bridge publishes a new command.
struct VssRefCommandKey {
    GamePhase phase = GamePhase::Stop;
    Call call = Call::None;
    Team team = Team::Yellow;
    int quadrant = 0;
    int half = 1;
    std::size_t calls = 0;  // a second identical call in a row (two goals) is news too
    bool operator==(const VssRefCommandKey& o) const {
        return phase == o.phase && call == o.call && team == o.team && quadrant == o.quadrant && half == o.half &&
               calls == o.calls;
    }
    bool operator!=(const VssRefCommandKey& o) const { return !(*this == o); }
};
VssRefCommandKey vssRefCommandKey(const GameState& game);

// A team's placement as vssim reads it: the team and (scene robot index,
// pose in m and rad, at rest) for each robot named.
struct VssRefTeamPlacement {
    Team team = Team::Yellow;
    std::vector<std::pair<int, RobotState>> poses;
};

// `placement` as vssim's placement, or nullopt with `*error` saying why:
// no frame, teamColor NONE or unknown, no robots, more robots than the team
// has, an id the team does not have, a robot named twice, a coordinate that
// is not finite, a pose not wholly inside the field. Whether the poses are
// legal for the call being played is the referee's to judge
// (checkTeamPlacement).
std::optional<VssRefTeamPlacement> vssRefPlacement(const VSSRef::team_to_ref::VSSRef_Placement& placement,
                                                   const Scene& scene, const TeamRoster& roster, QString* error);

// Degrees (as VSSReferee sends them) to radians wrapped to (-pi, pi].
double vssRefDegreesToRadians(double degrees);

}  // namespace vssim
