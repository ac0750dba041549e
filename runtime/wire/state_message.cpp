#include "wire/state_message.h"

#include <QJsonArray>

#include "wire/game_message.h"

namespace vssim {

QJsonObject stateJson(const Simulation& sim, std::int64_t frame, const GameState* game) {
    const WorldState& s = sim.state();
    QJsonArray robots;
    for (std::size_t i = 0; i < s.robots.size(); ++i) {
        const RobotState& r = s.robots[i];
        const RobotOutputs out = sim.robotOutputs(static_cast<int>(i));
        robots.append(QJsonObject{
            {"index", static_cast<int>(i)},
            {"on_field", !(i < s.offField.size() && s.offField[i])},
            {"x", r.x},
            {"y", r.y},
            {"theta", r.theta},
            {"v", r.v},
            {"omega", r.omega},
            {"right_voltage", s.voltages[i].right},
            {"left_voltage", s.voltages[i].left},
            {"right_current", out.current_right},
            {"left_current", out.current_left},
            {"right_wheel_speed", out.wheel_speed_right},
            {"left_wheel_speed", out.wheel_speed_left},
        });
    }
    QJsonObject json{
        {"frame", static_cast<double>(frame)},
        {"time", s.time},
        {"robots", robots},
        {"ball", QJsonObject{{"x", s.ball.x}, {"y", s.ball.y}, {"vx", s.ball.vx}, {"vy", s.ball.vy}}},
    };
    if (game) json["game"] = gameStateJson(*game);
    return json;
}

}  // namespace vssim
