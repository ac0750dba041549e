#include "match_setup.h"

#include <cmath>
#include <string>
#include <vector>

#include "vssim/game/referee.h"

namespace vssim {

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

Scene defaultMatchScene(TeamControl yellow, TeamControl blue) {
    Scene scene;
    scene.field = makeField(officialDimensions(FieldType::Vsss3v3));
    scene.ball = BallState{0.0, 0.0, 0.0, 0.0};
    scene.simulation.integrator = Integrator::Exact;  // as kickoff_3v3.json says, whatever the default
    // The shipped kick-off's layout (resources/scenes/kickoff_3v3.json).
    const struct { double x, y; } yellowSpots[] = {{-0.68, 0.0}, {-0.35, 0.25}, {-0.2, -0.1}};
    for (Team team : {Team::Yellow, Team::Blue}) {
        const bool mirrored = team == Team::Blue;  // yellow as listed, blue through the centre
        for (int k = 0; k < 3; ++k) {
            RobotSpec r;
            r.name = std::string(teamLabel(team)) + std::to_string(k);
            r.team = team;
            r.initial.x = mirrored ? -yellowSpots[k].x : yellowSpots[k].x;
            r.initial.y = mirrored ? -yellowSpots[k].y : yellowSpots[k].y;
            r.initial.theta = mirrored ? kPi : 0.0;
            scene.robots.push_back(r);
        }
    }
    scene.game.rules.referee = true;
    scene.game.yellow = yellow;
    scene.game.blue = blue;
    return scene;
}

bool playToFullTime(Match& match, double timeLimit, const std::function<void()>& afterTick) {
    const std::int64_t tick = match.tickSteps();
    while (match.game().phase != GamePhase::Finished) {
        const std::int64_t step = match.simulation().state().step;
        match.advanceTo((step / tick + 1) * tick);
        if (firstNonFiniteBody(match.simulation().state()) >= 0) return false;
        if (match.simulation().state().time > timeLimit) return false;
        if (afterTick) afterTick();
    }
    return true;
}

double matchTimeLimit(const GameRules& rules) {
    // A call at most every game tick would stop the game for stop_duration
    // each time; real matches take far less (a call every few seconds).
    const double played = rules.halves * rules.half_duration;
    return played * (1.0 + rules.stop_duration / std::max(rules.tick, 1e-3)) + 3600.0;
}

}  // namespace vssim
