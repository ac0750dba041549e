// FIRASim's interface end to end (docs/firasim.md): an EngineThread and a
// FirasimServer in process (and `vssim serve --firasim-sync` as a
// subprocess), driven by a C++ client built on our .proto files and
// QUdpSocket. Vision against the ground truth at the same step, replacement
// (degrees), turnon, goals (built-in referee and --referee external), sync
// determinism, bad input and a flood, and multicast on loopback where the kernel allows it. Vision goes to unicast
// 127.0.0.1 except in the multicast case.
#include <QProcess>
#include <QRegularExpression>
#include <QUdpSocket>
#include <QtTest>

#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <thread>

// POSIX sockets: the flooder is a plain sender in a thread of its own.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "firasim/packet_reader.h"
#include "firasim/vision_packet.h"
#include "firasim_client.h"
#include "realtime/monotonic_clock.h"

using namespace vssim;

using namespace vssim::test;

class TestFirasim : public QObject {
    Q_OBJECT
private slots:
    void visionMatchesTheState();
    void visionIsFilledAsFirasimFillsIt();
    void visionNoiseAndVanishing();
    void replacement();
    void turnOffAndOn();
    void replacementAcrossDatagrams();
    void ballOnAWallWithinTheSlack();
    void goalWithTheReferee();
    void goalWithAnExternalReferee();
    void syncIsDeterministic();
    void badInput();
    void flood();
    void multicastOnLoopback();
};

void TestFirasim::visionMatchesTheState() {
    Scene scene = kickoff();
    // Moving bodies, so that speeds and headings are checked too.
    scene.robots[0].initial.v = 0.3;
    scene.robots[0].initial.omega = 1.0;
    scene.robots[4].initial.v = -0.2;
    // Headings beyond a turn: the vision reports them wrapped to [-pi, pi].
    scene.robots[1].initial.theta = 7.5;
    scene.robots[5].initial.theta = -4.0;
    scene.ball.vx = 0.4;
    scene.ball.vy = -0.3;
    Fira f(scene, true);
    const std::optional<Environment> first = f.next();
    QVERIFY(first);
    QCOMPARE(first->step(), 0u);
    for (int k = 0; k < 5; ++k) {
        const Environment env = f.step();
        const WorldState truth = f.truthAt(env.step());
        QCOMPARE(static_cast<std::int64_t>(env.step()), truth.step);
        QCOMPARE(env.frame().ball().x(), truth.ball.x);
        QCOMPARE(env.frame().ball().y(), truth.ball.y);
        QCOMPARE(env.frame().ball().vx(), truth.ball.vx);
        QCOMPARE(env.frame().ball().vy(), truth.ball.vy);
        QCOMPARE(env.frame().ball().z(), scene.ball_params.radius);  // its centre's height, as FIRASim's
        QCOMPARE(env.frame().robots_yellow_size(), 3);
        QCOMPARE(env.frame().robots_blue_size(), 3);
        for (std::size_t i = 0; i < scene.robots.size(); ++i) {
            const bool yellow = scene.robots[i].team == Team::Yellow;
            const unsigned id = static_cast<unsigned>(yellow ? i : i - 3);
            const fira_message::Robot* r = findRobot(env, yellow, id);
            QVERIFY(r);
            const RobotState& s = truth.robots[i];
            QCOMPARE(r->x(), s.x);
            QCOMPARE(r->y(), s.y);
            QVERIFY(r->orientation() >= -M_PI && r->orientation() <= M_PI);
            QVERIFY(std::abs(r->orientation() - std::atan2(std::sin(s.theta), std::cos(s.theta))) < 1e-12);
            QCOMPARE(r->vx(), s.v * std::cos(s.theta));
            QCOMPARE(r->vy(), s.v * std::sin(s.theta));
            QCOMPARE(r->vorientation(), s.omega);
        }
        QCOMPARE(env.field().length(), 1.50);
        QCOMPARE(env.field().width(), 1.30);
        QCOMPARE(env.field().goal_width(), 0.40);
        QCOMPARE(env.field().goal_depth(), 0.10);
        QCOMPARE(env.field().center_radius(), 0.20);
        QCOMPARE(env.field().penalty_width(), 0.70);
        QCOMPARE(env.field().penalty_depth(), 0.15);
        QCOMPARE(env.field().penalty_point(), 0.375);
    }
    // The robot that moves does move in the vision.
    const Environment env = f.step();
    QVERIFY(findRobot(env, true, 0)->x() > scene.robots[0].initial.x + 0.01);
}

void TestFirasim::visionIsFilledAsFirasimFillsIt() {
    // The ball at rest at the centre, as at every kick-off: FIRASim sends
    // z = the height of its centre, so the Ball message is never all
    // defaults (proto3 would send it empty, and clients that convert it to
    // JSON find no "x"). `step` is the simulated time in whole milliseconds,
    // whatever vssim's dt (here 0.5 ms).
    Scene scene = kickoff();
    scene.simulation.dt = 0.0005;
    WorldState world = initialWorldState(scene);
    world.ball = BallState{0.0, 0.0, 0.0, 0.0};
    world.step = 67;
    world.time = 67 * 0.0005;  // 33.5 ms
    const TeamRoster roster(scene);
    const fira_message::sim_to_ref::Environment env =
        firasimEnvironment(firasimField(scene.field), roster, world, scene.ball_params.radius,
                           std::vector<char>(scene.robots.size(), 1), {0, 0});
    QCOMPARE(env.step(), 33u);
    QVERIFY(env.frame().has_ball());
    QCOMPARE(env.frame().ball().z(), scene.ball_params.radius);
    QCOMPARE(env.frame().ball().vz(), 0.0);  // FIRASim leaves it unset
    QVERIFY2(env.frame().ball().ByteSizeLong() > 0, "the ball at the centre is not an empty message on the wire");
    Environment parsed;
    QVERIFY(parsed.ParseFromString(env.SerializeAsString()));
    QVERIFY(parsed.frame().has_ball());
    QCOMPARE(parsed.frame().ball().z(), scene.ball_params.radius);
    // Whole milliseconds from steps whose product rounds below them: 17 ms of 1 ms steps.
    world.time = 17 * 0.001;
    QCOMPARE(firasimEnvironment(firasimField(scene.field), roster, world, scene.ball_params.radius,
                                std::vector<char>(scene.robots.size(), 1), {0, 0})
                 .step(),
             17u);
}

void TestFirasim::visionNoiseAndVanishing() {
    // The scene's camera adds noise to the vision, in metres and radians (the
    // packet's units), and leaves vanished bodies out: measured against the
    // ground truth at the same step over 1500 sync steps, 7 bodies each.
    // Tolerances: 5% on a standard deviation estimated from some 9,000
    // samples (its standard error is 0.75%); 4 binomial standard deviations
    // on the vanishing rate.
    Scene scene = kickoff();
    scene.camera.position_noise = 0.005;  // m
    scene.camera.heading_noise = 0.04;    // rad
    scene.camera.vanish = 0.1;
    scene.camera.seed = 17;
    scene.robots[0].initial.omega = 2.0;  // headings that wrap
    Fira f(scene, true);
    QVERIFY(f.next());
    double seen = 0, missing = 0, n = 0;
    double sx = 0, sxx = 0, sy = 0, syy = 0, st = 0, stt = 0, samples = 0, thetaSamples = 0;
    for (int k = 0; k < 1500; ++k) {
        const Environment env = f.step();
        const WorldState truth = f.truthAt(env.step());
        auto add = [&](double x, double y, double tx, double ty) {
            sx += x - tx, sxx += (x - tx) * (x - tx), sy += y - ty, syy += (y - ty) * (y - ty), samples += 1;
        };
        n += 1;
        if (env.frame().has_ball()) {
            seen += 1;
            add(env.frame().ball().x(), env.frame().ball().y(), truth.ball.x, truth.ball.y);
            QCOMPARE(env.frame().ball().vx(), truth.ball.vx);  // speeds stay exact
        } else {
            missing += 1;
        }
        for (std::size_t i = 0; i < scene.robots.size(); ++i) {
            const bool yellow = scene.robots[i].team == Team::Yellow;
            const fira_message::Robot* r = findRobot(env, yellow, static_cast<unsigned>(yellow ? i : i - 3));
            n += 1;
            if (!r) {
                missing += 1;
                continue;
            }
            seen += 1;
            const RobotState& s = truth.robots[i];
            add(r->x(), r->y(), s.x, s.y);
            QVERIFY(r->orientation() >= -M_PI && r->orientation() <= M_PI);
            const double d = std::remainder(r->orientation() - s.theta, 2 * M_PI);
            st += d, stt += d * d, thetaSamples += 1;
            QCOMPARE(r->vorientation(), s.omega);
        }
    }
    auto sd = [](double sum, double sumSq, double count) {
        return std::sqrt(sumSq / count - (sum / count) * (sum / count));
    };
    const double vanishRate = missing / n, sdX = sd(sx, sxx, samples), sdY = sd(sy, syy, samples),
                 sdTheta = sd(st, stt, thetaSamples);
    qInfo("FIRASim vision: position sd %.5f / %.5f m (configured %.3f), heading sd %.5f rad (%.3f), vanished %.4f "
          "(%.2f) of %.0f bodies",
          sdX, sdY, scene.camera.position_noise, sdTheta, scene.camera.heading_noise, vanishRate, scene.camera.vanish,
          n);
    QVERIFY2(std::abs(vanishRate - scene.camera.vanish) <= 4 * std::sqrt(0.1 * 0.9 / n),
             qPrintable(QString::number(vanishRate)));
    QVERIFY2(std::abs(sdX / scene.camera.position_noise - 1) < 0.05, qPrintable(QString::number(sdX)));
    QVERIFY2(std::abs(sdY / scene.camera.position_noise - 1) < 0.05, qPrintable(QString::number(sdY)));
    QVERIFY2(std::abs(sdTheta / scene.camera.heading_noise - 1) < 0.05, qPrintable(QString::number(sdTheta)));
}

void TestFirasim::replacement() {
    Fira f(kickoff(), true);
    QVERIFY(f.next());
    Packet p;
    replaceRobot(p, true, 1, 0.0, 0.4, 90.0);  // degrees
    replaceRobot(p, false, 2, -0.5, -0.4, -135.0);
    replaceBall(p, -0.3, -0.2, 0.5, 0.0);
    f.send(p);
    const Environment env = f.step();
    const fira_message::Robot* y1 = findRobot(env, true, 1);
    QVERIFY(y1);
    QVERIFY(std::abs(y1->x() - 0.0) < 1e-6 && std::abs(y1->y() - 0.4) < 1e-6);
    QVERIFY2(std::abs(y1->orientation() - kPi / 2) < 1e-6, qPrintable(QString::number(y1->orientation())));
    const fira_message::Robot* b2 = findRobot(env, false, 2);
    QVERIFY(std::abs(b2->x() + 0.5) < 1e-6 && std::abs(b2->y() + 0.4) < 1e-6);
    QVERIFY(std::abs(b2->orientation() + 0.75 * kPi) < 1e-6);
    // The ball rolled on from where it was put, at about 0.5 m/s.
    const auto& ball = env.frame().ball();
    QVERIFY2(ball.x() > -0.3 && ball.x() < -0.3 + 0.5 * 0.05, qPrintable(QString::number(ball.x())));
    QVERIFY(std::abs(ball.y() + 0.2) < 1e-6);
    QVERIFY(ball.vx() > 0.3 && ball.vx() <= 0.5);
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{0});

    // A swap within one packet: each robot onto the other's place is fine,
    // since the test is on the final poses.
    const fira_message::Robot before0 = *findRobot(env, true, 0);
    Packet swap;
    replaceRobot(swap, true, 0, 0.0, 0.4, 0.0);  // where yellow 1 is now
    replaceRobot(swap, true, 1, before0.x(), before0.y(), 0.0);
    f.send(swap);
    const Environment swapped = f.step();
    QVERIFY(std::abs(findRobot(swapped, true, 0)->y() - 0.4) < 1e-6);
    QVERIFY(std::abs(findRobot(swapped, true, 1)->x() - before0.x()) < 1e-6);
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{0});
}

void TestFirasim::replacementAcrossDatagrams() {
    // VSSReferee sends blue's robots, yellow's and the ball in three
    // datagrams: blue 1 onto yellow 1's spot is blocked until the next
    // datagram moves yellow 1 away, then applied.
    Fira f(kickoff(), true);
    const std::optional<Environment> first = f.next();
    QVERIFY(first);
    const fira_message::Robot y1 = *findRobot(*first, true, 1);
    Packet blues;
    replaceRobot(blues, false, 1, y1.x(), y1.y(), 0.0);
    f.send(blues);
    Packet yellows;
    replaceRobot(yellows, true, 1, y1.x(), y1.y() + 0.3, 0.0);
    f.send(yellows);
    Environment env = f.step();
    QVERIFY(std::abs(findRobot(env, false, 1)->x() - y1.x()) < 1e-6);
    QVERIFY(std::abs(findRobot(env, false, 1)->y() - y1.y()) < 1e-6);
    QVERIFY(std::abs(findRobot(env, true, 1)->y() - (y1.y() + 0.3)) < 1e-6);
    QCOMPARE(f.server->stats().deferredReplacements, std::int64_t{1});
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{0});
    // Onto a robot that stays: refused at the next tick (sync mode decides then).
    const fira_message::Robot y0 = *findRobot(env, true, 0);
    const fira_message::Robot b2 = *findRobot(env, false, 2);
    Packet onto;
    replaceRobot(onto, false, 2, y0.x(), y0.y(), 0.0);
    f.send(onto);
    env = f.step();
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{1});
    QVERIFY(std::hypot(findRobot(env, false, 2)->x() - b2.x(), findRobot(env, false, 2)->y() - b2.y()) < 1e-6);

    // In real time a blocked replacement waits out its grace (20 ms), then is refused.
    Fira live(kickoff(), false);
    const std::optional<Environment> now = live.next();
    QVERIFY(now);
    const fira_message::Robot ly0 = *findRobot(*now, true, 0);
    Packet stuck;
    replaceRobot(stuck, false, 2, ly0.x(), ly0.y(), 0.0);
    live.send(stuck);
    QTRY_COMPARE_WITH_TIMEOUT(live.server->stats().refusedReplacements, std::int64_t{1}, 5000);
    QCOMPARE(live.server->stats().deferredReplacements, std::int64_t{0});
}

void TestFirasim::ballOnAWallWithinTheSlack() {
    // A referee's float rounding puts a ball resting on a wall a few 1e-8 m
    // into it: accepted (within kReplacementWallSlack, 0.5 mm) and put back
    // on the field by the next contact pass; 2 mm into the wall is refused.
    Fira f(kickoff(), true);
    QVERIFY(f.next());
    const double top = 0.65 - 0.02135;  // the ball's centre when it touches the top wall, m
    Packet in;
    replaceBall(in, 0.27, top + 3e-8, 0.0, 0.0);
    f.send(in);
    Environment env = f.step();
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{0});
    QVERIFY(std::abs(env.frame().ball().x() - 0.27) < 1e-6);
    QVERIFY(env.frame().ball().y() <= top + 1e-9);
    Packet deep;
    replaceBall(deep, -0.27, top + 2e-3, 0.0, 0.0);
    f.send(deep);
    env = f.step();
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{1});
    QVERIFY(std::abs(env.frame().ball().x() - 0.27) < 1e-6);
}

void TestFirasim::turnOffAndOn() {
    Fira f(kickoff(), true);
    QVERIFY(f.next());
    Packet off;
    replaceRobot(off, false, 1, 0.0, 0.0, 0.0, false);
    f.send(off);
    Environment env = f.step();
    QCOMPARE(env.frame().robots_blue_size(), 2);
    QVERIFY(!findRobot(env, false, 1));
    QVERIFY(findRobot(env, false, 0) && findRobot(env, false, 2));
    QCOMPARE(env.frame().robots_yellow_size(), 3);
    env = f.step();
    QVERIFY(!findRobot(env, false, 1));
    // Back at a pose.
    Packet on;
    replaceRobot(on, false, 1, 0.3, -0.45, 180.0, true);
    f.send(on);
    env = f.step();
    const fira_message::Robot* b1 = findRobot(env, false, 1);
    QVERIFY(b1);
    QVERIFY(std::abs(b1->x() - 0.3) < 1e-6 && std::abs(b1->y() + 0.45) < 1e-6);
    QVERIFY(std::abs(std::abs(b1->orientation()) - kPi) < 1e-6);
}

void TestFirasim::goalWithTheReferee() {
    Scene scene = kickoff();
    scene.game.rules.referee = true;
    Fira f(scene, true);
    QVERIFY(f.next());
    EngineRequest on;
    on.kind = EngineRequest::Kind::ResumeGame;  // GAME_ON now rather than after the kick-off's STOP
    on.arrivalNs = monotonicNs();
    f.engine->post(on);
    Environment env = f.step();
    QCOMPARE(env.goals_yellow(), 0u);
    Packet shot;
    replaceBall(shot, 0.6, 0.1, 1.5, 0.0);  // into the goal at x > 0: blue's, so yellow scores
    f.send(shot);
    int steps = 0;
    while (env.goals_yellow() == 0 && steps++ < 120) env = f.step();
    QCOMPARE(env.goals_yellow(), 1u);
    QCOMPARE(env.goals_blue(), 0u);
    for (int k = 0; k < 30; ++k) env = f.step();
    QCOMPARE(env.goals_yellow(), 1u);
}

void TestFirasim::goalWithAnExternalReferee() {
    // vssim serve as a team would start it for VSSReferee: the built-in
    // referee off, the external referee keeping the score. FIRASim never
    // counts goals (its arbiter is switched off in its source), so the
    // vision's goal fields stay 0:0 through a goal, as FIRASim's do.
    QUdpSocket vision;
    QVERIFY(vision.bind(QHostAddress::LocalHost, 0));
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) env.remove(name);
    p.setProcessEnvironment(env);
    p.start(VSSIM_BINARY, {"serve", "kickoff_3v3", "--port", "0", "--yellow", "tcp", "--blue", "tcp", "--firasim-sync",
                           "--firasim-port", "0", "--vision-address", "127.0.0.1", "--vision-port",
                           QString::number(vision.localPort()), "--referee", "external", "--quit-after", "60"});
    QVERIFY(p.waitForStarted());
    QByteArray out;
    QRegularExpressionMatch m;
    const QRegularExpression line("firasim: commands on ([0-9.]+):([0-9]+), vision to 127\\.0\\.0\\.1:([0-9]+)");
    QElapsedTimer t;
    t.start();
    while (!(m = line.match(QString::fromUtf8(out))).hasMatch() && t.elapsed() < 20000) {
        p.waitForReadyRead(200);
        out += p.readAllStandardOutput();
    }
    QVERIFY2(m.hasMatch(), out.constData());
    QVERIFY(out.contains("listening on "));
    const quint16 port = static_cast<quint16>(m.captured(2).toUInt());
    QUdpSocket client;
    std::int64_t last = -1;
    auto step = [&](Packet packet) {
        packet.mutable_cmd();
        client.writeDatagram(bytes(packet), QHostAddress::LocalHost, port);
        QElapsedTimer w;
        w.start();
        while (w.elapsed() < 5000) {
            if (!vision.waitForReadyRead(100)) continue;
            while (vision.hasPendingDatagrams()) {
                QByteArray data(static_cast<qsizetype>(vision.pendingDatagramSize()), 0);
                vision.readDatagram(data.data(), data.size());
                Environment e;
                if (!e.ParseFromArray(data.constData(), static_cast<int>(data.size()))) qFatal("not an Environment");
                if (static_cast<std::int64_t>(e.step()) > last) {
                    last = e.step();
                    return std::optional(e);
                }
            }
        }
        return std::optional<Environment>();
    };
    std::optional<Environment> e = step({});
    QVERIFY(e);
    Packet shot;
    replaceBall(shot, 0.6, 0.1, 1.5, 0.0);
    e = step(shot);
    bool inGoal = false;
    for (int k = 0; k < 120 && e; ++k) {
        QCOMPARE(e->goals_yellow(), 0u);
        QCOMPARE(e->goals_blue(), 0u);
        inGoal = inGoal || e->frame().ball().x() > 0.75 + 0.0214;  // the whole ball past the line
        e = step({});
    }
    QVERIFY(e);
    QVERIFY2(inGoal, "the shot went in");
    QCOMPARE(e->goals_yellow(), 0u);
    QCOMPARE(e->goals_blue(), 0u);
    p.terminate();
    QVERIFY(p.waitForFinished(10000));
    QVERIFY2(p.readAllStandardError().contains("0:0, as FIRASim sends them (--referee external"),
             "the log says who keeps the score");
}

void TestFirasim::syncIsDeterministic() {
    auto run = [](QList<QByteArray>* out) {
        Fira f(kickoff(), true);
        if (!f.next()) qFatal("no first Environment");
        Packet setUp;
        replaceBall(setUp, 0.1, 0.05, -0.8, 0.3);
        replaceRobot(setUp, true, 2, -0.1, -0.3, 30.0);
        f.send(setUp);
        for (int k = 0; k < 90; ++k) {
            Packet p;
            command(p, true, 0, 10.0 + 0.1 * k, 12.0);
            command(p, false, 1, -8.0, 5.0 * std::sin(0.1 * k));
            if (k == 40) replaceBall(p, 0.0, 0.0, 1.0, 1.0);
            QByteArray raw;
            f.step(p, &raw);
            out->append(raw);
        }
    };
    QList<QByteArray> a, b;
    run(&a);
    run(&b);
    QCOMPARE(a.size(), 90);
    QCOMPARE(a, b);
}

void TestFirasim::badInput() {
    Fira f(kickoff(), true);
    QVERIFY(f.next());
    // Garbage: not a Packet.
    static const char garbage[] = "\xff\xff\xff\xff garbage \x01\x02";
    f.send(QByteArray(garbage, sizeof garbage - 1));  // 15 bytes, without the literal's NUL
    Environment env = f.step();
    QCOMPARE(f.server->stats().malformed, std::int64_t{1});
    // Oversized.
    f.send(QByteArray(FirasimServer::kMaxDatagramBytes + 100, '\x0a'));
    env = f.step();
    QCOMPARE(f.server->stats().oversized, std::int64_t{1});
    // An unknown robot, NaN and huge wheel speeds from yellow, and in the same
    // packet a replacement of a blue robot: blue's part still applies.
    Packet p;
    command(p, true, 7, 1.0, 1.0);
    command(p, false, 9, 1.0, 1.0);
    command(p, true, 0, std::nan(""), 1e30);
    command(p, true, 1, -INFINITY, 3.0);
    replaceRobot(p, false, 0, 0.5, 0.45, 0.0);
    env = f.step(p);
    QCOMPARE(f.server->stats().unknownRobots, std::int64_t{2});
    QCOMPARE(f.server->stats().clampedSpeeds, std::int64_t{2});
    const fira_message::Robot* b0 = findRobot(env, false, 0);
    QVERIFY(std::abs(b0->x() - 0.5) < 1e-6 && std::abs(b0->y() - 0.45) < 1e-6);
    bool changed = false;
    QCOMPARE(acceptWheelSpeed(std::nan(""), &changed), 0.0);
    QVERIFY(changed);
    changed = false;
    QCOMPARE(acceptWheelSpeed(1e30, &changed), kMaxWheelSpeed);
    QVERIFY(changed);
    changed = false;
    QCOMPARE(acceptWheelSpeed(-12.5, &changed), -12.5);
    QVERIFY(!changed);

    // Outside the field, onto another robot, onto the ball, non-finite: refused; the rest applies.
    const Environment before = env;
    Packet q;
    replaceRobot(q, true, 0, 1.0, 0.0, 0.0);                                               // beyond the goal line
    replaceRobot(q, true, 1, 0.74, 0.6, 0.0);                                              // into a corner
    replaceRobot(q, true, 2, b0->x() + 0.03, b0->y(), 0.0);                                // onto blue 0
    replaceRobot(q, false, 2, before.frame().ball().x(), before.frame().ball().y(), 0.0);  // onto the ball
    replaceRobot(q, false, 1, std::nan(""), 0.0, 0.0);                                     // NaN
    replaceBall(q, 0.0, 0.9, 0.0, 0.0);                                                    // outside
    env = f.step(q);
    QCOMPARE(f.server->stats().refusedReplacements, std::int64_t{6});
    for (const auto& [yellow, id] : {std::pair{true, 0u}, {true, 1u}, {true, 2u}, {false, 1u}, {false, 2u}}) {
        const fira_message::Robot* now = findRobot(env, yellow, id);
        const fira_message::Robot* then = findRobot(before, yellow, id);
        QVERIFY(now && then);
        // Not moved there: only as far as its wheels took it in one vision
        // period (robots driven above are moving), far less than any refused jump.
        QVERIFY2(std::hypot(now->x() - then->x(), now->y() - then->y()) < 0.01,
                 qPrintable(QString("%1 %2 moved from (%3, %4) to (%5, %6)")
                                .arg(yellow ? "yellow" : "blue")
                                .arg(id)
                                .arg(then->x())
                                .arg(then->y())
                                .arg(now->x())
                                .arg(now->y())));
    }
    QVERIFY(!f.log.isEmpty());
    QVERIFY(f.log.filter("refused").size() >= 1);
    // Still answering.
    Packet ok;
    replaceRobot(ok, true, 0, -0.5, 0.4, 45.0);
    env = f.step(ok);
    // Placed at rest; its last wheel speeds (0 and 1000 rad/s, clamped, from
    // above) still drive it, a few millimetres in one vision period.
    QVERIFY(std::hypot(findRobot(env, true, 0)->x() + 0.5, findRobot(env, true, 0)->y() - 0.4) < 0.01);
}

void TestFirasim::flood() {
    // Real time: 10,000 datagrams from yellow's side (garbage, NaN wheel
    // speeds, unknown robots) as fast as a thread can send them, while the
    // vision keeps coming and blue is left alone.
    Fira f(kickoff(), false);
    std::optional<Environment> start = f.next();
    QVERIFY(start);
    const quint16 port = f.server->port();
    Packet nan;
    command(nan, true, 0, std::nan(""), 1e9);
    Packet unknown;
    command(unknown, true, 42, 1.0, 1.0);
    const QByteArray kinds[3] = {bytes(nan), bytes(unknown), QByteArray("\x08\x96\x01garbage", 10)};
    std::atomic<bool> done{false};
    std::thread flooder([&] {
        const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in to{};
        to.sin_family = AF_INET;
        to.sin_port = htons(port);
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        for (int i = 0; i < 10000; ++i) {
            const QByteArray& d = kinds[i % 3];
            ::sendto(s, d.constData(), static_cast<size_t>(d.size()), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
        }
        ::close(s);
        done = true;
    });
    int visionDuringFlood = 0;
    while (!done) {
        if (f.next(100)) ++visionDuringFlood;
    }
    flooder.join();
    // The server reads the rest.
    std::optional<Environment> env = f.after(500);
    QVERIFY(env);
    const FirasimStats& s = f.server->stats();
    qInfo(
        "flood: %lld datagrams read (the kernel dropped the rest), %lld malformed, %lld unknown robots, %lld "
        "clamped, %lld busy, %lld deferred turns; %d Environments during the flood",
        static_cast<long long>(s.datagrams), static_cast<long long>(s.malformed),
        static_cast<long long>(s.unknownRobots), static_cast<long long>(s.clampedSpeeds),
        static_cast<long long>(s.busy), static_cast<long long>(s.deferredTurns), visionDuringFlood);
    QVERIFY(s.datagrams > 0);
    QVERIFY(s.malformed > 0 && s.unknownRobots > 0 && s.clampedSpeeds > 0);
    // Blue untouched: where it started.
    for (unsigned id = 0; id < 3; ++id) {
        const fira_message::Robot* now = findRobot(*env, false, id);
        const fira_message::Robot* then = findRobot(*start, false, id);
        QVERIFY(now && then);
        QCOMPARE(now->x(), then->x());
        QCOMPARE(now->y(), then->y());
        QCOMPARE(now->orientation(), then->orientation());
    }
    // And the server still answers blue.
    Packet place;
    replaceRobot(place, false, 1, 0.3, -0.45, 90.0);
    f.send(place);
    bool applied = false;
    for (int k = 0; k < 60 && !applied; ++k) {
        env = f.next();
        QVERIFY(env);
        const fira_message::Robot* b1 = findRobot(*env, false, 1);
        applied = std::abs(b1->x() - 0.3) < 1e-6 && std::abs(b1->y() + 0.45) < 1e-6;
    }
    QVERIFY2(applied, qPrintable(QStringLiteral("datagrams %1, replacements %2, refused %3, busy %4; log: %5")
                                     .arg(s.datagrams)
                                     .arg(s.replacements)
                                     .arg(s.refusedReplacements)
                                     .arg(s.busy)
                                     .arg(f.log.join(" | "))));
    // The log stayed bounded.
    QVERIFY2(f.log.size() <= 2 * RateLimitedLog::kLinesPerWindow, qPrintable(QString::number(f.log.size())));
}

void TestFirasim::multicastOnLoopback() {
    // The default vision address, 224.0.0.1, on this machine (TTL 0,
    // loopback on), where the kernel allows it.
    QString reason;
    bool received = false;
    {
        QUdpSocket receiver;
        if (!receiver.bind(QHostAddress::AnyIPv4, 0, QUdpSocket::ShareAddress | QUdpSocket::ReuseAddressHint)) {
            reason = "cannot bind: " + receiver.errorString();
        } else if (!receiver.joinMulticastGroup(QHostAddress("224.0.0.1"))) {
            reason = "cannot join 224.0.0.1: " + receiver.errorString();
        } else {
            FirasimSettings settings;
            settings.visionAddress = QHostAddress("224.0.0.1");
            settings.visionPort = receiver.localPort();
            Fira f(kickoff(), false, settings, false);
            QElapsedTimer t;
            t.start();
            while (!received && t.elapsed() < 2000) {
                QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
                while (receiver.hasPendingDatagrams()) {
                    QByteArray data(static_cast<qsizetype>(receiver.pendingDatagramSize()), 0);
                    receiver.readDatagram(data.data(), data.size());
                    Environment env;
                    received = env.ParseFromArray(data.constData(), static_cast<int>(data.size())) &&
                               env.frame().robots_yellow_size() == 3;
                }
                QThread::msleep(2);
            }
            if (!received)
                reason = QStringLiteral("nothing received in 2 s (%1 sent, %2 send errors%3)")
                             .arg(f.server->stats().visionSent)
                             .arg(f.server->stats().sendErrors)
                             .arg(f.log.isEmpty() ? QString() : ": " + f.log.last());
        }
    }
    if (received) {
        qInfo("multicast tested: vision received from 224.0.0.1 on loopback");
        return;
    }
    qInfo("multicast unavailable: %s, unicast tested", qPrintable(reason));
    Fira f(kickoff(), false);
    const std::optional<Environment> env = f.next();
    QVERIFY2(env, "unicast vision must work");
    QCOMPARE(env->frame().robots_yellow_size(), 3);
}

QTEST_MAIN(TestFirasim)
#include "test_firasim.moc"
