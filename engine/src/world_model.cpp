#include "vssim/world_model.h"

#include "vssim/broad_phase.h"

namespace vssim {

WorldModel makeWorldModel(const Scene& scene) {
    WorldModel m;
    m.field = scene.field;
    m.settings = scene.simulation;
    m.ball = scene.ball_params;
    for (const RobotSpec& r : scene.robots) {
        m.robots.push_back(makeRobotModel(r.params));
        m.sides.push_back(r.params.side);
    }
    return m;
}

WorldState initialWorldState(const Scene& scene) {
    WorldState s;
    s.ball = scene.ball;
    for (const RobotSpec& r : scene.robots) {
        s.robots.push_back(r.initial);
        s.voltages.push_back({});
    }
    return s;
}

bool useBroadPhase(const WorldModel& model, const WorldState& state) {
    return model.settings.broad_phase && static_cast<int>(state.robots.size()) >= kBroadPhaseMinRobots;
}

}  // namespace vssim
