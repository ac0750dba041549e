// Editing a scene's parameters (docs/scenes.md): the simulation settings, the
// field (its type, which sets the official dimensions, and each dimension),
// the ball and every robot's physical parameters. Poses,
// velocities and commands are not edited here (the app drags robots).
//
// The dialog edits a working copy: each widget writes only its own field
// when the user changes it, so accepting unchanged returns the scene as it
// came, to the last bit, and Cancel discards everything. Every spin box
// offers the range the scene reader accepts (scene_value_ranges.h), and
// accept() refuses what the reader would refuse.
#pragma once

#include <QDialog>
#include <QString>
#include <functional>
#include <vector>

#include "scene_value_ranges.h"
#include "vssim/scene.h"

class QComboBox;
class QDoubleSpinBox;
class QLineEdit;
class QListWidget;
class QWidget;

namespace vssim {

class SceneParametersDialog : public QDialog {
    Q_OBJECT
public:
    explicit SceneParametersDialog(const Scene& scene, QWidget* parent = nullptr);

    // The edited scene (the working copy); use it once exec() returned Accepted.
    Scene scene() const { return scene_; }

    // Why the edited scene cannot be accepted (names the robot or the body
    // and the problem), or an empty string when it can. accept() checks this.
    QString validationError() const;

public slots:
    // Closes with Accepted if validationError() is empty; otherwise shows it
    // in a warning and stays open.
    void accept() override;

    // The selected robot's right motor becomes its left motor too.
    void copyRightToLeft();
    // Every robot gets the selected robot's parameters (not its name, team or pose).
    void copyToAllRobots();

private:
    // A spin box showing `value`, with the unit as `suffix` and the range the
    // reader checks (scene_value_ranges.h); onEdit gets each changed value.
    QDoubleSpinBox* spinBox(const QString& objectName, const QString& suffix, int decimals, const AllowedRange& range,
                            double value, const std::function<void(double)>& onEdit);
    // A spin box bound to one parameter of the selected robot.
    QDoubleSpinBox* robotSpinBox(const QString& objectName, const QString& suffix, int decimals,
                                 const AllowedRange& range, std::function<double&(RobotParams&)> parameter);

    QWidget* simulationTab();
    QWidget* fieldTab();
    QWidget* ballTab();
    QWidget* robotsTab();

    void selectRobot(int index);  // shows robot `index` (or none: -1) in the editor
    void refreshRobotEditor();    // the editor's widgets from the working copy
    void refreshRobotListItem(int index);
    RobotSpec* selectedRobot();
    void updateRestitutionEnabled();
    // The field tab's boxes from the working copy's field (no edits), and
    // the box type's keys disabled.
    void refreshFieldEditor();
    // The working copy's field rebuilt from dimensions (walls, posts, ...).
    void setFieldDimensions(const FieldDimensions& dimensions);

    Scene scene_;  // the working copy
    int selected_ = -1;

    QComboBox* fieldType_ = nullptr;
    struct FieldBinding {
        QDoubleSpinBox* box;
        double FieldDimensions::*dimension;
        bool box_type_takes_it;  // a box (FieldType::Box) has this dimension
    };
    std::vector<FieldBinding> fieldBindings_;
    QComboBox* collisionModel_ = nullptr;
    QDoubleSpinBox* restitution_ = nullptr;
    QListWidget* robotList_ = nullptr;
    QWidget* robotEditor_ = nullptr;
    QLineEdit* robotName_ = nullptr;
    QComboBox* robotTeam_ = nullptr;
    struct RobotBinding {
        QDoubleSpinBox* box;
        std::function<double&(RobotParams&)> parameter;
    };
    std::vector<RobotBinding> robotBindings_;
};

}  // namespace vssim
