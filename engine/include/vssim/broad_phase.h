// Broad phase (sweep and prune): which robot pairs are close enough to need
// the narrow-phase tests of collision_detect.h. Without it every pair is
// tested, O(n^2) in the number of robots (the paper's cost); with it the cost
// is a sort plus the pairs that really are close, about O(n log n).
//
// Each robot is bounded by the disc of its half-diagonal (it contains the
// square at any heading) grown by `margin`. Intervals along x are sorted and
// swept; only pairs overlapping in x are checked in y. A uniform grid was the
// alternative: it needs a cell size, and a field of mixed robot sizes or one
// robot far away makes it large or sparse; sorting needs no tuning.
#pragma once

#include <utility>
#include <vector>

#include "vssim/robot_state.h"

namespace vssim {

// Below this many robots testing all pairs is cheaper than sorting (the
// contacts are the same either way); the world uses the broad phase from here on.
constexpr int kBroadPhaseMinRobots = 16;

// Appends to `pairs` every (i, j), i < j, whose grown bounding discs' boxes
// overlap, sorted by i then j: the same order as the all-pairs loop, so the
// contacts found (and so the results) do not depend on the broad phase.
// `scratch` is reused between calls: it keeps the previous order along x,
// which a world that moves a little per step only needs to touch up.
struct BroadPhaseScratch {
    std::vector<int> order;    // robots by increasing left edge
    std::vector<double> minX;  // left edges, m
};
void candidatePairs(const std::vector<RobotState>& robots, const std::vector<double>& sides, double margin,
                    BroadPhaseScratch& scratch, std::vector<std::pair<int, int>>& pairs);

// The same among the listed robots only (`listed`: increasing indices into
// robots and sides), at a cost that grows with the list, not with the
// robots: the pairs come as robot indices, sorted the same way. With
// `sweep` false, or fewer than kBroadPhaseMinRobots listed, every listed
// pair, in that order too. (The planner's moving robots among many at rest.)
struct ListedPairsScratch {
    BroadPhaseScratch sweep;         // kept between calls, as above
    std::vector<RobotState> poses;   // the listed robots'
    std::vector<double> sides;       // m
};
void listedCandidatePairs(const std::vector<int>& listed, const std::vector<RobotState>& robots,
                          const std::vector<double>& sides, double margin, bool sweep, ListedPairsScratch& scratch,
                          std::vector<std::pair<int, int>>& pairs);

}  // namespace vssim
