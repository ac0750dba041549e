#include "firasim/packet_reader.h"

#include <cmath>
#include <map>

#include "fira_packet.pb.h"
#include "realtime/engine_request.h"
#include "vssim/collision_detect.h"
#include "vssim/field.h"
#include "vssim/game/game_state.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

constexpr std::size_t kMaxProblemLines = 8;  // per packet: a packet of nonsense is one story
constexpr double kPi = 3.14159265358979323846;

void note(FirasimPacket& p, const QString& line) {
    if (p.problems.size() < kMaxProblemLines) p.problems.push_back(line);
}

const char* teamWord(bool yellow) { return yellow ? "yellow" : "blue"; }

bool finite(std::initializer_list<double> values) {
    for (double v : values)
        if (!std::isfinite(v)) return false;
    return true;
}

}  // namespace

double acceptWheelSpeed(double w, bool* changed) {
    if (std::isnan(w)) {
        *changed = true;
        return 0.0;
    }
    if (w > kMaxWheelSpeed || w < -kMaxWheelSpeed) {
        *changed = true;
        return w > 0 ? kMaxWheelSpeed : -kMaxWheelSpeed;
    }
    return w;
}

QString firasimRobotOverlap(const Scene& scene, int robot, const std::vector<RobotState>& poses,
                            const std::vector<char>& present, const BallState& ball) {
    const double side = scene.robots[robot].params.side;
    for (std::size_t j = 0; j < poses.size(); ++j) {
        if (static_cast<int>(j) == robot || !present[j]) continue;
        if (squareOverlap(poses[robot], side, poses[j], scene.robots[j].params.side).overlapping)
            return QString::fromStdString(scene.robots[j].name);
    }
    if (robotBallContact(poses[robot], side, robot, ball, scene.ball_params.radius)) return QStringLiteral("the ball");
    return {};
}

QString firasimBallOverlap(const Scene& scene, const BallState& ball, const std::vector<RobotState>& poses,
                           const std::vector<char>& present) {
    for (std::size_t j = 0; j < poses.size(); ++j)
        if (present[j] && robotBallContact(poses[j], scene.robots[j].params.side, static_cast<int>(j), ball,
                                           scene.ball_params.radius))
            return QString::fromStdString(scene.robots[j].name);
    return {};
}

FirasimPacket readFirasimPacket(const char* data, int size, const Scene& scene, const TeamRoster& roster,
                                const WorldState& current, const std::vector<char>& onField) {
    FirasimPacket out;
    fira_message::sim_to_ref::Packet packet;
    if (size < 0 || !packet.ParseFromArray(data, size)) return out;
    out.parsed = true;

    // Commands: the newest per robot, kept by team.
    out.hasCommands = packet.has_cmd();
    std::map<int, WheelSpeeds> speeds;  // by robot index: scene order within each team
    for (const fira_message::sim_to_ref::Command& c : packet.cmd().robot_commands()) {
        const Team team = c.yellowteam() ? Team::Yellow : Team::Blue;
        const int robot = roster.robotIndex(team, c.id());
        if (robot < 0) {
            ++out.unknownRobots;
            note(out,
                 QStringLiteral("command for %1 robot %2: no such robot").arg(teamWord(c.yellowteam())).arg(c.id()));
            continue;
        }
        bool changedRight = false, changedLeft = false;
        WheelSpeeds w{acceptWheelSpeed(c.wheel_right(), &changedRight), acceptWheelSpeed(c.wheel_left(), &changedLeft)};
        if (changedRight || changedLeft) {
            ++out.clampedSpeeds;
            note(out, QStringLiteral("command for %1 robot %2: wheel speeds (right %3, left %4) rad/s taken as "
                                     "(%5, %6) (NaN -> 0, limit +-%7)")
                          .arg(teamWord(c.yellowteam()))
                          .arg(c.id())
                          .arg(c.wheel_right())
                          .arg(c.wheel_left())
                          .arg(w.right)
                          .arg(w.left)
                          .arg(kMaxWheelSpeed));
        }
        speeds[robot] = w;
    }
    for (const auto& [robot, w] : speeds) out.wheelSpeeds[teamIndex(roster.teamOf(robot))].emplace_back(robot, w);

    if (!packet.has_replace()) return out;
    const fira_message::sim_to_ref::Replacement& replace = packet.replace();
    const Field& field = scene.field;

    // Each replacement on its own: known robot, finite, inside the field.
    std::optional<BallState> ball;
    if (replace.has_ball()) {
        const auto& b = replace.ball();
        BallState s{b.x(), b.y(), b.vx(), b.vy()};
        if (!finite({s.x, s.y, s.vx, s.vy}) || std::hypot(s.vx, s.vy) > kMaxPlacedBallSpeed) {
            ++out.refusedBad;
            note(out, QStringLiteral("ball replacement (%1, %2) m, (%3, %4) m/s refused: non-finite, or faster "
                                     "than %5 m/s")
                          .arg(s.x)
                          .arg(s.y)
                          .arg(s.vx)
                          .arg(s.vy)
                          .arg(kMaxPlacedBallSpeed));
        } else if (!discInsideField(field, scene.ball_params.radius - kReplacementWallSlack, s.x, s.y)) {
            ++out.refusedOutside;
            note(out, QStringLiteral("ball replacement at (%1, %2) m refused: not inside the field").arg(s.x).arg(s.y));
        } else {
            ball = s;
        }
    }
    std::map<int, FirasimPlacement> placements;  // the last per robot
    std::map<int, bool> offs;
    for (const fira_message::sim_to_ref::RobotReplacement& r : replace.robots()) {
        const Team team = r.yellowteam() ? Team::Yellow : Team::Blue;
        const unsigned id = r.position().robot_id();
        const int robot = roster.robotIndex(team, id);
        if (robot < 0) {
            ++out.unknownRobots;
            note(out,
                 QStringLiteral("replacement of %1 robot %2: no such robot").arg(teamWord(r.yellowteam())).arg(id));
            continue;
        }
        if (!r.turnon()) {
            placements.erase(robot);
            offs[robot] = true;
            continue;
        }
        const double degrees = r.position().orientation();
        RobotState pose;
        pose.x = r.position().x();
        pose.y = r.position().y();
        pose.theta = std::remainder(degrees * kPi / 180.0, 2.0 * kPi);
        if (!finite({pose.x, pose.y, degrees})) {
            ++out.refusedBad;
            note(out, QStringLiteral("replacement of %1 robot %2 refused: non-finite pose")
                          .arg(teamWord(r.yellowteam()))
                          .arg(id));
            continue;
        }
        if (!robotInsideField(field, scene.robots[robot].params.side - 2.0 * kReplacementWallSlack, pose.x, pose.y,
                              pose.theta)) {
            ++out.refusedOutside;
            note(out, QStringLiteral("replacement of %1 robot %2 at (%3, %4) m, %5 deg refused: not wholly inside "
                                     "the field")
                          .arg(teamWord(r.yellowteam()))
                          .arg(id)
                          .arg(pose.x)
                          .arg(pose.y)
                          .arg(degrees));
            continue;
        }
        offs.erase(robot);
        placements[robot] = FirasimPlacement{robot, pose};
    }

    // The final poses, once the whole packet is applied: who is on the field where.
    const std::size_t n = scene.robots.size();
    std::vector<RobotState> poses(n);
    std::vector<char> present(n, 1);
    for (std::size_t i = 0; i < n; ++i) {
        poses[i] = i < current.robots.size() ? current.robots[i] : scene.robots[i].initial;
        if (i < onField.size()) present[i] = onField[i];
    }
    for (const auto& [robot, off] : offs) present[robot] = 0;
    for (const auto& [robot, p] : placements) {
        poses[robot] = p.pose;
        present[robot] = 1;
    }
    // Refusing one body puts it back where it was, which may make another
    // replacement overlap it: check again until nothing more is refused.
    // Refused here means blocked: the server may still apply it once the
    // bodies in the way have moved (a referee's next datagram).
    std::vector<char> refused(n, 0);
    bool ballRefused = false;
    for (bool changed = true; changed;) {
        changed = false;
        const BallState& finalBall = ball && !ballRefused ? *ball : current.ball;
        for (const auto& [robot, p] : placements) {
            if (refused[robot]) continue;
            const QString onto = firasimRobotOverlap(scene, robot, poses, present, finalBall);
            if (onto.isEmpty()) continue;
            refused[robot] = 1;
            changed = true;
            out.blocked.push_back({p, QStringLiteral("replacement of %1 robot %2 at (%3, %4) m refused: it would overlap %5")
                                          .arg(teamWord(roster.teamOf(robot) == Team::Yellow))
                                          .arg(roster.idOf(robot))
                                          .arg(p.pose.x)
                                          .arg(p.pose.y)
                                          .arg(onto)});
            // It stays where it is (and off the field if it was off).
            const std::size_t i = static_cast<std::size_t>(robot);
            poses[i] = i < current.robots.size() ? current.robots[i] : scene.robots[i].initial;
            present[i] = i < onField.size() ? onField[i] : 1;
        }
        if (!ball || ballRefused) continue;
        const QString onto = firasimBallOverlap(scene, *ball, poses, present);
        if (onto.isEmpty()) continue;
        out.blockedBall = *ball;
        out.blockedBallWhy =
            QStringLiteral("ball replacement at (%1, %2) m refused: it would overlap %3").arg(ball->x).arg(ball->y).arg(onto);
        ballRefused = true;
        changed = true;
    }
    if (ballRefused) ball.reset();
    out.ball = ball;
    for (const auto& [robot, p] : placements)
        if (!refused[robot]) out.robots.push_back(p);
    for (const auto& [robot, off] : offs)
        if (robot < static_cast<int>(onField.size()) && onField[robot]) out.turnOff.push_back(robot);
    return out;
}

}  // namespace vssim
