#include "firasim/vision_packet.h"

#include <cmath>

#include "delivery/ground_truth_noise.h"
#include "vssim/game/game_state.h"

namespace vssim {

fira_message::Field firasimField(const Field& field) {
    const FieldDimensions& d = field.dimensions;
    fira_message::Field f;
    f.set_width(d.width);
    f.set_length(d.length);
    f.set_goal_width(d.goal_width);
    f.set_goal_depth(d.goal_depth);
    f.set_center_radius(d.centre_radius);
    f.set_penalty_width(d.goal_area_width);
    f.set_penalty_depth(d.goal_area_depth);
    // vssim keeps the mark's distance from the goal line; FIRASim's clients
    // read it from the centre (0.375 m on the 3 vs 3 field either way).
    f.set_penalty_point(d.penalty_mark > 0.0 ? 0.5 * d.length - d.penalty_mark : 0.0);
    return f;
}

fira_message::sim_to_ref::Environment firasimEnvironment(const fira_message::Field& field, const TeamRoster& roster,
                                                         const WorldState& world, double ballRadius,
                                                         const std::vector<char>& onField,
                                                         const std::array<int, 2>& goals, const CameraSettings& camera,
                                                         std::int64_t frame) {
    fira_message::sim_to_ref::Environment env;
    // FIRASim's step is its simulated time in whole milliseconds (its steps
    // times its step length, truncated), not a count of steps. The 1e-6 ms
    // keeps a whole millisecond that rounding put just below it.
    env.set_step(static_cast<std::uint32_t>(static_cast<std::uint64_t>(std::floor(world.time * 1000.0 + 1e-6))));
    fira_message::Frame* out = env.mutable_frame();
    CameraDrawKey key{camera.seed, kFirasimStream, frame, kBallBody};
    const ObservedPose seenBall = observePose(camera, key, world.ball.x, world.ball.y, 0.0);
    if (seenBall.visible) {
        fira_message::Ball* ball = out->mutable_ball();
        ball->set_x(seenBall.x);
        ball->set_y(seenBall.y);
        ball->set_z(ballRadius);
        ball->set_vx(world.ball.vx);
        ball->set_vy(world.ball.vy);
        ball->set_vz(0.0);
    }
    for (Team team : {Team::Yellow, Team::Blue}) {
        for (int index : roster.members(team)) {
            if (index >= static_cast<int>(world.robots.size())) continue;
            if (index < static_cast<int>(onField.size()) && !onField[index]) continue;
            const RobotState& s = world.robots[index];
            key.body = static_cast<std::uint64_t>(index);
            const ObservedPose seen = observePose(camera, key, s.x, s.y, s.theta);
            if (!seen.visible) continue;
            fira_message::Robot* r = team == Team::Yellow ? out->add_robots_yellow() : out->add_robots_blue();
            r->set_robot_id(roster.idOf(index));
            r->set_x(seen.x);
            r->set_y(seen.y);
            // Wrapped to [-pi, pi], as FIRASim reports it (the engine's theta accumulates turns).
            r->set_orientation(std::remainder(seen.theta, 2.0 * 3.14159265358979323846));
            r->set_vx(s.v * std::cos(s.theta));
            r->set_vy(s.v * std::sin(s.theta));
            r->set_vorientation(s.omega);
        }
    }
    *env.mutable_field() = field;
    env.set_goals_yellow(static_cast<std::uint32_t>(goals[teamIndex(Team::Yellow)]));
    env.set_goals_blue(static_cast<std::uint32_t>(goals[teamIndex(Team::Blue)]));
    return env;
}

}  // namespace vssim
