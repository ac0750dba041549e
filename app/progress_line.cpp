#include "progress_line.h"

#include <unistd.h>

namespace vssim {

ProgressLine::ProgressLine(QTextStream& err) : err_(err), enabled_(isatty(STDERR_FILENO)) { clock_.start(); }

bool ProgressLine::due() const { return enabled_ && clock_.elapsed() >= nextMs_; }

void ProgressLine::show(const QString& text) {
    if (!enabled_) return;
    nextMs_ = clock_.elapsed() + 500;
    // Pad over what a longer previous line left.
    err_ << '\r' << text.leftJustified(shownWidth_) << Qt::flush;
    shownWidth_ = std::max(shownWidth_, static_cast<int>(text.size()));
}

void ProgressLine::clear() {
    if (shownWidth_ > 0) err_ << '\r' << QString(shownWidth_, ' ') << '\r' << Qt::flush;
    shownWidth_ = 0;
}

}  // namespace vssim
