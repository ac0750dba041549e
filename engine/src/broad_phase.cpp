#include "vssim/broad_phase.h"

#include <algorithm>
#include <cmath>

#include "vssim/geometry.h"
#include "vssim/nearly_sorted.h"

namespace vssim {

void candidatePairs(const std::vector<RobotState>& robots, const std::vector<double>& sides, double margin,
                    BroadPhaseScratch& scratch, std::vector<std::pair<int, int>>& pairs) {
    const int n = static_cast<int>(robots.size());
    const std::size_t first = pairs.size();
    auto reach = [&](int i) { return boundingRadius(sides[i]) + margin; };  // m
    const bool reuse = static_cast<int>(scratch.order.size()) == n;         // the order of the previous call
    scratch.order.resize(n);
    scratch.minX.resize(n);
    for (int i = 0; i < n; ++i) {
        if (!reuse) scratch.order[i] = i;
        scratch.minX[i] = robots[i].x - reach(i);
    }
    // Ties broken by index, and NaN positions sorted last, so the order is total.
    auto before = [&](int a, int b) {
        const double xa = scratch.minX[a], xb = scratch.minX[b];
        if (xa < xb) return true;
        if (xb < xa) return false;
        const bool nanA = std::isnan(xa), nanB = std::isnan(xb);
        if (nanA != nanB) return nanB;
        return a < b;
    };
    if (reuse) {
        sortNearlySorted(scratch.order, before);  // (the previous call's order)
    } else {
        std::sort(scratch.order.begin(), scratch.order.end(), before);
    }
    for (int k = 0; k < n; ++k) {
        const int i = scratch.order[k];
        const double maxX = robots[i].x + reach(i);
        for (int l = k + 1; l < n; ++l) {
            const int j = scratch.order[l];
            if (!(scratch.minX[j] <= maxX)) break;  // sorted: nobody further along overlaps i in x
            if (std::abs(robots[i].y - robots[j].y) > reach(i) + reach(j)) continue;
            pairs.emplace_back(std::min(i, j), std::max(i, j));
        }
    }
    std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(first), pairs.end());
}

void listedCandidatePairs(const std::vector<int>& listed, const std::vector<RobotState>& robots,
                          const std::vector<double>& sides, double margin, bool sweep, ListedPairsScratch& scratch,
                          std::vector<std::pair<int, int>>& pairs) {
    const std::size_t m = listed.size();
    if (!sweep || static_cast<int>(m) < kBroadPhaseMinRobots) {
        for (std::size_t a = 0; a < m; ++a)
            for (std::size_t b = a + 1; b < m; ++b) pairs.emplace_back(listed[a], listed[b]);
        return;
    }
    scratch.poses.clear();
    scratch.sides.clear();
    for (const int i : listed) {
        scratch.poses.push_back(robots[std::size_t(i)]);
        scratch.sides.push_back(sides[std::size_t(i)]);
    }
    const std::size_t first = pairs.size();
    candidatePairs(scratch.poses, scratch.sides, margin, scratch.sweep, pairs);
    // Back to robot indices: the list increases, so the order is kept.
    for (std::size_t k = first; k < pairs.size(); ++k) pairs[k] = {listed[pairs[k].first], listed[pairs[k].second]};
}

}  // namespace vssim
