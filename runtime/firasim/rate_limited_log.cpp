#include "firasim/rate_limited_log.h"

namespace vssim {

void RateLimitedLog::log(const QString& line, std::int64_t nowNs) {
    if (windowStartNs_ < 0 || nowNs - windowStartNs_ >= kWindowNs) {
        if (suppressedInWindow_ > 0 && sink_)
            sink_(QStringLiteral("(%1 more lines like these in the last %2 s not shown)")
                      .arg(suppressedInWindow_)
                      .arg(kWindowNs / 1'000'000'000));
        windowStartNs_ = nowNs;
        linesInWindow_ = 0;
        suppressedInWindow_ = 0;
    }
    if (linesInWindow_ < kLinesPerWindow) {
        ++linesInWindow_;
        if (sink_) sink_(line);
    } else {
        ++suppressedInWindow_;
        ++suppressedTotal_;
    }
}

}  // namespace vssim
