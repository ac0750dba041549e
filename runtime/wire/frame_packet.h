// What the engine thread hands the server at a camera instant: the FRAME and
// STATE messages, complete and ready to write, one FRAME per distinct image
// subscription (kind, encoding, JPEG quality) so each is encoded once.
#pragma once

#include <QByteArray>
#include <QJsonObject>
#include <cstdint>
#include <utility>
#include <vector>

#include "vssim/camera/image_codec.h"
#include "wire/protocol.h"

namespace vssim {

struct ImageSubscription {
    protocol::FrameKind kind = protocol::FrameKind::Patches;  // Patches or Full
    ImageEncoding encoding = ImageEncoding::Png;
    int jpegQuality = 90;  // 1..100, JPEG only
    bool operator==(const ImageSubscription& o) const {
        return kind == o.kind && encoding == o.encoding &&
               (encoding != ImageEncoding::Jpeg || jpegQuality == o.jpegQuality);
    }
};

// "patches/png", "full/raw", "patches/jpeg90", ...: for logs and statistics.
QString subscriptionName(const ImageSubscription& s);

struct FramePacket {
    std::int64_t frame = 0;
    double time = 0.0;                                             // s
    std::int64_t instantNs = 0;  // monotonicNs() when the engine reached the instant (for the images' age)
    std::vector<std::pair<ImageSubscription, QByteArray>> images;  // complete FRAME messages
    QByteArray state;  // complete STATE message; empty when nobody subscribed
    QJsonObject stateJson;  // its JSON, for clients whose camera adds noise (wire/state_message.h)
};

}  // namespace vssim
