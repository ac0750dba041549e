#include "robot_inspector.h"

#include <QFormLayout>
#include <QLabel>
#include <QRegularExpression>
#include <cmath>

namespace vssim {

namespace {

// Form rows: key (objectName suffix) and the label shown beside the value.
struct Row {
    const char* key;
    const char* caption;
};
constexpr Row kRows[] = {
    {"name", "Robot"},
    {"team", "Team"},
    {"x", "x"},
    {"y", "y"},
    {"theta", "θ (heading)"},
    {"v", "v (forward)"},
    {"omega", "ω (yaw rate)"},
    {"wheelRight", "Wheel speed right"},
    {"wheelLeft", "Wheel speed left"},
    {"voltageRight", "Voltage right"},
    {"voltageLeft", "Voltage left"},
    {"currentRight", "Current right"},
    {"currentLeft", "Current left"},
    {"controller", "Driven by"},
};

QString number(double value, int decimals, const char* unit) {
    QString text = QString::asprintf("%.*f %s", decimals, value, unit);
    // A value that rounds to zero is shown as 0, not -0.000.
    if (text.startsWith('-') && text.indexOf(QRegularExpression("[1-9]")) < 0) text.remove(0, 1);
    return text;
}

}  // namespace

QString controllerText(const RobotControl& control) {
    switch (control.controller) {
        case RobotController::Tcp: return QStringLiteral("TCP client %1").arg(control.client);
        case RobotController::Manual:
            return control.tcpWhileManual ? QStringLiteral("manual (TCP voltages ignored)") : QStringLiteral("manual");
        case RobotController::None: break;
    }
    return QStringLiteral("nobody (0 V)");
}

RobotInspector::RobotInspector(QWidget* parent) : QWidget(parent) {
    auto* form = new QFormLayout(this);
    for (const Row& row : kRows) {
        auto* value = new QLabel(this);
        value->setObjectName(QStringLiteral("inspector.") + row.key);
        value->setTextInteractionFlags(Qt::TextSelectableByMouse);
        form->addRow(QString::fromUtf8(row.caption), value);
        values_[row.key] = value;
    }
    showRobot(Snapshot{}, -1);
}

void RobotInspector::set(const QString& key, const QString& text) { values_.at(key)->setText(text); }

void RobotInspector::showRobot(const Snapshot& s, int robot) {
    const auto index = static_cast<std::size_t>(robot);
    if (robot < 0 || index >= s.robots.size()) {
        // Each label set once: a label set to another text and back at every
        // refresh would be repainted each time (and the window with it).
        for (auto& [key, label] : values_)
            label->setText(key == QLatin1String("name") ? QStringLiteral("no robot selected") : QStringLiteral("–"));
        return;
    }
    if (s.scene && index < s.scene->robots.size()) {
        const RobotSpec& spec = s.scene->robots[index];
        set("name", QString::fromStdString(spec.name));
        set("team", spec.team == Team::Yellow ? QStringLiteral("yellow") : QStringLiteral("blue"));
    } else {
        set("name", QStringLiteral("robot %1").arg(robot));
        set("team", QStringLiteral("–"));
    }
    const RobotState& state = s.robots[index];
    set("x", number(state.x, 3, "m"));
    set("y", number(state.y, 3, "m"));
    // The engine keeps theta unwrapped (it counts turns); shown in (-180, 180] degrees.
    set("theta", number(std::remainder(state.theta, 2.0 * M_PI) * 180.0 / M_PI, 1, "deg"));
    set("v", number(state.v, 3, "m/s"));
    set("omega", number(state.omega, 2, "rad/s"));

    const RobotOutputs outputs = index < s.outputs.size() ? s.outputs[index] : RobotOutputs{};
    set("wheelRight", number(outputs.wheel_speed_right, 1, "rad/s"));
    set("wheelLeft", number(outputs.wheel_speed_left, 1, "rad/s"));
    set("currentRight", number(outputs.current_right, 3, "A"));
    set("currentLeft", number(outputs.current_left, 3, "A"));

    const Voltages volts = index < s.voltages.size() ? s.voltages[index] : Voltages{};
    set("voltageRight", number(volts.right, 2, "V"));
    set("voltageLeft", number(volts.left, 2, "V"));

    set("controller", drivenByText(s, robot));
}

std::optional<TeamControl> teamControlOf(const Snapshot& s, int robot) {
    if (!s.scene || robot < 0 || robot >= static_cast<int>(s.scene->robots.size())) return std::nullopt;
    return s.scene->robots[static_cast<std::size_t>(robot)].team == Team::Yellow ? s.gameSettings.yellow
                                                                                 : s.gameSettings.blue;
}

QString drivenByText(const Snapshot& s, int robot) {
    const auto index = static_cast<std::size_t>(robot);
    if (robot < 0 || index >= s.control.size()) return QStringLiteral("not known (watching a server)");
    const RobotControl& control = s.control[index];
    if (control.controller == RobotController::Manual) return controllerText(control);
    // The Match ignores TCP commands for a built-in or idle team's robots.
    switch (teamControlOf(s, robot).value_or(TeamControl::Remote)) {
        case TeamControl::Builtin: return QStringLiteral("the built-in team");
        case TeamControl::Idle: return QStringLiteral("nobody (idle team: 0 V)");
        case TeamControl::Remote: break;
    }
    const Voltages volts = index < s.voltages.size() ? s.voltages[index] : Voltages{};
    if (control.controller == RobotController::None && (volts.right != 0.0 || volts.left != 0.0))
        return QStringLiteral("the scene's own commands");
    return controllerText(control);
}

QString letGoText(const Snapshot& s, int robot) {
    const std::optional<TeamControl> control = teamControlOf(s, robot);
    if (!control) return QObject::tr("Let go (Esc)");  // no robot selected or driven: nothing to go back to yet
    switch (*control) {
        case TeamControl::Builtin: return QObject::tr("Let go (Esc): back to the built-in team");
        case TeamControl::Idle: return QObject::tr("Let go (Esc): back to 0 V (idle team)");
        case TeamControl::Remote: break;
    }
    return QObject::tr("Let go (Esc): back to TCP control");
}

}  // namespace vssim
