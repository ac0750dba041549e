#include "status_text.h"

#include <QStringList>
#include <cmath>

namespace vssim {

QString statusText(const Snapshot& s, double realTimeFactor) {
    QStringList parts;
    parts << QString::asprintf("t = %.3f s", s.time);
    parts << QStringLiteral("frame %1").arg(s.frame);
    if (s.mode == RunMode::Realtime)
        parts << QString::asprintf("realtime x%.2f", s.speed);
    else
        parts << QString::fromLatin1(runModeName(s.mode));
    if (s.fault) {
        parts << QStringLiteral("halted: ") + s.fault->message();
    } else if (s.paused) {  // nothing runs: no real-time factor or engine cost to show
        parts << QStringLiteral("paused");
    } else {
        if (std::isfinite(realTimeFactor) && realTimeFactor >= 0.0)
            parts << QString::asprintf("x%.2f real time", realTimeFactor);
        parts << QString::asprintf("engine %.1f ms per simulated s", s.stepCost * 1000.0);
    }
    return parts.join(QStringLiteral("   "));
}

}  // namespace vssim
