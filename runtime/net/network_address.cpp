#include "net/network_address.h"

namespace vssim {

std::optional<quint16> parsePort(const QString& text) {
    bool ok = false;
    const uint value = text.toUInt(&ok);
    if (!ok || value > 65535) return std::nullopt;
    return static_cast<quint16>(value);
}

std::optional<HostPort> parseHostPort(const QString& text) {
    const std::optional<quint16> port = parsePort(text.section(':', -1));
    if (!port || *port == 0) return std::nullopt;
    const QString host = text.contains(':') ? text.section(':', 0, -2) : QStringLiteral("127.0.0.1");
    if (host.isEmpty()) return std::nullopt;
    return HostPort{host, *port};
}

}  // namespace vssim
