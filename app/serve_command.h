// `vssim serve`: runs a scene in real time (or lockstep) headless and serves
// it over TCP (docs/protocol.md) until interrupted.
#pragma once

#include <QStringList>

namespace vssim {

// `arguments` starts with "serve". Exit code: 0 after SIGINT/SIGTERM or
// --quit-after, 2 bad usage or input, 1 cannot listen.
int serveCommand(const QStringList& arguments);

QString serveHelpText();

}  // namespace vssim
