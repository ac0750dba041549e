#include "wire/state_message.h"

#include <QJsonArray>

#include "delivery/ground_truth_noise.h"
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

QJsonObject observedStateJson(const QJsonObject& exact, const CameraSettings& camera, std::uint64_t stream) {
    if (!hasGroundTruthNoise(camera)) return exact;
    const bool vanishing = camera.vanish > 0.0;
    CameraDrawKey key{camera.seed, stream, static_cast<std::int64_t>(exact.value("frame").toDouble()), kWholeFrame};
    QJsonObject out = exact;
    QJsonArray robots;
    for (const QJsonValue& value : exact.value("robots").toArray()) {
        QJsonObject robot = value.toObject();
        key.body = static_cast<std::uint64_t>(robot.value("index").toInt());
        const ObservedPose pose = observePose(camera, key, robot.value("x").toDouble(), robot.value("y").toDouble(),
                                              robot.value("theta").toDouble());
        if (pose.visible) {
            robot["x"] = pose.x;
            robot["y"] = pose.y;
            robot["theta"] = pose.theta;
        } else {
            robot.remove("x");
            robot.remove("y");
            robot.remove("theta");
        }
        if (vanishing) robot["visible"] = pose.visible;
        robots.append(robot);
    }
    out["robots"] = robots;
    QJsonObject ball = exact.value("ball").toObject();
    key.body = kBallBody;
    const ObservedPose pose = observePose(camera, key, ball.value("x").toDouble(), ball.value("y").toDouble(), 0.0);
    if (pose.visible) {
        ball["x"] = pose.x;
        ball["y"] = pose.y;
    } else {
        ball.remove("x");
        ball.remove("y");
    }
    if (vanishing) ball["visible"] = pose.visible;
    out["ball"] = ball;
    return out;
}

}  // namespace vssim
