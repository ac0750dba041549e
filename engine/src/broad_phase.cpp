#include "vssim/broad_phase.h"

#include <algorithm>
#include <cmath>

namespace vssim {

void candidatePairs(const std::vector<RobotState>& robots, const std::vector<double>& sides, double margin,
                    BroadPhaseScratch& scratch, std::vector<std::pair<int, int>>& pairs) {
    const int n = static_cast<int>(robots.size());
    const std::size_t first = pairs.size();
    auto reach = [&](int i) { return sides[i] / std::sqrt(2.0) + margin; };  // m
    scratch.order.resize(n);
    scratch.minX.resize(n);
    for (int i = 0; i < n; ++i) {
        scratch.order[i] = i;
        scratch.minX[i] = robots[i].x - reach(i);
    }
    // Ties broken by index, and NaN positions sorted last, so the order is total.
    std::sort(scratch.order.begin(), scratch.order.end(), [&](int a, int b) {
        const double xa = scratch.minX[a], xb = scratch.minX[b];
        if (xa < xb) return true;
        if (xb < xa) return false;
        const bool nanA = std::isnan(xa), nanB = std::isnan(xb);
        if (nanA != nanB) return nanB;
        return a < b;
    });
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

}  // namespace vssim
