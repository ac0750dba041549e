// `vssim` (no arguments) and `vssim gui [SCENE] [options]`: the desktop app.
#pragma once

namespace vssim {

// Whether a window can be shown here (an X11 or Wayland display, or a Qt
// platform chosen explicitly); without one `vssim` runs the headless demo.
bool displayAvailable();

// Creates the QApplication itself; argv[1] is "gui" or absent.
int guiCommand(int argc, char** argv);

}  // namespace vssim
