// A window on a `vssim serve` running elsewhere (RemoteWatcher): the field,
// the selected robot's inspector and plots, and pause/resume/step/reset sent
// as CONTROL. Bodies can be dragged (place_robot / place_ball).
#pragma once

#include <QLabel>
#include <QMainWindow>
#include <QTimer>

#include "remote_watcher.h"

class QAction;

namespace vssim {

class FieldView;
class LivePlots;
class RobotInspector;

class RemoteWindow : public QMainWindow {
    Q_OBJECT
public:
    // Takes a connected watcher.
    explicit RemoteWindow(RemoteWatcher* watcher, QWidget* parent = nullptr);
    FieldView& fieldView() { return *field_; }
    RemoteWatcher& watcher() { return *watcher_; }

protected:
    void closeEvent(QCloseEvent* event) override;

private:
    void refresh();
    RemoteWatcher* watcher_;
    FieldView* field_;
    RobotInspector* inspector_;
    LivePlots* plots_;
    QTimer timer_;
    QTimer reconnect_;  // runs while the server is gone
    bool reconnecting_ = false;  // an attempt (with its nested event loop) is under way
    bool closeWhenDone_ = false;  // closed during an attempt: close once it returns
    QLabel* status_ = nullptr;
    QAction* step_ = nullptr;
};

}  // namespace vssim
