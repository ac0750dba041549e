// `vssim run`: a headless run of a scene that writes CSV, and the default
// demo run printed when vssim starts with no arguments.
#pragma once

#include <QString>
#include <QStringList>

namespace vssim {

// `vssim run ...`; `arguments` starts with "run".
// Returns the process exit code: 0 success, 2 bad usage or input, 1 a failure
// while writing.
int runCommand(const QStringList& arguments);

// `vssim demo`, and `vssim` with no arguments where there is no display:
// runs the built-in kick-off scene for a few seconds headless and prints a
// summary.
int demoCommand();

QString runHelpText();

}  // namespace vssim
