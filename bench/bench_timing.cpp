#include "bench_timing.h"

#include <algorithm>
#include <chrono>

namespace vssim::bench {

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Timing timeMedian(const std::function<void()>& work, int minRuns, double minSeconds, int maxRuns) {
    using Clock = std::chrono::steady_clock;
    work();  // warm-up: caches, page faults, lazily built tables
    std::vector<double> times;
    double total = 0.0;
    while (static_cast<int>(times.size()) < maxRuns &&
           (static_cast<int>(times.size()) < minRuns || total < minSeconds)) {
        const auto start = Clock::now();
        work();
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        times.push_back(seconds);
        total += seconds;
    }
    Timing t;
    t.runs = static_cast<int>(times.size());
    t.min = *std::min_element(times.begin(), times.end());
    t.median = median(times);
    return t;
}

}  // namespace vssim::bench
