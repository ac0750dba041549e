#include "remote_window.h"

#include <QCloseEvent>
#include <QDockWidget>
#include <QLabel>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>

#include "field_view.h"
#include "live_plots.h"
#include "robot_inspector.h"

namespace vssim {

RemoteWindow::RemoteWindow(RemoteWatcher* watcher, QWidget* parent) : QMainWindow(parent), watcher_(watcher) {
    watcher_->setParent(this);
    setWindowTitle(tr("vssim - watching %1").arg(watcher_->address()));
    field_ = new FieldView(this);
    setCentralWidget(field_);
    auto* panel = new QSplitter(Qt::Vertical);
    inspector_ = new RobotInspector(panel);
    plots_ = new LivePlots(panel);
    panel->addWidget(inspector_);
    panel->addWidget(plots_);
    auto* dock = new QDockWidget(tr("Selected robot"), this);
    dock->setObjectName("dock.robot");
    dock->setWidget(panel);
    addDockWidget(Qt::RightDockWidgetArea, dock);

    QToolBar* bar = addToolBar(tr("Server"));
    bar->addAction(tr("Pause"), this, [this] { watcher_->control("pause"); })->setObjectName("remote.pause");
    bar->addAction(tr("Resume"), this, [this] { watcher_->control("resume"); })->setObjectName("remote.resume");
    step_ = bar->addAction(tr("Step 30 ms"), this, [this] { watcher_->control("step", {{"duration", 0.03}}); });
    step_->setObjectName("remote.step");
    bar->addAction(tr("Reset"), this,
                   [this] {
                       watcher_->control("reset");
                       plots_->clear();
                   })
        ->setObjectName("remote.reset");

    connect(field_, &FieldView::robotPlaced, this,
            [this](int robot, const RobotState& pose, bool) { watcher_->placeRobot(robot, pose); });
    connect(field_, &FieldView::ballPlaced, this, [this](const BallState& ball, bool) { watcher_->placeBall(ball); });
    connect(field_, &FieldView::robotSelected, this, [this](int) { plots_->clear(); });
    connect(watcher_, &RemoteWatcher::message, this,
            [this](const QString& text) { statusBar()->showMessage(text, 5000); });
    // A server that went away (restarted, say) is tried again every 2 s.
    reconnect_.setInterval(2000);
    connect(watcher_, &RemoteWatcher::disconnected, this, [this] {
        statusBar()->showMessage(tr("%1 closed the connection: trying again every 2 s").arg(watcher_->address()));
        reconnect_.start();
    });
    connect(&reconnect_, &QTimer::timeout, this, [this] {
        QString error;
        // The attempt runs a nested event loop: a close meanwhile waits for it (closeEvent).
        reconnecting_ = true;
        const bool connected = watcher_->reconnect(&error, 500);
        reconnecting_ = false;
        if (closeWhenDone_) {
            close();
            return;
        }
        if (!connected) return;
        reconnect_.stop();
        plots_->clear();
        statusBar()->showMessage(tr("connected to %1 again").arg(watcher_->address()), 5000);
    });
    status_ = new QLabel(this);
    status_->setObjectName("remote.status");
    statusBar()->addPermanentWidget(status_);
    connect(&timer_, &QTimer::timeout, this, &RemoteWindow::refresh);
    timer_.start(33);
    resize(1100, 720);
}

void RemoteWindow::refresh() {
    const auto snapshot = watcher_->latest();
    if (!snapshot) return;
    field_->showSnapshot(snapshot);
    const int selected = field_->selectedRobot();
    inspector_->showRobot(*snapshot, selected);
    // Step works on a paused or lockstep server only (protocol.md, CONTROL step).
    step_->setEnabled(watcher_->connected() && (watcher_->paused() || watcher_->mode() == RunMode::Lockstep));
    if (selected >= 0) plots_->addSample(*snapshot, selected);
    status_->setText(tr("watching %1   t = %2 s   frame %3")
                         .arg(watcher_->address())
                         .arg(snapshot->time, 0, 'f', 3)
                         .arg(snapshot->frame));
}

void RemoteWindow::closeEvent(QCloseEvent* event) {
    // Deleted while a reconnection attempt's nested event loop runs, the
    // window would return into freed objects: it hides now and closes after.
    if (reconnecting_) {
        closeWhenDone_ = true;
        hide();
        event->ignore();
        return;
    }
    reconnect_.stop();
    event->accept();
}

}  // namespace vssim
