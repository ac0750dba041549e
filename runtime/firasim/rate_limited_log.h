// Log lines about bad input from the network, at a bounded rate: a flood of
// malformed packets must not become a flood of log lines. Each kind of
// problem is counted always; at most kLinesPerWindow lines are let through
// per window of kWindowNs, and the first line after a window that dropped
// some says how many were not shown.
#pragma once

#include <QString>
#include <cstdint>
#include <functional>

namespace vssim {

class RateLimitedLog {
public:
    static constexpr int kLinesPerWindow = 20;
    static constexpr std::int64_t kWindowNs = 10'000'000'000;  // 10 s

    explicit RateLimitedLog(std::function<void(const QString&)> sink) : sink_(std::move(sink)) {}
    // Logs `line` at wall time nowNs (monotonicNs()) if the window allows it.
    void log(const QString& line, std::int64_t nowNs);
    std::int64_t suppressed() const { return suppressedTotal_; }

private:
    std::function<void(const QString&)> sink_;
    std::int64_t windowStartNs_ = -1;
    int linesInWindow_ = 0;
    std::int64_t suppressedInWindow_ = 0;
    std::int64_t suppressedTotal_ = 0;
};

}  // namespace vssim
