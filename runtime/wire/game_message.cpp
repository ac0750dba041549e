#include "wire/game_message.h"

#include "io/scene_io.h"

namespace vssim {

QJsonObject gameStateJson(const GameState& game) {
    const RefereeCall& last = game.last;
    // Only a kick-off, a penalty kick and a goal kick are for a team.
    const bool forTeam = last.call != Call::None && last.call != Call::FreeBall;
    return QJsonObject{
        {"phase", gamePhaseName(game.phase)},
        {"call", callName(last.call)},
        {"team", forTeam ? QJsonValue(teamLabel(last.team)) : QJsonValue()},
        {"quadrant", last.quadrant},
        {"half", game.half},
        {"clock", game.clock},
        {"stop_left", game.stopLeft},
        {"goals",
         QJsonObject{{"yellow", game.goals[teamIndex(Team::Yellow)]}, {"blue", game.goals[teamIndex(Team::Blue)]}}},
        {"reason", QString::fromStdString(last.reason)},
        {"call_time", last.time},
        {"call_clock", last.clock},
    };
}

QJsonObject gameSettingsJson(const GameRules& rules, TeamControl yellow, TeamControl blue) {
    QJsonObject json = gameRulesToJson(rules);
    json["yellow"] = teamControlName(yellow);
    json["blue"] = teamControlName(blue);
    return json;
}

}  // namespace vssim
