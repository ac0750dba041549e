// Summary statistics over the most recent samples of a measurement (latency,
// frame period, render time): median, 99th percentile, maximum, mean and
// standard deviation, for `stats` replies and benchmarks.
#pragma once

#include <QJsonObject>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vssim {

struct SampleSummary {
    std::int64_t count = 0;                                               // samples ever added
    double median = 0.0, p99 = 0.0, max = 0.0, mean = 0.0, stddev = 0.0;  // over the kept ones
};

// {"count", "median", "p99", "max", "mean", "stddev"}, in the samples' unit.
QJsonObject toJson(const SampleSummary& summary);

class SampleStats {
public:
    explicit SampleStats(std::size_t keep = 8192) : keep_(keep) {}
    void add(double value);
    SampleSummary summary() const;
    void clear();

private:
    std::size_t keep_;
    std::vector<double> ring_;
    std::size_t next_ = 0;
    std::int64_t count_ = 0;
};

}  // namespace vssim
