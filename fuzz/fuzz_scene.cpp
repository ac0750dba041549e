// libFuzzer target: the scene reader (runtime/io/scene_io) on any bytes.
// A scene it accepts must survive a round trip: written back as JSON and
// read again, it is accepted again.
#include <QByteArray>
#include <QString>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const QByteArray json(reinterpret_cast<const char*>(data), static_cast<qsizetype>(size));
    QString error;
    const std::optional<vssim::Scene> scene = vssim::parseScene(json, &error);
    if (!scene) {
        if (error.isEmpty()) std::abort();  // a refusal always says why
        return 0;
    }
    QString again;
    if (!vssim::parseScene(vssim::sceneToJson(*scene), &again)) std::abort();
    return 0;
}
