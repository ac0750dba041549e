#include "firasim/vssref_command.h"

#include <cmath>

#include "vssim/field.h"

namespace vssim {

namespace {

constexpr double kPi = 3.14159265358979323846;

VSSRef::Color colorOf(Team team) { return team == Team::Yellow ? VSSRef::YELLOW : VSSRef::BLUE; }

VSSRef::Half halfOf(int half) {
    switch (half) {
        case 1: return VSSRef::FIRST_HALF;
        case 2: return VSSRef::SECOND_HALF;
        case 3: return VSSRef::OVERTIME_FIRST_HALF;
        case 4: return VSSRef::OVERTIME_SECOND_HALF;
        default: return VSSRef::NO_HALF;
    }
}

VSSRef::Quadrant quadrantEnum(int quadrant) {
    return quadrant >= 1 && quadrant <= 4 ? static_cast<VSSRef::Quadrant>(quadrant) : VSSRef::NO_QUADRANT;
}

}  // namespace

VSSRef::ref_to_team::VSSRef_Command vssRefCommand(const GameState& game, double time) {
    VSSRef::ref_to_team::VSSRef_Command command;
    command.set_timestamp(time);
    command.set_gamehalf(halfOf(game.half));
    command.set_teamcolor(VSSRef::NONE);
    command.set_foulquadrant(VSSRef::NO_QUADRANT);
    switch (game.phase) {
        case GamePhase::GameOn: command.set_foul(VSSRef::GAME_ON); break;
        case GamePhase::Halt:
        case GamePhase::Finished: command.set_foul(VSSRef::HALT); break;
        case GamePhase::Stop:
            switch (game.last.call) {
                case Call::None: command.set_foul(VSSRef::STOP); break;
                case Call::KickOff:
                    command.set_foul(VSSRef::KICKOFF);
                    command.set_teamcolor(colorOf(game.last.team));
                    break;
                case Call::PenaltyKick:
                    command.set_foul(VSSRef::PENALTY_KICK);
                    command.set_teamcolor(colorOf(game.last.team));
                    break;
                case Call::GoalKick:
                    command.set_foul(VSSRef::GOAL_KICK);
                    command.set_teamcolor(colorOf(game.last.team));
                    break;
                case Call::FreeBall:
                    command.set_foul(VSSRef::FREE_BALL);
                    command.set_foulquadrant(quadrantEnum(game.last.quadrant));
                    break;
            }
            break;
    }
    return command;
}

VssRefCommandKey vssRefCommandKey(const GameState& game) {
    VssRefCommandKey key;
    key.phase = game.phase;
    key.call = game.last.call;
    key.team = game.last.team;
    key.quadrant = game.last.quadrant;
    key.half = game.half;
    key.calls = game.calls.size();
    return key;
}

double vssRefDegreesToRadians(double degrees) {
    // Reduce in degrees first (exact for whole degrees), then convert.
    double d = std::fmod(degrees, 360.0);  // (-360, 360)
    if (d > 180.0) d -= 360.0;
    if (d <= -180.0) d += 360.0;
    return d * (kPi / 180.0);
}

std::optional<VssRefTeamPlacement> vssRefPlacement(const VSSRef::team_to_ref::VSSRef_Placement& placement,
                                                   const Scene& scene, const TeamRoster& roster, QString* error) {
    auto fail = [error](const QString& why) {
        *error = why;
        return std::nullopt;
    };
    if (!placement.has_world()) return fail(QStringLiteral("no world frame (VSSRef_Placement.world is missing)"));
    const VSSRef::Frame& frame = placement.world();
    VssRefTeamPlacement out;
    switch (frame.teamcolor()) {
        case VSSRef::YELLOW: out.team = Team::Yellow; break;
        case VSSRef::BLUE: out.team = Team::Blue; break;
        case VSSRef::NONE: return fail(QStringLiteral("teamColor is NONE: a placement is for YELLOW or BLUE"));
        default: return fail(QStringLiteral("teamColor %1 is not a colour (BLUE 0, YELLOW 1)").arg(frame.teamcolor()));
    }
    const char* team = teamLabel(out.team);
    const std::size_t members = roster.members(out.team).size();
    if (frame.robots_size() == 0) return fail(QStringLiteral("%1 placement names no robots").arg(team));
    if (static_cast<std::size_t>(frame.robots_size()) > members)
        return fail(QStringLiteral("%1 placement names %2 robots; the team has %3")
                        .arg(team)
                        .arg(frame.robots_size())
                        .arg(members));
    for (int i = 0; i < frame.robots_size(); ++i) {
        const VSSRef::Robot& r = frame.robots(i);
        const int index = roster.robotIndex(out.team, r.robot_id());
        if (index < 0)
            return fail(QStringLiteral("%1 robot_id %2: the team has ids 0 to %3")
                            .arg(team)
                            .arg(r.robot_id())
                            .arg(static_cast<long long>(members) - 1));
        for (const auto& [placed, pose] : out.poses)
            if (placed == index)
                return fail(QStringLiteral("%1 robot_id %2 is placed twice").arg(team).arg(r.robot_id()));
        if (!std::isfinite(r.x()) || !std::isfinite(r.y()) || !std::isfinite(r.orientation()))
            return fail(QStringLiteral("%1 robot_id %2: x %3 m, y %4 m, orientation %5 deg: not finite")
                            .arg(team)
                            .arg(r.robot_id())
                            .arg(r.x())
                            .arg(r.y())
                            .arg(r.orientation()));
        RobotState pose;
        pose.x = r.x();
        pose.y = r.y();
        pose.theta = vssRefDegreesToRadians(r.orientation());
        const RobotSpec& spec = scene.robots[static_cast<std::size_t>(index)];
        if (!robotInsideField(scene.field, spec.params.side, pose.x, pose.y, pose.theta))
            return fail(QStringLiteral("%1 robot_id %2 (%3) at (%4, %5) m, orientation %6 deg, would not lie wholly "
                                       "inside the field")
                            .arg(team)
                            .arg(r.robot_id())
                            .arg(QString::fromStdString(spec.name))
                            .arg(r.x())
                            .arg(r.y())
                            .arg(r.orientation()));
        out.poses.emplace_back(index, pose);
    }
    return out;
}

}  // namespace vssim
