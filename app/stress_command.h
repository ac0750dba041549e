// `vssim stress`: the numerical-stability stress tool. Runs random scenes
// (stress_scenes.h) with every integrator and collision model, checks every
// step (stress_checks.h) and prints a table, a summary and what failed.
#pragma once

#include <QString>
#include <QStringList>

namespace vssim {

// `vssim stress ...`; `arguments` starts with "stress".
// Returns the process exit code: 0 every check passed, 1 a check failed,
// 2 bad usage.
int stressCommand(const QStringList& arguments);

QString stressHelpText();

}  // namespace vssim
