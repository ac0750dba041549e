// libFuzzer target: what the TCP server reads from a client
// (docs/protocol.md): the byte stream split into messages (MessageReader,
// fed in pieces whose sizes the input's first byte chooses), and each
// message's payload checked as the server checks it (runtime/wire/protocol,
// runtime/net/client_requests) against the kick-off scene, for every role;
// FRAME payloads as a client's reader decodes them.
#include <QByteArray>
#include <QString>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "io/scene_io.h"
#include "kickoff_scene.h"
#include "net/client_requests.h"
#include "wire/protocol.h"

namespace {

using namespace vssim;

void check(const protocol::Message& m) {
    const Scene& scene = fuzz::kickoffScene();
    RequestError error;
    QString why;
    for (ClientRole role : {ClientRole::Yellow, ClientRole::Blue, ClientRole::Observer}) {
        switch (static_cast<protocol::MessageType>(m.type)) {
        case protocol::MessageType::Hello:
            if (role == ClientRole::Yellow)
                if (auto json = protocol::parseJsonObject(m.payload, &why)) (void)parseHello(*json, &error);
            break;
        case protocol::MessageType::Control:
            if (role == ClientRole::Yellow)
                if (auto json = protocol::parseJsonObject(m.payload, &why)) {
                    if (auto request = parseControl(*json, scene, &error)) (void)leavesTheGameAlone(*request);
                }
            break;
        case protocol::MessageType::Placement:
            if (auto json = protocol::parseJsonObject(m.payload, &why)) (void)parsePlacement(*json, scene, role, &error);
            break;
        case protocol::MessageType::Voltages:
            if (auto entries = protocol::decodeVoltages(m.payload, &why)) (void)checkVoltages(*entries, scene, role);
            break;
        case protocol::MessageType::WheelSpeeds:
            if (auto entries = protocol::decodeWheelSpeeds(m.payload, &why))
                (void)checkWheelSpeeds(*entries, scene, role);
            break;
        case protocol::MessageType::Frame:
            if (role == ClientRole::Observer) {
                protocol::FrameHeader header;
                std::vector<protocol::FramePatch> patches;
                (void)protocol::decodeFrame(m.payload, &header, &patches, &why);
            }
            break;
        default:
            break;
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    // The first byte: the size of the pieces the stream arrives in (1 to 256 bytes).
    const std::size_t piece = std::size_t{data[0]} + 1;
    const char* bytes = reinterpret_cast<const char*>(data + 1);
    const std::size_t n = size - 1;
    protocol::MessageReader reader(protocol::kMaxClientMessage);
    for (std::size_t at = 0; at < n; at += piece) {
        reader.append(QByteArray(bytes + at, static_cast<qsizetype>(std::min(piece, n - at))));
        for (;;) {
            protocol::Message message;
            std::uint32_t length = 0;
            const auto status = reader.next(&message, &length);
            if (status == protocol::MessageReader::Status::Message) {
                check(message);
                continue;
            }
            if (status == protocol::MessageReader::Status::NeedMore) break;
            return 0;  // Oversize or Empty: the server closes the connection
        }
    }
    return 0;
}
