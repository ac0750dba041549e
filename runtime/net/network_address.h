// Port numbers and HOST:PORT as people type them (command lines, dialogs).
#pragma once

#include <QString>
#include <optional>

namespace vssim {

// A TCP port, 0 to 65535 (0: any free port when listening).
std::optional<quint16> parsePort(const QString& text);

struct HostPort {
    QString host;  // as typed; 127.0.0.1 when only a port is given
    quint16 port = 0;
};
// "HOST:PORT" or "PORT" (port 1 to 65535; the last ':' splits, so an IPv6
// host may contain colons).
std::optional<HostPort> parseHostPort(const QString& text);

}  // namespace vssim
