// The STATE message's JSON (docs/protocol.md, STATE): the ground truth of
// every body at a camera instant, SI units.
#pragma once

#include <QJsonObject>
#include <cstdint>

#include "vssim/world.h"

namespace vssim {

QJsonObject stateJson(const Simulation& sim, std::int64_t frame);

}  // namespace vssim
