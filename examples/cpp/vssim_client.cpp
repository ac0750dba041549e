// A minimal vssim team client: drive one robot to the ball using only the camera.
//
// It shows the whole protocol of docs/protocol.md from a team's side:
//   1. connect over TCP and say HELLO as a team (yellow or blue);
//   2. read WELCOME (field, camera mapping, our robots) and the background FRAME;
//   3. for every following FRAME: paste its patches onto a copy of the background,
//      find our robot (team patch + identity patch) and the ball by colour, and
//      answer with VOLTAGES from a simple go-to-point controller;
//   4. in lockstep mode (`vssim serve --lockstep`) also advance simulated time
//      ourselves with CONTROL {"command": "step"}.
// It stops (0 V, exit 0) once the robot touches the ball as seen on the image,
// exits 1 if --max-time simulated seconds pass (from its first image) first and 2 on any connection or
// protocol error. Only POSIX sockets and OpenCV (core, imgproc, imgcodecs); the
// few JSON messages are handled by a tiny parser below.
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace {

// Message types (docs/protocol.md, "Framing").
enum : std::uint8_t { kHello = 0x01, kVoltages = 0x02, kControl = 0x03 };  // client -> server
enum : std::uint8_t {
    kWelcome = 0x81,
    kFrame = 0x82,
    kState = 0x83,
    kReply = 0x84,
    kError = 0x85
};  // server -> client
enum { kKindPatches = 0, kKindFull = 1, kKindBackground = 2 };
enum { kRaw = 0, kPng = 1, kJpeg = 2 };

constexpr double kStepDuration = 0.03;  // s of simulated time per CONTROL step (--lockstep)
constexpr int kSilenceTimeout = 10;     // s of wall-clock time without any message before giving up

// Camera colours, (B, G, R) as in OpenCV. Any two differ by at least 127 in some
// channel, so +-40 per channel never confuses them (red and the orange ball differ
// only in G) while still accepting blended edge pixels and JPEG noise.
const cv::Scalar kYellow(0, 255, 255), kBlue(255, 0, 0), kBall(0, 128, 255);
const cv::Scalar kIdentity[6] = {{0, 0, 255},   {0, 255, 0},     {255, 0, 255},   // red, green, magenta,
                                 {255, 255, 0}, {255, 255, 255}, {128, 0, 128}};  // cyan, white, purple
constexpr double kColourTolerance = 40;
constexpr int kMinBlobArea = 10;          // px: smaller blobs are edge artefacts or noise
constexpr int kForegroundThreshold = 40;  // a pixel is "new" if it differs this much from the background

struct ProtocolError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// ---------------------------------------------------------------------------
// A tiny JSON reader: enough for WELCOME, REPLY and ERROR.
// ---------------------------------------------------------------------------
struct Json {
    enum Type { Null, Bool, Number, String, Array, Object } type = Null;
    double number = 0;  // also 1/0 for booleans
    std::string text;
    std::vector<Json> items;
    std::map<std::string, Json> fields;

    const Json& operator[](const std::string& key) const {
        static const Json missing;
        auto it = fields.find(key);
        return it == fields.end() ? missing : it->second;
    }
    double num() const {
        if (type != Number) throw ProtocolError("a JSON number was expected");
        return number;
    }
    std::string str() const { return type == String ? text : type == Number ? std::to_string(number) : ""; }
};

class JsonParser {
public:
    explicit JsonParser(const std::string& s) : s_(s) {}
    Json parseDocument() {
        Json value = parseValue();
        skipSpace();
        if (pos_ != s_.size()) fail();
        return value;
    }

private:
    const std::string& s_;
    std::size_t pos_ = 0;

    [[noreturn]] void fail() { throw ProtocolError("malformed JSON from the server"); }
    void skipSpace() {
        while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\r' || s_[pos_] == '\n'))
            ++pos_;
    }
    bool eat(char c) {
        skipSpace();
        if (pos_ < s_.size() && s_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }
    bool eatWord(const char* w) {
        if (s_.compare(pos_, std::strlen(w), w) != 0) return false;
        pos_ += std::strlen(w);
        return true;
    }
    std::string parseString() {  // after the opening quote; \uXXXX beyond ASCII becomes '?'
        std::string out;
        while (pos_ < s_.size() && s_[pos_] != '"') {
            char c = s_[pos_++];
            if (c == '\\' && pos_ < s_.size()) {
                char e = s_[pos_++];
                if (e == 'u') {
                    out += '?';
                    pos_ += 4;
                    continue;
                }
                c = e == 'n' ? '\n' : e == 't' ? '\t' : e == 'r' ? '\r' : e == 'b' ? '\b' : e == 'f' ? '\f' : e;
            }
            out += c;
        }
        if (pos_++ >= s_.size()) fail();
        return out;
    }
    Json parseValue() {
        Json v;
        skipSpace();
        if (pos_ >= s_.size()) fail();
        if (eat('{')) {
            v.type = Json::Object;
            if (eat('}')) return v;
            do {
                if (!eat('"')) fail();
                std::string key = parseString();
                if (!eat(':')) fail();
                v.fields[key] = parseValue();
            } while (eat(','));
            if (!eat('}')) fail();
        } else if (eat('[')) {
            v.type = Json::Array;
            if (eat(']')) return v;
            do v.items.push_back(parseValue());
            while (eat(','));
            if (!eat(']')) fail();
        } else if (eat('"')) {
            v.type = Json::String;
            v.text = parseString();
        } else if (eatWord("true")) {
            v.type = Json::Bool;
            v.number = 1;
        } else if (eatWord("false")) {
            v.type = Json::Bool;
        } else if (eatWord("null")) {
        } else {
            const char* start = s_.c_str() + pos_;
            char* end = nullptr;
            v.type = Json::Number;
            v.number = std::strtod(start, &end);
            if (end == start) fail();
            pos_ += static_cast<std::size_t>(end - start);
        }
        return v;
    }
};

Json parseJson(const std::vector<std::uint8_t>& payload) {
    return JsonParser(std::string(payload.begin(), payload.end())).parseDocument();
}

// ---------------------------------------------------------------------------
// The connection: every message is u32 length (big-endian, counts type +
// payload) + u8 type + payload. All numbers are big-endian.
// ---------------------------------------------------------------------------
void putU32(std::vector<std::uint8_t>& b, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) b.push_back(std::uint8_t(v >> s));
}
void putF64(std::vector<std::uint8_t>& b, double d) {
    std::uint64_t v;
    std::memcpy(&v, &d, 8);
    for (int s = 56; s >= 0; s -= 8) b.push_back(std::uint8_t(v >> s));
}
std::uint64_t getBE(const std::uint8_t* p, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
    return v;
}
double getF64(const std::uint8_t* p) {
    std::uint64_t v = getBE(p, 8);
    double d;
    std::memcpy(&d, &v, 8);
    return d;
}

class Connection {
public:
    Connection(const std::string& host, const std::string& port) {
        addrinfo hints{}, *found = nullptr;
        hints.ai_family = AF_UNSPEC;
        hints.ai_socktype = SOCK_STREAM;
        if (int rc = getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0)
            throw ProtocolError("cannot resolve " + host + ": " + gai_strerror(rc));
        std::string why = "no address";
        for (addrinfo* a = found; a && fd_ < 0; a = a->ai_next) {
            fd_ = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
            if (fd_ >= 0 && connect(fd_, a->ai_addr, a->ai_addrlen) != 0) {
                why = std::strerror(errno);
                close(fd_);
                fd_ = -1;
            }
        }
        freeaddrinfo(found);
        if (fd_ < 0) throw ProtocolError("cannot connect to " + host + ":" + port + ": " + why);
        int one = 1;  // small messages (VOLTAGES, CONTROL) must leave at once, not wait for Nagle
        setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        timeval timeout{kSilenceTimeout, 0};
        setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    }
    ~Connection() {
        if (fd_ >= 0) close(fd_);
    }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    void send(std::uint8_t type, const std::vector<std::uint8_t>& payload) {
        std::vector<std::uint8_t> message;
        putU32(message, std::uint32_t(payload.size() + 1));
        message.push_back(type);
        message.insert(message.end(), payload.begin(), payload.end());
        for (std::size_t sent = 0; sent < message.size();) {
            ssize_t n = ::send(fd_, message.data() + sent, message.size() - sent, MSG_NOSIGNAL);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw ProtocolError(std::string("connection lost while sending: ") + std::strerror(errno));
            sent += std::size_t(n);
        }
    }
    void sendJson(std::uint8_t type, const std::string& json) { send(type, {json.begin(), json.end()}); }
    void sendVoltages(int robotIndex, double right, double left) {
        std::vector<std::uint8_t> p{1, std::uint8_t(robotIndex)};  // u8 count, then u8 index, f64 right, f64 left
        putF64(p, right);
        putF64(p, left);
        send(kVoltages, p);
    }
    // Whether another message has already arrived (a newer image, usually).
    bool moreWaiting() const {
        pollfd p{fd_, POLLIN, 0};
        return poll(&p, 1, 0) > 0 && (p.revents & POLLIN);
    }

    int sendStep() {  // CONTROL step with a fresh id, echoed in its REPLY or ERROR
        int id = nextId_++;
        char json[96];
        std::snprintf(json, sizeof json, "{\"command\": \"step\", \"duration\": %g, \"id\": %d}", kStepDuration, id);
        sendJson(kControl, json);
        return id;
    }
    // The next message: its type, and its payload in `payload`.
    std::uint8_t receive(std::vector<std::uint8_t>& payload) {
        std::uint8_t header[5];
        receiveExactly(header, 4);
        std::uint32_t length = std::uint32_t(getBE(header, 4));
        if (length < 1) throw ProtocolError("malformed message from the server: length 0");
        receiveExactly(header + 4, 1);
        payload.resize(length - 1);
        receiveExactly(payload.data(), payload.size());
        return header[4];
    }

private:
    int fd_ = -1;
    int nextId_ = 1;
    void receiveExactly(std::uint8_t* out, std::size_t n) {
        while (n > 0) {
            ssize_t got = recv(fd_, out, n, 0);
            if (got < 0 && errno == EINTR) continue;
            if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
                throw ProtocolError(
                    "no message from the server for " + std::to_string(kSilenceTimeout) +
                    " s (is it paused, or in lockstep mode while this client runs without --lockstep?)");
            if (got < 0) throw ProtocolError(std::string("connection lost: ") + std::strerror(errno));
            if (got == 0) throw ProtocolError("the server closed the connection");
            out += got;
            n -= std::size_t(got);
        }
    }
};

std::string describeError(const Json& e) { return "server ERROR " + e["error"].str() + ": " + e["message"].str(); }

// ---------------------------------------------------------------------------
// FRAME: u32 frame, f64 time, u8 kind, u8 encoding, u16 count, then per patch
// u16 x, y, w, h, u32 bytes and the image data.
// ---------------------------------------------------------------------------
struct Patch {
    int x = 0, y = 0;
    cv::Mat image;
};
struct Frame {
    std::uint32_t number = 0;
    double time = 0;
    int kind = 0;
    std::vector<Patch> patches;  // without the empty ones (bodies outside the image)
};

Frame parseFrame(const std::vector<std::uint8_t>& p) {
    if (p.size() < 16) throw ProtocolError("truncated FRAME");
    Frame f;
    f.number = std::uint32_t(getBE(&p[0], 4));
    f.time = getF64(&p[4]);
    f.kind = p[12];
    const int encoding = p[13], count = int(getBE(&p[14], 2));
    std::size_t at = 16;
    for (int i = 0; i < count; ++i) {
        if (at + 12 > p.size()) throw ProtocolError("truncated FRAME patch header");
        Patch patch;
        patch.x = int(getBE(&p[at], 2));
        patch.y = int(getBE(&p[at + 2], 2));
        const int w = int(getBE(&p[at + 4], 2)), h = int(getBE(&p[at + 6], 2));
        const std::size_t bytes = std::size_t(getBE(&p[at + 8], 4));
        at += 12;
        if (at + bytes > p.size()) throw ProtocolError("truncated FRAME patch data");
        if (w > 0 && h > 0) {
            if (encoding == kRaw) {  // rows top to bottom, 3 bytes B, G, R per pixel
                if (bytes != std::size_t(w) * std::size_t(h) * 3) throw ProtocolError("raw patch of the wrong size");
                patch.image = cv::Mat(h, w, CV_8UC3, const_cast<std::uint8_t*>(p.data() + at)).clone();
            } else if (encoding == kPng || encoding == kJpeg) {
                patch.image = cv::imdecode(cv::Mat(1, int(bytes), CV_8UC1, const_cast<std::uint8_t*>(p.data() + at)),
                                           cv::IMREAD_COLOR);
                if (patch.image.rows != h || patch.image.cols != w) throw ProtocolError("cannot decode a patch");
            } else {
                throw ProtocolError("unknown image encoding " + std::to_string(encoding));
            }
            f.patches.push_back(patch);
        }
        at += bytes;
    }
    return f;
}

// ---------------------------------------------------------------------------
// Vision: colour blobs -> robot pose and ball position, in the field frame.
// ---------------------------------------------------------------------------
struct Camera {  // from WELCOME: u = centre_u + scale x, v = centre_v - scale y
    double scale = 1, centreU = 0, centreV = 0;
    // Pixel indices (fractional for centroids) -> field metres; pixel i's centre is u = i + 0.5.
    cv::Point2d toField(cv::Point2d px) const {
        return {(px.x + 0.5 - centreU) / scale, (centreV - (px.y + 0.5)) / scale};
    }
};

// Centroids (pixel indices) of the blobs of one colour, largest first. Only
// pixels that differ from the background (`foreground`) count: that keeps the
// white field markings out of the white identity colour. A 3x3 opening removes
// one-pixel fringes, e.g. the purple anti-aliased edge of a magenta patch.
std::vector<cv::Point2d> findBlobs(const cv::Mat& image, const cv::Mat& foreground, const cv::Scalar& bgr) {
    cv::Mat mask, labels, stats, centroids;
    const cv::Scalar tolerance = cv::Scalar::all(kColourTolerance);
    cv::inRange(image, bgr - tolerance, bgr + tolerance, mask);
    mask &= foreground;
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::Mat::ones(3, 3, CV_8U));
    const int count = cv::connectedComponentsWithStats(mask, labels, stats, centroids);
    std::vector<std::pair<int, cv::Point2d>> blobs;
    for (int i = 1; i < count; ++i)  // label 0 is the background
        if (stats.at<int>(i, cv::CC_STAT_AREA) >= kMinBlobArea)
            blobs.push_back(
                {stats.at<int>(i, cv::CC_STAT_AREA), {centroids.at<double>(i, 0), centroids.at<double>(i, 1)}});
    std::sort(blobs.begin(), blobs.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<cv::Point2d> result;
    for (const auto& b : blobs) result.push_back(b.second);
    return result;
}

struct Pose {
    double x, y, theta;
};

// Each identity blob is paired with the nearest team-colour blob: on a robot their
// centroids are 0.5 side apart, so pairs farther than 0.75 side are rejected. The
// centre is their midpoint, the heading points from the team to the identity patch.
std::optional<Pose> findRobot(const cv::Mat& image, const cv::Mat& foreground, const Camera& camera,
                              const cv::Scalar& team, const cv::Scalar& identity, double side) {
    const std::vector<cv::Point2d> teamBlobs = findBlobs(image, foreground, team);
    double best = 0.75 * side * camera.scale;
    std::optional<Pose> pose;
    for (const cv::Point2d& id : findBlobs(image, foreground, identity))
        for (const cv::Point2d& tb : teamBlobs)
            if (double d = cv::norm(id - tb); d <= best) {
                best = d;
                const cv::Point2d a = camera.toField(tb), b = camera.toField(id);
                pose = Pose{(a.x + b.x) / 2, (a.y + b.y) / 2, std::atan2(b.y - a.y, b.x - a.x)};
            }
    return pose;
}

std::optional<cv::Point2d> findBall(const cv::Mat& image, const cv::Mat& foreground, const Camera& camera) {
    const std::vector<cv::Point2d> blobs = findBlobs(image, foreground, kBall);
    if (blobs.empty()) return std::nullopt;
    return camera.toField(blobs.front());  // the largest orange blob
}

// ---------------------------------------------------------------------------
// Control: heading error -> differential voltage, distance -> common voltage.
// VSSS robots are symmetric: a target behind is reached driving backwards,
// with a little hysteresis so that a nearly sideways target causes no dithering.
// ---------------------------------------------------------------------------
constexpr double kTurnGain = 1.2;       // V of differential voltage per rad of heading error
constexpr double kDistanceGain = 20.0;  // V of common voltage per m of distance
constexpr double kCruiseVoltage = 5.0;  // V: the common voltage never exceeds this (~1.2 m/s)

constexpr double kPi = 3.14159265358979323846;

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

struct GoToPoint {
    double maxVoltage;
    bool backwards = false;

    std::pair<double, double> command(const Pose& robot, const cv::Point2d& target) {  // (right, left)
        const double dx = target.x - robot.x, dy = target.y - robot.y;
        double error = wrapAngle(std::atan2(dy, dx) - robot.theta);  // heading error driving forwards
        backwards = std::abs(error) > kPi / 2 + (backwards ? -0.3 : 0.3);
        if (backwards) error = wrapAngle(error - kPi);  // heading error driving backwards
        // Slow down while the robot does not face the target (|error| <= ~pi/2 here).
        double common = std::min(kDistanceGain * std::hypot(dx, dy), kCruiseVoltage) * std::max(std::cos(error), 0.0);
        // > 0: turn left. Stay within +-maxVoltage on both wheels, turning first.
        const double differential = std::clamp(kTurnGain * error, -maxVoltage, maxVoltage);
        common = std::min(common, maxVoltage - std::abs(differential)) * (backwards ? -1 : 1);
        return {common + differential, common - differential};
    }
};

// ---------------------------------------------------------------------------
// The session
// ---------------------------------------------------------------------------
struct Options {
    std::string host = "127.0.0.1", port = "10030", team = "yellow", encoding = "png";
    int robot = 0;
    bool lockstep = false, verbose = false;
    double maxTime = 20;
};

const char* kUsage =
    "usage: vssim_example_client [--host H] [--port N] [--team yellow|blue] [--robot ID]\n"
    "                            [--encoding png|raw|jpeg] [--lockstep] [--max-time S] [--verbose]\n"
    "Drives one robot to the ball using only the camera images of a `vssim serve` server.\n"
    "  --host H        server address (default 127.0.0.1)\n"
    "  --port N        server port (default 10030)\n"
    "  --team T        yellow (default) or blue\n"
    "  --robot ID      the robot's id within the team, i.e. its identity colour (default 0)\n"
    "  --encoding E    image encoding: png (default), raw or jpeg\n"
    "  --lockstep      step simulated time ourselves, 0.03 s per decision (`vssim serve --lockstep`)\n"
    "  --max-time S    give up (exit 1) after S simulated seconds (default 20)\n"
    "  --verbose       print the estimates at every frame\n"
    "Exit status: 0 ball reached, 1 --max-time passed, 2 connection or protocol error.\n";

int run(const Options& o) {
    Connection conn(o.host, o.port);
    conn.sendJson(kHello, "{\"protocol\": 1, \"role\": \"" + o.team +
                              "\", \"name\": \"vssim example client (C++)\", "
                              "\"images\": \"patches\", \"encoding\": \"" +
                              o.encoding + "\"}");
    std::vector<std::uint8_t> payload;
    Json welcome;
    for (std::uint8_t type = 0; type != kWelcome;) {  // skip anything else before WELCOME
        type = conn.receive(payload);
        if (type == kError) throw ProtocolError(describeError(parseJson(payload)));  // e.g. role_taken
        if (type == kWelcome) welcome = parseJson(payload);
    }

    const Json& cam = welcome["camera"];
    const Camera camera{cam["scale"].num(), cam["centre_u"].num(), cam["centre_v"].num()};
    const Json* robot = nullptr;
    for (const Json& r : welcome["robots"].items)
        if (r["team"].str() == o.team && r["id"].num() == o.robot) robot = &r;
    if (!robot) throw ProtocolError("the scene has no " + o.team + " robot with id " + std::to_string(o.robot));
    const int index = int((*robot)["index"].num());
    const double side = (*robot)["side"].num();
    const double reachDistance = side / 2 + welcome["ball"]["radius"].num() + 0.015;
    const cv::Scalar team = o.team == "yellow" ? kYellow : kBlue, identity = kIdentity[o.robot % 6];
    GoToPoint controller{(*robot)["max_voltage"].num()};
    std::printf("connected to %s (%s mode) as %s: driving %s (index %d) to the ball\n", welcome["server"].str().c_str(),
                welcome["mode"].str().c_str(), o.team.c_str(), (*robot)["name"].str().c_str(), index);
    if (welcome["mode"].str() == "lockstep" && !o.lockstep)
        std::fprintf(stderr,
                     "note: the server is in lockstep mode: time only advances when a client steps it "
                     "(use --lockstep to do it from this client)\n");

    cv::Mat background, image, foreground;
    int stepId = 0;  // id of our CONTROL step awaiting its REPLY (lockstep only)
    long skipped = 0;  // images passed over because a newer one had already arrived
    char estimate[160] = "nothing seen yet";
    double startTime = -1;  // s, simulated time of the first image (-1: none yet)
    for (;;) {
        const std::uint8_t type = conn.receive(payload);
        if (type == kError) {
            const Json e = parseJson(payload);
            const bool ourStep = stepId != 0 && e["id"].type == Json::Number && e["id"].number == stepId;
            if (e["fatal"].number != 0 || ourStep)
                throw ProtocolError(describeError(e) +
                                    (ourStep ? " (step needs `vssim serve --lockstep`, or a paused server)" : ""));
            std::fprintf(stderr, "warning: %s\n", describeError(e).c_str());  // not fatal: carry on
            continue;
        }
        if (type == kReply) {
            // The FRAME of our step came before this REPLY and has been answered with
            // VOLTAGES already: advance time again. REPLYs we did not ask for: ignored.
            const Json r = parseJson(payload);
            if (o.lockstep && stepId != 0 && r["id"].type == Json::Number && r["id"].number == stepId)
                stepId = conn.sendStep();
            continue;
        }
        if (type != kFrame) continue;  // STATE (not asked for), unknown types: skip
        // In real time, act on the newest image: when more has already arrived
        // behind this FRAME, this client is behind the camera and a newer image
        // is on its way (lockstep: every step's FRAME counts).
        if (!o.lockstep && payload.size() > 12 && payload[12] != kKindBackground && conn.moreWaiting()) {
            ++skipped;
            continue;
        }

        const Frame frame = parseFrame(payload);
        if (frame.kind == kKindBackground) {
            if (frame.patches.size() != 1) throw ProtocolError("background FRAME without exactly one patch");
            background = frame.patches[0].image;
            if (o.lockstep && stepId == 0) stepId = conn.sendStep();  // get the first image
            continue;
        }
        if (background.empty()) throw ProtocolError("FRAME before the background FRAME");

        // Rebuild the full camera image: a fresh copy of the background, patches pasted in order.
        background.copyTo(image);
        for (const Patch& p : frame.patches) {
            const cv::Rect where(p.x, p.y, p.image.cols, p.image.rows);
            if ((where & cv::Rect(0, 0, image.cols, image.rows)) != where)
                throw ProtocolError("patch outside the image");
            p.image.copyTo(image(where));
        }
        cv::Mat difference;
        cv::absdiff(image, background, difference);
        cv::Mat channels[3];
        cv::split(difference, channels);
        foreground = cv::max(cv::max(channels[0], channels[1]), channels[2]) > kForegroundThreshold;

        const std::optional<Pose> pose = findRobot(image, foreground, camera, team, identity, side);
        const std::optional<cv::Point2d> ball = findBall(image, foreground, camera);
        double right = 0, left = 0;  // lost sight of something: wait for a better image
        if (!pose || !ball) {
            std::snprintf(estimate, sizeof estimate, "robot %sseen, ball %sseen", pose ? "" : "not ",
                          ball ? "" : "not ");
            if (o.verbose) std::printf("frame %u t=%.3f: %s\n", frame.number, frame.time, estimate);
        } else {
            const double distance = std::hypot(ball->x - pose->x, ball->y - pose->y);
            std::snprintf(estimate, sizeof estimate, "robot (%.3f, %.3f) ball (%.3f, %.3f)", pose->x, pose->y, ball->x,
                          ball->y);
            if (distance <= reachDistance) {
                conn.sendVoltages(index, 0, 0);
                std::printf("reached the ball at t=%.2f s (frame %u): %s (%ld older images skipped)\n", frame.time,
                            frame.number, estimate, skipped);
                return 0;
            }
            std::tie(right, left) = controller.command(*pose, *ball);
            if (o.verbose)
                std::printf(
                    "frame %u t=%.3f: robot (%.3f, %.3f, %.0f deg) ball (%.3f, %.3f) distance %.3f m -> "
                    "right %+.2f V left %+.2f V\n",
                    frame.number, frame.time, pose->x, pose->y, pose->theta * 180 / kPi, ball->x, ball->y, distance,
                    right, left);
        }
        if (startTime < 0) startTime = frame.time;  // --max-time counts from the first image
        if (frame.time - startTime >= o.maxTime) {
            conn.sendVoltages(index, 0, 0);
            std::fprintf(
                stderr,
                "did not reach the ball within %g s of simulated time from the first image (t=%.2f s, frame %u; "
                "last estimate: %s)\n",
                o.maxTime, frame.time, frame.number, estimate);
            return 1;
        }
        conn.sendVoltages(index, right, left);
    }
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s needs a value\n%s", arg.c_str(), kUsage);
                std::exit(2);
            }
            return argv[++i];
        };
        try {
            if (arg == "--help" || arg == "-h") {
                std::printf("%s", kUsage);
                return 0;
            } else if (arg == "--host")
                o.host = value();
            else if (arg == "--port")
                o.port = std::to_string(std::stoi(value()));
            else if (arg == "--team")
                o.team = value();
            else if (arg == "--robot")
                o.robot = std::stoi(value());
            else if (arg == "--encoding")
                o.encoding = value();
            else if (arg == "--lockstep")
                o.lockstep = true;
            else if (arg == "--max-time")
                o.maxTime = std::stod(value());
            else if (arg == "--verbose")
                o.verbose = true;
            else
                throw std::invalid_argument("unknown option");
        } catch (const std::logic_error&) {  // std::stoi/stod failures and unknown options
            std::fprintf(stderr, "bad option: %s\n%s", arg.c_str(), kUsage);
            return 2;
        }
    }
    if ((o.team != "yellow" && o.team != "blue") ||
        (o.encoding != "png" && o.encoding != "raw" && o.encoding != "jpeg") || o.robot < 0) {
        std::fprintf(stderr, "bad --team, --encoding or --robot\n%s", kUsage);
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // one line at a time, also into a pipe
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
}
