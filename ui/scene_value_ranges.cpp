#include "scene_value_ranges.h"

#include <algorithm>
#include <cmath>

namespace vssim {

SpinInterval spinInterval(const AllowedRange& range, int decimals) {
    const double smallestStep = std::pow(10.0, -decimals);
    double minimum = range.min;
    // A positive minimum the box would round to 0, or an excluded 0: the smallest value it shows.
    if ((minimum > 0.0 && minimum < smallestStep) || (minimum == 0.0 && range.aboveMin)) minimum = smallestStep;
    return {minimum, std::max(minimum, range.max)};
}

}  // namespace vssim
