// The selected robot at a glance: pose, velocities, wheels, motors and who
// drives it, from one snapshot. Fed by the main window; never reads the engine.
#pragma once

#include <QWidget>
#include <map>
#include <optional>

#include "realtime/snapshot.h"

class QLabel;

namespace vssim {

class RobotInspector : public QWidget {
    Q_OBJECT
public:
    explicit RobotInspector(QWidget* parent = nullptr);

    // Shows robot `robot` of the snapshot; -1 (or an index out of range):
    // "no robot selected" and every value blank.
    void showRobot(const Snapshot& s, int robot);

private:
    // The value labels by key ("name", "team", "x", ...): objectName "inspector.<key>".
    std::map<QString, QLabel*> values_;

    void set(const QString& key, const QString& text);
};

// Who drives a robot, as the inspector says it: "TCP client N",
// "manual (TCP voltages ignored)", "manual" or "nobody (0 V)".
QString controllerText(const RobotControl& control);

// The team control (built-in, remote or idle) of robot `robot`'s team in the
// snapshot; nullopt when the snapshot has no scene or no such robot.
std::optional<TeamControl> teamControlOf(const Snapshot& s, int robot);

// Who drives robot `robot` of the snapshot, as the inspector's "Driven by"
// says it: a person ("manual ..."), the built-in team, nobody for an idle
// team, else controllerText() or "the scene's own commands" (nobody's, yet
// with voltages); "not known (watching a server)" without control data.
QString drivenByText(const Snapshot& s, int robot);

// The Drive by hand dock's button: what robot `robot` goes back to when a
// person lets go of it ("Let go (Esc): back to the built-in team", "... back
// to TCP control", "... back to 0 V (idle team)"); the TCP text when no
// robot is known.
QString letGoText(const Snapshot& s, int robot);

}  // namespace vssim
