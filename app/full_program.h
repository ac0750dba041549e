// The program `vssim` hands the commands that need the GUI or the camera and
// network stacks to (`vssim gui`, `vssim serve`), so that the headless
// commands start without loading them (docs/performance.md, "Start-up").
#pragma once

#include <string>

namespace vssim {

// Where the full program is, from this program's own path: next to it (the
// build tree: build/app/vssim-full), or ../libexec/vssim/vssim-full (the
// installed layout: /usr/bin/vssim, /usr/libexec/vssim/vssim-full). Empty
// when neither exists (the message then says where it looked).
std::string fullProgramPath(std::string* lookedAt);

// Replaces this process by the full program with the same arguments; returns
// (exit status 127, after printing why) only if that fails.
int runFullProgram(char** argv);

}  // namespace vssim
