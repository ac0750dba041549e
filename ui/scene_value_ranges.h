// The numbers the scene reader accepts (runtime/io/scene_limits.h, the
// "allowed" columns of docs/scenes.md), as the closed intervals a
// QDoubleSpinBox needs: one source for the reader and the app's boxes.
#pragma once

#include "io/scene_limits.h"

namespace vssim {

struct SpinInterval {
    double minimum;
    double maximum;
};

// The interval a spin box showing `decimals` decimals offers for a key the
// reader checks against `range`: the range itself, except that a lower end
// the box cannot show (below 10^-decimals, or an excluded 0) becomes
// 10^-decimals.
SpinInterval spinInterval(const AllowedRange& range, int decimals);

}  // namespace vssim
