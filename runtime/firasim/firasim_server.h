// FIRASim's network interface on vssim (docs/firasim.md; wire format: shared
// vsss-game.md, "FIRASim's network interface"): commands and replacement in
// over UDP (fira_message.sim_to_ref.Packet, port 20011 by default), vision
// out (fira_message.sim_to_ref.Environment, multicast 224.0.0.1:10002 by
// default) at every camera instant of the engine. Lives in the main thread;
// never blocks.
//
// Each datagram becomes engine requests (packet_reader.h checks it first):
// one WheelSpeeds request per team commanded in it (the newest command per
// robot; the wheel-speed loop turns them into voltages), PlaceBall and
// PlaceRobot for the replacement (robots at rest), SetOnField for turnon.
// The engine's queue is shared fairly: each team's commands, and the
// replacements, have their own quota of requests waiting
// (kMaxQueuedPerSender); a packet beyond it is dropped (counted), so a team
// that floods cannot crowd the other one out.
//
// A flood: at most kMaxDatagramsPerTurn datagrams are read per turn of the
// event loop; the rest waits in the kernel (whose buffer, kReceiveBufferBytes,
// drops beyond). A datagram longer than kMaxDatagramBytes is dropped (counted).
// Every bad input is counted (stats()) and logged through a RateLimitedLog.
//
// Sync mode (--firasim-sync): the engine runs in lockstep; every Packet that
// carries the `cmd` field (even with no command in it) posts its requests
// and then a Step of one vision period, at whose end the Environment goes
// out. Packets without `cmd` (replacement only) and malformed ones do not
// step. Same packets in the same order, each sent after the previous
// Environment arrived: bit-identical vision.
#pragma once

#include <QHostAddress>
#include <QObject>
#include <QTimer>
#include <QUdpSocket>
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "firasim/packet_reader.h"
#include "firasim/rate_limited_log.h"
#include "firasim/team_roster.h"
#include "firasim/vision_feed.h"
#include "realtime/engine_thread.h"

namespace vssim {

struct FirasimSettings {
    QHostAddress listenAddress = QHostAddress::LocalHost;                    // where commands are received
    quint16 commandPort = 20011;                                             // 0: any free port
    QHostAddress visionAddress = QHostAddress(QStringLiteral("224.0.0.1"));  // multicast group or unicast host
    quint16 visionPort = 10002;
    int multicastTtl = 0;           // hops: 0 keeps the vision on this machine
    bool multicastLoopback = true;  // this machine's own sockets get the multicast too
    bool sync = false;              // the engine is in lockstep: each command packet steps one vision period
};

// What the server has seen and done since it started.
struct FirasimStats {
    std::int64_t datagrams = 0;            // received (read)
    std::int64_t commandPackets = 0;       // parsed packets with commands
    std::int64_t commands = 0;             // robot commands applied
    std::int64_t replacements = 0;         // bodies placed, taken off or brought back
    std::int64_t steps = 0;                // sync mode: steps posted
    std::int64_t malformed = 0;            // not a Packet
    std::int64_t oversized = 0;            // longer than kMaxDatagramBytes, dropped
    std::int64_t unknownRobots = 0;        // commands or replacements for robots the scene lacks
    std::int64_t clampedSpeeds = 0;        // NaN, infinite or too large wheel speeds
    std::int64_t refusedReplacements = 0;  // outside the field, overlapping (after the grace), non-finite
    std::int64_t deferredReplacements = 0;  // blocked by a body that moved out of the way within the grace
    std::int64_t busy = 0;                 // packets (or parts) dropped: the sender's quota was full
    std::int64_t deferredTurns = 0;        // turns that left datagrams in the kernel (a flood)
    std::int64_t visionSent = 0;           // Environments sent
    std::int64_t visionDropped = 0;        // Environments the main thread did not take in time
    std::int64_t sendErrors = 0;           // Environments the socket refused
    std::int64_t errors() const {
        return malformed + oversized + unknownRobots + clampedSpeeds + refusedReplacements + busy;
    }
};

class FirasimServer : public QObject {
    Q_OBJECT
public:
    static constexpr int kMaxDatagramsPerTurn = 256;
    // A replacement onto another body waits this long (wall clock) for the
    // body to move away (VSSReferee sends blue's robots, yellow's and the
    // ball in three datagrams) before it is refused. In sync mode a packet
    // that ticks decides at once, so that runs stay deterministic.
    static constexpr std::int64_t kOverlapGraceNs = 20'000'000;
    // What the server placed lately counts as where the bodies are, until
    // the vision shows it (a camera period or two).
    static constexpr std::int64_t kRecentPlacementNs = 200'000'000;
    static constexpr int kMaxDatagramBytes = 8192;
    static constexpr int kReceiveBufferBytes = 1 << 20;
    static constexpr int kMaxQueuedPerSender = 64;  // requests waiting for the engine, per team and for replacements

    // A server for `engine`, which must not have started yet (it registers a
    // VisionFeed), or, when `feed` is given, one attached to it before start.
    FirasimServer(const Scene& scene, EngineThread& engine, const FirasimSettings& settings,
                  std::shared_ptr<VisionFeed> feed = nullptr, QObject* parent = nullptr);
    ~FirasimServer() override;

    // Binds the command socket and prepares the vision socket; false with
    // `error` set when it cannot.
    bool listen(QString* error);
    bool listening() const { return listening_; }
    QHostAddress address() const { return commands_.localAddress(); }
    quint16 port() const { return commands_.localPort(); }
    const FirasimSettings& settings() const { return settings_; }
    const FirasimStats& stats() const { return stats_; }
    // Whether the vision address is a multicast group.
    bool multicast() const { return settings_.visionAddress.isMulticast(); }

signals:
    void logLine(const QString& line);

private:
    void readTurn();
    void handleDatagram(const QByteArray& data, std::int64_t arrivalNs);
    // Posts requests the engine handles together (EngineThread::postGroup);
    // false: that sender's quota is full, or the engine's queue.
    bool post(std::vector<EngineRequest> group, int sender);
    void sendVision();
    // The bodies as the server last knew them: the latest vision, with the
    // replacements it posted since on top (`present`: on the field).
    WorldState knownWorld(std::vector<char>& present, std::int64_t nowNs);
    // Blocked replacements: applies those now clear, refuses those whose
    // grace is over (or all of them, `final`), and sets the timer for the rest.
    void retryBlocked(std::int64_t nowNs, bool final);
    bool postPlacement(const FirasimPlacement& placement, std::int64_t arrivalNs);
    bool postBall(const BallState& ball, std::int64_t arrivalNs);
    void log(const QString& line);

    Scene scene_;
    TeamRoster roster_;
    EngineThread& engine_;
    FirasimSettings settings_;
    std::shared_ptr<VisionFeed> feed_;
    QUdpSocket commands_;
    QUdpSocket vision_;
    bool listening_ = false;
    bool turnScheduled_ = false;
    // Requests queued and not yet handled, by sender: [0] yellow's commands,
    // [1] blue's, [2] replacements, [3] sync steps.
    std::array<std::shared_ptr<std::atomic<int>>, 4> queued_;
    FirasimStats stats_;
    RateLimitedLog badInput_;
    QByteArray buffer_;
    struct Blocked {
        std::int64_t deadlineNs = 0;
        bool ball = false;
        FirasimPlacement placement;  // !ball
        BallState ballState;         // ball
        QString why;                 // the log line if it is refused
    };
    std::vector<Blocked> blocked_;
    QTimer blockedTimer_;
    std::map<int, std::pair<std::int64_t, RobotState>> recentRobots_;  // posted placements: (when, pose)
    std::optional<std::pair<std::int64_t, BallState>> recentBall_;
};

}  // namespace vssim
