// vssim's referee speaking VSSReferee's protocol (docs/firasim.md, "VSSReferee's protocol"): the
// translation of GameState to VSSRef_Command and of VSSRef_Placement to a
// team's placement, both ways, and the bridge in process with an engine in
// lockstep on the built-in kick-off (both teams remote): the kick-off, GAME_ON
// after the stop, a goal and the conceding team's kick-off, a team's own
// placement during STOP, illegal and malformed placements. Unicast on
// 127.0.0.1 throughout; one test tries multicast on loopback and says which
// it ran.
#include <QNetworkDatagram>
#include <QNetworkInterface>
#include <QUdpSocket>
#include <QtTest>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

#include "firasim/vssref_bridge.h"
#include "firasim/vssref_command.h"
#include "io/scene_io.h"
#include "realtime/engine_thread.h"
#include "vssim/game/placement.h"

using namespace vssim;
using VSSRef::ref_to_team::VSSRef_Command;
using VSSRef::team_to_ref::VSSRef_Placement;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The built-in kick-off with the referee on and both teams left to clients
// (nobody drives: the robots stand still unless placed).
Scene kickoffRemote() {
    QString error;
    std::optional<Scene> scene = loadSceneFile(":/scenes/kickoff_3v3.json", &error);
    if (!scene) qFatal("%s", qPrintable(error));
    scene->commands.clear();
    scene->game.rules.referee = true;
    scene->game.yellow = TeamControl::Remote;
    scene->game.blue = TeamControl::Remote;
    return *scene;
}

GameState stopped(Call call, Team team, int quadrant, int half = 1) {
    GameState g;
    g.phase = GamePhase::Stop;
    g.half = half;
    g.last.call = call;
    g.last.team = team;
    g.last.quadrant = quadrant;
    return g;
}

VSSRef_Placement placementOf(VSSRef::Color color, const std::vector<std::array<double, 4>>& robots) {
    VSSRef_Placement p;
    p.mutable_world()->set_teamcolor(color);
    for (const auto& [id, x, y, degrees] : robots) {
        VSSRef::Robot* r = p.mutable_world()->add_robots();
        r->set_robot_id(static_cast<unsigned>(id));
        r->set_x(x);
        r->set_y(y);
        r->set_orientation(degrees);
    }
    return p;
}

QByteArray bytesOf(const google::protobuf::Message& m) { return QByteArray::fromStdString(m.SerializeAsString()); }

// The latest record the engine reported, for the tests to compare with.
struct Watch {
    std::mutex mutex;
    InstantRecord latest;
    InstantRecord get() {
        std::lock_guard lock(mutex);
        return latest;
    }
};

// An engine in lockstep with a bridge on unicast 127.0.0.1: commands to a
// receiver of the test's, placements on a free port.
struct Rig {
    Scene scene = kickoffRemote();
    std::unique_ptr<EngineThread> engine;
    std::unique_ptr<VssRefBridge> bridge;
    std::shared_ptr<Watch> watch = std::make_shared<Watch>();
    QUdpSocket commands;  // the teams' side: receives VSSRef_Command
    QUdpSocket team;      // the teams' side: sends VSSRef_Placement
    QStringList log;

    explicit Rig(double repeatSeconds = 0.0) {
        if (!commands.bind(QHostAddress::LocalHost, 0)) qFatal("cannot bind a receiver");
        EngineLoopSettings loop;
        loop.mode = RunMode::Lockstep;
        engine = std::make_unique<EngineThread>(scene, loop);
        std::shared_ptr<Watch> w = watch;
        engine->addInstantObserver([w](const InstantRecord& r) {
            std::lock_guard lock(w->mutex);
            w->latest = r;
        });
        VssRefSettings settings;
        settings.commandAddress = QHostAddress::LocalHost;
        settings.commandPort = commands.localPort();
        settings.placementAddress = QHostAddress::LocalHost;
        settings.placementPort = 0;
        settings.repeatSeconds = repeatSeconds;
        bridge = std::make_unique<VssRefBridge>(scene, *engine, settings);
        QObject::connect(bridge.get(), &VssRefBridge::logLine, [this](const QString& line) { log << line; });
        QString error;
        if (!bridge->open(&error)) qFatal("%s", qPrintable(error));
        engine->start();
        QElapsedTimer t;
        t.start();
        while (!engine->started() && t.elapsed() < 5000) QThread::msleep(1);
    }
    ~Rig() {
        engine->requestStop();
        engine->wait();
        bridge.reset();
    }

    // The next command the bridge sent (within `ms` of wall time).
    std::optional<VSSRef_Command> nextCommand(int ms = 5000) {
        QElapsedTimer t;
        t.start();
        while (t.elapsed() < ms) {
            QCoreApplication::processEvents();
            if (commands.hasPendingDatagrams()) {
                const QNetworkDatagram d = commands.receiveDatagram();
                VSSRef_Command c;
                if (!c.ParseFromArray(d.data().constData(), static_cast<int>(d.data().size()))) return std::nullopt;
                return c;
            }
            QThread::msleep(1);
        }
        return std::nullopt;
    }

    // Advances simulated time by `duration` s and waits for the engine to get there.
    bool step(double duration) {
        const double target = watch->get().time + duration - 1e-9;
        EngineRequest r;
        r.kind = EngineRequest::Kind::Step;
        r.duration = duration;
        if (!engine->post(r)) return false;
        QElapsedTimer t;
        t.start();
        while (t.elapsed() < 10000) {
            QCoreApplication::processEvents();
            if (watch->get().time >= target) return true;
            QThread::msleep(1);
        }
        return false;
    }

    void place(const BallState& ball) {
        EngineRequest r;
        r.kind = EngineRequest::Kind::PlaceBall;
        r.ball = ball;
        engine->post(r);
    }

    void sendPlacement(const QByteArray& bytes) {
        team.writeDatagram(bytes, QHostAddress::LocalHost, bridge->placementPort());
    }
};

// Whether `team` may put robot `robot` at `pose` now (the referee's own check).
bool legal(const Scene& scene, const InstantRecord& now, Team team, int robot, const RobotState& pose) {
    Placement p;
    p.robots = now.world.robots;
    p.ball = now.world.ball;
    p.robots[static_cast<std::size_t>(robot)] = pose;
    std::vector<Team> teams;
    std::vector<std::string> names;
    for (const RobotSpec& r : scene.robots) teams.push_back(r.team), names.push_back(r.name);
    return checkTeamPlacement(makeWorldModel(scene), teams, names, scene.game.rules, now.game.last, team, p).empty();
}

}  // namespace

class TestVssRef : public QObject {
    Q_OBJECT
private slots:
    void commandForEveryCall();
    void commandForPhasesAndHalves();
    void commandKeyChanges();
    void degreesToRadians();
    void placementTranslated();
    void badPlacements();
    void bridgeGoalKickoffAndPlacements();
    void bridgeRepeatsTheCurrentCommand();
    void bridgeOnMulticastLoopback();
};

void TestVssRef::commandForEveryCall() {
    struct Case {
        Call call;
        Team team;
        int quadrant;
        VSSRef::Foul foul;
        VSSRef::Color color;
        VSSRef::Quadrant q;
    };
    const Case cases[] = {
        {Call::KickOff, Team::Yellow, 0, VSSRef::KICKOFF, VSSRef::YELLOW, VSSRef::NO_QUADRANT},
        {Call::KickOff, Team::Blue, 0, VSSRef::KICKOFF, VSSRef::BLUE, VSSRef::NO_QUADRANT},
        {Call::PenaltyKick, Team::Yellow, 0, VSSRef::PENALTY_KICK, VSSRef::YELLOW, VSSRef::NO_QUADRANT},
        {Call::PenaltyKick, Team::Blue, 0, VSSRef::PENALTY_KICK, VSSRef::BLUE, VSSRef::NO_QUADRANT},
        {Call::GoalKick, Team::Yellow, 0, VSSRef::GOAL_KICK, VSSRef::YELLOW, VSSRef::NO_QUADRANT},
        {Call::GoalKick, Team::Blue, 0, VSSRef::GOAL_KICK, VSSRef::BLUE, VSSRef::NO_QUADRANT},
        {Call::FreeBall, Team::Yellow, 1, VSSRef::FREE_BALL, VSSRef::NONE, VSSRef::QUADRANT_1},
        {Call::FreeBall, Team::Blue, 2, VSSRef::FREE_BALL, VSSRef::NONE, VSSRef::QUADRANT_2},
        {Call::FreeBall, Team::Yellow, 3, VSSRef::FREE_BALL, VSSRef::NONE, VSSRef::QUADRANT_3},
        {Call::FreeBall, Team::Yellow, 4, VSSRef::FREE_BALL, VSSRef::NONE, VSSRef::QUADRANT_4},
        {Call::None, Team::Yellow, 0, VSSRef::STOP, VSSRef::NONE, VSSRef::NO_QUADRANT},
    };
    for (const Case& c : cases) {
        const VSSRef_Command cmd = vssRefCommand(stopped(c.call, c.team, c.quadrant), 12.5);
        QCOMPARE(cmd.foul(), c.foul);
        QCOMPARE(cmd.teamcolor(), c.color);
        QCOMPARE(cmd.foulquadrant(), c.q);
        QCOMPARE(cmd.timestamp(), 12.5);
        QCOMPARE(cmd.gamehalf(), VSSRef::FIRST_HALF);
    }
}

void TestVssRef::commandForPhasesAndHalves() {
    GameState g = stopped(Call::KickOff, Team::Blue, 0, 2);
    g.phase = GamePhase::GameOn;
    VSSRef_Command cmd = vssRefCommand(g, 3.0);
    QCOMPARE(cmd.foul(), VSSRef::GAME_ON);
    QCOMPARE(cmd.teamcolor(), VSSRef::NONE);
    QCOMPARE(cmd.foulquadrant(), VSSRef::NO_QUADRANT);
    QCOMPARE(cmd.gamehalf(), VSSRef::SECOND_HALF);
    g.phase = GamePhase::Halt;
    QCOMPARE(vssRefCommand(g, 3.0).foul(), VSSRef::HALT);
    QCOMPARE(vssRefCommand(g, 3.0).teamcolor(), VSSRef::NONE);
    g.phase = GamePhase::Finished;
    QCOMPARE(vssRefCommand(g, 3.0).foul(), VSSRef::HALT);
    const std::pair<int, VSSRef::Half> halves[] = {
        {1, VSSRef::FIRST_HALF},           {2, VSSRef::SECOND_HALF}, {3, VSSRef::OVERTIME_FIRST_HALF},
        {4, VSSRef::OVERTIME_SECOND_HALF}, {5, VSSRef::NO_HALF},     {0, VSSRef::NO_HALF}};
    for (const auto& [half, want] : halves) {
        g.half = half;
        QCOMPARE(vssRefCommand(g, 0.0).gamehalf(), want);
    }
    // A free ball whose quadrant is out of range says none.
    QCOMPARE(vssRefCommand(stopped(Call::FreeBall, Team::Yellow, 7), 0.0).foulquadrant(), VSSRef::NO_QUADRANT);
}

void TestVssRef::commandKeyChanges() {
    GameState a = stopped(Call::KickOff, Team::Yellow, 0);
    GameState b = a;
    QVERIFY(vssRefCommandKey(a) == vssRefCommandKey(b));
    b.clock = 17.0;  // the clock and the timers are not news
    b.ballStuckFor = 2.0;
    QVERIFY(vssRefCommandKey(a) == vssRefCommandKey(b));
    b.phase = GamePhase::GameOn;
    QVERIFY(vssRefCommandKey(a) != vssRefCommandKey(b));
    b = a;
    b.last.team = Team::Blue;
    QVERIFY(vssRefCommandKey(a) != vssRefCommandKey(b));
    b = a;
    b.half = 2;
    QVERIFY(vssRefCommandKey(a) != vssRefCommandKey(b));
    b = a;
    b.calls.push_back(b.last);  // the same call again (two goals by the same team)
    QVERIFY(vssRefCommandKey(a) != vssRefCommandKey(b));
}

void TestVssRef::degreesToRadians() {
    QCOMPARE(vssRefDegreesToRadians(0.0), 0.0);
    QCOMPARE(vssRefDegreesToRadians(90.0), kPi / 2);
    QCOMPARE(vssRefDegreesToRadians(-90.0), -kPi / 2);
    QCOMPARE(vssRefDegreesToRadians(180.0), kPi);
    QCOMPARE(vssRefDegreesToRadians(-180.0), kPi);  // (-pi, pi]
    QCOMPARE(vssRefDegreesToRadians(270.0), -kPi / 2);
    QCOMPARE(vssRefDegreesToRadians(540.0), kPi);
    QCOMPARE(vssRefDegreesToRadians(-725.0), -5.0 * kPi / 180.0);
    QVERIFY(std::abs(vssRefDegreesToRadians(45.0) - kPi / 4) < 1e-15);
}

void TestVssRef::placementTranslated() {
    const Scene scene = kickoffRemote();
    const TeamRoster roster(scene);
    QString error;
    auto p = vssRefPlacement(placementOf(VSSRef::BLUE, {{{2, 0.3, -0.2, 90.0}}, {{0, 0.6, 0.0, 180.0}}}), scene, roster,
                             &error);
    QVERIFY2(p, qPrintable(error));
    QCOMPARE(p->team, Team::Blue);
    QCOMPARE(p->poses.size(), std::size_t(2));
    QCOMPARE(p->poses[0].first, roster.robotIndex(Team::Blue, 2));
    QCOMPARE(p->poses[0].first, 5);  // blue2 in the scene
    QCOMPARE(p->poses[0].second.x, 0.3);
    QCOMPARE(p->poses[0].second.y, -0.2);
    QCOMPARE(p->poses[0].second.theta, kPi / 2);
    QCOMPARE(p->poses[0].second.v, 0.0);
    QCOMPARE(p->poses[1].first, 3);
    QCOMPARE(p->poses[1].second.theta, kPi);
    p = vssRefPlacement(placementOf(VSSRef::YELLOW, {{{1, -0.3, 0.2, -45.0}}}), scene, roster, &error);
    QVERIFY2(p, qPrintable(error));
    QCOMPARE(p->team, Team::Yellow);
    QCOMPARE(p->poses[0].first, 1);
    QVERIFY(std::abs(p->poses[0].second.theta + kPi / 4) < 1e-15);
}

void TestVssRef::badPlacements() {
    const Scene scene = kickoffRemote();
    const TeamRoster roster(scene);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    struct Case {
        VSSRef_Placement placement;
        const char* expect;  // a piece of the message
    };
    VSSRef_Placement noWorld;
    VSSRef_Placement badColour = placementOf(VSSRef::YELLOW, {{{0, -0.3, 0.0, 0.0}}});
    badColour.mutable_world()->set_teamcolor(static_cast<VSSRef::Color>(9));
    const Case cases[] = {
        {noWorld, "no world frame"},
        {placementOf(VSSRef::NONE, {{{0, 0.3, 0.0, 0.0}}}), "NONE"},
        {badColour, "not a colour"},
        {placementOf(VSSRef::BLUE, {}), "no robots"},
        {placementOf(VSSRef::BLUE, {{{3, 0.3, 0.0, 0.0}}}), "robot_id 3"},
        {placementOf(VSSRef::BLUE, {{{0, 0.3, 0.0, 0.0}}, {{0, 0.5, 0.0, 0.0}}}), "placed twice"},
        {placementOf(VSSRef::BLUE,
                     {{{0, 0.3, 0.0, 0.0}}, {{1, 0.5, 0.0, 0.0}}, {{2, 0.5, 0.3, 0.0}}, {{2, 0.5, -0.3, 0.0}}}),
         "4 robots"},
        {placementOf(VSSRef::BLUE, {{{0, nan, 0.0, 0.0}}}), "not finite"},
        {placementOf(VSSRef::BLUE, {{{0, 0.3, inf, 0.0}}}), "not finite"},
        {placementOf(VSSRef::BLUE, {{{0, 0.3, 0.0, nan}}}), "not finite"},
        {placementOf(VSSRef::BLUE, {{{0, 2.0, 0.0, 0.0}}}), "inside the field"},
        {placementOf(VSSRef::YELLOW, {{{0, -0.74, 0.64, 0.0}}}), "inside the field"},  // through a corner
    };
    for (const Case& c : cases) {
        QString error;
        QVERIFY(!vssRefPlacement(c.placement, scene, roster, &error));
        QVERIFY2(error.contains(QLatin1String(c.expect)), qPrintable(error));
    }
}

void TestVssRef::bridgeGoalKickoffAndPlacements() {
    Rig rig;
    // Instant 0: the first half's kick-off, yellow's.
    std::optional<VSSRef_Command> c = rig.nextCommand();
    QVERIFY(c);
    QCOMPARE(c->foul(), VSSRef::KICKOFF);
    QCOMPARE(c->teamcolor(), VSSRef::YELLOW);
    QCOMPARE(c->foulquadrant(), VSSRef::NO_QUADRANT);
    QCOMPARE(c->gamehalf(), VSSRef::FIRST_HALF);
    QCOMPARE(c->timestamp(), 0.0);

    // GAME_ON after the stop (4 s), told at the first camera instant after
    // it: in lockstep, the end of the step.
    QVERIFY(rig.step(4.5));
    c = rig.nextCommand();
    QVERIFY(c);
    QCOMPARE(c->foul(), VSSRef::GAME_ON);
    QCOMPARE(c->teamcolor(), VSSRef::NONE);
    QVERIFY2(std::abs(c->timestamp() - 4.5) < 1e-9, qPrintable(QString::number(c->timestamp())));

    // A placement while the game is on: refused, counted.
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{1, 0.4, 0.3, 180.0}}})));
    QTRY_COMPARE(rig.bridge->stats().notStopped, std::int64_t(1));

    // The ball into blue's goal (x > 0.75): yellow scores, blue kicks off.
    BallState ball;
    ball.x = 0.80;
    ball.y = 0.0;
    rig.place(ball);
    QVERIFY(rig.step(0.1));
    c = rig.nextCommand();
    QVERIFY(c);
    QCOMPARE(c->foul(), VSSRef::KICKOFF);
    QCOMPARE(c->teamcolor(), VSSRef::BLUE);
    QCOMPARE(c->gamehalf(), VSSRef::FIRST_HALF);
    QVERIFY2(std::abs(c->timestamp() - 4.6) < 1e-9, qPrintable(QString::number(c->timestamp())));
    const InstantRecord now = rig.watch->get();
    QCOMPARE(now.game.phase, GamePhase::Stop);
    QCOMPARE(now.game.goals[0], 1);

    // Blue places a robot of its own where the rules allow it (a spot the
    // referee's own check accepts, among a few), with its heading in degrees.
    const TeamRoster roster(rig.scene);
    int id = -1;
    RobotState pose;
    for (unsigned candidate : {2u, 1u, 0u}) {
        const std::pair<double, double> spots[] = {{0.45, 0.42}, {0.45, -0.42}, {0.3, 0.5}, {0.3, -0.5}};
        for (const auto& [x, y] : spots) {
            RobotState p;
            p.x = x, p.y = y, p.theta = kPi / 2;  // 90 degrees
            const int robot = roster.robotIndex(Team::Blue, candidate);
            if (legal(rig.scene, now, Team::Blue, robot, p)) {
                id = static_cast<int>(candidate);
                pose = p;
                break;
            }
        }
        if (id >= 0) break;
    }
    QVERIFY2(id >= 0, "no legal spot found for the test's placement");
    const int robot = roster.robotIndex(Team::Blue, static_cast<unsigned>(id));
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{double(id), pose.x, pose.y, 90.0}}})));
    QTRY_COMPARE(rig.bridge->stats().placementsPosted, std::int64_t(1));
    QVERIFY(rig.step(0.03));
    RobotState at = rig.watch->get().world.robots[static_cast<std::size_t>(robot)];
    QCOMPARE(at.x, pose.x);
    QCOMPARE(at.y, pose.y);
    QCOMPARE(at.theta, kPi / 2);
    QCOMPARE(at.v, 0.0);

    // Illegal for the kick-off: a blue robot in yellow's half. Refused before
    // the engine, counted; the robot stays.
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{double(id), -0.4, 0.4, 0.0}}})));
    QTRY_COMPARE(rig.bridge->stats().illegal, std::int64_t(1));
    QVERIFY(rig.log.last().contains("own half"));
    // Bad ones: colour NONE, an id blue does not have, NaN, outside the field.
    rig.sendPlacement(bytesOf(placementOf(VSSRef::NONE, {{{0, 0.4, 0.4, 0.0}}})));
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{5, 0.4, 0.4, 0.0}}})));
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{0, std::nan(""), 0.4, 0.0}}})));
    rig.sendPlacement(bytesOf(placementOf(VSSRef::BLUE, {{{0, 0.4, 3.0, 0.0}}})));
    QTRY_COMPARE(rig.bridge->stats().rejected, std::int64_t(4));
    // Garbage: not protobuf at all, protobuf without a world frame, too big.
    rig.sendPlacement(QByteArray(40, '\xff'));
    rig.sendPlacement(QByteArray("hello, referee"));
    rig.sendPlacement(QByteArray(8000, 'x'));
    QTRY_COMPARE(rig.bridge->stats().malformed, std::int64_t(3));
    QCOMPARE(rig.bridge->stats().placementDatagrams, std::int64_t(1 + 1 + 1 + 4 + 3));
    QCOMPARE(rig.bridge->stats().placementsPosted, std::int64_t(1));
    QVERIFY(rig.step(0.03));
    at = rig.watch->get().world.robots[static_cast<std::size_t>(robot)];
    QCOMPARE(at.x, pose.x);
    QCOMPARE(at.y, pose.y);

    // GAME_ON again after the stop; nothing else was sent in between.
    QVERIFY(rig.step(4.0));
    c = rig.nextCommand();
    QVERIFY(c);
    QCOMPARE(c->foul(), VSSRef::GAME_ON);
    QVERIFY(!rig.nextCommand(100));
    QCOMPARE(rig.bridge->stats().commandsSent, std::int64_t(4));
    QCOMPARE(rig.bridge->stats().sendErrors, std::int64_t(0));
}

void TestVssRef::bridgeRepeatsTheCurrentCommand() {
    Rig rig(0.05);  // every 50 ms of wall time
    std::optional<VSSRef_Command> first = rig.nextCommand();
    QVERIFY(first);
    QCOMPARE(first->foul(), VSSRef::KICKOFF);
    for (int i = 0; i < 3; ++i) {
        const std::optional<VSSRef_Command> again = rig.nextCommand(1000);
        QVERIFY(again);
        QCOMPARE(again->foul(), VSSRef::KICKOFF);
        QCOMPARE(again->teamcolor(), VSSRef::YELLOW);
    }
    QVERIFY(rig.bridge->stats().commandsSent >= 4);
}

void TestVssRef::bridgeOnMulticastLoopback() {
    // The league's group on ports of the test's own (the defaults may be in
    // use by a VSSReferee on this machine).
    const quint16 commandPort = static_cast<quint16>(42000 + QCoreApplication::applicationPid() % 1000);
    const quint16 placementPort = static_cast<quint16>(commandPort + 1000);
    const QHostAddress group(QStringLiteral("224.5.23.2"));
    QNetworkInterface loopback;
    for (const QNetworkInterface& i : QNetworkInterface::allInterfaces())
        if (i.flags().testFlag(QNetworkInterface::IsLoopBack)) loopback = i;
    QUdpSocket receiver;
    QString reason;
    if (!loopback.isValid())
        reason = "no loopback interface";
    else if (!receiver.bind(QHostAddress::AnyIPv4, commandPort, QAbstractSocket::ShareAddress))
        reason = "cannot bind port " + QString::number(commandPort) + ": " + receiver.errorString();
    else if (!receiver.joinMulticastGroup(group, loopback))
        reason = "cannot join 224.5.23.2 on " + loopback.name() + ": " + receiver.errorString();
    if (!reason.isEmpty()) {
        qInfo("multicast unavailable: %s; unicast tested", qPrintable(reason));
        return;
    }

    Scene scene = kickoffRemote();
    EngineLoopSettings loop;
    loop.mode = RunMode::Lockstep;
    EngineThread engine(scene, loop);
    VssRefSettings settings;  // 224.5.23.2, TTL 0, loopback
    settings.commandPort = commandPort;
    settings.placementPort = placementPort;
    settings.repeatSeconds = 0.0;
    auto bridge = std::make_unique<VssRefBridge>(scene, engine, settings);
    QString error;
    if (!bridge->open(&error)) {
        qInfo("multicast unavailable: %s; unicast tested", qPrintable(error));
        return;
    }
    engine.start();
    std::optional<VSSRef_Command> c;
    QElapsedTimer t;
    t.start();
    while (!c && t.elapsed() < 3000) {
        QCoreApplication::processEvents();
        if (receiver.hasPendingDatagrams()) {
            const QNetworkDatagram d = receiver.receiveDatagram();
            VSSRef_Command got;
            if (got.ParseFromArray(d.data().constData(), static_cast<int>(d.data().size()))) c = got;
        }
        QThread::msleep(1);
    }
    if (!c) {
        const VssRefStats s = bridge->stats();
        engine.requestStop();
        engine.wait();
        // Sent but never delivered: the kernel does not loop multicast back.
        QVERIFY2(s.commandsSent > 0 || s.sendErrors > 0, "the bridge sent nothing");
        qInfo("multicast unavailable: %lld commands sent to 224.5.23.2:%u on %s, none delivered; unicast tested",
              static_cast<long long>(s.commandsSent), commandPort, qPrintable(loopback.name()));
        return;
    }
    QCOMPARE(c->foul(), VSSRef::KICKOFF);
    QCOMPARE(c->teamcolor(), VSSRef::YELLOW);

    // A team's placement to the group reaches the bridge (the game is in
    // STOP for yellow's kick-off: a legal one is posted).
    QUdpSocket team;
    team.bind(QHostAddress::AnyIPv4, 0);
    team.setSocketOption(QAbstractSocket::MulticastTtlOption, 0);
    team.setSocketOption(QAbstractSocket::MulticastLoopbackOption, 1);
    team.setMulticastInterface(loopback);
    team.writeDatagram(bytesOf(placementOf(VSSRef::YELLOW, {{{1, -0.45, 0.42, 0.0}}})), group, placementPort);
    QTRY_COMPARE_WITH_TIMEOUT(bridge->stats().placementDatagrams, std::int64_t(1), 3000);
    qInfo("multicast on loopback tested: 224.5.23.2:%u commands, 224.5.23.2:%u placements (posted %lld)", commandPort,
          placementPort, static_cast<long long>(bridge->stats().placementsPosted));
    engine.requestStop();
    engine.wait();
}

QTEST_GUILESS_MAIN(TestVssRef)
#include "test_vssref.moc"
