// The wire format of docs/protocol.md, version 1: length-prefixed messages
// (u32 big-endian length of type + payload, u8 type, payload), JSON or
// big-endian binary payloads. Encoding and decoding only; no sockets.
#pragma once

#include <QByteArray>
#include <QJsonObject>
#include <QString>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "vssim/camera/image_codec.h"
#include "vssim/robot_state.h"
#include "vssim/speed_controller.h"

namespace vssim::protocol {

constexpr int kVersion = 1;
constexpr std::uint16_t kDefaultPort = 10030;
constexpr std::uint32_t kMaxClientMessage = 65536;     // bytes after the length field
constexpr std::uint32_t kMaxServerMessage = 1u << 26;  // 64 MiB, for clients' readers

enum class MessageType : std::uint8_t {
    Hello = 0x01,
    Voltages = 0x02,
    Control = 0x03,
    Placement = 0x04,
    WheelSpeeds = 0x05,
    Welcome = 0x81,
    Frame = 0x82,
    State = 0x83,
    Reply = 0x84,
    Error = 0x85,
    Referee = 0x86,
};

struct Message {
    std::uint8_t type = 0;
    QByteArray payload;
};

// One complete message: length, type, payload.
QByteArray encodeMessage(MessageType type, const QByteArray& payload);
QByteArray encodeJsonMessage(MessageType type, const QJsonObject& object);

// Splits a byte stream into messages as bytes arrive.
class MessageReader {
public:
    enum class Status { Message, NeedMore, Oversize, Empty };
    explicit MessageReader(std::uint32_t maxLength) : maxLength_(maxLength) {}
    void append(const QByteArray& bytes) { buffer_.append(bytes); }
    // Message: *out holds the next message. NeedMore: wait for bytes.
    // Oversize: the length field exceeds maxLength (the stream cannot be
    // resynchronised). Empty: a length of 0 (no type byte), also fatal.
    Status next(Message* out, std::uint32_t* length = nullptr);
    std::size_t buffered() const { return static_cast<std::size_t>(buffer_.size()) - consumed_; }

private:
    std::uint32_t maxLength_;
    QByteArray buffer_;
    std::size_t consumed_ = 0;
};

// Parses a JSON object payload; nullopt and *error when it is not one.
std::optional<QJsonObject> parseJsonObject(const QByteArray& payload, QString* error);

// VOLTAGES: u8 count, then count x (u8 robot, f64 right, f64 left). Throws
// std::invalid_argument unless there are 1 to 255 entries with robots 0 to 255.
QByteArray encodeVoltages(const std::vector<std::pair<int, Voltages>>& entries);
// Checks the layout only (sizes); robots and values are the server's to check.
std::optional<std::vector<std::pair<int, Voltages>>> decodeVoltages(const QByteArray& payload, QString* error);
// WHEEL_SPEEDS: the same layout, in rad/s: targets for the robots' speed loops.
QByteArray encodeWheelSpeeds(const std::vector<std::pair<int, WheelSpeeds>>& entries);
std::optional<std::vector<std::pair<int, WheelSpeeds>>> decodeWheelSpeeds(const QByteArray& payload, QString* error);

// FRAME.
enum class FrameKind : std::uint8_t { Patches = 0, Full = 1, Background = 2 };
struct FramePatch {
    int x = 0, y = 0, w = 0, h = 0;  // pixels
    std::vector<std::uint8_t> data;  // encoded image of the w x h patch (empty when w or h is 0)
};
struct FrameHeader {
    std::uint32_t frame = 0;
    double time = 0.0;  // s
    FrameKind kind = FrameKind::Patches;
    ImageEncoding encoding = ImageEncoding::Png;
};
QByteArray encodeFrame(const FrameHeader& header, const std::vector<FramePatch>& patches);
bool decodeFrame(const QByteArray& payload, FrameHeader* header, std::vector<FramePatch>* patches, QString* error);

std::uint8_t encodingCode(ImageEncoding encoding);

}  // namespace vssim::protocol
