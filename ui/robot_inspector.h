// The selected robot at a glance: pose, velocities, wheels, motors and who
// drives it, from one snapshot. Fed by the main window; never reads the engine.
#pragma once

#include <QWidget>
#include <map>

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

}  // namespace vssim
