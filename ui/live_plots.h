// The last few seconds of one robot's motion and motors, as three small
// stacked charts: velocities (v in m/s, omega in rad/s), voltages (right and
// left, V) and currents (right and left, A), against simulated time (s).
// Fed sample by sample by the main window; never reads the engine.
#pragma once

#include <QColor>
#include <QRect>
#include <QWidget>
#include <vector>

#include "realtime/snapshot.h"

namespace vssim {

class LivePlots : public QWidget {
    Q_OBJECT
public:
    static constexpr int kCharts = 3;  // velocities, voltages, currents

    // windowSeconds: simulated time kept and shown, s. maxSamples: above
    // this, every other stored sample is dropped (the newest always kept).
    explicit LivePlots(QWidget* parent = nullptr, double windowSeconds = 5.0, int maxSamples = 2000);

    // Adds robot `robot` of the snapshot. Ignored when s.time is not later
    // than the last sample's. Starts afresh when the robot changes or time
    // went backwards (a reset). Drops samples older than the window.
    void addSample(const Snapshot& s, int robot);
    void clear();
    int sampleCount() const { return static_cast<int>(samples_.size()); }
    int robot() const { return robot_; }
    double windowSeconds() const { return window_; }

    // Where chart `index` (0 velocities, 1 voltages, 2 currents) plots, in
    // widget pixels, at the current size.
    QRect chartRect(int index) const;
    // The colours of the two series of each chart (first: v / right; second: omega / left).
    static QColor firstColour() { return QColor(220, 50, 47); }
    static QColor secondColour() { return QColor(38, 110, 210); }

    QSize sizeHint() const override { return {360, 420}; }

protected:
    void paintEvent(QPaintEvent* event) override;

private:
    struct Sample {
        double t;              // simulated time, s
        double v, omega;       // m/s, rad/s
        double eRight, eLeft;  // V
        double iRight, iLeft;  // A
    };
    std::vector<Sample> samples_;
    int robot_ = -1;
    double window_;
    int maxSamples_;

    void thin();
};

}  // namespace vssim
