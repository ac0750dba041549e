#include "vssim/world_model.h"

#include <cmath>

#include "vssim/broad_phase.h"

namespace vssim {

WorldModel makeWorldModel(const Scene& scene) {
    WorldModel m;
    m.field = scene.field;
    m.settings = scene.simulation;
    m.ball = scene.ball_params;
    m.robots.reserve(scene.robots.size());  // (a RobotModel is over 500 bytes: no regrowth)
    m.sides.reserve(scene.robots.size());
    for (const RobotSpec& r : scene.robots) {
        m.robots.push_back(makeRobotModel(r.params));
        m.sides.push_back(r.params.side);
    }
    return m;
}

WorldState initialWorldState(const Scene& scene) {
    WorldState s;
    s.ball = scene.ball;
    s.robots.reserve(scene.robots.size());
    s.voltages.reserve(scene.robots.size());
    for (const RobotSpec& r : scene.robots) {
        s.robots.push_back(r.initial);
        s.voltages.push_back({});
    }
    s.speedLoops.assign(scene.robots.size(), {});
    s.offField.assign(scene.robots.size(), 0);
    return s;
}

int firstNonFiniteBody(const WorldState& state) {
    auto finite = [](std::initializer_list<double> values) {
        for (double v : values)
            if (!std::isfinite(v)) return false;
        return true;
    };
    const int robots = static_cast<int>(state.robots.size());
    for (int i = 0; i < robots; ++i) {
        const RobotState& r = state.robots[i];
        if (!finite({r.x, r.y, r.theta, r.v, r.omega})) return i;
    }
    const BallState& b = state.ball;
    return finite({b.x, b.y, b.vx, b.vy}) ? -1 : robots;
}

bool useBroadPhase(const WorldModel& model, const WorldState& state) {
    return model.settings.broad_phase && static_cast<int>(state.robots.size()) >= kBroadPhaseMinRobots;
}

}  // namespace vssim
