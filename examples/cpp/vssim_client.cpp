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

// Camera colours, (B, G, R) as in OpenCV (docs/protocol.md, "The camera").
const cv::Scalar kYellow(0, 255, 255), kBlue(255, 0, 0), kBall(0, 128, 255);  // the ball is orange
const cv::Scalar kIdentity[6] = {{0, 0, 255},   {0, 255, 0},     {255, 0, 255},   // red, green, magenta,
                                 {255, 255, 0}, {255, 255, 255}, {128, 0, 128}};  // cyan, white, purple
// Colours are told apart by hue, which neither uneven light (vignetting,
// gradients: they scale B, G and R alike) nor blur (it blends a patch with the
// black body: a darker pixel of the same hue) change; a colour cast moves it by
// a few degrees at most. Hues in OpenCV's units (0..180, 2 degrees each): red 0,
// orange 15, yellow 30, green 60, cyan 90, blue 120, magenta and purple 150.
// Orange lies 15 from red and yellow, so +-7 keeps every class apart.
constexpr int kHueTolerance = 7;
constexpr int kMinSaturation = 128;      // of 255: coloured patches are saturated, white and greys are not
constexpr int kMinValue = 50;            // of 255: darker pixels (the body, the floor) have no reliable hue
constexpr int kWhiteMaxSaturation = 70;  // white: little saturation (a colour cast gives it ~20) ...
constexpr int kWhiteMinValue = 100;      // ... and bright (a vignetted corner still leaves ~160)
// Magenta and purple share a hue: an identity blob's mean brightness (V) over
// its team patch's must be within this factor of the nominal ratio (1 for
// magenta, 0.5 for purple): the two patches lie side by side, under the same light.
constexpr double kBrightnessRatioTolerance = 1.4;
constexpr int kMinBlobArea = 10;          // px (after the opening): smaller blobs are edge artefacts or noise
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

// WELCOME's <where>.<key> as a finite number (positive if asked), or a clear error.
double cameraNumber(const Json& object, const std::string& key, bool positive = false,
                    const std::string& where = "camera") {
    const Json& v = object[key];
    if (v.type != Json::Number || !std::isfinite(v.number) || (positive && v.number <= 0))
        throw ProtocolError("WELCOME's " + where + "." + key + " is " + (v.type == Json::Null ? "missing" : "not") +
                            " a finite" + (positive ? " positive" : "") + " number");
    return v.number;
}

// Pixel -> field, from WELCOME's "camera" (docs/protocol.md, "The camera").
//
// "orthographic" (also a camera without "projection", from older servers): the
// ideal top view, u = centre_u + scale x, v = centre_v - scale y, in continuous
// coordinates where pixel column i covers u in [i, i+1) (its centre at i + 0.5).
// Every height looks the same.
//
// "pinhole": a camera `mount_height` m above the field centre looking straight down,
// u along +x and v along -y, through a lens with OpenCV's distortion model
// (k1, k2, p1, p2, k3); pixel centres at integer coordinates (OpenCV's
// convention: a centroid of pixel indices goes in as it is). A pixel is
// undistorted to normalised image coordinates (x_n, y_n), the inverse of
//   x_d = x_n R + 2 p1 x_n y_n + p2 (r^2 + 2 x_n^2),  y_d = y_n R + p1 (r^2 + 2 y_n^2) + 2 p2 x_n y_n,
//   R = 1 + k1 r^2 + k2 r^4 + k3 r^6,  r^2 = x_n^2 + y_n^2,  (x_d, y_d) = ((u - cx) / fx, (v - cy) / fy),
// by Newton's method (what cv::undistortPoints computes, which is in OpenCV's
// calib3d module: this client needs only core and imgproc), then its viewing
// ray is cut with the horizontal plane z of what was seen:
//   x = x_n (height - z),  y = -y_n (height - z).
// The plane matters (parallax): a robot's patches lie on its top face, z = side,
// which at 0.7 m from the centre appears 2.7 cm farther out than the floor point
// under it would; the ball is seen around its centre, z = radius.
//
// `delay` is how old an image is when it arrives: the camera's latency, half its
// jitter and half its exposure (a blurred blob is where the body was in the
// middle of the exposure), from WELCOME's camera.settings; 0 without them.
struct Camera {
    bool pinhole = false;
    double scale = 1, centreU = 0, centreV = 0;                               // orthographic
    double height = 2, fx = 1, fy = 1, cx = 0, cy = 0;                        // pinhole
    double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;                            // pinhole: lens distortion
    double delay = 0;                                                         // s

    explicit Camera(const Json& c) {
        if (c.type != Json::Object) throw ProtocolError("WELCOME has no camera object");
        const std::string projection = c["projection"].type == Json::Null ? "orthographic" : c["projection"].str();
        if (projection == "orthographic") {
            scale = cameraNumber(c, "scale", true);
            centreU = cameraNumber(c, "centre_u");
            centreV = cameraNumber(c, "centre_v");
        } else if (projection == "pinhole") {
            pinhole = true;
            // The camera's height above the field, m: "mount_height" ("height" is
            // the image's, px), else the camera settings' "height".
            const Json& s = c["settings"];
            height = c["mount_height"].type == Json::Null && s["height"].type != Json::Null
                         ? cameraNumber(s, "height", true, "camera.settings")
                         : cameraNumber(c, "mount_height", true);
            const Json& m = c["matrix"];
            auto entry = [&](int row, int column) {
                if (m.type != Json::Array || m.items.size() != 3 || m.items[row].type != Json::Array ||
                    m.items[row].items.size() != 3 || m.items[row].items[column].type != Json::Number ||
                    !std::isfinite(m.items[row].items[column].number))
                    throw ProtocolError("WELCOME's camera.matrix is not a 3 x 3 array of numbers");
                return m.items[row].items[column].number;
            };
            fx = entry(0, 0), cx = entry(0, 2), fy = entry(1, 1), cy = entry(1, 2);
            if (!(fx > 0 && fy > 0) || entry(0, 1) != 0 || entry(1, 0) != 0 || entry(2, 0) != 0 || entry(2, 1) != 0 ||
                entry(2, 2) != 1)
                throw ProtocolError("WELCOME's camera.matrix is not [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0");
            const Json& d = c["distortion"];
            if (d.type != Json::Null) {
                if (d.type != Json::Array || (d.items.size() != 4 && d.items.size() != 5))
                    throw ProtocolError("WELCOME's camera.distortion is not [k1, k2, p1, p2, k3]");
                double* coefficient[5] = {&k1, &k2, &p1, &p2, &k3};
                for (std::size_t i = 0; i < d.items.size(); ++i) {
                    if (d.items[i].type != Json::Number || !std::isfinite(d.items[i].number))
                        throw ProtocolError("WELCOME's camera.distortion is not [k1, k2, p1, p2, k3]: not numbers");
                    *coefficient[i] = d.items[i].number;
                }
            }
        } else {
            throw ProtocolError("WELCOME's camera.projection is \"" + projection +
                                "\": expected \"orthographic\" or \"pinhole\"");
        }
        const Json& s = c["settings"];
        if (s.type != Json::Null && s.type != Json::Object) throw ProtocolError("WELCOME's camera.settings is not an object");
        const std::pair<const char*, double> parts[] = {{"latency", 1.0}, {"jitter", 0.5}, {"exposure", 0.5}};
        for (const auto& [key, weight] : parts)
            if (s[key].type != Json::Null) delay += weight * cameraNumber(s, key, false, "camera.settings");
    }

    // The distortion of normalised image coordinates (OpenCV's model, above).
    cv::Point2d distort(cv::Point2d n) const {
        const double r2 = n.x * n.x + n.y * n.y, radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
        return {n.x * radial + 2 * p1 * n.x * n.y + p2 * (r2 + 2 * n.x * n.x),
                n.y * radial + p1 * (r2 + 2 * n.y * n.y) + 2 * p2 * n.x * n.y};
    }
    // Its inverse by Newton's method, from the distorted point, to 1e-12.
    cv::Point2d undistort(cv::Point2d d) const {
        cv::Point2d n = d;
        for (int i = 0; i < 50; ++i) {
            const cv::Point2d residual = distort(n) - d;
            if (std::hypot(residual.x, residual.y) < 1e-12) break;
            const double r2 = n.x * n.x + n.y * n.y, radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
            const double slope = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // d radial / d r^2
            const double a = radial + 2 * n.x * n.x * slope + 2 * p1 * n.y + 6 * p2 * n.x;  // d x_d / d x_n
            const double b = 2 * n.x * n.y * slope + 2 * p1 * n.x + 2 * p2 * n.y;         // d x_d / d y_n = d y_d / d x_n
            const double e = radial + 2 * n.y * n.y * slope + 6 * p1 * n.y + 2 * p2 * n.x;  // d y_d / d y_n
            const double det = a * e - b * b;
            if (det == 0 || !std::isfinite(det)) break;
            n -= cv::Point2d((e * residual.x - b * residual.y) / det, (a * residual.y - b * residual.x) / det);
        }
        return n;
    }
    // Pixel coordinates in OpenCV's convention (pixel centres at integers: a
    // centroid of pixel indices) of something at height z m -> field metres.
    cv::Point2d toField(cv::Point2d px, double z) const {
        if (!pinhole) return {(px.x + 0.5 - centreU) / scale, (centreV - (px.y + 0.5)) / scale};
        if (!(z < height)) throw std::invalid_argument("a point at or above the camera");
        const cv::Point2d n = undistort({(px.x - cx) / fx, (px.y - cy) / fy});
        return {n.x * (height - z), -n.y * (height - z)};
    }
};

struct Blob {
    cv::Point2d centroid;  // pixel indices (OpenCV's convention)
    int area = 0;          // px
    double value = 0;      // mean V (brightness) of its pixels
};

// The HSV of a nominal colour (OpenCV's units: hue 0..180).
cv::Vec3b hsvOf(const cv::Scalar& bgr) {
    cv::Mat pixel(1, 1, CV_8UC3, bgr), hsv;
    cv::cvtColor(pixel, hsv, cv::COLOR_BGR2HSV);
    return hsv.at<cv::Vec3b>(0, 0);
}

// The blobs of one colour's class in the HSV image, largest first. Only pixels
// that differ from the background (`foreground`) count: that keeps the white
// field markings and the grey walls out of the white class. A 3x3 opening
// removes what is one or two pixels wide (anti-aliased fringes, isolated noisy
// pixels); blobs still under kMinBlobArea pixels are dropped.
std::vector<Blob> findBlobs(const cv::Mat& hsv, const cv::Mat& foreground, const cv::Scalar& bgr) {
    const cv::Vec3b nominal = hsvOf(bgr);
    cv::Mat mask, labels, stats, centroids;
    if (nominal[1] == 0) {  // white: any hue, little saturation, bright
        cv::inRange(hsv, cv::Scalar(0, 0, kWhiteMinValue), cv::Scalar(180, kWhiteMaxSaturation, 255), mask);
    } else {  // hue within the tolerance, around the circle (180 = 0)
        const int low = nominal[0] - kHueTolerance, high = nominal[0] + kHueTolerance;
        cv::inRange(hsv, cv::Scalar(std::max(low, 0), kMinSaturation, kMinValue),
                    cv::Scalar(std::min(high, 179), 255, 255), mask);
        cv::Mat wrapped;
        if (low < 0) cv::inRange(hsv, cv::Scalar(low + 180, kMinSaturation, kMinValue), cv::Scalar(179, 255, 255), wrapped);
        if (high > 179) cv::inRange(hsv, cv::Scalar(0, kMinSaturation, kMinValue), cv::Scalar(high - 180, 255, 255), wrapped);
        if (!wrapped.empty()) mask |= wrapped;
    }
    mask &= foreground;
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::Mat::ones(3, 3, CV_8U));
    const int count = cv::connectedComponentsWithStats(mask, labels, stats, centroids);
    std::vector<double> valueSum(std::size_t(count), 0.0);
    for (int r = 0; r < labels.rows; ++r) {
        const int* label = labels.ptr<int>(r);
        const cv::Vec3b* pixel = hsv.ptr<cv::Vec3b>(r);
        for (int c = 0; c < labels.cols; ++c)
            if (label[c] > 0) valueSum[std::size_t(label[c])] += pixel[c][2];
    }
    std::vector<Blob> blobs;
    for (int i = 1; i < count; ++i) {  // label 0 is the background
        const int area = stats.at<int>(i, cv::CC_STAT_AREA);
        if (area >= kMinBlobArea)
            blobs.push_back({{centroids.at<double>(i, 0), centroids.at<double>(i, 1)}, area, valueSum[std::size_t(i)] / area});
    }
    std::sort(blobs.begin(), blobs.end(), [](const Blob& a, const Blob& b) { return a.area > b.area; });
    return blobs;
}

struct Pose {
    double x, y, theta;
};

// The patches lie on the robot's top face: their centroids are mapped to the
// field at z = side. Each identity blob is paired with the nearest team blob:
// on a robot their centres are 0.5 side apart, so pairs farther than 0.75 side
// are rejected. Identity colours of the same hue (magenta, purple) differ in
// brightness: the identity blob's mean V over the team blob's must be near the
// nominal ratio. The centre is the midpoint, the heading points from the team
// to the identity patch.
std::optional<Pose> findRobot(const cv::Mat& hsv, const cv::Mat& foreground, const Camera& camera,
                              const cv::Scalar& team, const cv::Scalar& identity, double side) {
    const std::vector<Blob> teamBlobs = findBlobs(hsv, foreground, team);
    const double expectedRatio = double(hsvOf(identity)[2]) / hsvOf(team)[2];
    double best = 0.75 * side;
    std::optional<Pose> pose;
    for (const Blob& id : findBlobs(hsv, foreground, identity)) {
        const cv::Point2d b = camera.toField(id.centroid, side);
        for (const Blob& tb : teamBlobs) {
            if (std::abs(std::log(id.value / tb.value / expectedRatio)) > std::log(kBrightnessRatioTolerance)) continue;
            const cv::Point2d a = camera.toField(tb.centroid, side);
            if (const double d = std::hypot(b.x - a.x, b.y - a.y); d <= best) {
                best = d;
                pose = Pose{(a.x + b.x) / 2, (a.y + b.y) / 2, std::atan2(b.y - a.y, b.x - a.x)};
            }
        }
    }
    return pose;
}

std::optional<cv::Point2d> findBall(const cv::Mat& hsv, const cv::Mat& foreground, const Camera& camera,
                                    double radius) {
    const std::vector<Blob> blobs = findBlobs(hsv, foreground, kBall);
    if (blobs.empty()) return std::nullopt;
    return camera.toField(blobs.front().centroid, radius);  // the largest orange blob, seen around its centre
}

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// Where a body is now, from an image `delay` s old: constant velocity.
// An image shows the world as it was `delay` s ago (Camera::delay: 55 to 60 ms
// with the realistic camera), while the voltages we send act from now on;
// steering from the image as it is would chase where the robot was (at 1.2 m/s,
// 6.6 cm back) and overshoot every turn. So each body is moved forward by its
// velocity times the delay. The velocity is the change between consecutive
// images over their time difference (frame times: skipped or dropped frames are
// accounted for), smoothed over about two images; a gap longer than 0.2 s
// starts again from rest. With the ideal camera, delay 0: the image as it is.
struct Predictor {
    double delay;
    bool angular;  // the last coordinate is an angle
    std::vector<double> last, velocity;
    double lastTime = 0;

    std::vector<double> update(double time, std::vector<double> observed) {
        if (delay <= 0) return observed;
        std::vector<double> v(observed.size(), 0.0);
        if (!last.empty() && time - lastTime > 0 && time - lastTime <= 0.2) {
            for (std::size_t i = 0; i < v.size(); ++i) {
                double change = observed[i] - last[i];
                if (angular && i + 1 == v.size()) change = wrapAngle(change);
                v[i] = change / (time - lastTime);
                if (!velocity.empty()) v[i] = 0.5 * v[i] + 0.5 * velocity[i];  // smoothing: half the newest
            }
        }
        last = observed, lastTime = time, velocity = v;
        for (std::size_t i = 0; i < v.size(); ++i) observed[i] += v[i] * delay;
        if (angular) observed.back() = wrapAngle(observed.back());
        return observed;
    }
};

// ---------------------------------------------------------------------------
// Control: heading error -> differential voltage, distance -> common voltage.
// VSSS robots are symmetric: a target behind is reached driving backwards,
// with a little hysteresis so that a nearly sideways target causes no dithering.
// ---------------------------------------------------------------------------
constexpr double kTurnGain = 1.2;       // V of differential voltage per rad of heading error
constexpr double kDistanceGain = 20.0;  // V of common voltage per m of distance
constexpr double kCruiseVoltage = 5.0;  // V: the common voltage never exceeds this (~1.2 m/s)

constexpr double kPi = 3.14159265358979323846;

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
// Getting unstuck. A robot caught on a goal post or in a corner (the post in
// front of one face and the robot's own corner inside the goal mouth, say)
// can neither drive on (its wheels do not slip sideways) nor turn there: the
// go-to-point law keeps pushing it in. When the commands have asked for
// motion for kStuckTime while the robot, as the images show it, moved less
// than kStuckDistance and turned less than kStuckTurn, it drives its last
// command in reverse for kBackOffTime, then carries on.
// ---------------------------------------------------------------------------
constexpr double kStuckTime = 0.5;       // s of simulated time (frame times)
constexpr double kStuckDistance = 0.01;  // m: a still robot's estimates stay within 3 mm
constexpr double kStuckTurn = 0.2;       // rad: and within 4 degrees (0.07 rad) of its heading
constexpr double kBackOffTime = 0.3;     // s
constexpr double kDrivenVoltage = 2.0;   // V: |right| + |left| at least this asks for motion
constexpr double kTimeSlack = 1e-6;      // s: frame times carry rounding; a frame at a limit counts as there

struct Unstick {
    bool anchored = false;
    Pose anchor{};              // where the robot was when it last moved (m, m, rad)
    double anchorTime = 0;      // s (frame time): and when
    double lastTime = -1;       // s: the last frame time seen (a `reset` starts time again)
    double backOffStart = -1;   // s (frame time): when the last back-off began (-1: none)
    std::pair<double, double> backOff{0, 0};     // V (right, left)
    long backOffs = 0;          // how many so far

    bool backingOff(double time) const {
        return backOffStart >= 0 && time >= backOffStart && time - backOffStart < kBackOffTime - kTimeSlack;
    }

    // The robot not seen in this frame: its motion is not known, so the wait starts again.
    void forget() { anchored = false; }

    // The voltages (right, left) to send at `time` for `command`, the robot seen at `pose`.
    std::pair<double, double> voltages(double time, const Pose& pose, std::pair<double, double> command) {
        if (time < lastTime) {  // time went back (a reset): what came before is gone
            const long count = backOffs;
            *this = Unstick{};
            backOffs = count;
        }
        lastTime = time;
        if (backingOff(time)) return backOff;
        const bool driven = std::abs(command.first) + std::abs(command.second) >= kDrivenVoltage;
        const bool moved = anchored && (std::hypot(pose.x - anchor.x, pose.y - anchor.y) > kStuckDistance ||
                                        std::abs(wrapAngle(pose.theta - anchor.theta)) > kStuckTurn);
        if (!anchored || moved || !driven) {
            anchored = true, anchor = pose, anchorTime = time;
            return command;
        }
        if (time - anchorTime < kStuckTime - kTimeSlack) return command;
        backOff = {-command.first, -command.second};
        backOffStart = time;
        ++backOffs;
        anchored = false;  // measured again from after the back-off
        return backOff;
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
    double delay = -1;  // s; < 0: from WELCOME's camera settings
};

const char* kUsage =
    "usage: vssim_example_client [--host H] [--port N] [--team yellow|blue] [--robot ID]\n"
    "                            [--encoding png|raw|jpeg] [--lockstep] [--max-time S] [--delay S] [--verbose]\n"
    "Drives one robot to the ball using only the camera images of a `vssim serve` server.\n"
    "  --host H        server address (default 127.0.0.1)\n"
    "  --port N        server port (default 10030)\n"
    "  --team T        yellow (default) or blue\n"
    "  --robot ID      the robot's id within the team, i.e. its identity colour (default 0)\n"
    "  --encoding E    image encoding: png (default), raw or jpeg\n"
    "  --lockstep      step simulated time ourselves, 0.03 s per decision (`vssim serve --lockstep`)\n"
    "  --max-time S    give up (exit 1) after S simulated seconds (default 20)\n"
    "  --delay S       how old an image is on arrival: the robot and the ball are predicted S s forward\n"
    "                  (default: WELCOME's camera latency + jitter/2 + exposure/2; 0 for the ideal camera)\n"
    "  --verbose       print the estimates at every frame\n"
    "Vision (examples/README.md): pixels that differ from the background are classed by hue\n"
    "(saturation and brightness above a floor; white: low saturation; purple: magenta at half the\n"
    "team patch's brightness), opened 3x3, blobs under 10 px dropped; the robot is its identity blob\n"
    "next to its team blob. A centroid (c, r) of pixel indices becomes metres through WELCOME's camera:\n"
    "orthographic x = (c + 0.5 - centre_u) / scale, y = (centre_v - r - 0.5) / scale; pinhole: undistorted\n"
    "(matrix, distortion; Newton's method) to (x_n, y_n), then x = x_n (mount_height - z),\n"
    "y = -y_n (mount_height - z) at the height z seen: z = side for the patches on the robot's top face,\n"
    "z = radius for the ball. Robot and ball are predicted forward over the delay (constant velocity).\n"
    "A robot that has not moved 1 cm or turned 0.2 rad in the images for 0.5 s while driven (|right| +\n"
    "|left| >= 2 V; caught on a goal post or in a corner) drives its last command in reverse for 0.3 s.\n"
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

    const Camera camera(welcome["camera"]);
    const double delay = o.delay >= 0 ? o.delay : camera.delay;
    const Json* robot = nullptr;
    for (const Json& r : welcome["robots"].items)
        if (r["team"].str() == o.team && r["id"].num() == o.robot) robot = &r;
    if (!robot) throw ProtocolError("the scene has no " + o.team + " robot with id " + std::to_string(o.robot));
    const int index = int((*robot)["index"].num());
    const double side = (*robot)["side"].num();
    const double ballRadius = welcome["ball"]["radius"].num();
    const double reachDistance = side / 2 + ballRadius + 0.015;
    const cv::Scalar team = o.team == "yellow" ? kYellow : kBlue, identity = kIdentity[o.robot % 6];
    GoToPoint controller{(*robot)["max_voltage"].num()};
    Unstick unstick;
    Predictor robotPredictor{delay, true}, ballPredictor{delay, false};
    std::printf("connected to %s (%s mode) as %s: driving %s (index %d) to the ball; %s camera", welcome["server"].str().c_str(),
                welcome["mode"].str().c_str(), o.team.c_str(), (*robot)["name"].str().c_str(), index,
                camera.pinhole ? "pinhole" : "orthographic");
    if (delay > 0) std::printf(", images %.0f ms old", delay * 1000);
    std::printf("\n");
    if (welcome["mode"].str() == "lockstep" && !o.lockstep)
        std::fprintf(stderr,
                     "note: the server is in lockstep mode: time only advances when a client steps it "
                     "(use --lockstep to do it from this client)\n");

    cv::Mat background, image, foreground, hsv;
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

        cv::cvtColor(image, hsv, cv::COLOR_BGR2HSV);
        std::optional<Pose> pose = findRobot(hsv, foreground, camera, team, identity, side);
        const std::optional<Pose> seen = pose;  // as the image shows it (Unstick: no prediction's noise)
        std::optional<cv::Point2d> ball = findBall(hsv, foreground, camera, ballRadius);
        // Where they are now, the image being `delay` s old (Predictor).
        if (pose) {
            const std::vector<double> p = robotPredictor.update(frame.time, {pose->x, pose->y, pose->theta});
            pose = Pose{p[0], p[1], p[2]};
        }
        if (ball) {
            const std::vector<double> b = ballPredictor.update(frame.time, {ball->x, ball->y});
            ball = cv::Point2d(b[0], b[1]);
        }
        double right = 0, left = 0;  // lost sight of something: wait for a better image
        if (!pose || !ball) {
            unstick.forget();
            std::snprintf(estimate, sizeof estimate, "robot %sseen, ball %sseen", pose ? "" : "not ",
                          ball ? "" : "not ");
            if (o.verbose) std::printf("frame %u t=%.3f: %s\n", frame.number, frame.time, estimate);
        } else {
            const double distance = std::hypot(ball->x - pose->x, ball->y - pose->y);
            std::snprintf(estimate, sizeof estimate, "robot (%.3f, %.3f) ball (%.3f, %.3f)", pose->x, pose->y, ball->x,
                          ball->y);
            if (distance <= reachDistance) {
                conn.sendVoltages(index, 0, 0);
                std::printf("reached the ball at t=%.2f s (frame %u): %s (%ld older images skipped, back-offs: %ld)\n",
                            frame.time, frame.number, estimate, skipped, unstick.backOffs);
                return 0;
            }
            std::tie(right, left) = unstick.voltages(frame.time, *seen, controller.command(*pose, *ball));
            if (o.verbose)
                std::printf(
                    "frame %u t=%.3f: robot (%.3f, %.3f, %.0f deg) ball (%.3f, %.3f) distance %.3f m -> "
                    "right %+.2f V left %+.2f V%s\n",
                    frame.number, frame.time, pose->x, pose->y, pose->theta * 180 / kPi, ball->x, ball->y, distance,
                    right, left, unstick.backingOff(frame.time) ? " (backing off)" : "");
        }
        if (startTime < 0) startTime = frame.time;  // --max-time counts from the first image
        if (frame.time - startTime >= o.maxTime) {
            conn.sendVoltages(index, 0, 0);
            std::fprintf(
                stderr,
                "did not reach the ball within %g s of simulated time from the first image (t=%.2f s, frame %u; "
                "last estimate: %s; back-offs: %ld)\n",
                o.maxTime, frame.time, frame.number, estimate, unstick.backOffs);
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
            else if (arg == "--delay")
                o.delay = std::stod(value());
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
    if (!(o.maxTime > 0) || !std::isfinite(o.maxTime)) {
        std::fprintf(stderr, "bad --max-time %g: expected a positive number of seconds\n%s", o.maxTime, kUsage);
        return 2;
    }
    if (o.delay != -1 && !(o.delay >= 0 && o.delay <= 1)) {
        std::fprintf(stderr, "bad --delay %g: expected 0 to 1 s\n%s", o.delay, kUsage);
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
