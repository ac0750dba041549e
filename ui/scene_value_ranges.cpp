#include "scene_value_ranges.h"

#include <cmath>

namespace vssim {

SpinInterval spinInterval(SceneRange range, int decimals, double cap) {
    const double smallestStep = std::pow(10.0, -decimals);
    switch (range) {
        case SceneRange::Positive: return {smallestStep, cap};
        case SceneRange::NonNegative: return {0.0, cap};
        case SceneRange::UnitInterval: return {0.0, 1.0};
        case SceneRange::TimeStep: return {smallestStep, kMaxSceneTimeStep};
    }
    return {0.0, cap};
}

}  // namespace vssim
