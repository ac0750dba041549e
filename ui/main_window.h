// The desktop app's window: the field view in the middle, the selected
// robot's inspector and live plots, the camera image the clients receive,
// the TCP connections, manual driving (keyboard, gamepad, on-screen
// joystick), and the run controls. It reads the engine's snapshots on a
// timer (default 30 Hz) and turns what the person does into requests.
#pragma once

#include <QElapsedTimer>
#include <QMainWindow>
#include <QTimer>
#include <QUndoStack>
#include <memory>
#include <optional>

#include "app_session.h"
#include "drive_mapping.h"
#include "keyboard_driver.h"

class QAction;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QMenu;
class QCheckBox;
class QDockWidget;
class QPushButton;

namespace vssim {

class CameraView;
class ConnectionsPanel;
class Scoreboard;
class FieldView;
class GamepadInput;
class JoystickWidget;
class LivePlots;
class RobotInspector;

class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    // `scenePath`: where the scene came from (for the title and Save).
    MainWindow(const Scene& scene, const QString& scenePath, const ServerSettings& server, QWidget* parent = nullptr);
    ~MainWindow() override;

    AppSession& session() { return *session_; }
    FieldView& fieldView() { return *field_; }
    // Loads a scene file (a path or a built-in name); false and a message box on error.
    bool openScene(const QString& pathOrName, bool interactive = true);
    // Writes the scene with the bodies where they are now; a path without a
    // suffix gets ".json".
    bool saveScene(const QString& path, QString* error);
    // The manual-driving state, for tests and the UI.
    int manualRobot() const { return manualRobot_; }
    void releaseManual();
    void setRefreshRate(double hz);

protected:
    void closeEvent(QCloseEvent* event) override;

private:
    void buildActions();
    void buildDocks();
    void buildToolBar();
    void refresh();
    // A new scene in the snapshots: camera, plots, undo history, selection, toolbar.
    void showScene(std::shared_ptr<const Scene> scene);
    void onKey(int key, bool pressed);
    bool drivable(int robot) const;  // a robot of the scene being run (not one just replaced)
    void onStick(double x, double y, bool fromGamepad);
    void sendManual(const Voltages& volts);
    void applySettingsFromToolbar();
    void showSettings(const SimulationSettings& settings);
    void updateRecentMenu();
    void addRecent(const QString& path);
    void updateTitle();

    std::unique_ptr<AppSession> session_;
    std::shared_ptr<const Scene> shownScene_;         // the snapshots' scene the window was last set up for
    std::shared_ptr<const Snapshot> cameraSnapshot_;  // the one the camera dock shows
    QString scenePath_;
    FieldView* field_ = nullptr;
    RobotInspector* inspector_ = nullptr;
    LivePlots* plots_ = nullptr;
    CameraView* camera_ = nullptr;
    ConnectionsPanel* connections_ = nullptr;
    Scoreboard* scoreboard_ = nullptr;
    JoystickWidget* joystick_ = nullptr;
    GamepadInput* gamepad_ = nullptr;
    QLabel* driveStatus_ = nullptr;
    QPushButton* release_ = nullptr;  // "Let go (Esc): back to ..."
    QLabel* gamepadStatus_ = nullptr;
    QComboBox* mapping_ = nullptr;
    QCheckBox* throughSpeedLoop_ = nullptr;  // drive by wheel speeds, through the robot's speed loop
    QComboBox* speed_ = nullptr;
    QComboBox* integrator_ = nullptr;
    QDoubleSpinBox* dt_ = nullptr;
    QComboBox* collision_ = nullptr;
    QDoubleSpinBox* restitution_ = nullptr;
    QLabel* status_ = nullptr;
    QDockWidget* robotDock_ = nullptr;
    QAction* playPause_ = nullptr;
    QAction* step_ = nullptr;
    QMenu* recentMenu_ = nullptr;
    QUndoStack undo_;
    QTimer timer_;
    int tick_ = 0;
    KeyboardDriver keyboard_;
    int manualRobot_ = -1;  // the robot a person drives, or -1
    Voltages stickVolts_;   // from the joystick or gamepad
    bool stickActive_ = false;
    std::optional<RobotState> dragBefore_;
    int dragRobot_ = -1;
    std::optional<BallState> ballBefore_;
    // Real-time factor: simulated time over wall time between refreshes.
    QElapsedTimer wall_;
    double lastSimTime_ = 0.0;
    qint64 lastWallMs_ = 0;
    double factor_ = 0.0;
    double shownDt_ = 0.0, shownRestitution_ = 0.0;  // what showSettings() put in the boxes
    qint64 lastConnectionsMs_ = 0;
    QString lastWatched_;  // the last server address watched (File > Watch a server)
};

}  // namespace vssim
