// `vssim match`: a whole match played headless, the referee on and both
// teams built in (or idle); prints the score and the referee's calls.
#pragma once

#include <QString>
#include <QStringList>

namespace vssim {

// `vssim match ...`; `arguments` starts with "match".
// Returns the process exit code: 0 success, 2 bad usage or input, 1 a failure
// while writing or a state that stopped being finite.
int matchCommand(const QStringList& arguments);

QString matchHelpText();

}  // namespace vssim
