#include "realtime/simulation_fault.h"

#include <QStringList>

#include "io/printable_text.h"

namespace vssim {

namespace {

QString values(std::initializer_list<std::pair<const char*, double>> named, std::initializer_list<const char*> units) {
    QStringList parts;
    auto unit = units.begin();
    for (const auto& [name, value] : named)
        parts << QStringLiteral("%1 = %2 %3").arg(name).arg(value, 0, 'g', 6).arg(*unit++);
    return parts.join(", ");
}

}  // namespace

QString SimulationFault::message() const {
    return QStringLiteral("at t = %1 s, %2 has a non-finite state").arg(time, 0, 'g', 10).arg(bodyText);
}

std::optional<SimulationFault> findSimulationFault(const Simulation& simulation) {
    const WorldState& s = simulation.state();
    const int body = firstNonFiniteBody(s);
    if (body < 0) return std::nullopt;
    SimulationFault fault;
    fault.time = s.time;
    fault.body = body;
    if (body < static_cast<int>(s.robots.size())) {
        const RobotState& r = s.robots[body];
        fault.bodyText = QStringLiteral("robot \"%1\" (%2)")
                             .arg(printableText(QString::fromStdString(simulation.scene().robots[body].name), 40),
                                  values({{"x", r.x}, {"y", r.y}, {"theta", r.theta}, {"v", r.v}, {"omega", r.omega}},
                                         {"m", "m", "rad", "m/s", "rad/s"}));
    } else {
        const BallState& b = s.ball;
        fault.bodyText =
            QStringLiteral("the ball (%1)")
                .arg(values({{"x", b.x}, {"y", b.y}, {"vx", b.vx}, {"vy", b.vy}}, {"m", "m", "m/s", "m/s"}));
    }
    return fault;
}

}  // namespace vssim
