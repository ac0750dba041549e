// Benchmark 8: FIRASim's interface (`vssim serve --firasim`), seen from its
// clients as FIRASim-based team software uses it: the 3-vs-3 kick-off with
// both teams remote and no referee (so the vision comes at 60 Hz of
// simulated time), two team clients, one per team, each with its own UDP
// socket for commands, and the vision sent by unicast to the bench's own
// socket on 127.0.0.1 (one socket: unicast reaches one receiver; both team
// clients act on what it receives). Four scenarios:
//
//   - "firasim realtime": real time x1 for a minute (--quick: 3 s), each
//     team sending wheel speeds for its three robots every 7 ms, not in step
//     with the vision (blue 3.5 ms after yellow). Recorded at the client: each
//     Environment's arrival (period, lost ones by `step` gaps), the bytes of
//     each Environment and each command packet; at the server (a TCP
//     observer's CONTROL stats at the end): the command latency, arrival to
//     application, which covers FIRASim's wheel-speed requests too.
//   - "tcp realtime": the baseline, in the same run: the same scene and
//     clients through the TCP protocol (docs/protocol.md), VOLTAGES every
//     7 ms, the ground truth (STATE) at the TCP camera's 30 ms, no images.
//   - "firasim max": `--speed max` for 20 s (--quick: 2 s), each team
//     answering every Environment with a command packet: simulated seconds
//     per wall second (from the Environments' `step`, dt 1 ms) and
//     Environments received per second.
//   - "firasim sync": `--firasim-sync`, one client sending both teams'
//     commands in one packet and waiting for the Environment of that tick,
//     20 s (--quick: 2 s): ticks per second and the round trip.
//
// The client waits in ppoll() on its sockets (no busy loop: the machine's
// cores are the server's) and stamps each packet as it reads it.
#include <QCoreApplication>
#include <QFile>
#include <QJsonArray>
#include <QProcess>
#include <QRandomGenerator>
#include <QRegularExpression>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "benchmarks.h"
#include "fira_packet.pb.h"
#include "net/protocol_client.h"
#include "realtime/monotonic_clock.h"
#include "realtime/sample_stats.h"

namespace vssim::bench {

namespace {

using fira_message::sim_to_ref::Environment;
using fira_message::sim_to_ref::Packet;

constexpr double kDt = 0.001;                       // the kick-off scene's step, s
constexpr double kVisionPeriodSteps = 1000 / 60.0;  // 60 Hz on 1 ms steps
constexpr std::int64_t kCommandPeriodNs = 7'000'000;
constexpr double kMaxWheelSpeed = 30.0;  // rad/s, the commands' range (0.75 m/s at the rim)

// A UDP socket on 127.0.0.1, POSIX: the bench stamps each datagram as it reads it.
class Udp {
public:
    Udp() {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        if (fd_ < 0) throw std::runtime_error("cannot create a UDP socket");
        const int buffer = 4 << 20;  // max mode: the vision comes in bursts
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof a;
        if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
            ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length) != 0)
            throw std::runtime_error("cannot bind a UDP socket on 127.0.0.1");
        port_ = ntohs(a.sin_port);
    }
    ~Udp() { ::close(fd_); }
    Udp(const Udp&) = delete;
    Udp& operator=(const Udp&) = delete;
    int fd() const { return fd_; }
    quint16 port() const { return port_; }
    void sendTo(quint16 port, const std::string& bytes) const {
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = htons(port);
        if (::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a) < 0)
            throw std::runtime_error("sendto failed");
    }
    // The next datagram waiting, without blocking (false: none).
    bool receive(std::string* bytes) const {
        buffer_.resize(65536);
        const ssize_t got = ::recv(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
        if (got < 0) return false;
        bytes->assign(buffer_.data(), static_cast<std::size_t>(got));
        return true;
    }

private:
    int fd_ = -1;
    quint16 port_ = 0;
    mutable std::vector<char> buffer_;
};

// How far each arrival falls from its instant's place on the simulated-time
// schedule (arrival minus simulated time, wall clock, ms), less the median
// offset: the jitter that the whole-step pattern of the period does not explain.
class ScheduleJitter {
public:
    void add(std::int64_t arrivalNs, double simulatedSeconds) {
        offsetsMs_.push_back(1e-6 * static_cast<double>(arrivalNs) - 1e3 * simulatedSeconds);
    }
    SampleSummary summary() const {
        std::vector<double> sorted = offsetsMs_;
        if (sorted.empty()) return {};
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
        const double median = sorted[sorted.size() / 2];
        SampleStats deviation{1 << 20};
        for (double o : offsetsMs_) deviation.add(std::abs(o - median));
        return deviation.summary();
    }

private:
    std::vector<double> offsetsMs_;
};

// Datagrams the kernel dropped at our UDP socket on `port` (a full receive
// buffer), from /proc/net/udp; -1 when it cannot tell.
std::int64_t kernelDrops(quint16 port) {
    QFile file(QStringLiteral("/proc/net/udp"));
    if (!file.open(QIODevice::ReadOnly)) return -1;
    const QString local = QStringLiteral("0100007F:%1").arg(port, 4, 16, QLatin1Char('0')).toUpper();
    for (const QByteArray& line : file.readAll().split('\n')) {
        const QStringList fields = QString::fromLatin1(line).simplified().split(' ');
        if (fields.size() >= 13 && fields[1] == local) return fields.last().toLongLong();
    }
    return -1;
}

// Waits until one of `fds` is readable or `deadlineNs` (monotonicNs) passes.
void waitReadable(const std::vector<int>& fds, std::int64_t deadlineNs) {
    std::vector<pollfd> p;
    for (int fd : fds) p.push_back({fd, POLLIN, 0});
    const std::int64_t left = std::max<std::int64_t>(0, deadlineNs - monotonicNs());
    const timespec timeout{static_cast<time_t>(left / 1'000'000'000), static_cast<long>(left % 1'000'000'000)};
    ::ppoll(p.data(), p.size(), &timeout, nullptr);
}

// `vssim serve` with the kick-off, both teams remote, no referee, as a process.
struct Server {
    QProcess process;
    quint16 tcpPort = 0;
    quint16 firasimPort = 0;

    Server(const Options& options, const QStringList& extra, double seconds, bool firasim) {
        process.setProcessChannelMode(QProcess::ForwardedErrorChannel);
        QStringList arguments = {"serve",        QString::fromStdString(options.sceneFile),
                                 "--port",       "0",
                                 "--yellow",     "tcp",
                                 "--blue",       "tcp",
                                 "--referee",    "off",
                                 "--quit-after", QString::number(seconds + 30)};
        process.start(QStringLiteral(VSSIM_BINARY), arguments + extra);
        if (!process.waitForStarted(5000)) throw std::runtime_error("vssim serve did not start");
        tcpPort = static_cast<quint16>(readLine().section(':', -1).toUInt());  // "listening on 127.0.0.1:PORT"
        if (firasim) {
            // "firasim: commands on 127.0.0.1:PORT, vision to ..."
            const QRegularExpressionMatch m = QRegularExpression("commands on [^ ]+:(\\d+),").match(readLine());
            firasimPort = m.hasMatch() ? static_cast<quint16>(m.captured(1).toUInt()) : 0;
        }
        if (tcpPort == 0 || (firasim && firasimPort == 0))
            throw std::runtime_error("unexpected start lines from vssim serve");
    }
    ~Server() {
        process.terminate();
        process.waitForFinished(5000);
    }
    QString readLine() {
        while (!process.canReadLine())
            if (!process.waitForReadyRead(10000)) throw std::runtime_error("vssim serve printed nothing");
        return QString::fromUtf8(process.readLine()).trimmed();
    }
};

// The server's measurements (CONTROL stats) through `client`.
QJsonObject serverStats(ProtocolClient& client) {
    client.sendJson(protocol::MessageType::Control, QJsonObject{{"command", "stats"}});
    const auto reply = client.nextOf(protocol::MessageType::Reply, 10000);
    if (!reply) throw std::runtime_error("no reply to CONTROL stats");
    return jsonPayload(reply->message)["stats"].toObject();
}

void row(std::ostream& out, const char* scenario, const char* source, const char* metric, const QJsonObject& s) {
    out << '"' << scenario << "\"," << source << ',' << metric << ',' << s["count"].toDouble() << ','
        << s["median"].toDouble() << ',' << s["p99"].toDouble() << ',' << s["max"].toDouble() << ','
        << s["mean"].toDouble() << ',' << s["stddev"].toDouble() << '\n';
}

void row(std::ostream& out, const char* scenario, const char* source, const char* metric, const SampleSummary& s) {
    row(out, scenario, source, metric, toJson(s));
}

// A single figure: count 1, the value as the median.
void value(std::ostream& out, const char* scenario, const char* source, const char* metric, double v) {
    out << '"' << scenario << "\"," << source << ',' << metric << ",1," << v << ",,,,\n";
}

std::string quartiles(const QJsonObject& s) {
    std::ostringstream text;
    text << "median " << s["median"].toDouble() << ", p99 " << s["p99"].toDouble() << ", max " << s["max"].toDouble();
    return text.str();
}

std::string jitterText(const SampleSummary& s) {
    std::ostringstream text;
    text << "median " << s.median << " ms, p99 " << s.p99 << " ms, max " << s.max << " ms";
    return text.str();
}

// One team's command packet: wheel speeds for its three robots.
std::string commandPacket(QRandomGenerator& random, bool yellow, bool bothTeams = false) {
    Packet p;
    for (bool team : {true, false}) {
        if (!bothTeams && team != yellow) continue;
        for (unsigned id = 0; id < 3; ++id) {
            auto* c = p.mutable_cmd()->add_robot_commands();
            c->set_id(id);
            c->set_yellowteam(team);
            c->set_wheel_left(random.bounded(2 * kMaxWheelSpeed) - kMaxWheelSpeed);
            c->set_wheel_right(random.bounded(2 * kMaxWheelSpeed) - kMaxWheelSpeed);
        }
    }
    std::string bytes;
    p.SerializeToString(&bytes);
    return bytes;
}

// The vision as it arrives: period, losses by `step`, bytes.
struct VisionLog {
    SampleStats periodMs{1 << 20};
    SampleStats bytes{1 << 20};
    ScheduleJitter jitter;
    std::map<std::int64_t, std::int64_t> stepGaps;  // steps between consecutive Environments -> count
    std::int64_t received = 0, lost = 0;
    std::int64_t firstStep = -1, lastStep = -1, firstNs = 0, lastNs = -1;

    // Returns the Environment's step.
    std::int64_t add(const std::string& data, std::int64_t arrivalNs) {
        Environment env;
        if (!env.ParseFromString(data)) throw std::runtime_error("the vision is not an Environment");
        const std::int64_t step = env.step();
        bytes.add(static_cast<double>(data.size()));
        jitter.add(arrivalNs, kDt * static_cast<double>(step));
        if (lastNs >= 0) periodMs.add(1e-6 * static_cast<double>(arrivalNs - lastNs));
        if (lastStep >= 0) {
            ++stepGaps[step - lastStep];
            // Camera instant k falls on the step nearest k x 16.67.
            const auto index = [](std::int64_t s) { return std::llround(static_cast<double>(s) / kVisionPeriodSteps); };
            lost += std::max<std::int64_t>(0, index(step) - index(lastStep) - 1);
        } else {
            firstStep = step;
            firstNs = arrivalNs;
        }
        lastStep = step;
        lastNs = arrivalNs;
        ++received;
        return step;
    }
    double wallSeconds() const { return 1e-9 * static_cast<double>(lastNs - firstNs); }
    double simulatedSeconds() const { return kDt * static_cast<double>(lastStep - firstStep); }
    // "16 steps: N, 17 steps: M" and the longer gaps (instants lost) in one figure.
    std::string gaps() const {
        std::ostringstream text;
        std::int64_t longer = 0, longest = 0;
        for (const auto& [steps, count] : stepGaps) {
            if (steps <= 17) {
                text << steps << " steps: " << count << ", ";
            } else {
                longer += count;
                longest = std::max(longest, steps);
            }
        }
        text << "longer: " << longer;
        if (longer > 0) text << " (the longest " << longest << " steps)";
        return text.str();
    }
};

// Real time x1: both teams command every 7 ms; the vision is logged.
void firasimRealtime(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 3.0 : 60.0;
    Udp vision, yellow, blue;
    Server server(options,
                  {"--firasim", "--firasim-port", "0", "--vision-address", "127.0.0.1", "--vision-port",
                   QString::number(vision.port())},
                  duration, true);
    ProtocolClient observer;
    if (!observer.connectTo(server.tcpPort) ||
        !observer.hello(QJsonObject{{"protocol", 1}, {"role", "observer"}, {"images", "none"}}))
        throw std::runtime_error("the TCP observer could not connect");

    QRandomGenerator random(7);
    VisionLog seen;
    SampleStats commandBytes[2];
    std::int64_t commands[2] = {0, 0};
    const std::int64_t startNs = monotonicNs(), endNs = startNs + static_cast<std::int64_t>(duration * 1e9);
    std::int64_t next[2] = {startNs, startNs + kCommandPeriodNs / 2};  // yellow, blue
    std::string data;
    for (std::int64_t now = monotonicNs(); now < endNs; now = monotonicNs()) {
        for (int team : {0, 1}) {
            if (now < next[team]) continue;
            const std::string packet = commandPacket(random, team == 0);
            (team == 0 ? yellow : blue).sendTo(server.firasimPort, packet);
            commandBytes[team].add(static_cast<double>(packet.size()));
            ++commands[team];
            next[team] += kCommandPeriodNs;
        }
        while (vision.receive(&data)) seen.add(data, monotonicNs());
        waitReadable({vision.fd()}, std::min({next[0], next[1], endNs}));
    }
    const std::int64_t drops = kernelDrops(vision.port());
    const QJsonObject stats = serverStats(observer);

    const char* s = "firasim realtime";
    row(out, s, "server", "command_latency_ms", stats["command_latency_ms"].toObject());
    row(out, s, "server", "command_delay_ms", stats["command_delay_ms"].toObject());
    row(out, s, "client", "vision_period_ms", seen.periodMs.summary());
    row(out, s, "client", "vision_schedule_deviation_ms", seen.jitter.summary());
    row(out, s, "client", "environment_bytes", seen.bytes.summary());
    row(out, s, "client", "command_packet_bytes_yellow", commandBytes[0].summary());
    row(out, s, "client", "command_packet_bytes_blue", commandBytes[1].summary());
    value(out, s, "client", "vision_received", static_cast<double>(seen.received));
    value(out, s, "client", "vision_lost", static_cast<double>(seen.lost));
    value(out, s, "client", "vision_kernel_drops", static_cast<double>(drops));
    value(out, s, "client", "vision_per_wall_second", static_cast<double>(seen.received - 1) / seen.wallSeconds());
    value(out, s, "client", "commands_sent", static_cast<double>(commands[0] + commands[1]));
    value(out, s, "server", "late_commands", stats["late_commands"].toDouble());
    for (const auto& [steps, count] : seen.stepGaps)
        out << '"' << s << "\",client,steps_between_environments," << count << ',' << steps << ",,,,\n";

    const SampleSummary period = seen.periodMs.summary();
    log << "  firasim realtime: " << duration << " s, " << commands[0] + commands[1]
        << " command packets (both teams, 7 ms each), late " << stats["late_commands"].toInt() << "\n"
        << "  command latency (arrival -> applied): " << quartiles(stats["command_latency_ms"].toObject()) << " ms\n"
        << "  vision at the client: " << seen.received << " Environments, " << seen.lost << " lost (" << drops
        << " dropped by the kernel); period median " << period.median << " ms, stddev " << period.stddev << " ms, p99 "
        << period.p99 << " ms, max " << period.max << " ms\n"
        << "  steps between Environments: " << seen.gaps() << "\n"
        << "  arrival against the simulated-time schedule, |deviation|: " << jitterText(seen.jitter.summary()) << "\n"
        << "  bytes: Environment " << seen.bytes.summary().median << ", command packet (3 robots) yellow "
        << commandBytes[0].summary().median << ", blue " << commandBytes[1].summary().median << "\n";
}

// The baseline: the same through the TCP protocol, VOLTAGES every 7 ms,
// STATE at the TCP camera's 30 ms.
void tcpRealtime(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 3.0 : 60.0;
    Server server(options, {}, duration, false);
    ProtocolClient team[2];
    std::vector<int> robots[2];
    for (int t : {0, 1}) {
        const QString role = t == 0 ? "yellow" : "blue";
        const std::optional<QJsonObject> welcome =
            team[t].connectTo(server.tcpPort)
                ? team[t].hello(QJsonObject{{"protocol", 1}, {"role", role}, {"images", "none"}, {"state", true}})
                : std::nullopt;
        if (!welcome) throw std::runtime_error("a TCP team client could not connect");
        for (const QJsonValue& r : (*welcome)["robots"].toArray())
            if (r["team"].toString() == role) robots[t].push_back(r["index"].toInt());
    }
    QRandomGenerator random(7);
    SampleStats periodMs[2], stateBytes{1 << 20}, voltagesBytes;
    ScheduleJitter jitter;
    std::int64_t lastNs[2] = {-1, -1}, lastFrame[2] = {-1, -1}, states[2] = {0, 0}, lost[2] = {0, 0};
    std::int64_t commands = 0;
    const std::int64_t startNs = monotonicNs(), endNs = startNs + static_cast<std::int64_t>(duration * 1e9);
    std::int64_t next[2] = {startNs, startNs + kCommandPeriodNs / 2};
    for (std::int64_t now = monotonicNs(); now < endNs; now = monotonicNs()) {
        for (int t : {0, 1}) {
            if (now < next[t]) continue;
            std::vector<std::pair<int, Voltages>> entries;
            for (int r : robots[t]) entries.push_back({r, {random.bounded(14.8) - 7.4, random.bounded(14.8) - 7.4}});
            const QByteArray payload = protocol::encodeVoltages(entries);
            team[t].send(protocol::MessageType::Voltages, payload);
            voltagesBytes.add(
                static_cast<double>(protocol::encodeMessage(protocol::MessageType::Voltages, payload).size()));
            ++commands;
            next[t] += kCommandPeriodNs;
        }
        QCoreApplication::processEvents();  // the clients read what has arrived, stamped as they read it
        for (int t : {0, 1}) {
            while (auto r = team[t].poll()) {
                if (r->message.type != static_cast<std::uint8_t>(protocol::MessageType::State)) continue;
                const QJsonObject state = jsonPayload(r->message);
                const std::int64_t frame = state["frame"].toInteger(-1);
                if (t == 0) jitter.add(r->arrivalNs, state["time"].toDouble());
                if (lastNs[t] >= 0) periodMs[t].add(1e-6 * static_cast<double>(r->arrivalNs - lastNs[t]));
                if (lastFrame[t] >= 0 && frame > lastFrame[t] + 1) lost[t] += frame - lastFrame[t] - 1;
                lastNs[t] = r->arrivalNs;
                lastFrame[t] = frame;
                ++states[t];
                if (t == 0)
                    stateBytes.add(static_cast<double>(
                        protocol::encodeMessage(protocol::MessageType::State, r->message.payload).size()));
            }
        }
        waitReadable({static_cast<int>(team[0].socket().socketDescriptor()),
                      static_cast<int>(team[1].socket().socketDescriptor())},
                     std::min({next[0], next[1], endNs}));
    }
    const QJsonObject stats = serverStats(team[0]);

    const char* s = "tcp realtime";
    row(out, s, "server", "command_latency_ms", stats["command_latency_ms"].toObject());
    row(out, s, "server", "command_delay_ms", stats["command_delay_ms"].toObject());
    row(out, s, "server", "camera_period_ms", stats["frame_period_ms"].toObject());
    row(out, s, "client", "state_period_ms", periodMs[0].summary());
    row(out, s, "client", "state_period_ms_blue", periodMs[1].summary());
    row(out, s, "client", "state_schedule_deviation_ms", jitter.summary());
    row(out, s, "client", "state_bytes", stateBytes.summary());
    row(out, s, "client", "voltages_message_bytes", voltagesBytes.summary());
    value(out, s, "client", "states_received", static_cast<double>(states[0]));
    value(out, s, "client", "states_lost", static_cast<double>(lost[0] + lost[1]));
    value(out, s, "client", "commands_sent", static_cast<double>(commands));
    value(out, s, "server", "late_commands", stats["late_commands"].toDouble());

    const SampleSummary period = periodMs[0].summary();
    log << "  tcp realtime (baseline): " << duration << " s, " << commands << " VOLTAGES (both teams, 7 ms each), late "
        << stats["late_commands"].toInt() << "\n"
        << "  command latency (arrival -> applied): " << quartiles(stats["command_latency_ms"].toObject()) << " ms\n"
        << "  STATE at the yellow client: " << states[0] << " received, " << lost[0] << " lost (blue " << lost[1]
        << "); period median " << period.median << " ms, stddev " << period.stddev << " ms, p99 " << period.p99
        << " ms, max " << period.max << " ms\n"
        << "  arrival against the simulated-time schedule, |deviation|: " << jitterText(jitter.summary()) << "\n"
        << "  bytes: STATE " << stateBytes.summary().median << ", VOLTAGES (3 robots) "
        << voltagesBytes.summary().median << "\n";
}

// --speed max: each team answers every Environment.
void firasimMax(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 2.0 : 20.0;
    Udp vision, yellow, blue;
    Server server(options,
                  {"--firasim", "--speed", "max", "--firasim-port", "0", "--vision-address", "127.0.0.1",
                   "--vision-port", QString::number(vision.port())},
                  duration, true);
    ProtocolClient observer;
    if (!observer.connectTo(server.tcpPort) ||
        !observer.hello(QJsonObject{{"protocol", 1}, {"role", "observer"}, {"images", "none"}}))
        throw std::runtime_error("the TCP observer could not connect");
    QRandomGenerator random(11);
    VisionLog seen;
    std::int64_t commands = 0;
    const std::int64_t startNs = monotonicNs(), endNs = startNs + static_cast<std::int64_t>(duration * 1e9);
    std::string data;
    for (std::int64_t now = monotonicNs(); now < endNs; now = monotonicNs()) {
        while (vision.receive(&data)) {
            seen.add(data, monotonicNs());
            yellow.sendTo(server.firasimPort, commandPacket(random, true));
            blue.sendTo(server.firasimPort, commandPacket(random, false));
            commands += 2;
        }
        waitReadable({vision.fd()}, endNs);
    }
    const std::int64_t drops = kernelDrops(vision.port());
    const QJsonObject stats = serverStats(observer);
    const double rate = seen.simulatedSeconds() / seen.wallSeconds();
    const double visionRate = static_cast<double>(seen.received - 1) / seen.wallSeconds();

    const char* s = "firasim max";
    row(out, s, "server", "command_latency_ms", stats["command_latency_ms"].toObject());
    row(out, s, "client", "vision_period_ms", seen.periodMs.summary());
    value(out, s, "client", "simulated_seconds_per_wall_second", rate);
    value(out, s, "client", "vision_per_wall_second", visionRate);
    value(out, s, "client", "vision_received", static_cast<double>(seen.received));
    value(out, s, "client", "vision_lost", static_cast<double>(seen.lost));
    value(out, s, "client", "vision_kernel_drops", static_cast<double>(drops));
    value(out, s, "client", "commands_sent", static_cast<double>(commands));
    // Each command packet the engine applied is one latency sample; the rest
    // were refused as busy (a team's quota of requests waiting was full).
    const double applied = stats["command_latency_ms"].toObject()["count"].toDouble();
    value(out, s, "server", "commands_applied", applied);

    log << "  firasim max: " << seen.wallSeconds() << " s, " << seen.simulatedSeconds() << " s simulated: " << rate
        << "x real time; " << visionRate << " Environments/s received (" << seen.received << ", " << seen.lost
        << " instants not received, " << drops << " of them dropped by the kernel), " << commands
        << " command packets answered, " << applied << " of them applied ("
        << 100.0 * applied / static_cast<double>(commands) << " %; the rest refused as busy)\n"
        << "  command latency (arrival -> applied): " << quartiles(stats["command_latency_ms"].toObject()) << " ms\n"
        << "  steps between Environments: " << seen.gaps() << "\n";
}

// --firasim-sync: one client, both teams' commands in one packet, waiting
// for each tick's Environment.
void firasimSync(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 2.0 : 20.0;
    Udp vision, client;
    Server server(options,
                  {"--firasim-sync", "--firasim-port", "0", "--vision-address", "127.0.0.1", "--vision-port",
                   QString::number(vision.port())},
                  duration, true);
    QRandomGenerator random(13);
    std::string data;
    std::int64_t lastStep = -1;
    // Waits for the Environment of a step beyond the last one seen.
    auto tick = [&](const std::string& packet) {
        client.sendTo(server.firasimPort, packet);
        const std::int64_t giveUpNs = monotonicNs() + 10'000'000'000;
        for (;;) {
            while (vision.receive(&data)) {
                Environment env;
                if (!env.ParseFromString(data)) throw std::runtime_error("the vision is not an Environment");
                if (static_cast<std::int64_t>(env.step()) > lastStep) {
                    lastStep = env.step();
                    return;
                }
            }
            if (monotonicNs() > giveUpNs) throw std::runtime_error("sync: no Environment after a command packet");
            waitReadable({vision.fd()}, giveUpNs);
        }
    };
    tick(commandPacket(random, true, true));  // a first tick; an Environment of step 0 may have come before
    ::usleep(200'000);
    while (vision.receive(&data)) {
        Environment env;
        if (env.ParseFromString(data)) lastStep = std::max<std::int64_t>(lastStep, env.step());
    }
    const std::int64_t firstStep = lastStep;
    SampleStats roundTripMs{1 << 20};
    std::int64_t ticks = 0;
    const std::int64_t startNs = monotonicNs(), endNs = startNs + static_cast<std::int64_t>(duration * 1e9);
    while (monotonicNs() < endNs) {
        const std::string packet = commandPacket(random, true, true);
        const std::int64_t sentNs = monotonicNs();
        tick(packet);
        roundTripMs.add(1e-6 * static_cast<double>(monotonicNs() - sentNs));
        ++ticks;
    }
    const double seconds = 1e-9 * static_cast<double>(monotonicNs() - startNs);
    const double simulated = kDt * static_cast<double>(lastStep - firstStep);

    const char* s = "firasim sync";
    row(out, s, "client", "tick_round_trip_ms", roundTripMs.summary());
    value(out, s, "client", "ticks_per_wall_second", static_cast<double>(ticks) / seconds);
    value(out, s, "client", "simulated_seconds_per_wall_second", simulated / seconds);

    log << "  firasim sync: " << ticks << " ticks in " << seconds << " s: " << static_cast<double>(ticks) / seconds
        << " ticks/s, " << simulated / seconds << "x real time; round trip median " << roundTripMs.summary().median
        << " ms, p99 " << roundTripMs.summary().p99 << " ms\n";
}

}  // namespace

int firasimLatency(const Options& options, std::ostream& out, std::ostream& log) {
    out << "scenario,source,metric,count,median,p99,max,mean,stddev\n" << std::setprecision(6);
    // The machine's load beside each scenario: the cores are shared.
    auto load = [&log] {
        QFile file(QStringLiteral("/proc/loadavg"));
        if (file.open(QIODevice::ReadOnly))
            log << "  load average: " << file.readLine().trimmed().toStdString() << "\n";
    };
    for (auto scenario : {firasimRealtime, tcpRealtime, firasimMax, firasimSync}) {
        load();
        scenario(options, out, log);
    }
    load();
    return 0;
}

}  // namespace vssim::bench
