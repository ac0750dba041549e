// The scene parameters dialog: a faithful working copy (unchanged in,
// unchanged out; one edit changes one field), the copy buttons, validation
// on accept, and spin-box ranges that are exactly what the scene reader
// accepts (docs/scenes.md).
#include <QtTest>

#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLineEdit>
#include <QListWidget>
#include <QMessageBox>
#include <QPushButton>
#include <QTimer>
#include <cmath>
#include <functional>

#include "io/scene_io.h"
#include "scene_parameters_dialog.h"

using namespace vssim;

namespace {

// The kick-off's bodies without its game: the dialog has no game controls
// yet, and some of its choices (a step longer than the game's tick, a box
// field) make a scene with a referee unreadable; these tests are about the
// physics it edits.
Scene kickoff() {
    QString error;
    std::optional<Scene> scene = loadSceneFile(":/scenes/kickoff_3v3.json", &error);
    if (!scene) qFatal("cannot load the kick-off scene: %s", qPrintable(error));
    scene->game = GameSettings{};
    return *scene;
}

QJsonObject json(const Scene& scene) { return QJsonDocument::fromJson(sceneToJson(scene)).object(); }

bool readerAccepts(const Scene& scene) {
    QString error;
    return parseScene(sceneToJson(scene), &error).has_value();
}

template <typename W>
W* child(const QObject& dialog, const char* name) {
    W* widget = dialog.findChild<W*>(QLatin1String(name));
    if (!widget) qFatal("no widget named %s", name);
    return widget;
}

void selectRobot(const SceneParametersDialog& dialog, int index) {
    child<QListWidget>(dialog, "robots.list")->setCurrentRow(index);
}

// robots[index].params from a scene's JSON.
QJsonObject robotParamsJson(const QJsonObject& scene, int index) {
    return scene["robots"].toArray()[index].toObject()["params"].toObject();
}

// Replaces the user's edit: types `text` into the line edit as a user would.
void typeInto(QLineEdit* edit, const QString& text) {
    edit->selectAll();
    QTest::keyClick(edit, Qt::Key_Backspace);
    QTest::keyClicks(edit, text);
}

}  // namespace

class TestSceneDialog : public QObject {
    Q_OBJECT
private slots:
    void acceptingUnchangedReturnsTheSameScene();
    void untouchedValuesKeepEveryBit();
    void oneEditChangesOneField();
    void simulationSettings();
    void copyRightToLeft();
    void copyToAllRobots();
    void restitutionOnlyForImpulse();
    void robotOutsideShrunkFieldIsRefused();
    void ballOutsideIsRefused();
    void namesMustBeUniqueAndNonEmpty();
    void spinRangesAreTheReaders_data();
    void spinRangesAreTheReaders();
    void fieldTypeSetsOfficialDimensions();
    void inconsistentFieldIsRefused();
};

void TestSceneDialog::acceptingUnchangedReturnsTheSameScene() {
    const Scene original = kickoff();
    SceneParametersDialog dialog(original);
    QCOMPARE(dialog.validationError(), QString());
    dialog.accept();
    QCOMPARE(dialog.result(), int(QDialog::Accepted));
    QCOMPARE(sceneToJson(dialog.scene()), sceneToJson(original));
}

void TestSceneDialog::untouchedValuesKeepEveryBit() {
    // Values that the spin boxes cannot show exactly survive being shown.
    Scene original = kickoff();
    original.robots[0].params.right.rotor_inertia = 1.234567891234e-10;
    original.robots[0].params.mass = 0.1234567891;
    original.ball_params.friction = 0.0123456789;
    original.field = makeRectangularField(1.5000001, 1.3000002);
    SceneParametersDialog dialog(original);
    for (int i = 0; i < int(original.robots.size()); ++i) selectRobot(dialog, i);
    selectRobot(dialog, 0);
    QCOMPARE(sceneToJson(dialog.scene()), sceneToJson(original));
}

void TestSceneDialog::oneEditChangesOneField() {
    const Scene original = kickoff();
    SceneParametersDialog dialog(original);
    selectRobot(dialog, 2);
    auto* resistance = child<QDoubleSpinBox>(dialog, "robot.right.resistance");
    QCOMPARE(resistance->value(), original.robots[2].params.right.resistance);
    resistance->setValue(13.5);
    const Scene edited = dialog.scene();
    QCOMPARE(edited.robots[2].params.right.resistance, 13.5);
    // Put the one value back: everything else must be as it was.
    QJsonObject back = json(edited);
    QJsonArray robots = back["robots"].toArray();
    QJsonObject robot = robots[2].toObject();
    QJsonObject params = robot["params"].toObject();
    QJsonObject right = params["right"].toObject();
    QCOMPARE(right["resistance"].toDouble(), 13.5);
    right["resistance"] = original.robots[2].params.right.resistance;
    params["right"] = right;
    robot["params"] = params;
    robots[2] = robot;
    back["robots"] = robots;
    QCOMPARE(back, json(original));
}

void TestSceneDialog::simulationSettings() {
    const Scene original = kickoff();
    SceneParametersDialog dialog(original);
    auto* integrator = child<QComboBox>(dialog, "simulation.integrator");
    QCOMPARE(integrator->currentText(), QString("exact"));  // the kick-off's
    integrator->setCurrentIndex(integrator->findText("rk4"));
    child<QDoubleSpinBox>(dialog, "simulation.dt")->setValue(0.002);
    child<QDoubleSpinBox>(dialog, "field.length")->setValue(1.8);
    const Scene edited = dialog.scene();
    QCOMPARE(edited.simulation.integrator, Integrator::Rk4);
    QCOMPARE(edited.simulation.dt, 0.002);
    QCOMPARE(edited.field.length, 1.8);
    QCOMPARE(edited.field.width, original.field.width);
    QCOMPARE(edited.field.dimensions.type, FieldType::Vsss3v3);  // the rest of the official field stays
    QCOMPARE(edited.field.dimensions.goal_width, 0.40);
    FieldDimensions d = original.field.dimensions;
    d.length = 1.8;
    const Field rebuilt = makeField(d);  // the walls moved too
    QCOMPARE(edited.field.walls.size(), rebuilt.walls.size());
    for (std::size_t i = 0; i < rebuilt.walls.size(); ++i) {
        QVERIFY(edited.field.walls[i].a == rebuilt.walls[i].a);
        QVERIFY(edited.field.walls[i].b == rebuilt.walls[i].b);
    }
}

void TestSceneDialog::copyRightToLeft() {
    const Scene original = kickoff();
    SceneParametersDialog dialog(original);
    selectRobot(dialog, 1);
    child<QDoubleSpinBox>(dialog, "robot.right.resistance")->setValue(10.0);
    child<QDoubleSpinBox>(dialog, "robot.right.k")->setValue(0.12);
    child<QDoubleSpinBox>(dialog, "robot.right.wheel_radius")->setValue(0.03);
    child<QPushButton>(dialog, "robot.copy_right_to_left")->click();
    const Scene edited = dialog.scene();
    const QJsonObject params = robotParamsJson(json(edited), 1);
    QCOMPARE(params["left"], params["right"]);
    QCOMPARE(edited.robots[1].params.left.resistance, 10.0);
    QCOMPARE(child<QDoubleSpinBox>(dialog, "robot.left.k")->value(), 0.12);  // the editor shows it
    QCOMPARE(child<QDoubleSpinBox>(dialog, "robot.left.wheel_radius")->value(), 0.03);
    for (int i : {0, 2, 3, 4, 5}) QCOMPARE(robotParamsJson(json(edited), i), robotParamsJson(json(original), i));
}

void TestSceneDialog::copyToAllRobots() {
    const Scene original = kickoff();
    SceneParametersDialog dialog(original);
    selectRobot(dialog, 3);
    child<QDoubleSpinBox>(dialog, "robot.mass")->setValue(0.25);
    child<QDoubleSpinBox>(dialog, "robot.left.friction")->setValue(2e-4);
    child<QPushButton>(dialog, "robot.copy_to_all")->click();
    const Scene edited = dialog.scene();
    const QJsonObject all = json(edited), before = json(original);
    for (int i = 0; i < int(edited.robots.size()); ++i) {
        QCOMPARE(robotParamsJson(all, i), robotParamsJson(all, 3));
        // Name, team and pose stay.
        QJsonObject robot = all["robots"].toArray()[i].toObject(), old = before["robots"].toArray()[i].toObject();
        robot.remove("params");
        old.remove("params");
        QCOMPARE(robot, old);
    }
    QCOMPARE(edited.robots[0].params.mass, 0.25);
    QCOMPARE(edited.robots[5].params.left.friction, 2e-4);
    selectRobot(dialog, 0);
    QCOMPARE(child<QDoubleSpinBox>(dialog, "robot.mass")->value(), 0.25);
    QCOMPARE(dialog.validationError(), QString());
}

void TestSceneDialog::restitutionOnlyForImpulse() {
    SceneParametersDialog dialog(kickoff());
    auto* model = child<QComboBox>(dialog, "simulation.collision_model");
    auto* restitution = child<QDoubleSpinBox>(dialog, "simulation.restitution");
    QCOMPARE(model->currentText(), QString("paper"));
    QVERIFY(!restitution->isEnabled());
    model->setCurrentIndex(model->findText("impulse"));
    QVERIFY(restitution->isEnabled());
    restitution->setValue(0.5);
    QCOMPARE(dialog.scene().simulation.collision_model, CollisionModel::Impulse);
    QCOMPARE(dialog.scene().simulation.restitution, 0.5);
    model->setCurrentIndex(model->findText("paper"));
    QVERIFY(!restitution->isEnabled());
    QCOMPARE(dialog.scene().simulation.collision_model, CollisionModel::Paper);
}

void TestSceneDialog::robotOutsideShrunkFieldIsRefused() {
    SceneParametersDialog dialog(kickoff());
    child<QDoubleSpinBox>(dialog, "field.length")->setValue(1.2);  // yellow0 and blue0 are at |x| = 0.68 m
    QVERIFY(dialog.validationError().contains("yellow0"));
    QVERIFY(dialog.validationError().contains("outside"));

    // accept() shows the warning and keeps the dialog open.
    bool accepted = false;
    connect(&dialog, &QDialog::accepted, [&] { accepted = true; });
    QString shown;
    QTimer closer;
    connect(&closer, &QTimer::timeout, [&] {
        if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
            shown = box->text();
            box->close();
        }
    });
    closer.start(10);
    dialog.show();
    dialog.accept();
    closer.stop();
    QCOMPARE(shown, dialog.validationError());
    QVERIFY(!accepted);
    QVERIFY(dialog.isVisible());

    // Large enough again: accepted.
    child<QDoubleSpinBox>(dialog, "field.length")->setValue(1.5);
    QCOMPARE(dialog.validationError(), QString());
    dialog.accept();
    QVERIFY(accepted);
}

void TestSceneDialog::ballOutsideIsRefused() {
    SceneParametersDialog dialog(kickoff());
    child<QDoubleSpinBox>(dialog, "ball.radius")->setValue(0.7);  // wider than the 1.3 m field
    QVERIFY(dialog.validationError().contains("ball"));
}

void TestSceneDialog::namesMustBeUniqueAndNonEmpty() {
    SceneParametersDialog dialog(kickoff());
    auto* list = child<QListWidget>(dialog, "robots.list");
    auto* name = child<QLineEdit>(dialog, "robot.name");
    selectRobot(dialog, 1);
    QCOMPARE(name->text(), QString("yellow1"));

    typeInto(name, "yellow0");
    QCOMPARE(dialog.scene().robots[1].name, std::string("yellow0"));
    QCOMPARE(list->item(1)->text(), QString("yellow0 (yellow)"));
    QVERIFY(dialog.validationError().contains("\"yellow0\""));
    QVERIFY(dialog.validationError().contains("unique"));

    typeInto(name, "");
    QVERIFY(dialog.validationError().contains("no name"));

    typeInto(name, "a,b");  // what only the reader knows: in its words
    QVERIFY(dialog.validationError().contains("commas"));

    typeInto(name, "striker");
    child<QComboBox>(dialog, "robot.team")->setCurrentIndex(1);
    QCOMPARE(dialog.validationError(), QString());
    QCOMPARE(dialog.scene().robots[1].team, Team::Blue);
    QCOMPARE(list->item(1)->text(), QString("striker (blue)"));
}

using SceneValue = std::function<double&(Scene&)>;
Q_DECLARE_METATYPE(SceneValue)

void TestSceneDialog::spinRangesAreTheReaders_data() {
    QTest::addColumn<QString>("box");
    QTest::addColumn<QString>("suffix");
    QTest::addColumn<SceneValue>("value");
    QTest::addColumn<bool>("boundedAbove");  // whether the reader has a maximum
    QTest::newRow("dt") << "simulation.dt"
                        << " s" << SceneValue([](Scene& s) -> double& { return s.simulation.dt; }) << true;
    QTest::newRow("restitution") << "simulation.restitution"
                                 << "" << SceneValue([](Scene& s) -> double& { return s.simulation.restitution; })
                                 << true;
    QTest::newRow("ball.friction") << "ball.friction"
                                   << " N s/m" << SceneValue([](Scene& s) -> double& { return s.ball_params.friction; })
                                   << false;
    QTest::newRow("mass") << "robot.mass"
                          << " kg" << SceneValue([](Scene& s) -> double& { return s.robots[2].params.mass; }) << false;
    QTest::newRow("max_voltage") << "robot.max_voltage"
                                 << " V"
                                 << SceneValue([](Scene& s) -> double& { return s.robots[2].params.max_voltage; })
                                 << false;
    QTest::newRow("right.resistance") << "robot.right.resistance"
                                      << " ohm" << SceneValue([](Scene& s) -> double& {
                                             return s.robots[2].params.right.resistance;
                                         })
                                      << false;
    QTest::newRow("left.rotor_inertia") << "robot.left.rotor_inertia"
                                        << " kg m²" << SceneValue([](Scene& s) -> double& {
                                               return s.robots[2].params.left.rotor_inertia;
                                           })
                                        << false;
}

void TestSceneDialog::spinRangesAreTheReaders() {
    QFETCH(QString, box);
    QFETCH(QString, suffix);
    QFETCH(SceneValue, value);
    QFETCH(bool, boundedAbove);
    SceneParametersDialog dialog(kickoff());
    selectRobot(dialog, 2);
    auto* spin = child<QDoubleSpinBox>(dialog, qPrintable(box));
    QCOMPARE(spin->suffix(), suffix);
    const double resolution = std::pow(10.0, spin->decimals());
    // Both ends of the box are accepted by the reader.
    for (const double end : {spin->minimum(), spin->maximum()}) {
        spin->setValue(end);
        Scene scene = dialog.scene();
        QCOMPARE(value(scene), end);
        QVERIFY2(readerAccepts(scene), qPrintable(QString("%1 = %2").arg(box).arg(end)));
    }
    // One step of the box's resolution beyond them is refused.
    Scene below = dialog.scene();
    value(below) = (std::round(spin->minimum() * resolution) - 1.0) / resolution;
    QVERIFY2(!readerAccepts(below), qPrintable(QString("%1 = %2").arg(box).arg(value(below))));
    if (boundedAbove) {
        Scene above = dialog.scene();
        value(above) = (std::round(spin->maximum() * resolution) + 1.0) / resolution;
        QVERIFY2(!readerAccepts(above), qPrintable(QString("%1 = %2").arg(box).arg(value(above))));
    }
}

void TestSceneDialog::fieldTypeSetsOfficialDimensions() {
    SceneParametersDialog dialog(kickoff());
    auto* type = child<QComboBox>(dialog, "field.type");
    QCOMPARE(type->currentData().toInt(), int(FieldType::Vsss3v3));
    QCOMPARE(child<QDoubleSpinBox>(dialog, "field.goal_width")->value(), 0.40);
    QVERIFY(child<QDoubleSpinBox>(dialog, "field.goal_width")->isEnabled());

    type->setCurrentIndex(type->findData(int(FieldType::Vsss5v5)));
    const FieldDimensions five = dialog.scene().field.dimensions;
    QCOMPARE(five.type, FieldType::Vsss5v5);
    QCOMPARE(five.length, 2.20);
    QCOMPARE(five.width, 1.80);
    QCOMPARE(five.goal_depth, 0.15);
    QCOMPARE(five.centre_radius, 0.25);
    QCOMPARE(five.free_ball_y, 0.40);
    QCOMPARE(dialog.scene().field.walls.size(), std::size_t(16));
    // The boxes show the new values.
    QCOMPARE(child<QDoubleSpinBox>(dialog, "field.length")->value(), 2.20);
    QCOMPARE(child<QDoubleSpinBox>(dialog, "field.free_ball_y")->value(), 0.40);
    QCOMPARE(dialog.validationError(), QString());  // the kick-off's bodies fit

    // One dimension changed by hand: only it.
    child<QDoubleSpinBox>(dialog, "field.corner_leg")->setValue(0.05);
    QCOMPARE(dialog.scene().field.dimensions.corner_leg, 0.05);
    QCOMPARE(dialog.scene().field.dimensions.goal_width, 0.40);
    QCOMPARE(dialog.scene().field.dimensions.type, FieldType::Vsss5v5);

    // The box: the seed's 1.50 x 1.30 m, its goal keys disabled and zero.
    type->setCurrentIndex(type->findData(int(FieldType::Box)));
    const Scene box = dialog.scene();
    QCOMPARE(box.field.dimensions.type, FieldType::Box);
    QCOMPARE(box.field.length, 1.50);
    QCOMPARE(box.field.dimensions.goal_width, 0.0);
    QCOMPARE(box.field.walls.size(), std::size_t(4));
    QVERIFY(!child<QDoubleSpinBox>(dialog, "field.goal_width")->isEnabled());
    QVERIFY(child<QDoubleSpinBox>(dialog, "field.centre_radius")->isEnabled());
    QVERIFY(readerAccepts(box));
}

void TestSceneDialog::inconsistentFieldIsRefused() {
    SceneParametersDialog dialog(kickoff());
    child<QDoubleSpinBox>(dialog, "field.goal_width")->setValue(1.2);  // wider than the wall between the corners
    QVERIFY2(dialog.validationError().contains("goal_width"), qPrintable(dialog.validationError()));
    QVERIFY(dialog.validationError().contains("wider than its wall"));
    child<QDoubleSpinBox>(dialog, "field.goal_width")->setValue(0.5);
    QCOMPARE(dialog.validationError(), QString());
    QCOMPARE(dialog.scene().field.dimensions.goal_width, 0.5);
    QVERIFY(readerAccepts(dialog.scene()));
}

QTEST_MAIN(TestSceneDialog)
#include "test_scene_dialog.moc"
