#include "realtime/snapshot.h"

namespace vssim {

Snapshot takeSnapshot(const EngineLoop& loop, std::shared_ptr<const Scene> scene, double stepCost, std::int64_t nowNs) {
    const Simulation& sim = loop.simulation();
    Snapshot s;
    s.time = sim.state().time;
    s.step = sim.state().step;
    s.frame = loop.frame();
    s.mode = loop.mode();
    s.paused = loop.paused();
    s.fault = loop.fault();
    s.speed = loop.speed();
    s.robots = sim.state().robots;
    s.offField = sim.state().offField;
    s.voltages = sim.state().voltages;
    s.outputs.reserve(s.robots.size());
    for (std::size_t i = 0; i < s.robots.size(); ++i) s.outputs.push_back(sim.robotOutputs(static_cast<int>(i)));
    s.ball = sim.state().ball;
    s.control = loop.control();
    const Match& match = loop.match();
    s.game = match.game();
    s.gameSettings = match.scene().game;
    s.gameSettings.yellow = match.control(Team::Yellow);
    s.gameSettings.blue = match.control(Team::Blue);
    s.scene = std::move(scene);
    s.stepCost = stepCost;
    s.publishedNs = nowNs;
    return s;
}

}  // namespace vssim
