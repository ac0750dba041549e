// The main window's status-bar line for a snapshot.
#pragma once

#include <QString>

#include "realtime/snapshot.h"

namespace vssim {

// E.g. "t = 12.345 s   frame 411   realtime x1.00   x0.99 real time
// engine 0.9 ms per simulated s   paused". The mode is "realtime xSPEED"
// (the requested factor), "max" or "lockstep"; realTimeFactor is the one the
// caller measured (simulated s per wall s; negative or NaN: not shown).
QString statusText(const Snapshot& s, double realTimeFactor);

}  // namespace vssim
