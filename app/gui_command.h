// `vssim` (no arguments) and `vssim gui [SCENE] [options]`: the desktop app.
#pragma once

namespace vssim {

// Creates the QApplication itself; argv[1] is "gui" or absent.
int guiCommand(int argc, char** argv);

}  // namespace vssim
