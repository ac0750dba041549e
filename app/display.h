// Whether a window can be shown here, without loading any GUI library.
#pragma once

namespace vssim {

// An X11 or Wayland display, or a Qt platform chosen explicitly: then
// `vssim` with no arguments opens the desktop app; without one it runs the
// headless demo.
bool displayAvailable();

}  // namespace vssim
