// vssim's built-in referee speaking VSSReferee's protocol (docs/firasim.md, "VSSReferee's protocol"):
// team software written for the league's automatic referee plays against
// vssim's own, without running VSSReferee.
//
//  - Commands out: a VSSRef_Command (vssref_command.h) to the command
//    address (multicast 224.5.23.2:10003 by default) whenever the game's
//    phase, call or half changes, in the order the engine went through
//    them, and the current one again every `repeatSeconds` of wall time, so
//    that a client that joins late learns the state.
//  - Placements in: VSSRef_Placement datagrams on the placement address
//    (multicast 224.5.23.2:10004 by default: the bridge joins the group on
//    the chosen interface; a unicast address is bound instead). A valid one
//    during STOP that keeps the rules of the call becomes the team's own
//    placement (EngineRequest::Placement), which the engine checks again.
//    Bad datagrams are counted (stats()) and logged at a bounded rate
//    (logLine), never fatal.
//
// Multicast stays on the host by default (TTL 0, the loopback interface).
// The team roster (team colour + id -> robot index) is the scene's given at
// construction; a scene loaded later with other robots is not followed.
#pragma once

#include <QHostAddress>
#include <QNetworkInterface>
#include <QObject>
#include <QString>
#include <QTimer>
#include <QUdpSocket>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "firasim/rate_limited_log.h"
#include "firasim/team_roster.h"
#include "firasim/vssref_command.h"
#include "realtime/engine_thread.h"
#include "vssim/world_model.h"

namespace vssim {

struct VssRefSettings {
    QHostAddress commandAddress{QStringLiteral("224.5.23.2")};  // multicast group or unicast host
    quint16 commandPort = 10003;
    QHostAddress placementAddress{QStringLiteral("224.5.23.2")};  // group to join, or unicast address to bind
    quint16 placementPort = 10004;  // 0 with a unicast address: any free port (placementPort())
    int multicastTtl = 0;           // 0: the datagrams never leave this host
    QString interfaceName;          // multicast interface; empty: the loopback interface
    double repeatSeconds = 1.0;     // wall-clock period of repeating the current command, s; 0: never
};

// What the bridge counted since it opened.
struct VssRefStats {
    std::int64_t commandsSent = 0;        // datagrams sent to the command address
    std::int64_t sendErrors = 0;          // sends the system refused
    std::int64_t placementDatagrams = 0;  // datagrams received on the placement address
    std::int64_t placementsPosted = 0;    // valid and legal: handed to the engine
    std::int64_t malformed = 0;           // not a VSSRef_Placement (garbage, no world frame)
    std::int64_t rejected = 0;            // colour NONE, unknown robot ids, NaN, outside the field...
    std::int64_t illegal = 0;             // against the rules of the call being played
    std::int64_t notStopped = 0;          // arrived while the game was not in STOP, or without a referee
    std::int64_t engineBusy = 0;          // the engine's queue, or the team's share of it, was full
};

class VssRefBridge : public QObject {
    Q_OBJECT
public:
    // Registers an observer with `engine`: construct before engine.start().
    VssRefBridge(const Scene& scene, EngineThread& engine, const VssRefSettings& settings, QObject* parent = nullptr);
    ~VssRefBridge() override;

    // Opens the sockets (sending and receiving); false with `*error` when the
    // address cannot be bound or the group joined.
    bool open(QString* error);
    quint16 placementPort() const { return placementSocket_.localPort(); }
    const VssRefSettings& settings() const { return settings_; }
    VssRefStats stats() const { return stats_; }
    // The last command sent (nothing sent yet: false).
    bool lastCommand(VSSRef::ref_to_team::VSSRef_Command* command) const;

signals:
    // A line for the operator's log (bad datagrams, at a bounded rate; send failures).
    void logLine(const QString& line);

private:
    // What the engine thread hands over (under shared_->mutex).
    struct Latest {
        bool seen = false;
        bool referee = false;
        double time = 0.0;  // simulated time of the latest record, s
        GameState game;     // phase, half and last call only (no history, no timers)
        std::size_t calls = 0;
        WorldState world;  // the bodies during STOP (for checking placements)
    };
    struct Change {
        VssRefCommandKey key;
        VSSRef::ref_to_team::VSSRef_Command command;
    };
    struct Shared {
        std::mutex mutex;
        VssRefBridge* owner = nullptr;  // null once the bridge is gone
        Latest latest;
        bool haveKey = false;
        VssRefCommandKey key;         // of the last change queued
        std::vector<Change> changes;  // not yet sent, oldest first
    };
    static void observe(Shared& shared, const InstantRecord& record);
    void sendChanges();
    void repeatCurrent();
    void send(const VSSRef::ref_to_team::VSSRef_Command& command);
    void readPlacements();
    void handlePlacement(const QByteArray& datagram, const QHostAddress& from);
    void log(const QString& line);

    const Scene scene_;
    EngineThread& engine_;
    const VssRefSettings settings_;
    const TeamRoster roster_;
    const WorldModel model_;
    std::vector<Team> teams_;
    std::vector<std::string> names_;
    std::shared_ptr<Shared> shared_;
    QUdpSocket commandSocket_;
    QUdpSocket placementSocket_;
    QNetworkInterface interface_;
    QTimer repeat_;
    RateLimitedLog log_;
    VssRefStats stats_;
    bool sent_ = false;
    VSSRef::ref_to_team::VSSRef_Command last_;
    bool readScheduled_ = false;  // a turn to read the rest of the placements is queued
    // Placements posted and not yet handled by the engine, by team ([Yellow], [Blue]).
    std::array<std::shared_ptr<std::atomic<int>>, 2> queuedPlacements_{std::make_shared<std::atomic<int>>(0),
                                                                        std::make_shared<std::atomic<int>>(0)};
};

}  // namespace vssim
