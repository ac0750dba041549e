// Watching a `vssim serve` running elsewhere (another process, another
// machine), as an observer client of docs/protocol.md: the WELCOME gives the
// scene's shape (field, robots, ball) and each STATE a Snapshot, so the same
// field view, inspector and plots work on it. Control goes out as CONTROL
// messages (pause, resume, step, reset, place_robot, place_ball).
#pragma once

#include <QObject>
#include <memory>

#include "net/protocol_client.h"
#include "realtime/snapshot.h"

namespace vssim {

class RemoteWatcher : public QObject {
    Q_OBJECT
public:
    explicit RemoteWatcher(QObject* parent = nullptr);
    ~RemoteWatcher() override;
    // Connects and says HELLO as an observer of the ground truth; false and
    // *error (what and where) when that fails.
    bool connectTo(const QString& host, quint16 port, QString* error, int timeoutMs = 5000);
    // The same server again (it restarted); false while it is not back.
    bool reconnect(QString* error, int timeoutMs = 1000) { return connectTo(host_, port_, error, timeoutMs); }
    std::shared_ptr<const Snapshot> latest() const { return latest_; }
    // As the server last said (WELCOME, and the replies to pause and resume).
    bool paused() const { return paused_; }
    RunMode mode() const { return mode_; }
    bool connected() const;
    QString address() const { return address_; }
    // CONTROL messages; `args` as in docs/protocol.md.
    void control(const QString& command, const QJsonObject& args = {});
    void placeRobot(int robot, const RobotState& pose);
    void placeBall(const BallState& ball);

signals:
    void snapshotReceived();
    void message(const QString& text);  // errors and replies, for a status bar
    void disconnected();

private:
    void drain();
    ProtocolClient client_;
    std::shared_ptr<const Scene> scene_;
    std::shared_ptr<const Snapshot> latest_;
    QString address_;
    QString host_;
    quint16 port_ = 0;
    RunMode mode_ = RunMode::Realtime;
    bool paused_ = false;
    double speed_ = 1.0;
};

// A Snapshot from a STATE message's JSON and the scene from the WELCOME.
std::optional<Snapshot> snapshotFromState(const QJsonObject& state, std::shared_ptr<const Scene> scene);
// The scene a WELCOME describes (field, ball radius, robots' names, teams,
// sides and maximum voltages; other parameters are the defaults).
std::optional<Scene> sceneFromWelcome(const QJsonObject& welcome, QString* error);

}  // namespace vssim
