// `vssim run`: a headless run of a scene that writes CSV, and the default
// demo run printed when vssim starts with no arguments.
#pragma once

#include <QString>
#include <QStringList>

namespace vssim {

// Resolves a scene argument: an existing file, or the name of a built-in
// example scene ("kickoff_3v3" or "kickoff_3v3.json"). Returns an empty
// string when neither exists.
QString resolveScenePath(const QString& argument);

// Names of the built-in example scenes, sorted.
QStringList builtinSceneNames();

// `vssim run ...`; `arguments` starts with "run".
// Returns the process exit code: 0 success, 2 bad usage or input, 1 a failure
// while writing.
int runCommand(const QStringList& arguments);

// `vssim` with no arguments (until the desktop app exists): runs the built-in
// kick-off scene for a few seconds headless and prints a summary.
int demoCommand();

QString runHelpText();

}  // namespace vssim
