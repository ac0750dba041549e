#include "wire/protocol.h"

#include <QJsonDocument>
#include <QJsonParseError>
#include <QtEndian>
#include <cstring>
#include <stdexcept>

namespace vssim::protocol {

namespace {

void putU8(QByteArray& out, std::uint8_t v) { out.append(static_cast<char>(v)); }
void putU16(QByteArray& out, std::uint16_t v) {
    char b[2];
    qToBigEndian(v, b);
    out.append(b, 2);
}
void putU32(QByteArray& out, std::uint32_t v) {
    char b[4];
    qToBigEndian(v, b);
    out.append(b, 4);
}
void putF64(QByteArray& out, double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    char b[8];
    qToBigEndian(bits, b);
    out.append(b, 8);
}

// Bounds-checked big-endian reading of a payload.
class Cursor {
public:
    explicit Cursor(const QByteArray& bytes)
        : p_(reinterpret_cast<const unsigned char*>(bytes.constData())), n_(bytes.size()) {}
    bool has(std::size_t k) const { return n_ - at_ >= k; }
    std::size_t left() const { return n_ - at_; }
    std::uint8_t u8() { return p_[at_++]; }
    std::uint16_t u16() {
        auto v = qFromBigEndian<std::uint16_t>(p_ + at_);
        at_ += 2;
        return v;
    }
    std::uint32_t u32() {
        auto v = qFromBigEndian<std::uint32_t>(p_ + at_);
        at_ += 4;
        return v;
    }
    double f64() {
        const auto bits = qFromBigEndian<std::uint64_t>(p_ + at_);
        at_ += 8;
        double v;
        std::memcpy(&v, &bits, 8);
        return v;
    }
    const unsigned char* take(std::size_t k) {
        const unsigned char* q = p_ + at_;
        at_ += k;
        return q;
    }

private:
    const unsigned char* p_;
    std::size_t n_;
    std::size_t at_ = 0;
};

}  // namespace

QByteArray encodeMessage(MessageType type, const QByteArray& payload) {
    QByteArray out;
    out.reserve(5 + payload.size());
    putU32(out, static_cast<std::uint32_t>(payload.size() + 1));
    putU8(out, static_cast<std::uint8_t>(type));
    out.append(payload);
    return out;
}

QByteArray encodeJsonMessage(MessageType type, const QJsonObject& object) {
    return encodeMessage(type, QJsonDocument(object).toJson(QJsonDocument::Compact));
}

MessageReader::Status MessageReader::next(Message* out, std::uint32_t* length) {
    if (buffered() < 4) return Status::NeedMore;
    const auto* p = reinterpret_cast<const unsigned char*>(buffer_.constData()) + consumed_;
    const std::uint32_t n = qFromBigEndian<std::uint32_t>(p);
    if (length) *length = n;
    if (n == 0) return Status::Empty;
    if (n > maxLength_) return Status::Oversize;
    if (buffered() < 4 + static_cast<std::size_t>(n)) return Status::NeedMore;
    out->type = p[4];
    out->payload = QByteArray(reinterpret_cast<const char*>(p + 5), static_cast<qsizetype>(n - 1));
    consumed_ += 4 + n;
    // Drop consumed bytes now and then, not on every message.
    if (consumed_ > 65536 && consumed_ * 2 > static_cast<std::size_t>(buffer_.size())) {
        buffer_.remove(0, static_cast<qsizetype>(consumed_));
        consumed_ = 0;
    }
    return Status::Message;
}

std::optional<QJsonObject> parseJsonObject(const QByteArray& payload, QString* error) {
    QJsonParseError parseError;
    const QJsonDocument doc = QJsonDocument::fromJson(payload, &parseError);
    if (parseError.error != QJsonParseError::NoError) {
        *error = QStringLiteral("invalid JSON at byte %1: %2").arg(parseError.offset).arg(parseError.errorString());
        return std::nullopt;
    }
    if (!doc.isObject()) {
        *error = QStringLiteral("expected a JSON object");
        return std::nullopt;
    }
    return doc.object();
}

namespace {

// VOLTAGES and WHEEL_SPEEDS share a layout: u8 count, then count x (u8
// robot, f64 right, f64 left); T is Voltages or WheelSpeeds.
template <typename T>
QByteArray encodePairs(const std::vector<std::pair<int, T>>& entries, const char* name) {
    if (entries.empty() || entries.size() > 255)
        throw std::invalid_argument(std::string("encode ") + name + ": 1 to 255 entries");
    QByteArray out;
    putU8(out, static_cast<std::uint8_t>(entries.size()));
    for (const auto& [robot, e] : entries) {
        if (robot < 0 || robot > 255)
            throw std::invalid_argument(std::string("encode ") + name + ": robot indices are 0 to 255");
        putU8(out, static_cast<std::uint8_t>(robot));
        putF64(out, e.right);
        putF64(out, e.left);
    }
    return out;
}

template <typename T>
std::optional<std::vector<std::pair<int, T>>> decodePairs(const QByteArray& payload, const char* name,
                                                           QString* error) {
    Cursor c(payload);
    if (!c.has(1)) {
        *error = QStringLiteral("%1: empty payload (expected a count byte)").arg(name);
        return std::nullopt;
    }
    const int count = c.u8();
    const qsizetype want = 1 + 17 * static_cast<qsizetype>(count);
    if (count == 0 || payload.size() != want) {
        *error = count == 0 ? QStringLiteral("%1: count is 0").arg(name)
                            : QStringLiteral("%1: %2 entries need %3 payload bytes, got %4")
                                  .arg(name)
                                  .arg(count)
                                  .arg(want)
                                  .arg(payload.size());
        return std::nullopt;
    }
    std::vector<std::pair<int, T>> entries;
    for (int i = 0; i < count; ++i) {
        const int robot = c.u8();
        T e;
        e.right = c.f64();
        e.left = c.f64();
        entries.emplace_back(robot, e);
    }
    return entries;
}

}  // namespace

QByteArray encodeVoltages(const std::vector<std::pair<int, Voltages>>& entries) {
    return encodePairs(entries, "VOLTAGES");
}

std::optional<std::vector<std::pair<int, Voltages>>> decodeVoltages(const QByteArray& payload, QString* error) {
    return decodePairs<Voltages>(payload, "VOLTAGES", error);
}

QByteArray encodeWheelSpeeds(const std::vector<std::pair<int, WheelSpeeds>>& entries) {
    return encodePairs(entries, "WHEEL_SPEEDS");
}

std::optional<std::vector<std::pair<int, WheelSpeeds>>> decodeWheelSpeeds(const QByteArray& payload,
                                                                           QString* error) {
    return decodePairs<WheelSpeeds>(payload, "WHEEL_SPEEDS", error);
}

std::uint8_t encodingCode(ImageEncoding encoding) {
    switch (encoding) {
        case ImageEncoding::Raw: return 0;
        case ImageEncoding::Png: return 1;
        case ImageEncoding::Jpeg: return 2;
    }
    return 255;
}

QByteArray encodeFrame(const FrameHeader& header, const std::vector<FramePatch>& patches) {
    QByteArray out;
    std::size_t bytes = 16;
    for (const FramePatch& p : patches) bytes += 12 + p.data.size();
    out.reserve(static_cast<qsizetype>(bytes));
    putU32(out, header.frame);
    putF64(out, header.time);
    putU8(out, static_cast<std::uint8_t>(header.kind));
    putU8(out, encodingCode(header.encoding));
    putU16(out, static_cast<std::uint16_t>(patches.size()));
    for (const FramePatch& p : patches) {
        putU16(out, static_cast<std::uint16_t>(p.x));
        putU16(out, static_cast<std::uint16_t>(p.y));
        putU16(out, static_cast<std::uint16_t>(p.w));
        putU16(out, static_cast<std::uint16_t>(p.h));
        putU32(out, static_cast<std::uint32_t>(p.data.size()));
        out.append(reinterpret_cast<const char*>(p.data.data()), static_cast<qsizetype>(p.data.size()));
    }
    return out;
}

bool decodeFrame(const QByteArray& payload, FrameHeader* header, std::vector<FramePatch>* patches, QString* error) {
    Cursor c(payload);
    if (!c.has(16)) {
        *error = QStringLiteral("FRAME: %1 bytes is shorter than the 16-byte header").arg(payload.size());
        return false;
    }
    header->frame = c.u32();
    header->time = c.f64();
    const int kind = c.u8();
    const int encoding = c.u8();
    const int count = c.u16();
    if (kind > 2 || encoding > 2) {
        *error = QStringLiteral("FRAME: unknown kind %1 or encoding %2").arg(kind).arg(encoding);
        return false;
    }
    header->kind = static_cast<FrameKind>(kind);
    header->encoding = encoding == 0 ? ImageEncoding::Raw : encoding == 1 ? ImageEncoding::Png : ImageEncoding::Jpeg;
    patches->clear();
    for (int i = 0; i < count; ++i) {
        if (!c.has(12)) {
            *error = QStringLiteral("FRAME: patch %1 of %2: header cut short").arg(i).arg(count);
            return false;
        }
        FramePatch p;
        p.x = c.u16();
        p.y = c.u16();
        p.w = c.u16();
        p.h = c.u16();
        const std::uint32_t n = c.u32();
        if (!c.has(n)) {
            *error = QStringLiteral("FRAME: patch %1 of %2 declares %3 bytes, %4 left")
                         .arg(i)
                         .arg(count)
                         .arg(n)
                         .arg(c.left());
            return false;
        }
        const unsigned char* d = c.take(n);
        p.data.assign(d, d + n);
        patches->push_back(std::move(p));
    }
    if (c.left() != 0) {
        *error = QStringLiteral("FRAME: %1 bytes left over after %2 patches").arg(c.left()).arg(count);
        return false;
    }
    return true;
}

}  // namespace vssim::protocol
