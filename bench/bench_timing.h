// Wall-clock timing for the benchmarks (never used by the engine): run a
// piece of work several times and keep the median, the figure the docs quote.
#pragma once

#include <functional>
#include <vector>

namespace vssim::bench {

struct Timing {
    double median = 0.0;  // s
    double min = 0.0;     // s
    int runs = 0;
};

// Runs `work` once to warm up, then at least `minRuns` times and until
// `minSeconds` have passed (at most `maxRuns`), and returns the median.
Timing timeMedian(const std::function<void()>& work, int minRuns = 3, double minSeconds = 0.3, int maxRuns = 50);

double median(std::vector<double> values);

}  // namespace vssim::bench
