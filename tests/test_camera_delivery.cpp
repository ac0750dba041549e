// The camera's delivery and ground-truth noise (docs/protocol.md, FRAME and
// STATE; issue 17): the counter-based draws, one client's link on its own
// (latency, jitter, drops, order, a reset), and end to end through the TCP
// server in lockstep: the drop rate, the delay's range and mean, STATE's
// position and heading noise and vanishing bodies measured against the
// configured values with stated tolerances; two runs byte for byte; zero
// per-client settings giving exactly the ideal stream; WELCOME's camera; and
// HELLO's `camera` errors.
#include <QtTest>

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "delivery/camera_draws.h"
#include "delivery/frame_delivery.h"
#include "delivery/ground_truth_noise.h"
#include "io/scene_io.h"
#include "net/control_server.h"
#include "net/protocol_client.h"
#include "realtime/engine_thread.h"
#include "served_server.h"

using namespace vssim;
using protocol::MessageType;
using test::kickoff;
using test::Served;

namespace {

QJsonObject hello(const QString& role, const QString& images, bool state, const QJsonObject& camera = {}) {
    QJsonObject json{{"protocol", 1}, {"role", role}, {"images", images}, {"encoding", "png"}, {"state", state}};
    if (!camera.isEmpty()) json["camera"] = camera;
    return json;
}

std::unique_ptr<ProtocolClient> join(quint16 port, const QJsonObject& json, QJsonObject* welcome = nullptr) {
    auto client = std::make_unique<ProtocolClient>();
    if (!client->connectTo(port)) return nullptr;
    const std::optional<QJsonObject> w = client->hello(json);
    if (!w) return nullptr;
    if (welcome) *welcome = *w;
    if (json["images"].toString() != "none" && !client->nextOf(MessageType::Frame)) return nullptr;
    return client;
}

// Sends a step; returns the REPLY, the messages before it in `before`.
QJsonObject step(ProtocolClient& client, double duration, std::vector<protocol::Message>* before) {
    client.sendJson(MessageType::Control, QJsonObject{{"command", "step"}, {"duration", duration}, {"id", 1}});
    for (;;) {
        const auto r = client.next();
        if (!r) return {};
        if (r->message.type == std::uint8_t(MessageType::Reply) || r->message.type == std::uint8_t(MessageType::Error))
            return jsonPayload(r->message);
        before->push_back(r->message);
    }
}

// The HELLO's ERROR: its code and message (empty when a WELCOME came).
QJsonObject helloError(quint16 port, const QByteArray& payload) {
    ProtocolClient client;
    if (!client.connectTo(port)) return {};
    client.send(MessageType::Hello, payload);
    const auto r = client.nextOf(MessageType::Error);
    return r ? jsonPayload(r->message) : QJsonObject{};
}

// Sample mean and standard deviation.
struct Moments {
    double n = 0, sum = 0, sumSq = 0;
    void add(double x) { n += 1, sum += x, sumSq += x * x; }
    double mean() const { return sum / n; }
    double stddev() const { return std::sqrt(std::max(0.0, sumSq / n - mean() * mean())); }
};

// Whether a measured rate lies within 4 binomial standard deviations of p over n trials.
bool withinBinomial(double measured, double p, double n) {
    return std::abs(measured - p) <= 4.0 * std::sqrt(p * (1 - p) / n);
}

}  // namespace

class TestCameraDelivery : public QObject {
    Q_OBJECT
private slots:
    void drawsAreUniformGaussianAndKeyed() {
        // 200,000 draws over frames: the uniform's mean 1/2 and variance 1/12,
        // the Gaussian's mean 0 and variance 1, within 4 standard errors.
        const int n = 200000;
        Moments u, g;
        for (int f = 0; f < n; ++f) {
            const CameraDrawKey key{7, clientStream(2, 0), f, 3};
            const double x = cameraUniform(key, CameraDraw::Drop);
            QVERIFY(x >= 0.0 && x < 1.0);
            u.add(x);
            g.add(cameraGaussian(key, CameraDraw::NoiseX));
        }
        QVERIFY2(std::abs(u.mean() - 0.5) < 4 * std::sqrt(1.0 / 12 / n), qPrintable(QString::number(u.mean())));
        QVERIFY(std::abs(u.stddev() - std::sqrt(1.0 / 12)) < 0.005);
        QVERIFY2(std::abs(g.mean()) < 4 / std::sqrt(n), qPrintable(QString::number(g.mean())));
        QVERIFY2(std::abs(g.stddev() - 1.0) < 4 / std::sqrt(2.0 * n), qPrintable(QString::number(g.stddev())));
        // Each part of the key matters; the same key gives the same bits.
        const CameraDrawKey key{7, clientStream(0, 0), 10, 2};
        QCOMPARE(cameraBits(key, CameraDraw::Jitter), cameraBits(key, CameraDraw::Jitter));
        std::set<std::uint64_t> seen{cameraBits(key, CameraDraw::Jitter)};
        seen.insert(cameraBits({8, key.stream, 10, 2}, CameraDraw::Jitter));
        seen.insert(cameraBits({7, clientStream(1, 0), 10, 2}, CameraDraw::Jitter));
        seen.insert(cameraBits({7, clientStream(0, 1), 10, 2}, CameraDraw::Jitter));
        seen.insert(cameraBits({7, key.stream, 11, 2}, CameraDraw::Jitter));
        seen.insert(cameraBits({7, key.stream, 10, 3}, CameraDraw::Jitter));
        seen.insert(cameraBits(key, CameraDraw::Drop));
        QCOMPARE(seen.size(), std::size_t(7));
        QVERIFY(clientStream(0, 0) != kFirasimStream && clientStream(2, 5) != clientStream(1, 5));
    }

    void wrapToPiIsHalfOpen() {
        QCOMPARE(wrapToPi(M_PI), M_PI);
        QCOMPARE(wrapToPi(-M_PI), M_PI);
        QVERIFY(std::abs(wrapToPi(3 * M_PI + 0.25) - (-M_PI + 0.25)) < 1e-12);
        QVERIFY(std::abs(wrapToPi(-7.0) - (-7.0 + 2 * M_PI)) < 1e-12);
    }

    void linkDropsDelaysAndKeepsOrder() {
        // One client's link on its own: frames every 1/60 s, due-checked at each.
        CameraSettings camera;
        camera.latency = 0.05, camera.jitter = 0.04, camera.drop = 0.15, camera.seed = 3;
        FrameDelivery link(camera, clientStream(0, 0));
        QVERIFY(!link.immediate());
        QVERIFY(FrameDelivery(idealCamera(), 1).immediate());
        const int frames = 6000;
        const double period = 1.0 / 60;
        Moments scheduledDelay;
        std::map<std::int64_t, double> deliveredAt;
        std::int64_t last = -1;
        for (int f = 0; f < frames; ++f) {
            const double t = f * period;
            if (const auto at = link.scheduled(f, t)) {
                QVERIFY(*at >= t + camera.latency && *at <= t + camera.latency + camera.jitter);
                scheduledDelay.add(*at - t);
            }
            link.capture({f, t, 0, QByteArray::number(f), {}});
            for (const FrameDelivery::Captured& c : link.due(t)) {
                QVERIFY2(c.frame > last, "a frame overtook an earlier one");
                last = c.frame;
                deliveredAt[c.frame] = t;
            }
        }
        const double n = frames, dropped = static_cast<double>(link.dropped());
        QVERIFY2(withinBinomial(dropped / n, camera.drop, n), qPrintable(QString::number(dropped / n)));
        QCOMPARE(static_cast<double>(deliveredAt.size() + link.waiting()), n - dropped);
        // The draws: mean latency + jitter / 2 within 4 standard errors of a uniform.
        const double wantMean = camera.latency + camera.jitter / 2;
        QVERIFY2(std::abs(scheduledDelay.mean() - wantMean) <
                     4 * camera.jitter / std::sqrt(12.0 * scheduledDelay.n),
                 qPrintable(QString::number(scheduledDelay.mean())));
        // Delivered: at least the latency, at most latency + jitter plus one period of rounding up.
        for (const auto& [f, at] : deliveredAt) {
            const double delay = at - f * period;
            QVERIFY2(delay >= camera.latency - 1e-9 && delay <= camera.latency + camera.jitter + period + 1e-9,
                     qPrintable(QString("frame %1 after %2 s").arg(f).arg(delay)));
        }
        // Time going back (a reset) discards what was on its way.
        QVERIFY(link.waiting() > 0);
        link.capture({0, 0.0, 0, "again", {}});
        QVERIFY(link.waiting() <= 1);
        const auto afterReset = link.due(1.0);
        QVERIFY(afterReset.size() <= 1);
        if (!afterReset.empty()) QCOMPARE(afterReset[0].frameMessage, QByteArray("again"));
    }

    void linkHoldsAtMostItsBytes() {
        // 1 s of latency with 1 kB frames every 10 ms and room for 10 kB: the
        // 10 newest wait, the older ones are dropped, oldest first.
        CameraSettings camera;
        camera.latency = 1.0;
        FrameDelivery link(camera, 1, 10'000);
        for (int f = 0; f < 50; ++f) link.capture({f, 0.01 * f, 0, QByteArray(900, 'f'), QByteArray(100, 's')});
        QCOMPARE(link.waiting(), std::size_t(10));
        QCOMPARE(link.waitingBytes(), qint64(10'000));
        QCOMPARE(link.overflowed(), std::int64_t(40));
        QCOMPARE(link.dropped(), std::int64_t(0));
        const auto due = link.due(2.0);
        QCOMPARE(due.size(), std::size_t(10));
        QCOMPARE(due.front().frame, std::int64_t(40));
        QCOMPARE(link.waitingBytes(), qint64(0));
        // One frame larger than the room still waits (the newest always does).
        link.capture({50, 0.5, 0, QByteArray(20'000, 'f'), {}});
        QCOMPARE(link.waiting(), std::size_t(1));
    }

    void observedPoseNoiseAndVanishing() {
        CameraSettings camera;
        camera.position_noise = 0.004, camera.heading_noise = 0.03, camera.vanish = 0.05, camera.seed = 11;
        Moments dx, dy, dtheta;
        double vanished = 0, n = 0;
        for (int f = 0; f < 20000; ++f) {
            for (std::uint64_t body : {std::uint64_t{0}, std::uint64_t{4}, kBallBody}) {
                const ObservedPose p = observePose(camera, {camera.seed, 9, f, body}, 0.3, -0.2, 3.1);
                n += 1;
                if (!p.visible) {
                    vanished += 1;
                    continue;
                }
                dx.add(p.x - 0.3), dy.add(p.y + 0.2), dtheta.add(wrapToPi(p.theta - 3.1));
                QVERIFY(p.theta > -M_PI && p.theta <= M_PI);
            }
        }
        QVERIFY(withinBinomial(vanished / n, camera.vanish, n));
        QVERIFY2(std::abs(dx.stddev() / camera.position_noise - 1) < 0.03, qPrintable(QString::number(dx.stddev())));
        QVERIFY(std::abs(dy.stddev() / camera.position_noise - 1) < 0.03);
        QVERIFY2(std::abs(dtheta.stddev() / camera.heading_noise - 1) < 0.03,
                 qPrintable(QString::number(dtheta.stddev())));
        QVERIFY(std::abs(dx.mean()) < 4 * camera.position_noise / std::sqrt(dx.n));
        // Zero settings leave the pose exactly as it was (theta not even wrapped).
        const ObservedPose exact = observePose(idealCamera(), {1, 1, 1, 0}, 0.1, 0.2, 9.0);
        QVERIFY(exact.visible && exact.x == 0.1 && exact.y == 0.2 && exact.theta == 9.0);
        QVERIFY(!hasGroundTruthNoise(idealCamera()) && hasGroundTruthNoise(realisticCamera()));
    }

    void lockstepDropsAndDelays() {
        // An observer's link (latency L, jitter J, drop p) over STATE alone. The
        // client steps in cycles: one step of 0.03 s (longer than J: frame A,
        // the cycle's first, is never held back behind an earlier frame), then
        // 25 of g = 0.002 s (instants to see A's delivery at, and frames of
        // their own). A's measured delay is L + J U rounded up to g: L plus g
        // times a whole number from 1 to J / g, equally likely, mean
        // L + J / 2 + g / 2.
        const double L = 0.03, J = 0.02, g = 0.002, p = 0.2, longStep = 0.03;
        const int cycles = 1000, shortSteps = 25;
        Served served(kickoff(), RunMode::Lockstep);
        auto client = join(served.server->port(), hello("observer", "none", true,
                                                         {{"latency", L}, {"jitter", J}, {"drop", p}, {"seed", 5}}));
        QVERIFY(client);
        std::map<std::int64_t, double> captured;   // frame -> its time
        std::map<std::int64_t, double> delivered;  // frame -> the instant it came at
        std::set<std::int64_t> cycleStarts;
        std::set<double> instants{0.0};  // s
        std::int64_t lastFrame = 0;
        for (int c = 0; c < cycles; ++c) {
            for (int s = 0; s <= shortSteps; ++s) {
                std::vector<protocol::Message> before;
                const QJsonObject reply = step(*client, s == 0 ? longStep : g, &before);
                QVERIFY(reply["ok"].toBool());
                const std::int64_t frame = reply["frame"].toInteger();
                const double time = reply["time"].toDouble();
                QCOMPARE(frame, lastFrame + 1);
                captured[frame] = time;
                instants.insert(time);
                if (s == 0) cycleStarts.insert(frame);
                for (const protocol::Message& m : before) {
                    QCOMPARE(m.type, std::uint8_t(MessageType::State));
                    const std::int64_t f = jsonPayload(m)["frame"].toInteger();
                    QVERIFY2(f > (delivered.empty() ? 0 : delivered.rbegin()->first), "frames out of order");
                    // Its own instant's time and number, not the delivery's.
                    QVERIFY(jsonPayload(m)["time"].toDouble() <= time);
                    delivered[f] = time;
                }
                lastFrame = frame;
            }
        }
        // Frames captured in the last L + J may still be on their way.
        std::int64_t settled = 0, lost = 0;
        Moments delayA;
        for (const auto& [f, t] : captured) {
            if (t > captured.rbegin()->second - L - J - g) continue;
            ++settled;
            auto it = delivered.find(f);
            if (it == delivered.end()) {
                ++lost;
                continue;
            }
            // Not before its latency, and at the first instant after its due
            // time at the latest: the instant before the delivery came earlier
            // than capture + L + J (the longest a frame may be held).
            const double delay = it->second - t;
            const auto at = instants.find(it->second);
            QVERIFY(at != instants.end() && at != instants.begin());
            const double previous = *std::prev(at);
            QVERIFY2(delay >= L - 1e-9 && previous < t + L + J + 1e-9,
                     qPrintable(QString("frame %1 delivered %2 s after its capture").arg(f).arg(delay)));
            if (cycleStarts.count(f)) delayA.add(delay);
        }
        const double dropRate = static_cast<double>(lost) / static_cast<double>(settled);
        qInfo("drop: %.4f measured over %lld frames, %.4f configured", dropRate, static_cast<long long>(settled), p);
        QVERIFY2(withinBinomial(dropRate, p, static_cast<double>(settled)), qPrintable(QString::number(dropRate)));
        // Uniform over g, 2g, ..., J: standard deviation g sqrt((m^2 - 1) / 12), m = J / g.
        const double m = J / g, wantMean = L + J / 2 + g / 2, spread = g * std::sqrt((m * m - 1) / 12);
        qInfo("delay of unobstructed frames: mean %.5f s (want %.5f), sd %.5f s (want %.5f), n %.0f", delayA.mean(),
              wantMean, delayA.stddev(), spread, delayA.n);
        QVERIFY(delayA.n > 0.7 * cycles);
        QVERIFY2(std::abs(delayA.mean() - wantMean) < 4 * spread / std::sqrt(delayA.n),
                 qPrintable(QString::number(delayA.mean())));
        QVERIFY(std::abs(delayA.stddev() / spread - 1) < 0.1);
    }

    void stateNoiseAndVanishing() {
        // Two observers of the same instants: one exact (the scene's ideal
        // camera), one with noise; the differences' spread is the noise.
        const double sigma = 0.01, sigmaTheta = 0.05, vanish = 0.1;
        Served served(kickoff(), RunMode::Lockstep);
        const quint16 port = served.server->port();
        auto driver = join(port, hello("yellow", "none", false));
        auto exact = join(port, hello("observer", "none", true));
        auto noisy = join(port, hello("observer", "none", true,
                                      {{"position_noise", sigma}, {"heading_noise", sigmaTheta}, {"vanish", vanish}}));
        QVERIFY(driver && exact && noisy);
        // Robots turning and driving, so that headings go past +-pi.
        driver->send(MessageType::Voltages, protocol::encodeVoltages({{0, {3.0, -3.0}}, {1, {4.0, 2.0}}}));
        const int steps = 1500;
        Moments dx, dy, dtheta;
        double seen = 0, missing = 0;
        for (int n = 0; n < steps; ++n) {
            std::vector<protocol::Message> ignored;
            QVERIFY(step(*driver, 0.01, &ignored)["ok"].toBool());
            const auto a = exact->nextOf(MessageType::State), b = noisy->nextOf(MessageType::State);
            QVERIFY(a && b);
            const QJsonObject truth = jsonPayload(a->message), seenState = jsonPayload(b->message);
            QCOMPARE(seenState["frame"], truth["frame"]);
            QCOMPARE(seenState["time"], truth["time"]);
            QVERIFY(!truth["ball"].toObject().contains("visible"));
            auto compare = [&](const QJsonObject& t, const QJsonObject& s, bool robot) {
                QVERIFY(s.contains("visible"));
                if (!s["visible"].toBool()) {
                    missing += 1;
                    QVERIFY(!s.contains("x") && !s.contains("y") && !s.contains("theta"));
                    return;
                }
                seen += 1;
                dx.add(s["x"].toDouble() - t["x"].toDouble());
                dy.add(s["y"].toDouble() - t["y"].toDouble());
                if (robot) {
                    const double theta = s["theta"].toDouble();
                    QVERIFY(theta > -M_PI && theta <= M_PI);
                    dtheta.add(wrapToPi(theta - t["theta"].toDouble()));
                }
            };
            const QJsonArray tr = truth["robots"].toArray(), sr = seenState["robots"].toArray();
            QCOMPARE(sr.size(), tr.size());
            for (int i = 0; i < tr.size(); ++i) {
                const QJsonObject t = tr[i].toObject(), s = sr[i].toObject();
                // What the camera does not measure stays exact.
                for (const char* key : {"index", "on_field", "v", "omega", "right_voltage", "left_voltage",
                                        "right_current", "left_current", "right_wheel_speed", "left_wheel_speed"})
                    QCOMPARE(s[key], t[key]);
                compare(t, s, true);
            }
            const QJsonObject tb = truth["ball"].toObject(), sb = seenState["ball"].toObject();
            QCOMPARE(sb["vx"], tb["vx"]);
            QCOMPARE(sb["vy"], tb["vy"]);
            compare(tb, sb, false);
        }
        const double vanishRate = missing / (seen + missing);
        qInfo("STATE: position sd %.5f / %.5f m (x / y), heading sd %.5f rad, vanished %.4f (configured %.3f m, "
              "%.3f rad, %.3f) over %.0f bodies",
              dx.stddev(), dy.stddev(), dtheta.stddev(), vanishRate, sigma, sigmaTheta, vanish, seen + missing);
        QVERIFY(withinBinomial(vanishRate, vanish, seen + missing));
        QVERIFY2(std::abs(dx.stddev() / sigma - 1) < 0.05, qPrintable(QString::number(dx.stddev())));
        QVERIFY2(std::abs(dy.stddev() / sigma - 1) < 0.05, qPrintable(QString::number(dy.stddev())));
        QVERIFY2(std::abs(dtheta.stddev() / sigmaTheta - 1) < 0.05, qPrintable(QString::number(dtheta.stddev())));
        QVERIFY(std::abs(dx.mean()) < 4 * sigma / std::sqrt(dx.n));
    }

    void lockstepRunsRepeatByteForByte() {
        // A realistic link and noise, images and STATE: every message the
        // client gets, in order, the same in two runs; a different seed differs.
        auto run = [](int seed) {
            Scene scene = kickoff();
            scene.camera.latency = 0.05, scene.camera.jitter = 0.02, scene.camera.drop = 0.1;
            scene.camera.position_noise = 0.003, scene.camera.heading_noise = 0.02, scene.camera.vanish = 0.05;
            Served served(scene, RunMode::Lockstep);
            auto client = join(served.server->port(), hello("yellow", "patches", true, {{"seed", seed}}));
            std::vector<std::pair<std::uint8_t, QByteArray>> received;
            if (!client) return received;
            for (int n = 0; n < 200; ++n) {
                const double e = 6.0 * std::sin(0.2 * n);
                client->send(MessageType::Voltages, protocol::encodeVoltages({{0, {e, 6.0 - e}}, {2, {5.0, 5.0}}}));
                std::vector<protocol::Message> before;
                const QJsonObject reply = step(*client, 0.01 + 0.001 * (n % 4), &before);
                if (!reply["ok"].toBool()) return decltype(received){};
                for (const auto& m : before) received.emplace_back(m.type, m.payload);
                received.emplace_back(std::uint8_t(MessageType::Reply), QJsonDocument(reply).toJson());
            }
            return received;
        };
        const auto a = run(4), b = run(4), c = run(5);
        QVERIFY(a.size() > 400);
        QVERIFY(a == b);
        QVERIFY(a != c);
    }

    void zeroLinkGivesTheIdealStream() {
        // A scene whose camera delays, drops and adds noise, and a client that
        // sets all of it to zero, gets exactly what a client of the ideal
        // camera gets: the same bytes in the same order (FRAME, STATE, REPLY).
        auto run = [](const Scene& scene, const QJsonObject& camera) {
            Served served(scene, RunMode::Lockstep);
            auto client = join(served.server->port(), hello("yellow", "patches", true, camera));
            std::vector<std::pair<std::uint8_t, QByteArray>> received;
            if (!client) return received;
            for (int n = 0; n < 60; ++n) {
                client->send(MessageType::Voltages, protocol::encodeVoltages({{0, {4.0, 3.0}}}));
                std::vector<protocol::Message> before;
                const QJsonObject reply = step(*client, 0.03, &before);
                for (const auto& m : before) received.emplace_back(m.type, m.payload);
                received.emplace_back(std::uint8_t(MessageType::Reply), QJsonDocument(reply).toJson());
            }
            return received;
        };
        Scene noisyScene = kickoff();
        noisyScene.camera.latency = 0.05, noisyScene.camera.jitter = 0.01, noisyScene.camera.drop = 0.2;
        noisyScene.camera.position_noise = 0.01, noisyScene.camera.heading_noise = 0.1, noisyScene.camera.vanish = 0.2;
        const QJsonObject zero{{"latency", 0}, {"jitter", 0}, {"drop", 0}, {"position_noise", 0},
                               {"heading_noise", 0}, {"vanish", 0}};
        const auto ideal = run(kickoff(), {});
        const auto zeroed = run(noisyScene, zero);
        QCOMPARE(ideal.size(), std::size_t(60 * 3));
        for (std::size_t i = 0; i < ideal.size(); i += 3) {
            QCOMPARE(ideal[i].first, std::uint8_t(MessageType::Frame));
            QCOMPARE(ideal[i + 1].first, std::uint8_t(MessageType::State));
            QCOMPARE(ideal[i + 2].first, std::uint8_t(MessageType::Reply));
        }
        QVERIFY(ideal == zeroed);
        // And the scene's own link does change it.
        QVERIFY(run(noisyScene, {}) != ideal);
    }

    void delayedFramesComeAfterLaterReplies() {
        // Latency of 3 steps exactly: a step's REPLY does not wait for its
        // FRAME, which comes just before the REPLY of the step 3 later.
        Served served(kickoff(), RunMode::Lockstep);
        auto client = join(served.server->port(), hello("yellow", "patches", true, {{"latency", 0.03}}));
        QVERIFY(client);
        for (int n = 1; n <= 10; ++n) {
            std::vector<protocol::Message> before;
            const QJsonObject reply = step(*client, 0.01, &before);
            QCOMPARE(reply["frame"].toInt(), n);
            if (n <= 3) {
                QVERIFY(before.empty());
                continue;
            }
            QCOMPARE(before.size(), std::size_t(2));
            QCOMPARE(before[0].type, std::uint8_t(MessageType::Frame));
            protocol::FrameHeader header;
            std::vector<protocol::FramePatch> patches;
            QString error;
            QVERIFY(protocol::decodeFrame(before[0].payload, &header, &patches, &error));
            QCOMPARE(int(header.frame), n - 3);
            QVERIFY(std::abs(header.time - 0.01 * (n - 3)) < 1e-12);
            QCOMPARE(jsonPayload(before[1])["frame"].toInt(), n - 3);
        }
        // A reset discards the frames on their way; frame 0 comes 0.03 s later.
        client->sendJson(MessageType::Control, QJsonObject{{"command", "reset"}});
        const auto reply = client->nextOf(MessageType::Reply);
        QVERIFY(reply);
        QCOMPARE(jsonPayload(reply->message)["frame"].toInt(), 0);
        std::vector<int> frames;
        for (int n = 1; n <= 3; ++n) {
            std::vector<protocol::Message> before;
            step(*client, 0.01, &before);
            for (const auto& m : before)
                if (m.type == std::uint8_t(MessageType::State)) frames.push_back(jsonPayload(m)["frame"].toInt());
        }
        QCOMPARE(frames, std::vector<int>{0});
    }

    void welcomeDescribesTheCamera() {
        Scene scene = kickoff();
        scene.camera = realisticCamera();
        Served served(scene, RunMode::Lockstep);
        QJsonObject welcome;
        auto client = join(served.server->port(), hello("observer", "none", true, {{"drop", 0.25}, {"seed", 9}}),
                           &welcome);
        QVERIFY(client);
        const QJsonObject camera = welcome["camera"].toObject();
        // The keys clients had before, unchanged.
        QCOMPARE(camera["width"].toInt(), 640);
        QCOMPARE(camera["height"].toInt(), 480);
        QCOMPARE(camera["images"].toString(), QString("none"));
        QCOMPARE(camera["projection"].toString(), QString("pinhole"));
        QCOMPARE(camera["mount_height"].toDouble(), scene.camera.height);
        const QJsonArray k = camera["matrix"].toArray();
        QCOMPARE(k.size(), 3);
        const double scale = camera["scale"].toDouble();
        // focal_length 0: the ideal scale times the height; principal point at the centre, OpenCV's pixel centres.
        QCOMPARE(k[0].toArray()[0].toDouble(), scale * scene.camera.height);
        QCOMPARE(k[1].toArray()[1].toDouble(), scale * scene.camera.height);
        QCOMPARE(k[0].toArray()[2].toDouble(), camera["centre_u"].toDouble() - 0.5);
        QCOMPARE(k[1].toArray()[2].toDouble(), camera["centre_v"].toDouble() - 0.5);
        QCOMPARE(k[2].toArray(), (QJsonArray{0.0, 0.0, 1.0}));
        QCOMPARE(camera["distortion"].toArray(), (QJsonArray{scene.camera.k1, scene.camera.k2, scene.camera.p1,
                                                             scene.camera.p2, scene.camera.k3}));
        // The client's own settings: the scene's, with its HELLO's over them.
        CameraSettings want = scene.camera;
        want.drop = 0.25, want.seed = 9;
        QString error;
        const auto settings =
            cameraSettingsFromJson(camera["settings"].toObject(), idealCamera(), "settings", &error);
        QVERIFY2(settings, qPrintable(error));
        QVERIFY(*settings == want);
    }

    void helloCameraErrors() {
        Served served(kickoff(), RunMode::Lockstep);
        const quint16 port = served.server->port();
        auto error = [&](const QJsonObject& camera) {
            QJsonObject json = hello("observer", "none", true);
            json["camera"] = camera;
            return helloError(port, QJsonDocument(json).toJson(QJsonDocument::Compact));
        };
        auto check = [&](const QJsonObject& e, const QString& part) {
            if (!e["message"].toString().contains(part)) qWarning() << e;
            return e["error"].toString() == "malformed" && e["fatal"].toBool() && e["message"].toString().contains(part);
        };
        QVERIFY(check(error({{"drop", 1.5}}), "HELLO: camera.drop: must be between 0 and 0.9 (got 1.5)"));
        QVERIFY(check(error({{"latency", -0.1}}), "camera.latency: must be between 0 and 1 s (got -0.1)"));
        QVERIFY(check(error({{"jitter", "0.01"}}), "camera.jitter: expected a number"));
        QVERIFY(check(error({{"vanish", QJsonValue()}}), "camera.vanish: expected a number"));
        QVERIFY(check(error({{"seed", 1.5}}), "camera.seed: must be a whole number"));
        QVERIFY(check(error({{"noise", 3}}), "camera.noise: the image formation"));
        QVERIFY(check(error({{"noise", 3}}), "per scene"));
        QVERIFY(check(error({{"preset", "realistic"}}), "camera.preset"));
        QVERIFY(check(error({{"k1", 0.1}}), "camera.k1"));
        QVERIFY(check(error({{"lag", 0.1}}), "camera.lag: unknown key"));
        // Not an object; not JSON (a NaN is not a JSON number).
        QJsonObject notObject = hello("observer", "none", true);
        notObject["camera"] = 0.5;
        QVERIFY(check(helloError(port, QJsonDocument(notObject).toJson()), "camera: expected an object"));
        const QJsonObject nan =
            helloError(port, R"({"protocol": 1, "role": "observer", "camera": {"position_noise": NaN}})");
        QCOMPARE(nan["error"].toString(), QString("malformed"));
        QVERIFY(nan["message"].toString().startsWith("HELLO"));
        // The server carries on: a good HELLO with every per-client key is welcome.
        QJsonObject welcome;
        QVERIFY(join(port,
                     hello("observer", "none", true,
                           {{"latency", 0.1}, {"jitter", 0.01}, {"drop", 0.5}, {"position_noise", 0.002},
                            {"heading_noise", 0.02}, {"vanish", 0.01}, {"seed", 12}}),
                     &welcome));
        QCOMPARE(welcome["camera"].toObject()["settings"].toObject()["latency"].toDouble(), 0.1);
    }
};

QTEST_GUILESS_MAIN(TestCameraDelivery)
#include "test_camera_delivery.moc"
