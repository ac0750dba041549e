// A progress line for the long headless commands (vssim run, vssim match):
// written on standard error and rewritten in place, only when standard
// error is a terminal, first after a second, then at most twice a second,
// and erased when the work is done, so that what a command prints stays
// clean.
#pragma once

#include <QElapsedTimer>
#include <QString>
#include <QTextStream>

namespace vssim {

class ProgressLine {
public:
    // `err`: the command's standard-error stream (the line and the
    // command's own messages go out in order).
    explicit ProgressLine(QTextStream& err);
    // Whether a line is due now: a caller builds its text only then.
    bool due() const;
    void show(const QString& text);
    // Erases the line, if one is shown.
    void clear();
    // Since construction, s of wall time.
    double elapsedSeconds() const { return static_cast<double>(clock_.nsecsElapsed()) * 1e-9; }

private:
    QTextStream& err_;
    bool enabled_;
    int shownWidth_ = 0;  // characters of the line shown, 0 when none
    qint64 nextMs_ = 1000;
    QElapsedTimer clock_;
};

}  // namespace vssim
