#include "firasim/firasim_server.h"

#include <QTimer>

#include "firasim/packet_reader.h"
#include "realtime/monotonic_clock.h"

namespace vssim {

namespace {
constexpr int kCommandsYellow = 0, kCommandsBlue = 1, kReplacements = 2, kSteps = 3;
}

FirasimServer::FirasimServer(const Scene& scene, EngineThread& engine, const FirasimSettings& settings,
                             std::shared_ptr<VisionFeed> feed, QObject* parent)
    : QObject(parent),
      scene_(scene),
      roster_(scene),
      engine_(engine),
      settings_(settings),
      feed_(feed ? std::move(feed) : VisionFeed::attach(engine)),
      commands_(this),
      vision_(this),
      badInput_([this](const QString& line) { emit logLine(QStringLiteral("firasim: ") + line); }) {
    for (auto& q : queued_) q = std::make_shared<std::atomic<int>>(0);
    connect(&commands_, &QUdpSocket::readyRead, this, &FirasimServer::readTurn);
    blockedTimer_.setSingleShot(true);
    connect(&blockedTimer_, &QTimer::timeout, this, [this] { retryBlocked(monotonicNs(), false); });
}

FirasimServer::~FirasimServer() {
    // No wake-up comes after this; queued ones die with the object.
    feed_->deactivate();
}

bool FirasimServer::listen(QString* error) {
    if (!commands_.bind(settings_.listenAddress, settings_.commandPort)) {
        *error = QStringLiteral("FIRASim commands: cannot listen on %1:%2: %3")
                     .arg(settings_.listenAddress.toString())
                     .arg(settings_.commandPort)
                     .arg(commands_.errorString());
        return false;
    }
    commands_.setSocketOption(QAbstractSocket::ReceiveBufferSizeSocketOption, kReceiveBufferBytes);
    const bool v6 = settings_.visionAddress.protocol() == QAbstractSocket::IPv6Protocol;
    if (!vision_.bind(v6 ? QHostAddress(QHostAddress::AnyIPv6) : QHostAddress(QHostAddress::AnyIPv4), 0)) {
        *error = QStringLiteral("FIRASim vision: cannot open a socket: %1").arg(vision_.errorString());
        commands_.close();
        return false;
    }
    if (multicast()) {
        vision_.setSocketOption(QAbstractSocket::MulticastTtlOption, settings_.multicastTtl);
        vision_.setSocketOption(QAbstractSocket::MulticastLoopbackOption, settings_.multicastLoopback ? 1 : 0);
    }
    listening_ = true;
    feed_->activate(scene_,
                    [this] { QMetaObject::invokeMethod(this, &FirasimServer::sendVision, Qt::QueuedConnection); });
    return true;
}

void FirasimServer::readTurn() {
    turnScheduled_ = false;
    // Every turn reads at least once, even when Qt said readyRead and an
    // earlier turn took the datagram already: a QUdpSocket stops notifying
    // until readDatagram() is called after its readyRead.
    for (int n = 0;; ++n) {
        if (n == kMaxDatagramsPerTurn) {
            // The rest waits in the kernel: vision and the other events go first.
            ++stats_.deferredTurns;
            if (!turnScheduled_) {
                turnScheduled_ = true;
                QTimer::singleShot(0, this, &FirasimServer::readTurn);
            }
            return;
        }
        // One byte more than allowed: a datagram that fills it is too long
        // (the kernel drops the part that does not fit).
        buffer_.resize(kMaxDatagramBytes + 1);
        const qint64 got = commands_.readDatagram(buffer_.data(), buffer_.size());
        if (got < 0) return;  // nothing more waits
        const std::int64_t arrivalNs = monotonicNs();
        ++stats_.datagrams;
        if (got > kMaxDatagramBytes) {
            ++stats_.oversized;
            log(QStringLiteral("a datagram of more than %1 bytes dropped").arg(kMaxDatagramBytes));
            continue;
        }
        buffer_.resize(static_cast<qsizetype>(got));
        handleDatagram(buffer_, arrivalNs);
    }
}

bool FirasimServer::post(std::vector<EngineRequest> group, int sender) {
    const std::shared_ptr<std::atomic<int>>& queued = queued_[static_cast<std::size_t>(sender)];
    const int n = static_cast<int>(group.size());
    // Beyond the quota, unless nothing of this sender waits (a replacement of
    // every robot of a big scene is one group larger than the quota).
    if (queued->load() > 0 && queued->load() + n > kMaxQueuedPerSender) return false;
    for (EngineRequest& r : group) r.queued = queued;
    queued->fetch_add(n);
    if (!engine_.postGroup(std::move(group))) {
        queued->fetch_sub(n);
        return false;
    }
    return true;
}

WorldState FirasimServer::knownWorld(std::vector<char>& present, std::int64_t nowNs) {
    const std::optional<WorldState> latest = feed_->latestWorld();
    WorldState world = latest ? *latest : initialWorldState(scene_);
    present = feed_->onField();
    present.resize(scene_.robots.size(), 1);
    for (auto it = recentRobots_.begin(); it != recentRobots_.end();) {
        if (nowNs - it->second.first > kRecentPlacementNs) {
            it = recentRobots_.erase(it);
            continue;
        }
        if (it->first < static_cast<int>(world.robots.size())) world.robots[it->first] = it->second.second;
        ++it;
    }
    if (recentBall_ && nowNs - recentBall_->first > kRecentPlacementNs) recentBall_.reset();
    if (recentBall_) world.ball = recentBall_->second;
    return world;
}

bool FirasimServer::postPlacement(const FirasimPlacement& placement, std::int64_t arrivalNs) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::PlaceRobot;
    r.arrivalNs = arrivalNs;
    r.robot = placement.robot;
    r.robotPose = placement.pose;  // at rest: v = omega = 0
    EngineRequest on = r;
    on.kind = EngineRequest::Kind::SetOnField;  // after the pose; nothing for a robot already on the field
    on.onField = true;
    if (!post({r, on}, kReplacements)) return false;
    ++stats_.replacements;
    feed_->setOnField(placement.robot, true);
    recentRobots_[placement.robot] = {arrivalNs, placement.pose};
    return true;
}

bool FirasimServer::postBall(const BallState& ball, std::int64_t arrivalNs) {
    EngineRequest r;
    r.kind = EngineRequest::Kind::PlaceBall;
    r.arrivalNs = arrivalNs;
    r.ball = ball;
    if (!post({r}, kReplacements)) return false;
    ++stats_.replacements;
    recentBall_ = std::pair{arrivalNs, ball};
    return true;
}

void FirasimServer::retryBlocked(std::int64_t nowNs, bool final) {
    std::int64_t nextDeadline = -1;
    for (bool progress = true; progress && !blocked_.empty();) {
        progress = false;
        for (auto it = blocked_.begin(); it != blocked_.end();) {
            std::vector<char> present;
            const WorldState world = knownWorld(present, nowNs);
            QString onto;
            if (it->ball) {
                onto = firasimBallOverlap(scene_, it->ballState, world.robots, present);
            } else {
                std::vector<RobotState> poses = world.robots;
                poses[static_cast<std::size_t>(it->placement.robot)] = it->placement.pose;
                present[static_cast<std::size_t>(it->placement.robot)] = 1;
                onto = firasimRobotOverlap(scene_, it->placement.robot, poses, present, world.ball);
            }
            if (onto.isEmpty()) {  // the way is clear now
                const bool posted =
                    it->ball ? postBall(it->ballState, nowNs) : postPlacement(it->placement, nowNs);
                if (posted) {
                    ++stats_.deferredReplacements;
                } else {
                    ++stats_.busy;
                    log(QStringLiteral("a replacement dropped: %1 requests already wait for the engine")
                            .arg(kMaxQueuedPerSender));
                }
                it = blocked_.erase(it);
                progress = true;
                continue;
            }
            if (final || nowNs >= it->deadlineNs) {
                ++stats_.refusedReplacements;
                log(it->why);
                it = blocked_.erase(it);
                continue;
            }
            nextDeadline = nextDeadline < 0 ? it->deadlineNs : std::min(nextDeadline, it->deadlineNs);
            ++it;
        }
    }
    if (blocked_.empty()) {
        blockedTimer_.stop();
    } else if (nextDeadline >= 0) {
        blockedTimer_.start(static_cast<int>(std::max<std::int64_t>(1, (nextDeadline - nowNs + 999'999) / 1'000'000)));
    }
}

void FirasimServer::handleDatagram(const QByteArray& data, std::int64_t arrivalNs) {
    std::vector<char> onField;
    const WorldState current = knownWorld(onField, arrivalNs);
    const FirasimPacket p =
        readFirasimPacket(data.constData(), static_cast<int>(data.size()), scene_, roster_, current, onField);
    if (!p.parsed) {
        ++stats_.malformed;
        log(QStringLiteral("a datagram of %1 bytes is not a fira_message.sim_to_ref.Packet: ignored").arg(data.size()));
        return;
    }
    stats_.unknownRobots += p.unknownRobots;
    stats_.clampedSpeeds += p.clampedSpeeds;
    stats_.refusedReplacements += p.refusedOutside + p.refusedBad;
    for (const QString& line : p.problems) log(line);

    const bool step = settings_.sync && p.hasCommands;
    if (p.hasCommands) ++stats_.commandPackets;
    for (int team : {kCommandsYellow, kCommandsBlue}) {
        const auto& speeds = p.wheelSpeeds[static_cast<std::size_t>(team)];
        if (speeds.empty()) continue;
        EngineRequest r;
        r.kind = EngineRequest::Kind::WheelSpeeds;
        r.arrivalNs = arrivalNs;
        r.client = -1;
        r.wheelSpeeds = speeds;
        if (post({std::move(r)}, team)) {
            stats_.commands += static_cast<std::int64_t>(speeds.size());
        } else {
            ++stats_.busy;
            log(QStringLiteral("%1's commands dropped: %2 of its requests already wait for the engine")
                    .arg(team == kCommandsYellow ? "yellow" : "blue")
                    .arg(kMaxQueuedPerSender));
        }
    }
    // The replacement as one group, which the engine handles between two
    // steps: robots off, robots placed (and on the field: after the pose, so
    // that a robot coming back never appears where it was left), the ball.
    std::vector<EngineRequest> group;
    auto add = [&](EngineRequest r) {
        r.arrivalNs = arrivalNs;
        r.client = -1;
        group.push_back(std::move(r));
    };
    for (int robot : p.turnOff) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::SetOnField;
        r.robot = robot;
        r.onField = false;
        add(std::move(r));
    }
    for (const FirasimPlacement& placement : p.robots) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::PlaceRobot;
        r.robot = placement.robot;
        r.robotPose = placement.pose;  // at rest: v = omega = 0
        add(r);
        r.kind = EngineRequest::Kind::SetOnField;
        r.onField = true;  // nothing for a robot already on the field
        add(std::move(r));
    }
    if (p.ball) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::PlaceBall;
        r.ball = *p.ball;
        add(std::move(r));
    }
    if (!group.empty()) {
        if (post(std::move(group), kReplacements)) {
            stats_.replacements += static_cast<std::int64_t>(p.turnOff.size() + p.robots.size() + (p.ball ? 1 : 0));
            for (int robot : p.turnOff) feed_->setOnField(robot, false);
            for (const FirasimPlacement& placement : p.robots) {
                feed_->setOnField(placement.robot, true);
                recentRobots_[placement.robot] = {arrivalNs, placement.pose};
            }
            if (p.ball) recentBall_ = std::pair{arrivalNs, *p.ball};
        } else {
            ++stats_.busy;
            log(QStringLiteral("a replacement dropped: %1 requests already wait for the engine")
                    .arg(kMaxQueuedPerSender));
        }
    }
    // Replacements onto a body wait for it to move (a referee's next datagram),
    // or, in sync mode, are decided before this packet's tick.
    for (const auto& [placement, why] : p.blocked) blocked_.push_back({arrivalNs + kOverlapGraceNs, false, placement, {}, why});
    if (p.blockedBall) blocked_.push_back({arrivalNs + kOverlapGraceNs, true, {}, *p.blockedBall, p.blockedBallWhy});
    if (!blocked_.empty()) retryBlocked(arrivalNs, step);
    if (step) {
        // Sync mode: after this packet's commands and replacement (the queue keeps their order).
        EngineRequest r;
        r.kind = EngineRequest::Kind::Step;
        r.arrivalNs = arrivalNs;
        r.client = -1;
        r.duration = engine_.framePeriod();  // one vision period (the engine rounds it up to whole steps)
        if (post({std::move(r)}, kSteps)) {
            ++stats_.steps;
        } else {
            ++stats_.busy;
            log(QStringLiteral("sync: a tick dropped: %1 steps already wait for the engine").arg(kMaxQueuedPerSender));
        }
    }
}

void FirasimServer::sendVision() {
    for (const VisionItem& item : feed_->take()) {
        if (vision_.writeDatagram(item.bytes, settings_.visionAddress, settings_.visionPort) < 0) {
            ++stats_.sendErrors;
            log(QStringLiteral("vision to %1:%2 not sent: %3")
                    .arg(settings_.visionAddress.toString())
                    .arg(settings_.visionPort)
                    .arg(vision_.errorString()));
        } else {
            ++stats_.visionSent;
        }
    }
    stats_.visionDropped = feed_->dropped();
}

void FirasimServer::log(const QString& line) { badInput_.log(line, monotonicNs()); }

}  // namespace vssim
