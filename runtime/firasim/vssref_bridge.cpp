#include "firasim/vssref_bridge.h"

#include <QMetaObject>
#include <QNetworkDatagram>
#include <cmath>

#include "realtime/monotonic_clock.h"
#include "vssim/game/placement.h"

namespace vssim {

namespace {

// A VSSRef_Placement of six robots is about 150 bytes; anything far larger
// is not one (read and dropped as malformed).
constexpr qint64 kMaxPlacementBytes = 4096;
// Datagrams read per turn of the event loop (the rest waits for the next
// turn, behind the vision and the TCP clients), and placements of one team
// waiting for the engine (more are dropped: a team's flood cannot fill the
// engine's queue ahead of the other team's commands).
constexpr int kMaxPlacementsPerTurn = 64;
constexpr int kMaxQueuedPlacementsPerTeam = 8;

QString describe(const QHostAddress& address, quint16 port) {
    return QStringLiteral("%1:%2").arg(address.toString()).arg(port);
}

}  // namespace

VssRefBridge::VssRefBridge(const Scene& scene, EngineThread& engine, const VssRefSettings& settings, QObject* parent)
    : QObject(parent),
      scene_(scene),
      engine_(engine),
      settings_(settings),
      roster_(scene),
      model_(makeWorldModel(scene)),
      shared_(std::make_shared<Shared>()),
      log_([this](const QString& line) { emit logLine(line); }) {
    for (const RobotSpec& robot : scene.robots) {
        teams_.push_back(robot.team);
        names_.push_back(robot.name);
    }
    shared_->owner = this;
    // The observer holds the shared state, not the bridge: it outlives the bridge.
    std::shared_ptr<Shared> shared = shared_;
    engine_.addInstantObserver([shared](const InstantRecord& record) { observe(*shared, record); });
    repeat_.setTimerType(Qt::PreciseTimer);
    connect(&repeat_, &QTimer::timeout, this, &VssRefBridge::repeatCurrent);
    connect(&placementSocket_, &QUdpSocket::readyRead, this, &VssRefBridge::readPlacements);
}

VssRefBridge::~VssRefBridge() {
    std::lock_guard lock(shared_->mutex);
    shared_->owner = nullptr;  // queued calls to this object are dropped with it (QObject)
}

// On the engine thread: copy what the commands and the placement checks
// need, and queue a change when the command's contents changed.
void VssRefBridge::observe(Shared& shared, const InstantRecord& record) {
    std::lock_guard lock(shared.mutex);
    Latest& latest = shared.latest;
    latest.seen = true;
    latest.referee = record.referee;
    latest.time = record.time;
    if (!record.referee) return;
    latest.game.phase = record.game.phase;
    latest.game.half = record.game.half;
    latest.game.last = record.game.last;
    latest.calls = record.game.calls.size();
    if (record.game.phase == GamePhase::Stop) latest.world = record.world;
    const VssRefCommandKey key = vssRefCommandKey(record.game);
    if (shared.haveKey && key == shared.key) return;
    shared.haveKey = true;
    shared.key = key;
    shared.changes.push_back({key, vssRefCommand(latest.game, record.time)});
    if (shared.changes.size() == 1 && shared.owner)
        QMetaObject::invokeMethod(shared.owner, &VssRefBridge::sendChanges, Qt::QueuedConnection);
}

bool VssRefBridge::open(QString* error) {
    // The multicast interface: the one named, or the loopback one.
    if (settings_.commandAddress.isMulticast() || settings_.placementAddress.isMulticast()) {
        if (settings_.interfaceName.isEmpty()) {
            for (const QNetworkInterface& i : QNetworkInterface::allInterfaces())
                if (i.flags().testFlag(QNetworkInterface::IsLoopBack)) {
                    interface_ = i;
                    break;
                }
        } else {
            interface_ = QNetworkInterface::interfaceFromName(settings_.interfaceName);
        }
        if (!interface_.isValid()) {
            *error = settings_.interfaceName.isEmpty()
                         ? QStringLiteral("no loopback network interface for VSSReferee's multicast")
                         : QStringLiteral("no network interface \"%1\"").arg(settings_.interfaceName);
            return false;
        }
    }

    // Commands out. A multicast sender binds the interface's IPv4 address;
    // a unicast one to this host binds loopback.
    QHostAddress from(QHostAddress::AnyIPv4);
    if (settings_.commandAddress.isMulticast()) {
        for (const QNetworkAddressEntry& entry : interface_.addressEntries())
            if (entry.ip().protocol() == QAbstractSocket::IPv4Protocol) {
                from = entry.ip();
                break;
            }
    } else if (settings_.commandAddress.isLoopback()) {
        from = QHostAddress(QHostAddress::LocalHost);
    }
    if (!commandSocket_.bind(from, 0)) {
        *error =
            QStringLiteral("VSSRef commands: cannot bind %1: %2").arg(from.toString(), commandSocket_.errorString());
        return false;
    }
    if (settings_.commandAddress.isMulticast()) {
        commandSocket_.setSocketOption(QAbstractSocket::MulticastTtlOption, settings_.multicastTtl);
        commandSocket_.setSocketOption(QAbstractSocket::MulticastLoopbackOption, 1);
        commandSocket_.setMulticastInterface(interface_);
    }

    // Placements in.
    const QHostAddress& at = settings_.placementAddress;
    if (at.isMulticast()) {
        // Bound to the group itself, so that only its datagrams arrive;
        // shared, so that other listeners (VSSReferee) may bind it too.
        const auto mode = QAbstractSocket::ShareAddress | QAbstractSocket::ReuseAddressHint;
        if (!placementSocket_.bind(at, settings_.placementPort, mode) &&
            !placementSocket_.bind(QHostAddress::AnyIPv4, settings_.placementPort, mode)) {
            *error = QStringLiteral("VSSRef placements: cannot bind port %1: %2")
                         .arg(settings_.placementPort)
                         .arg(placementSocket_.errorString());
            return false;
        }
        if (!placementSocket_.joinMulticastGroup(at, interface_)) {
            *error = QStringLiteral("VSSRef placements: cannot join %1 on %2: %3")
                         .arg(at.toString(), interface_.name(), placementSocket_.errorString());
            placementSocket_.close();
            return false;
        }
    } else if (!placementSocket_.bind(at, settings_.placementPort)) {
        *error = QStringLiteral("VSSRef placements: cannot bind %1: %2")
                     .arg(describe(at, settings_.placementPort), placementSocket_.errorString());
        return false;
    }

    if (settings_.repeatSeconds > 0.0) {
        repeat_.start(static_cast<int>(std::max(1.0, std::round(settings_.repeatSeconds * 1000.0))));
    }
    sendChanges();  // anything the engine reported before
    return true;
}

bool VssRefBridge::lastCommand(VSSRef::ref_to_team::VSSRef_Command* command) const {
    if (!sent_) return false;
    *command = last_;
    return true;
}

void VssRefBridge::sendChanges() {
    if (commandSocket_.state() != QAbstractSocket::BoundState) return;  // open() sends them
    std::vector<Change> changes;
    {
        std::lock_guard lock(shared_->mutex);
        changes.swap(shared_->changes);
    }
    for (const Change& change : changes) send(change.command);
}

void VssRefBridge::repeatCurrent() {
    sendChanges();
    if (!sent_) return;
    VSSRef::ref_to_team::VSSRef_Command command = last_;
    {
        std::lock_guard lock(shared_->mutex);
        if (!shared_->latest.referee) return;
        command.set_timestamp(shared_->latest.time);
    }
    send(command);
}

void VssRefBridge::send(const VSSRef::ref_to_team::VSSRef_Command& command) {
    const std::string bytes = command.SerializeAsString();
    const qint64 n = commandSocket_.writeDatagram(bytes.data(), static_cast<qint64>(bytes.size()),
                                                  settings_.commandAddress, settings_.commandPort);
    last_ = command;
    sent_ = true;
    if (n == static_cast<qint64>(bytes.size())) {
        ++stats_.commandsSent;
    } else {
        ++stats_.sendErrors;
        log(QStringLiteral("VSSRef command to %1 not sent: %2")
                .arg(describe(settings_.commandAddress, settings_.commandPort), commandSocket_.errorString()));
    }
}

void VssRefBridge::readPlacements() {
    readScheduled_ = false;
    for (int read = 0; placementSocket_.hasPendingDatagrams(); ++read) {
        if (read == kMaxPlacementsPerTurn) {
            if (!readScheduled_) {
                readScheduled_ = true;
                QTimer::singleShot(0, this, &VssRefBridge::readPlacements);
            }
            return;
        }
        const qint64 size = placementSocket_.pendingDatagramSize();
        if (size > kMaxPlacementBytes) {
            const QNetworkDatagram dropped = placementSocket_.receiveDatagram(0);  // discards it
            ++stats_.placementDatagrams;
            ++stats_.malformed;
            log(QStringLiteral("VSSRef placement from %1: %2 bytes, not a placement; ignored")
                    .arg(describe(dropped.senderAddress(), static_cast<quint16>(dropped.senderPort())))
                    .arg(size));
            continue;
        }
        const QNetworkDatagram datagram = placementSocket_.receiveDatagram(kMaxPlacementBytes);
        if (!datagram.isValid()) break;
        ++stats_.placementDatagrams;
        handlePlacement(datagram.data(), datagram.senderAddress());
    }
}

void VssRefBridge::handlePlacement(const QByteArray& bytes, const QHostAddress& from) {
    const QString source = QStringLiteral("VSSRef placement from %1").arg(from.toString());
    VSSRef::team_to_ref::VSSRef_Placement message;
    if (!message.ParseFromArray(bytes.constData(), static_cast<int>(bytes.size())) || !message.has_world()) {
        ++stats_.malformed;
        log(QStringLiteral("%1: %2 bytes that are not a VSSRef_Placement with a world frame; ignored")
                .arg(source)
                .arg(bytes.size()));
        return;
    }
    QString why;
    const std::optional<VssRefTeamPlacement> placement = vssRefPlacement(message, scene_, roster_, &why);
    if (!placement) {
        ++stats_.rejected;
        log(QStringLiteral("%1 refused: %2").arg(source, why));
        return;
    }
    Latest latest;
    {
        std::lock_guard lock(shared_->mutex);
        latest = shared_->latest;
    }
    if (!latest.referee || latest.game.phase != GamePhase::Stop) {
        ++stats_.notStopped;
        log(QStringLiteral("%1 (%2) refused: %3")
                .arg(source, QString::fromLatin1(teamLabel(placement->team)),
                     !latest.referee ? QStringLiteral("the built-in referee is off")
                                     : QStringLiteral("placements are taken only while the game is stopped "
                                                      "(KICKOFF, FREE_BALL, PENALTY_KICK, GOAL_KICK); it is %1")
                                           .arg(QString::fromLatin1(gamePhaseName(latest.game.phase)))));
        return;
    }
    // The referee's rules for the call, against the bodies as the engine
    // last reported them (it checks again when it applies the placement).
    Placement proposed;
    proposed.robots = latest.world.robots;
    proposed.ball = latest.world.ball;
    proposed.offField = latest.world.offField;
    if (proposed.robots.size() == scene_.robots.size()) {
        for (const auto& [robot, pose] : placement->poses) proposed.robots[static_cast<std::size_t>(robot)] = pose;
        const std::string illegal =
            checkTeamPlacement(model_, teams_, names_, scene_.game.rules, latest.game.last, placement->team, proposed);
        if (!illegal.empty()) {
            ++stats_.illegal;
            log(QStringLiteral("%1 (%2) refused: %3 (for the %4); the referee's placement stays")
                    .arg(source, QString::fromLatin1(teamLabel(placement->team)), QString::fromStdString(illegal),
                         QString::fromLatin1(callName(latest.game.last.call))));
            return;
        }
    }
    EngineRequest request;
    request.kind = EngineRequest::Kind::Placement;
    request.command = QStringLiteral("vssref_placement");
    request.arrivalNs = monotonicNs();
    request.client = -1;  // no reply
    request.team = placement->team;
    request.poses = placement->poses;
    const std::shared_ptr<std::atomic<int>>& queued = queuedPlacements_[teamIndex(placement->team)];
    if (queued->load() >= kMaxQueuedPlacementsPerTeam) {
        ++stats_.engineBusy;
        log(QStringLiteral("%1 dropped: %2 of this team's placements already wait for the engine")
                .arg(source)
                .arg(kMaxQueuedPlacementsPerTeam));
        return;
    }
    request.queued = queued;
    queued->fetch_add(1);
    if (!engine_.post(std::move(request))) {
        queued->fetch_sub(1);
        ++stats_.engineBusy;
        log(QStringLiteral("%1 dropped: the engine's queue is full").arg(source));
        return;
    }
    ++stats_.placementsPosted;
}

void VssRefBridge::log(const QString& line) { log_.log(line, monotonicNs()); }

}  // namespace vssim
