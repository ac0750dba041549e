#include "scene_parameters_dialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMessageBox>
#include <QPushButton>
#include <QSet>
#include <QSignalBlocker>
#include <QTabWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cstring>

#include "io/scene_io.h"
#include "vssim/field.h"

namespace vssim {

namespace {

// A combo box whose items carry the enum values, showing their scene-file names.
template <typename Enum>
QComboBox* enumComboBox(const QString& objectName, std::initializer_list<Enum> values, Enum current,
                        QString (*name)(Enum)) {
    auto* box = new QComboBox;
    box->setObjectName(objectName);
    for (Enum value : values) box->addItem(name(value), static_cast<int>(value));
    box->setCurrentIndex(box->findData(static_cast<int>(current)));
    return box;
}

template <typename Enum>
Enum enumOf(const QComboBox* box) {
    return static_cast<Enum>(box->currentData().toInt());
}

QString number(double x) { return QString::number(x, 'g', 6); }

}  // namespace

SceneParametersDialog::SceneParametersDialog(const Scene& scene, QWidget* parent) : QDialog(parent), scene_(scene) {
    setWindowTitle(tr("Scene parameters"));
    auto* tabs = new QTabWidget;
    tabs->setObjectName("tabs");
    tabs->addTab(simulationTab(), tr("Simulation"));
    tabs->addTab(fieldTab(), tr("Field"));
    tabs->addTab(ballTab(), tr("Ball"));
    tabs->addTab(robotsTab(), tr("Robots"));

    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
    connect(buttons, &QDialogButtonBox::accepted, this, &SceneParametersDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &SceneParametersDialog::reject);

    auto* layout = new QVBoxLayout(this);
    layout->addWidget(tabs);
    layout->addWidget(buttons);
}

QDoubleSpinBox* SceneParametersDialog::spinBox(const QString& objectName, const QString& suffix, int decimals,
                                               const AllowedRange& range, double value,
                                               const std::function<void(double)>& onEdit) {
    auto* box = new QDoubleSpinBox;
    box->setObjectName(objectName);
    box->setDecimals(decimals);  // before the range, which is rounded to it
    const SpinInterval interval = spinInterval(range, decimals);
    box->setRange(interval.minimum, interval.maximum);
    box->setSuffix(suffix);
    box->setStepType(QAbstractSpinBox::AdaptiveDecimalStepType);
    box->setValue(value);
    // Connected after the value is shown: only the user's edits (and tests'
    // setValue) reach the working copy, so untouched values keep every bit.
    connect(box, &QDoubleSpinBox::valueChanged, this, onEdit);
    return box;
}

QDoubleSpinBox* SceneParametersDialog::robotSpinBox(const QString& objectName, const QString& suffix, int decimals,
                                                    const AllowedRange& range,
                                                    std::function<double&(RobotParams&)> parameter) {
    QDoubleSpinBox* box = spinBox(objectName, suffix, decimals, range, 0.0, [this, parameter](double value) {
        if (RobotSpec* robot = selectedRobot()) parameter(robot->params) = value;
    });
    robotBindings_.push_back({box, std::move(parameter)});
    return box;
}

QWidget* SceneParametersDialog::simulationTab() {
    SimulationSettings& s = scene_.simulation;
    auto* integrator = enumComboBox("simulation.integrator", {Integrator::Euler, Integrator::Rk4, Integrator::Exact},
                                    s.integrator, &integratorName);
    connect(integrator, &QComboBox::currentIndexChanged, this,
            [this, integrator] { scene_.simulation.integrator = enumOf<Integrator>(integrator); });
    collisionModel_ = enumComboBox("simulation.collision_model", {CollisionModel::Paper, CollisionModel::Impulse},
                                   s.collision_model, &collisionModelName);
    connect(collisionModel_, &QComboBox::currentIndexChanged, this, [this] {
        scene_.simulation.collision_model = enumOf<CollisionModel>(collisionModel_);
        updateRestitutionEnabled();
    });
    auto* dt = spinBox("simulation.dt", " s", 6, scene_limits::kTimeStep, s.dt,
                       [this](double v) { scene_.simulation.dt = v; });
    restitution_ = spinBox("simulation.restitution", QString(), 3, scene_limits::kUnitInterval, s.restitution,
                           [this](double v) { scene_.simulation.restitution = v; });
    restitution_->setToolTip(tr("Coefficient of restitution of the impulse model; the paper model ignores it"));
    updateRestitutionEnabled();

    auto* tab = new QWidget;
    auto* form = new QFormLayout(tab);
    form->addRow(tr("Integrator"), integrator);
    form->addRow(tr("Time step"), dt);
    form->addRow(tr("Collision model"), collisionModel_);
    form->addRow(tr("Restitution"), restitution_);
    return tab;
}

QWidget* SceneParametersDialog::fieldTab() {
    // The type sets every dimension to its official value; each box then
    // changes one dimension, and the walls are rebuilt around the origin.
    fieldType_ = new QComboBox;
    fieldType_->setObjectName("field.type");
    const std::pair<FieldType, QString> types[] = {{FieldType::Box, tr("Box (closed, no goals)")},
                                                   {FieldType::Vsss3v3, tr("VSSS 3 vs 3 (1.50 × 1.30 m)")},
                                                   {FieldType::Vsss5v5, tr("VSSS 5 vs 5 (2.20 × 1.80 m)")}};
    for (const auto& [type, label] : types) fieldType_->addItem(label, static_cast<int>(type));
    fieldType_->setCurrentIndex(fieldType_->findData(static_cast<int>(scene_.field.dimensions.type)));
    connect(fieldType_, &QComboBox::currentIndexChanged, this, [this] {
        setFieldDimensions(officialDimensions(enumOf<FieldType>(fieldType_)));
        refreshFieldEditor();
    });

    const std::pair<const char*, const char*> labels[] = {
        {"length", QT_TR_NOOP("Length (along x, goal line to goal line)")},
        {"width", QT_TR_NOOP("Width (along y)")},
        {"goal_width", QT_TR_NOOP("Goal width")},
        {"goal_depth", QT_TR_NOOP("Goal depth")},
        {"corner_leg", QT_TR_NOOP("Corner triangles' legs")},
        {"centre_radius", QT_TR_NOOP("Centre circle radius")},
        {"goal_area_depth", QT_TR_NOOP("Goal area depth")},
        {"goal_area_width", QT_TR_NOOP("Goal area width")},
        {"penalty_mark", QT_TR_NOOP("Penalty mark from the goal line")},
        {"free_ball_x", QT_TR_NOOP("Free-ball marks from the goal line")},
        {"free_ball_y", QT_TR_NOOP("Free-ball marks from the long axis")},
    };
    auto* tab = new QWidget;
    auto* form = new QFormLayout(tab);
    form->addRow(tr("Type"), fieldType_);
    for (const FieldDimensionKey& k : kFieldDimensionKeys) {
        double FieldDimensions::*dimension = k.dimension;
        QDoubleSpinBox* box =
            spinBox(QStringLiteral("field.%1").arg(QLatin1String(k.key)), " m", 3, k.range,
                    scene_.field.dimensions.*dimension, [this, dimension](double v) {
                        FieldDimensions d = scene_.field.dimensions;
                        d.*dimension = v;
                        // A box too small for its centre circle has none (as in a scene file).
                        if (d.type == FieldType::Box && !(d.centre_radius < 0.5 * std::min(d.length, d.width)))
                            d.centre_radius = boxDimensions(d.length, d.width).centre_radius;
                        setFieldDimensions(d);
                    });
        fieldBindings_.push_back({box, k.dimension, k.box});
        QString label = tr("Length");
        for (const auto& [key, text] : labels)
            if (std::strcmp(key, k.key) == 0) label = tr(text);
        form->addRow(label, box);
    }
    auto* note = new QLabel(
        tr("The type sets the official dimensions (docs/scenes.md); a box is a closed rectangle without goals, "
           "corner triangles or goal areas."));
    note->setWordWrap(true);
    form->addRow(note);
    refreshFieldEditor();
    return tab;
}

void SceneParametersDialog::setFieldDimensions(const FieldDimensions& dimensions) {
    scene_.field = makeField(dimensions);
}

void SceneParametersDialog::refreshFieldEditor() {
    const FieldDimensions& d = scene_.field.dimensions;
    for (FieldBinding& binding : fieldBindings_) {
        const QSignalBlocker block(binding.box);  // showing a value is not editing it
        binding.box->setValue(d.*binding.dimension);
        binding.box->setEnabled(d.type != FieldType::Box || binding.box_type_takes_it);
    }
}

QWidget* SceneParametersDialog::ballTab() {
    BallParams& b = scene_.ball_params;
    auto* mass = spinBox("ball.mass", " kg", 4, scene_limits::kBallMass, b.mass,
                         [this](double v) { scene_.ball_params.mass = v; });
    auto* radius = spinBox("ball.radius", " m", 5, scene_limits::kBallRadius, b.radius,
                           [this](double v) { scene_.ball_params.radius = v; });
    auto* friction = spinBox("ball.friction", " N s/m", 5, scene_limits::kBallFriction, b.friction,
                             [this](double v) { scene_.ball_params.friction = v; });
    auto* tab = new QWidget;
    auto* form = new QFormLayout(tab);
    form->addRow(tr("Mass"), mass);
    form->addRow(tr("Radius"), radius);
    form->addRow(tr("Viscous friction"), friction);
    return tab;
}

QWidget* SceneParametersDialog::robotsTab() {
    robotList_ = new QListWidget;
    robotList_->setObjectName("robots.list");
    robotList_->setMinimumWidth(robotList_->fontMetrics().horizontalAdvance("yellow10 (yellow)") + 32);
    for (std::size_t i = 0; i < scene_.robots.size(); ++i) {
        robotList_->addItem(QString());
        refreshRobotListItem(static_cast<int>(i));
    }

    robotName_ = new QLineEdit;
    robotName_->setObjectName("robot.name");
    connect(robotName_, &QLineEdit::textEdited, this, [this](const QString& text) {
        if (RobotSpec* robot = selectedRobot()) robot->name = text.toStdString();
        refreshRobotListItem(selected_);
    });
    robotTeam_ = enumComboBox("robot.team", {Team::Yellow, Team::Blue}, Team::Yellow, &teamName);
    connect(robotTeam_, &QComboBox::currentIndexChanged, this, [this] {
        if (RobotSpec* robot = selectedRobot()) robot->team = enumOf<Team>(robotTeam_);
        refreshRobotListItem(selected_);
    });

    using P = RobotParams;
    auto member = [](double P::*field) { return [field](P& p) -> double& { return p.*field; }; };
    auto* body = new QFormLayout;
    body->addRow(tr("Name"), robotName_);
    body->addRow(tr("Team"), robotTeam_);
    body->addRow(tr("Side"), robotSpinBox("robot.side", " m", 4, scene_limits::kRobotSide, member(&P::side)));
    body->addRow(tr("Mass"), robotSpinBox("robot.mass", " kg", 4, scene_limits::kRobotMass, member(&P::mass)));
    QDoubleSpinBox* inertia =
        robotSpinBox("robot.inertia", " kg m²", 9, scene_limits::kRobotInertia, member(&P::inertia));
    inertia->setToolTip(tr("Yaw inertia about the centre of mass; a uniform cube has mass × side² / 6"));
    body->addRow(tr("Yaw inertia"), inertia);
    body->addRow(tr("Wheel base"),
                 robotSpinBox("robot.wheel_base", " m", 4, scene_limits::kWheelBase, member(&P::wheel_base)));
    body->addRow(tr("Linear friction"), robotSpinBox("robot.friction_linear", " N s/m", 5,
                                                     scene_limits::kLinearFriction, member(&P::friction_linear)));
    body->addRow(tr("Angular friction"), robotSpinBox("robot.friction_angular", " N m s/rad", 7,
                                                      scene_limits::kAngularFriction, member(&P::friction_angular)));
    body->addRow(tr("Max voltage"),
                 robotSpinBox("robot.max_voltage", " V", 3, scene_limits::kMaxVoltage, member(&P::max_voltage)));

    // The two motors side by side: one row per parameter, right then left.
    struct MotorRow {
        const char* label;
        const char* key;
        const char* suffix;
        int decimals;
        AllowedRange range;
        double MotorParams::*field;
    };
    const MotorRow rows[] = {
        {QT_TR_NOOP("Wheel radius"), "wheel_radius", " m", 4, scene_limits::kWheelRadius, &MotorParams::wheel_radius},
        {QT_TR_NOOP("Resistance"), "resistance", " ohm", 3, scene_limits::kResistance, &MotorParams::resistance},
        {QT_TR_NOOP("K (back-EMF = torque)"), "k", " V s/rad", 4, scene_limits::kMotorConstant, &MotorParams::k},
        {QT_TR_NOOP("Rotor inertia"), "rotor_inertia", " kg m²", 9, scene_limits::kRotorInertia,
         &MotorParams::rotor_inertia},
        {QT_TR_NOOP("Friction"), "friction", " N m s/rad", 7, scene_limits::kMotorFriction, &MotorParams::friction},
    };
    const std::pair<const char*, MotorParams P::*> sides[] = {{"right", &P::right}, {"left", &P::left}};
    auto* motors = new QGroupBox(tr("Motors (values at the wheel)"));
    auto* grid = new QGridLayout(motors);
    grid->addWidget(new QLabel(tr("Right")), 0, 1, Qt::AlignHCenter);
    grid->addWidget(new QLabel(tr("Left")), 0, 2, Qt::AlignHCenter);
    int row = 1;
    for (const MotorRow& r : rows) {
        grid->addWidget(new QLabel(tr(r.label)), row, 0);
        int column = 1;
        for (const auto& [side, motor] : sides) {
            const QString name = QStringLiteral("robot.%1.%2").arg(QLatin1String(side), QLatin1String(r.key));
            auto parameter = [motor = motor, field = r.field](P& p) -> double& { return (p.*motor).*field; };
            grid->addWidget(robotSpinBox(name, r.suffix, r.decimals, r.range, parameter), row, column++);
        }
        ++row;
    }

    auto* copyRight = new QPushButton(tr("Copy right to left"));
    copyRight->setObjectName("robot.copy_right_to_left");
    connect(copyRight, &QPushButton::clicked, this, &SceneParametersDialog::copyRightToLeft);
    auto* copyAll = new QPushButton(tr("Copy to all robots"));
    copyAll->setObjectName("robot.copy_to_all");
    copyAll->setToolTip(tr("Give every robot this robot's parameters (names, teams and poses stay)"));
    connect(copyAll, &QPushButton::clicked, this, &SceneParametersDialog::copyToAllRobots);
    auto* buttons = new QHBoxLayout;
    buttons->addWidget(copyRight);
    buttons->addWidget(copyAll);
    buttons->addStretch();

    robotEditor_ = new QWidget;
    robotEditor_->setObjectName("robot.editor");
    auto* editor = new QVBoxLayout(robotEditor_);
    editor->addLayout(body);
    editor->addWidget(motors);
    editor->addLayout(buttons);
    editor->addWidget(
        new QLabel(tr("Initial poses are not edited here: move the bodies on the field, then File > Save scene as... "
                      "writes them as the initial poses.")));
    editor->addStretch();

    connect(robotList_, &QListWidget::currentRowChanged, this, &SceneParametersDialog::selectRobot);
    auto* tab = new QWidget;
    auto* layout = new QHBoxLayout(tab);
    layout->addWidget(robotList_, 1);
    layout->addWidget(robotEditor_, 3);
    if (scene_.robots.empty())
        selectRobot(-1);
    else
        robotList_->setCurrentRow(0);
    return tab;
}

void SceneParametersDialog::selectRobot(int index) {
    selected_ = index;
    robotEditor_->setEnabled(selectedRobot() != nullptr);
    refreshRobotEditor();
}

void SceneParametersDialog::refreshRobotEditor() {
    RobotSpec* robot = selectedRobot();
    if (!robot) return;
    // Showing values is not editing them: no signal may write back.
    const QSignalBlocker blockName(robotName_), blockTeam(robotTeam_);
    robotName_->setText(QString::fromStdString(robot->name));
    robotTeam_->setCurrentIndex(robotTeam_->findData(static_cast<int>(robot->team)));
    for (RobotBinding& binding : robotBindings_) {
        const QSignalBlocker block(binding.box);
        binding.box->setValue(binding.parameter(robot->params));
    }
}

void SceneParametersDialog::refreshRobotListItem(int index) {
    if (index < 0 || index >= static_cast<int>(scene_.robots.size())) return;
    const RobotSpec& robot = scene_.robots[index];
    const QString name = robot.name.empty() ? tr("(no name)") : QString::fromStdString(robot.name);
    robotList_->item(index)->setText(QStringLiteral("%1 (%2)").arg(name, teamName(robot.team)));
}

RobotSpec* SceneParametersDialog::selectedRobot() {
    if (selected_ < 0 || selected_ >= static_cast<int>(scene_.robots.size())) return nullptr;
    return &scene_.robots[selected_];
}

void SceneParametersDialog::updateRestitutionEnabled() {
    restitution_->setEnabled(scene_.simulation.collision_model == CollisionModel::Impulse);
}

void SceneParametersDialog::copyRightToLeft() {
    RobotSpec* robot = selectedRobot();
    if (!robot) return;
    robot->params.left = robot->params.right;
    refreshRobotEditor();
}

void SceneParametersDialog::copyToAllRobots() {
    RobotSpec* robot = selectedRobot();
    if (!robot) return;
    const RobotParams params = robot->params;
    for (RobotSpec& other : scene_.robots) other.params = params;
    refreshRobotEditor();
}

QString SceneParametersDialog::validationError() const {
    const Field& field = scene_.field;
    const FieldProblem problem = checkFieldDimensions(field.dimensions);
    if (problem.key)
        return tr("The field's %1: %2.").arg(QLatin1String(problem.key), QString::fromUtf8(problem.reason));
    const QString fieldSize = tr("the %1 × %2 m field").arg(number(field.length), number(field.width));
    QSet<QString> names;
    for (std::size_t i = 0; i < scene_.robots.size(); ++i) {
        const QString name = QString::fromStdString(scene_.robots[i].name);
        if (name.isEmpty()) return tr("Robot %1 in the list has no name.").arg(i + 1);
        if (names.contains(name)) return tr("Two robots are named \"%1\": names must be unique.").arg(name);
        names.insert(name);
    }
    const BallState& ball = scene_.ball;
    if (!discInsideField(field, scene_.ball_params.radius, ball.x, ball.y))
        return tr("The ball (radius %1 m, at (%2, %3) m) would be outside %4.")
            .arg(number(scene_.ball_params.radius), number(ball.x), number(ball.y), fieldSize);
    for (const RobotSpec& robot : scene_.robots)
        if (!robotInsideField(field, robot.params.side, robot.initial.x, robot.initial.y, robot.initial.theta))
            return tr("Robot \"%1\" (side %2 m, at (%3, %4) m) would be outside %5.")
                .arg(QString::fromStdString(robot.name), number(robot.params.side), number(robot.initial.x),
                     number(robot.initial.y), fieldSize);
    // Whatever else the scene reader refuses (e.g. a comma in a name), in its words.
    QString error;
    if (!parseScene(sceneToJson(scene_), &error)) return tr("The scene file reader refuses this scene: %1").arg(error);
    return {};
}

void SceneParametersDialog::accept() {
    const QString error = validationError();
    if (!error.isEmpty()) {
        QMessageBox::warning(this, tr("Scene parameters"), error);
        return;
    }
    QDialog::accept();
}

}  // namespace vssim
