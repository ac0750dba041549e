#include "realtime/sample_stats.h"

#include <algorithm>
#include <cmath>

namespace vssim {

QJsonObject toJson(const SampleSummary& s) {
    return QJsonObject{{"count", static_cast<double>(s.count)},
                       {"median", s.median},
                       {"p99", s.p99},
                       {"max", s.max},
                       {"mean", s.mean},
                       {"stddev", s.stddev}};
}

void SampleStats::add(double value) {
    ++count_;
    if (ring_.size() < keep_) {
        ring_.push_back(value);
        return;
    }
    ring_[next_] = value;
    next_ = (next_ + 1) % keep_;
}

void SampleStats::clear() {
    ring_.clear();
    next_ = 0;
    count_ = 0;
}

SampleSummary SampleStats::summary() const {
    SampleSummary s;
    s.count = count_;
    if (ring_.empty()) return s;
    std::vector<double> sorted = ring_;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    // Nearest-rank percentiles.
    auto rank = [&](double q) {
        return sorted[std::min(n - 1, static_cast<std::size_t>(std::ceil(q * n)) - (q > 0 ? 1 : 0))];
    };
    s.median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    s.p99 = rank(0.99);
    s.max = sorted.back();
    double sum = 0.0;
    for (double v : sorted) sum += v;
    s.mean = sum / n;
    double sq = 0.0;
    for (double v : sorted) sq += (v - s.mean) * (v - s.mean);
    s.stddev = n > 1 ? std::sqrt(sq / (n - 1)) : 0.0;
    return s;
}

}  // namespace vssim
