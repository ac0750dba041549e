#include "main_window.h"

#include <QActionGroup>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QSaveFile>
#include <QScreen>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSignalBlocker>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>
#include <QUndoCommand>
#include <QVBoxLayout>
#include <algorithm>

#include "camera_view.h"
#include "connections_panel.h"
#include "field_view.h"
#include "gamepad_input.h"
#include "io/scene_io.h"
#include "joystick_widget.h"
#include "live_plots.h"
#include "net/network_address.h"
#include "remote_window.h"
#include "robot_inspector.h"
#include "scene_parameters_dialog.h"
#include "scene_value_ranges.h"
#include "scoreboard.h"
#include "status_text.h"
#include "vssim/robot_model.h"
#include "wire/protocol.h"

namespace vssim {

namespace {

// Moving a body by hand, undoable. The body is already where the person
// dropped it when the command is pushed, so the first redo does nothing.
class PlaceBodyCommand : public QUndoCommand {
public:
    PlaceBodyCommand(AppSession& session, int robot, RobotState before, RobotState after, const QString& name)
        : QUndoCommand(describe(before, after).arg(name)),
          session_(session),
          robot_(robot),
          robotBefore_(before),
          robotAfter_(after) {}
    PlaceBodyCommand(AppSession& session, BallState before, BallState after)
        : QUndoCommand(before.x == after.x && before.y == after.y ? QObject::tr("Set the ball's velocity")
                                                                  : QObject::tr("Move the ball")),
          session_(session),
          robot_(-1),
          ballBefore_(before),
          ballAfter_(after) {}
    // "Move %1", "Turn %1" or "Set %1's velocity": what the Edit menu's Undo names.
    static QString describe(const RobotState& before, const RobotState& after) {
        if (before.x != after.x || before.y != after.y) return QObject::tr("Move %1");
        if (before.theta != after.theta) return QObject::tr("Turn %1");
        return QObject::tr("Set %1's velocity");
    }
    void undo() override { place(true); }
    void redo() override {
        if (first_) {
            first_ = false;
            return;
        }
        place(false);
    }

private:
    void place(bool before) {
        if (robot_ >= 0)
            session_.placeRobot(robot_, before ? robotBefore_ : robotAfter_);
        else
            session_.placeBall(before ? ballBefore_ : ballAfter_);
    }
    AppSession& session_;
    int robot_;
    RobotState robotBefore_, robotAfter_;
    BallState ballBefore_, ballAfter_;
    bool first_ = true;
};

const struct {
    const char* label;
    double speed;  // 0: as fast as possible
} kSpeeds[] = {{"x0.1", 0.1}, {"x0.25", 0.25}, {"x0.5", 0.5}, {"x1", 1.0}, {"x2", 2.0}, {"x4", 4.0}, {"max", 0.0}};

}  // namespace

MainWindow::MainWindow(const Scene& scene, const QString& scenePath, const ServerSettings& server, QWidget* parent)
    : QMainWindow(parent), scenePath_(scenePath) {
    session_ = std::make_unique<AppSession>(scene, server);
    field_ = new FieldView(this);
    setCentralWidget(field_);
    buildDocks();
    buildActions();
    buildToolBar();
    status_ = new QLabel(this);
    statusBar()->addWidget(status_, 1);
    if (!session_->listening())
        statusBar()->showMessage(tr("TCP server not started: %1").arg(session_->listenError()), 15000);

    connect(field_, &FieldView::robotSelected, this, [this](int) {
        plots_->clear();
        refresh();
    });
    connect(field_, &FieldView::robotDragStarted, this, [this](int robot, const RobotState& before) {
        dragRobot_ = robot;
        dragBefore_ = before;
    });
    connect(field_, &FieldView::robotPlaced, this, [this](int robot, const RobotState& pose, bool finished) {
        session_->placeRobot(robot, pose);
        if (finished && dragBefore_ && dragRobot_ == robot) {
            undo_.push(new PlaceBodyCommand(*session_, robot, *dragBefore_, pose,
                                            QString::fromStdString(session_->scene().robots[robot].name)));
            dragBefore_.reset();
        }
    });
    connect(field_, &FieldView::ballDragStarted, this, [this](const BallState& before) { ballBefore_ = before; });
    connect(field_, &FieldView::ballPlaced, this, [this](const BallState& ball, bool finished) {
        session_->placeBall(ball);
        if (finished && ballBefore_) {
            undo_.push(new PlaceBodyCommand(*session_, *ballBefore_, ball));
            ballBefore_.reset();
        }
    });
    connect(field_, &FieldView::keyChanged, this, &MainWindow::onKey);
    // Keys held when the field loses focus would never be seen released: stop.
    connect(field_, &FieldView::focusLost, this, [this] {
        if (keyboard_.active()) {
            keyboard_.releaseAll();
            sendManual(Voltages{});
        }
    });

    refresh();  // the first snapshot: the scene's settings in the toolbar, its robots in the camera view
    if (session_->listening())
        connections_->setListening(tr("%1:%2 for TCP clients (docs/protocol.md)")
                                       .arg(session_->server().address().toString())
                                       .arg(session_->port()));
    else
        connections_->listeningLabel()->setText(
            tr("No TCP server: %1 (vssim gui --port N picks another port)").arg(session_->listenError()));
    wall_.start();
    connect(&timer_, &QTimer::timeout, this, &MainWindow::refresh);
    setRefreshRate(30.0);
    updateTitle();
    // As large as the plots and the joystick want (1280 x 1100), or the
    // screen's free area where that is smaller (the docks then scroll).
    const QRect free = screen() ? screen()->availableGeometry() : QRect(0, 0, 1280, 1100);
    resize(std::min(1280, free.width()), std::min(1100, free.height()));
    resizeDocks({robotDock_, findChild<QDockWidget*>("dock.game")}, {360, 220}, Qt::Horizontal);
    resizeDocks({findChild<QDockWidget*>("dock.connections")}, {130}, Qt::Vertical);
}

MainWindow::~MainWindow() { timer_.stop(); }

void MainWindow::closeEvent(QCloseEvent* event) {
    timer_.stop();
    if (gamepad_) gamepad_->stop();
    event->accept();
}

void MainWindow::setRefreshRate(double hz) { timer_.start(static_cast<int>(1000.0 / hz)); }

void MainWindow::buildDocks() {
    auto dock = [this](const QString& title, QWidget* widget, Qt::DockWidgetArea area, const char* name) {
        auto* d = new QDockWidget(title, this);
        d->setObjectName(name);
        d->setWidget(widget);
        addDockWidget(area, d);
        return d;
    };
    // A right-hand dock's content scrolls when the screen is too short for
    // it, so that the window fits a small screen (1024 x 768) and keeps the
    // docks' readable width.
    auto scrolling = [](QWidget* content) {
        auto* area = new QScrollArea;
        area->setWidget(content);
        area->setWidgetResizable(true);
        area->setFrameShape(QFrame::NoFrame);
        area->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
        area->setMinimumWidth(300 + area->verticalScrollBar()->sizeHint().width());
        return area;
    };
    auto* robotPanel = new QSplitter(Qt::Vertical);
    inspector_ = new RobotInspector(robotPanel);
    plots_ = new LivePlots(robotPanel);
    robotPanel->addWidget(inspector_);
    robotPanel->addWidget(plots_);
    QDockWidget* robotDock = dock(tr("Selected robot"), scrolling(robotPanel), Qt::RightDockWidgetArea, "dock.robot");
    robotDock_ = robotDock;

    camera_ = new CameraView;
    QDockWidget* cameraDock =
        dock(tr("Camera (what clients receive)"), camera_, Qt::RightDockWidgetArea, "dock.camera");

    scoreboard_ = new Scoreboard;
    dock(tr("Game"), scoreboard_, Qt::LeftDockWidgetArea, "dock.game");
    scoreboard_->setMinimumWidth(200);
    connect(scoreboard_, &Scoreboard::gameOnRequested, this,
            [this] { session_->post(EngineRequest::Kind::ResumeGame); });
    connect(scoreboard_, &Scoreboard::haltRequested, this, [this] { session_->post(EngineRequest::Kind::HaltGame); });
    connect(scoreboard_, &Scoreboard::callRequested, this, [this](Call call, Team team, int quadrant) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::CallFoul;
        r.call = call;
        r.team = team;
        r.quadrant = quadrant;
        session_->post(std::move(r));
    });
    connect(scoreboard_, &Scoreboard::teamControlRequested, this, [this](Team team, TeamControl control) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::SetTeamControl;
        r.team = team;
        r.control = control;
        session_->post(std::move(r));
    });

    connections_ = new ConnectionsPanel;
    connections_->setMaximumHeight(195);  // the listening line, the FIRASim line, a few rows
    dock(tr("TCP connections"), connections_, Qt::BottomDockWidgetArea, "dock.connections");
    connect(connections_, &ConnectionsPanel::firasimToggled, this, [this](bool on) {
        if (!on) {
            session_->stopFirasim();
            connections_->showFirasimOff();
            return;
        }
        QString error;
        if (session_->startFirasim(&error))
            connections_->showFirasim(*session_->firasim());
        else
            connections_->showFirasimOff(error);
    });

    auto* drive = new QWidget;
    auto* layout = new QVBoxLayout(drive);
    driveStatus_ = new QLabel(drive);
    driveStatus_->setObjectName("drive.status");
    driveStatus_->setWordWrap(true);
    layout->addWidget(driveStatus_);
    auto* form = new QFormLayout;
    mapping_ = new QComboBox(drive);
    mapping_->addItems(
        {tr("Arcade (one stick: forward and turn)"), tr("Tank (left stick: left wheel, right stick: right wheel)")});
    form->addRow(tr("Stick mapping"), mapping_);
    throughSpeedLoop_ = new QCheckBox(tr("Wheel speeds (through the speed loop)"), drive);
    throughSpeedLoop_->setObjectName("drive.wheelSpeeds");
    throughSpeedLoop_->setToolTip(
        tr("Send wheel-speed targets (a full stick: the robot's free wheel speed) to the robot's on-board PI "
           "loop instead of voltages, as FIRASim clients do"));
    form->addRow(QString(), throughSpeedLoop_);
    gamepadStatus_ = new QLabel(drive);
    form->addRow(tr("Gamepad"), gamepadStatus_);
    layout->addLayout(form);
    joystick_ = new JoystickWidget(drive);
    joystick_->setMaximumSize(220, 220);
    joystick_->setToolTip(
        tr("On-screen joystick: drag the knob to drive the selected robot (with the stick mapping above)"));
    layout->addWidget(joystick_, 1, Qt::AlignHCenter);
    // Its text names what the robot goes back to (refresh(): letGoText()).
    release_ = new QPushButton(tr("Let go (Esc)"), drive);
    release_->setObjectName("drive.release");
    layout->addWidget(release_);
    QDockWidget* driveDock = dock(tr("Drive by hand"), scrolling(drive), Qt::RightDockWidgetArea, "dock.drive");
    // Below the robot and camera tabs, not among them: the joystick and the
    // plots are seen together. (Split first: a dock split from a tabbed one
    // would become another tab.)
    splitDockWidget(robotDock, driveDock, Qt::Vertical);
    tabifyDockWidget(robotDock, cameraDock);
    robotDock->raise();
    // The right-hand docks keep a readable width on a small screen (1024 x 768).
    for (QWidget* w : {static_cast<QWidget*>(robotPanel), static_cast<QWidget*>(camera_), drive})
        w->setMinimumWidth(300);
    resizeDocks({robotDock}, {380}, Qt::Horizontal);
    resizeDocks({findChild<QDockWidget*>("dock.game")}, {220}, Qt::Horizontal);
    connect(release_, &QPushButton::clicked, this, &MainWindow::releaseManual);
    connect(joystick_, &JoystickWidget::moved, this, [this](double x, double y) { onStick(x, y, false); });

    gamepad_ = new GamepadInput(this);
    gamepadStatus_->setText(gamepad_->available() ? tr("none connected (plug one in)")
                                                  : tr("unavailable: %1").arg(gamepad_->errorString()));
    connect(gamepad_, &GamepadInput::connectedChanged, this, [this](bool connected, const QString& name) {
        gamepadStatus_->setText(connected ? name : tr("none connected (plug one in)"));
    });
    connect(gamepad_, &GamepadInput::axesChanged, this, [this](double lx, double ly, double rx, double ry) {
        // A small dead zone: worn sticks do not rest exactly at 0.
        constexpr double kDeadzone = 0.08;
        if (mapping_->currentIndex() == 0)
            onStick(applyDeadzone(lx, kDeadzone), applyDeadzone(ly, kDeadzone), true);
        else
            onStick(applyDeadzone(ry, kDeadzone), applyDeadzone(ly, kDeadzone),
                    true);  // tank: x is the right wheel's stick
        (void)rx;
    });
    gamepad_->start();
}

void MainWindow::buildActions() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    file->addAction(tr("&Open scene..."), QKeySequence::Open, this, [this] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Open scene"), QString(), tr("Scenes (*.json)"));
        if (!path.isEmpty()) openScene(path);
    });
    QMenu* examples = file->addMenu(tr("&Example scenes"));
    for (const QString& name : builtinSceneNames()) examples->addAction(name, this, [this, name] { openScene(name); });
    recentMenu_ = file->addMenu(tr("&Recent scenes"));
    updateRecentMenu();
    // (QKeySequence::SaveAs has no key on X11: the shortcut is spelled out.)
    file->addAction(tr("&Save scene as..."), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S), this, [this] {
        // The dialog adds ".json" before it asks about overwriting an existing file.
        QFileDialog dialog(this, tr("Save scene (bodies where they are now)"), QString(), tr("Scenes (*.json)"));
        dialog.setAcceptMode(QFileDialog::AcceptSave);
        dialog.setDefaultSuffix(QStringLiteral("json"));
        if (dialog.exec() != QDialog::Accepted || dialog.selectedFiles().isEmpty()) return;
        const QString path = dialog.selectedFiles().first();
        QString error;
        if (!saveScene(path, &error)) QMessageBox::warning(this, tr("Save scene"), error);
    });
    file->addAction(tr("&Watch a server..."), this, [this] {
        bool ok = false;
        // No default address: this window's own server (port %1) is not worth watching.
        const QString target = QInputDialog::getText(
            this, tr("Watch a server"),
            tr("A running vssim serve, as HOST:PORT or PORT (this window itself serves on port %1):")
                .arg(session_->port()),
            QLineEdit::Normal, lastWatched_, &ok);
        if (!ok) return;
        const std::optional<HostPort> address = parseHostPort(target);
        auto* watcher = new RemoteWatcher;
        QString error;
        if (!address || !watcher->connectTo(address->host, address->port, &error)) {
            delete watcher;
            QMessageBox::warning(this, tr("Watch a server"),
                                 error.isEmpty() ? tr("expected HOST:PORT, got \"%1\"").arg(target) : error);
            return;
        }
        lastWatched_ = target;
        auto* window = new RemoteWindow(watcher);
        window->setAttribute(Qt::WA_DeleteOnClose);
        window->show();
    });
    file->addSeparator();
    // Quit ends everything: this window, any watch windows, the engine and the server.
    QAction* quit = file->addAction(tr("&Quit"), QKeySequence(Qt::CTRL | Qt::Key_Q), this, [] {
        QApplication::closeAllWindows();
        QApplication::quit();
    });
    quit->setObjectName("action.quit");

    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    QAction* undo = undo_.createUndoAction(this, tr("&Undo"));
    undo->setShortcut(QKeySequence::Undo);
    undo->setObjectName("action.undo");
    QAction* redo = undo_.createRedoAction(this, tr("&Redo"));
    redo->setShortcut(QKeySequence::Redo);
    redo->setObjectName("action.redo");
    edit->addAction(undo);
    edit->addAction(redo);
    edit->addSeparator();
    edit->addAction(tr("Robot, ball and field &parameters..."), this, [this] {
        SceneParametersDialog dialog(session_->scene(), this);
        if (dialog.exec() != QDialog::Accepted || sceneToJson(dialog.scene()) == sceneToJson(session_->scene())) return;
        releaseManual();
        session_->loadScene(dialog.scene());  // the rest follows in refresh(), from the snapshots
    });
    // The sides (GameRules::left_team): swapping them starts the match again.
    QAction* blueLeft = edit->addAction(tr("&Blue defends the left goal (FIRASim's layout)"));
    blueLeft->setObjectName("action.blueOnLeft");
    blueLeft->setCheckable(true);
    blueLeft->setToolTip(tr("The team that defends the goal at x < 0; swapping starts the match again"));
    connect(edit, &QMenu::aboutToShow, this, [this, blueLeft] {
        const QSignalBlocker block(blueLeft);
        blueLeft->setChecked(session_->scene().game.rules.left_team == Team::Blue);
    });
    connect(blueLeft, &QAction::toggled, this, [this](bool blue) {
        Scene scene = session_->scene();
        scene.game.rules.left_team = blue ? Team::Blue : Team::Yellow;
        releaseManual();
        session_->loadScene(scene);
    });

    QMenu* view = menuBar()->addMenu(tr("&View"));
    QAction* trails = view->addAction(tr("&Trails"));
    trails->setCheckable(true);
    trails->setChecked(true);
    connect(trails, &QAction::toggled, field_, &FieldView::setShowTrails);
    QAction* arrows = view->addAction(tr("&Velocity arrows"));
    arrows->setCheckable(true);
    arrows->setChecked(true);
    connect(arrows, &QAction::toggled, field_, &FieldView::setShowVelocities);
    view->addAction(tr("&Reset zoom and pan"), field_, &FieldView::resetView);
    QMenu* rate = view->addMenu(tr("Refresh &rate"));
    auto* rates = new QActionGroup(rate);
    for (double hz : {2.0, 10.0, 30.0, 60.0}) {
        QAction* a = rate->addAction(tr("%1 Hz").arg(hz), this, [this, hz] { setRefreshRate(hz); });
        a->setCheckable(true);
        a->setChecked(hz == 30.0);  // the default (setRefreshRate in the constructor)
        a->setObjectName(QStringLiteral("action.rate%1").arg(hz));
        rates->addAction(a);
    }

    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->addAction(tr("&Controls"), this,
                    [this] { QMessageBox::information(this, tr("Controls"), field_->toolTip()); });
    help->addAction(tr("&About vssim"), this, [this] {
        QMessageBox::about(this, tr("About vssim"),
                           tr("vssim %1: a simulator of IEEE Very Small Size Soccer robots, driven by motor voltages.\n"
                              "Clients connect over TCP (docs/protocol.md).")
                               .arg(VSSIM_VERSION));
    });
}

void MainWindow::buildToolBar() {
    QToolBar* bar = addToolBar(tr("Run"));
    bar->setObjectName("toolbar.run");
    playPause_ = bar->addAction(tr("Pause"), this, [this] {
        const auto s = session_->latest();
        session_->post(s && s->paused ? EngineRequest::Kind::Resume : EngineRequest::Kind::Pause);
    });
    playPause_->setShortcut(Qt::Key_Space);
    playPause_->setObjectName("action.playPause");
    step_ = bar->addAction(tr("Step 30 ms"), this, [this] {
        EngineRequest r;
        r.kind = EngineRequest::Kind::Step;
        r.duration = 0.03;
        session_->post(std::move(r));
    });
    step_->setObjectName("action.step");
    step_->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Right));
    QAction* reset = bar->addAction(tr("Reset"), this, [this] {
        session_->post(EngineRequest::Kind::Reset);
        plots_->clear();
    });
    reset->setObjectName("action.reset");
    reset->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_R));
    bar->addSeparator();
    bar->addWidget(new QLabel(tr(" Speed ")));
    speed_ = new QComboBox(bar);
    for (const auto& s : kSpeeds) speed_->addItem(s.label);
    speed_->setCurrentIndex(3);
    bar->addWidget(speed_);
    connect(speed_, &QComboBox::currentIndexChanged, this, [this](int i) { session_->setSpeed(kSpeeds[i].speed); });
    for (auto [key, step] : {std::pair{Qt::Key_Up, 1}, std::pair{Qt::Key_Down, -1}}) {
        auto* change = new QAction(this);
        change->setShortcut(QKeySequence(Qt::CTRL | key));
        change->setObjectName(step > 0 ? "action.faster" : "action.slower");
        connect(change, &QAction::triggered, this, [this, step] {
            speed_->setCurrentIndex(std::clamp(speed_->currentIndex() + step, 0, speed_->count() - 1));
        });
        addAction(change);
    }
    bar->addSeparator();
    integrator_ = new QComboBox(bar);
    integrator_->addItems({"euler", "rk4", "exact"});
    integrator_->setToolTip(tr("Integrator (docs/model.md)"));
    integrator_->setObjectName("toolbar.integrator");
    bar->addWidget(integrator_);
    dt_ = new QDoubleSpinBox(bar);
    dt_->setDecimals(6);
    const SpinInterval dtRange = spinInterval(scene_limits::kTimeStep, dt_->decimals());  // as the scene reader
    dt_->setRange(dtRange.minimum, dtRange.maximum);
    dt_->setSingleStep(0.0005);
    dt_->setSuffix(" s");
    dt_->setToolTip(tr("Integration step dt"));
    dt_->setObjectName("toolbar.dt");
    bar->addWidget(dt_);
    collision_ = new QComboBox(bar);
    collision_->addItems({"paper", "impulse"});
    collision_->setToolTip(tr("Collision model"));
    bar->addWidget(collision_);
    restitution_ = new QDoubleSpinBox(bar);
    restitution_->setRange(0.0, 1.0);
    restitution_->setDecimals(3);
    restitution_->setSingleStep(0.05);
    restitution_->setPrefix(tr("e = "));
    restitution_->setToolTip(tr("Restitution (impulse model only)"));
    bar->addWidget(restitution_);
    for (QComboBox* c : {integrator_, collision_})
        connect(c, &QComboBox::activated, this, &MainWindow::applySettingsFromToolbar);
    for (QDoubleSpinBox* s : {dt_, restitution_})
        connect(s, &QDoubleSpinBox::editingFinished, this, &MainWindow::applySettingsFromToolbar);
}

void MainWindow::showSettings(const SimulationSettings& settings) {
    integrator_->setCurrentText(integratorName(settings.integrator));
    dt_->setValue(settings.dt);
    collision_->setCurrentText(collisionModelName(settings.collision_model));
    restitution_->setValue(settings.restitution);
    restitution_->setEnabled(settings.collision_model == CollisionModel::Impulse);
    shownDt_ = dt_->value();
    shownRestitution_ = restitution_->value();
}

void MainWindow::applySettingsFromToolbar() {
    SimulationSettings settings = session_->scene().simulation;
    settings.integrator = *integratorFromName(integrator_->currentText());
    // A box that still shows what showSettings() put there keeps the exact
    // value (the box rounds to its decimals).
    if (dt_->value() != shownDt_) settings.dt = dt_->value();
    if (restitution_->value() != shownRestitution_) settings.restitution = restitution_->value();
    settings.collision_model = *collisionModelFromName(collision_->currentText());
    restitution_->setEnabled(settings.collision_model == CollisionModel::Impulse);
    const SimulationSettings& now = session_->scene().simulation;
    if (settings.integrator == now.integrator && settings.dt == now.dt &&
        settings.collision_model == now.collision_model && settings.restitution == now.restitution)
        return;
    session_->applySettings(settings);
    statusBar()->showMessage(tr("New simulation settings: the bodies stay where they are, the clock restarts at 0"),
                             5000);
}

bool MainWindow::openScene(const QString& pathOrName, bool interactive) {
    const QString path = resolveScenePath(pathOrName);
    QString error;
    std::optional<Scene> scene = path.isEmpty() ? std::nullopt : loadSceneFile(path, &error);
    if (scene) {
        // A camera the server and the camera dock could not draw (a lens that folds the image over, ...).
        if (const std::string problem = cameraProblem(*scene); !problem.empty()) {
            error = path + ": " + QString::fromStdString(problem);
            scene.reset();
        }
    }
    if (!scene) {
        if (path.isEmpty()) error = sceneNotFoundMessage(pathOrName);
        if (interactive) QMessageBox::warning(this, tr("Open scene"), error);
        return false;
    }
    releaseManual();
    field_->setSelectedRobot(-1);  // the old scene's robot
    // Paused at t = 0, so the person sees the scene begin (Space plays it);
    // the rest follows in refresh(), from the snapshots.
    session_->loadScene(*scene, true);
    statusBar()->showMessage(tr("Opened %1, paused at t = 0: Space or Play runs it").arg(QFileInfo(path).baseName()),
                             8000);
    scenePath_ = path;
    if (!path.startsWith(":/")) addRecent(QFileInfo(path).absoluteFilePath());
    updateTitle();
    return true;
}

bool MainWindow::saveScene(const QString& chosenPath, QString* error) {
    // Scene files end in .json: the Open dialog shows only those.
    const QString path = QFileInfo(chosenPath).suffix().isEmpty() ? chosenPath + QStringLiteral(".json") : chosenPath;
    const auto snapshot = session_->latest();
    Scene scene = session_->scene();
    if (snapshot && snapshot->robots.size() == scene.robots.size()) {
        for (std::size_t i = 0; i < scene.robots.size(); ++i) scene.robots[i].initial = snapshot->robots[i];
        scene.ball = snapshot->ball;
    }
    QSaveFile file(path);
    if (!file.open(QIODevice::WriteOnly) || file.write(sceneToJson(scene)) < 0 || !file.commit()) {
        *error = tr("%1: cannot write: %2").arg(path, file.errorString());
        return false;
    }
    scenePath_ = path;
    addRecent(QFileInfo(path).absoluteFilePath());
    updateTitle();
    return true;
}

void MainWindow::addRecent(const QString& path) {
    QSettings settings;
    QStringList recent = settings.value("recentScenes").toStringList();
    recent.removeAll(path);
    recent.prepend(path);
    while (recent.size() > 8) recent.removeLast();
    settings.setValue("recentScenes", recent);
    updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
    recentMenu_->clear();
    const QStringList recent = QSettings().value("recentScenes").toStringList();
    for (const QString& path : recent) recentMenu_->addAction(path, this, [this, path] { openScene(path); });
    recentMenu_->setEnabled(!recent.isEmpty());
}

void MainWindow::updateTitle() {
    setWindowTitle(tr("vssim - %1").arg(scenePath_.startsWith(":/") ? QFileInfo(scenePath_).baseName() : scenePath_));
}

bool MainWindow::drivable(int robot) const {
    // Against the scene being run: the view's selection comes from its last
    // snapshot, which may still show the scene just replaced.
    return robot >= 0 && robot < static_cast<int>(session_->scene().robots.size());
}

void MainWindow::onKey(int key, bool pressed) {
    if (key == Qt::Key_Escape && pressed) {
        releaseManual();
        return;
    }
    // Space reaches the field when the window shortcut did not fire (e.g. the
    // window is not the active one): the same play/pause.
    if (key == Qt::Key_Space) {
        if (pressed) playPause_->trigger();
        return;
    }
    if (!keyboard_.handleKey(key, pressed)) return;
    const int selected = field_->selectedRobot();
    if (manualRobot_ < 0 && drivable(selected) && keyboard_.active()) manualRobot_ = selected;
    if (manualRobot_ >= 0) {
        const double max = session_->scene().robots[manualRobot_].params.max_voltage;
        sendManual(keyboard_.voltages(max));
    }
}

void MainWindow::onStick(double x, double y, bool fromGamepad) {
    (void)fromGamepad;
    const int selected = field_->selectedRobot();
    stickActive_ = std::abs(x) > 0.05 || std::abs(y) > 0.05;
    if (manualRobot_ < 0 && drivable(selected) && stickActive_) manualRobot_ = selected;
    if (manualRobot_ < 0) return;
    const double max = session_->scene().robots[manualRobot_].params.max_voltage;
    stickVolts_ =
        stickActive_
            ? stickToVoltages(x, y, mapping_->currentIndex() == 0 ? DriveMapping::Arcade : DriveMapping::Tank, max)
            : Voltages{};
    sendManual(stickVolts_);
}

void MainWindow::sendManual(const Voltages& volts) {
    if (manualRobot_ < 0) return;
    if (!throughSpeedLoop_->isChecked()) return session_->driveManually(manualRobot_, volts);
    // The stick as a fraction of the free wheel speed: what both wheels reach at full voltage.
    const RobotParams& params = session_->scene().robots[manualRobot_].params;
    const Eigen::Vector2d free = steadyStateVelocity(makeRobotModel(params), {params.max_voltage, params.max_voltage});
    const double freeWheelSpeed = std::abs(free(0)) / params.right.wheel_radius;  // rad/s
    session_->driveManually(manualRobot_, voltagesToWheelSpeeds(volts, params.max_voltage, freeWheelSpeed));
}

void MainWindow::releaseManual() {
    if (manualRobot_ >= 0) session_->releaseManual(manualRobot_);
    manualRobot_ = -1;
    keyboard_.releaseAll();
    stickActive_ = false;
}

void MainWindow::showScene(std::shared_ptr<const Scene> scene) {
    // Whoever replaced the scene (Open, the example and recent menus, the
    // parameters dialog), the engine's snapshots are where the window learns it.
    shownScene_ = std::move(scene);
    camera_->setScene(*shownScene_);
    plots_->clear();
    undo_.clear();  // the old scene's moves
    if (field_->selectedRobot() >= static_cast<int>(shownScene_->robots.size())) field_->setSelectedRobot(-1);
    showSettings(shownScene_->simulation);
}

void MainWindow::refresh() {
    const std::shared_ptr<const Snapshot> snapshot = session_->latest();
    if (!snapshot) return;
    if (snapshot->scene && snapshot->scene != shownScene_) showScene(snapshot->scene);
    ++tick_;
    // Real-time factor over the last half second or so.
    const qint64 nowMs = wall_.elapsed();
    if (nowMs - lastWallMs_ >= 500) {
        if (snapshot->time >= lastSimTime_ && lastWallMs_ > 0)
            factor_ = (snapshot->time - lastSimTime_) / (1e-3 * static_cast<double>(nowMs - lastWallMs_));
        lastSimTime_ = snapshot->time;
        lastWallMs_ = nowMs;
    }
    field_->showSnapshot(snapshot);
    // A robot driven by hand keeps getting its voltages (and stays manual).
    if (manualRobot_ >= 0 && manualRobot_ < static_cast<int>(snapshot->robots.size())) {
        const double max = session_->scene().robots[manualRobot_].params.max_voltage;
        sendManual(keyboard_.active() ? keyboard_.voltages(max) : stickActive_ ? stickVolts_ : Voltages{});
    }
    const int selected = field_->selectedRobot();
    inspector_->showRobot(*snapshot, selected);
    if (selected >= 0) plots_->addSample(*snapshot, selected);
    // The camera image about 5 times a second, and only when there is a new one.
    if (camera_->isVisible() && tick_ % 6 == 0 && snapshot != cameraSnapshot_) {
        camera_->showSnapshot(*snapshot);
        cameraSnapshot_ = snapshot;
    }
    if (tick_ % 3 == 0)
        scoreboard_->setGame(snapshot->game, snapshot->gameSettings.rules, snapshot->gameSettings.yellow,
                             snapshot->gameSettings.blue);
    if (nowMs - lastConnectionsMs_ >= 1000) {
        connections_->setClients(session_->server().clients(), 1e-3 * static_cast<double>(nowMs - lastConnectionsMs_));
        if (session_->firasim()) connections_->showFirasim(*session_->firasim());
        lastConnectionsMs_ = nowMs;
    }
    status_->setText(statusText(*snapshot, factor_));
    playPause_->setText(snapshot->paused ? tr("Play") : tr("Pause"));
    // The speed may have been changed by a TCP client (CONTROL speed).
    const double shownSpeed = snapshot->mode == RunMode::Max ? 0.0 : snapshot->speed;
    for (int i = 0; i < speed_->count(); ++i) {
        if (kSpeeds[i].speed == shownSpeed && speed_->currentIndex() != i) {
            const QSignalBlocker block(speed_);
            speed_->setCurrentIndex(i);
        }
    }
    step_->setEnabled(snapshot->paused);
    const QString letGo = letGoText(*snapshot, manualRobot_ >= 0 ? manualRobot_ : selected);
    if (release_->text() != letGo) release_->setText(letGo);
    const Scene* scene = snapshot->scene.get();
    if (manualRobot_ >= 0 && scene && manualRobot_ < static_cast<int>(scene->robots.size())) {
        const bool tcp =
            manualRobot_ < static_cast<int>(snapshot->control.size()) && snapshot->control[manualRobot_].tcpWhileManual;
        driveStatus_->setText(tr("Driving %1 by hand%2. Esc or the button below lets go.")
                                  .arg(QString::fromStdString(scene->robots[manualRobot_].name))
                                  .arg(tcp ? tr(": its TCP voltages are ignored") : QString()));
    } else {
        driveStatus_->setText(
            selected >= 0 ? tr("W A S D or the arrow keys (field focused), the joystick below or a gamepad drive %1.")
                                .arg(QString::fromStdString(scene->robots[selected].name))
                          : tr("Click a robot to select it, then drive it with W A S D, the arrow keys, "
                               "the joystick below or a gamepad."));
    }
}

}  // namespace vssim
