// The numbers the scene reader accepts (runtime/io/scene_io.cpp; the "allowed"
// columns of docs/scenes.md), as the closed intervals a QDoubleSpinBox needs.
#pragma once

#include "io/scene_io.h"  // kMaxSceneTimeStep

namespace vssim {

// The kinds of range the reader checks on a numeric key.
enum class SceneRange {
    Positive,      // "> 0"
    NonNegative,   // ">= 0"
    UnitInterval,  // simulation.restitution: 0 to 1, both included
    TimeStep,      // simulation.dt: > 0 and <= kMaxSceneTimeStep
};

struct SpinInterval {
    double minimum;
    double maximum;
};

// The interval a spin box showing `decimals` decimals offers for a key of
// this range. A "> 0" key starts at the smallest positive value the box can
// show (10^-decimals), a ">= 0" key at 0. The reader puts no upper bound on
// Positive and NonNegative keys; for them `cap` (in the key's unit) is the
// box's own limit. UnitInterval and TimeStep ignore `cap`.
SpinInterval spinInterval(SceneRange range, int decimals, double cap);

}  // namespace vssim
