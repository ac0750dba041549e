#include "live_plots.h"

#include <QPainter>
#include <QPainterPath>
#include <algorithm>
#include <cmath>

namespace vssim {

namespace {

// One curve of a chart: its legend name, unit and colour.
struct Series {
    QString name;
    QString unit;
    QColor colour;
    double minSpan;  // the smallest height of the chart's scale, in `unit`: noise stays flat
};

constexpr int kMarginLeft = 72;      // px, room for the min/max labels
constexpr int kMarginRight = 84;     // px, room for a second unit's labels
constexpr int kTitleHeight = 16;     // px
constexpr int kTimeAxisHeight = 16;  // px

// [lo, hi] of some values with 5 % to spare, at least minSpan high (about
// the values' middle), so that numerical noise around a constant is drawn
// flat rather than stretched to the full height.
std::pair<double, double> rangeOf(const std::vector<double>& values, double minSpan) {
    double lo = *std::min_element(values.begin(), values.end());
    double hi = *std::max_element(values.begin(), values.end());
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
    if (hi - lo < minSpan) {
        const double middle = 0.5 * (lo + hi);
        lo = middle - 0.5 * minSpan;
        hi = middle + 0.5 * minSpan;
    }
    return {lo, hi};
}

// "%.2f unit", with a value that rounds to zero shown as 0.00 (not -0.00).
QString axisLabel(double value, const QString& unit) {
    if (std::abs(value) < 0.005) value = 0.0;
    return QString::asprintf("%.2f %s", value, qPrintable(unit));
}

}  // namespace

LivePlots::LivePlots(QWidget* parent, double windowSeconds, int maxSamples)
    : QWidget(parent), window_(windowSeconds), maxSamples_(std::max(2, maxSamples)) {
    setMinimumSize(240, 240);
}

void LivePlots::clear() {
    samples_.clear();
    robot_ = -1;
    update();
}

void LivePlots::addSample(const Snapshot& s, int robot) {
    const auto index = static_cast<std::size_t>(robot);
    if (robot < 0 || index >= s.robots.size()) {
        if (robot_ != -1) clear();
        return;
    }
    if (robot != robot_ || (!samples_.empty() && s.time < samples_.back().t)) {
        samples_.clear();
        robot_ = robot;
    }
    if (!samples_.empty() && s.time <= samples_.back().t) return;

    const Voltages e = index < s.voltages.size() ? s.voltages[index] : Voltages{};
    const RobotOutputs out = index < s.outputs.size() ? s.outputs[index] : RobotOutputs{};
    samples_.push_back(
        {s.time, s.robots[index].v, s.robots[index].omega, e.right, e.left, out.current_right, out.current_left});

    const double oldest = s.time - window_;
    const auto firstKept =
        std::find_if(samples_.begin(), samples_.end(), [&](const Sample& x) { return x.t >= oldest; });
    samples_.erase(samples_.begin(), firstKept);
    if (static_cast<int>(samples_.size()) > maxSamples_) thin();
    update();
}

// Keeps every other sample counted back from the newest, so the newest stays.
void LivePlots::thin() {
    std::vector<Sample> kept;
    kept.reserve(samples_.size() / 2 + 1);
    const std::size_t n = samples_.size();
    for (std::size_t i = (n - 1) % 2; i < n; i += 2) kept.push_back(samples_[i]);
    samples_ = std::move(kept);
}

QRect LivePlots::chartRect(int index) const {
    const int band = height() / kCharts;
    const int top = index * band + kTitleHeight;
    return QRect(kMarginLeft, top, std::max(1, width() - kMarginLeft - kMarginRight),
                 std::max(1, band - kTitleHeight - kTimeAxisHeight));
}

void LivePlots::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), palette().window());
    p.setRenderHint(QPainter::Antialiasing, false);
    const QString titles[kCharts] = {tr("Velocities"), tr("Voltages"), tr("Currents")};
    const std::vector<Series> series[kCharts] = {
        {{"v", "m/s", firstColour(), 0.1}, {"ω", "rad/s", secondColour(), 1.0}},
        {{"right", "V", firstColour(), 1.0}, {"left", "V", secondColour(), 1.0}},
        {{"right", "A", firstColour(), 0.1}, {"left", "A", secondColour(), 0.1}},
    };
    const double tEnd = samples_.empty() ? window_ : std::max(window_, samples_.back().t);
    const double tStart = tEnd - window_;

    for (int c = 0; c < kCharts; ++c) {
        const QRect area = chartRect(c);
        p.fillRect(area, Qt::white);
        p.setPen(palette().color(QPalette::WindowText));
        p.drawRect(area.adjusted(0, 0, -1, -1));

        // Title and legend.
        int x = area.left();
        p.drawText(QPoint(x, area.top() - 4), titles[c]);
        x += p.fontMetrics().horizontalAdvance(titles[c]) + 12;
        for (const Series& s : series[c]) {
            p.fillRect(QRect(x, area.top() - 10, 12, 4), s.colour);
            x += 16;
            const QString entry = QStringLiteral("%1 (%2)").arg(s.name, s.unit);
            p.drawText(QPoint(x, area.top() - 4), entry);
            x += p.fontMetrics().horizontalAdvance(entry) + 12;
        }

        // Time axis, s.
        const int base = area.bottom() + p.fontMetrics().ascent() + 2;
        p.drawText(QPoint(area.left(), base), QString::asprintf("%.1f s", tStart));
        const QString endLabel = QString::asprintf("%.1f s", tEnd);
        p.drawText(QPoint(area.right() - p.fontMetrics().horizontalAdvance(endLabel), base), endLabel);
        p.drawText(QPoint(area.center().x() - 8, base), QStringLiteral("t (s)"));
        if (samples_.size() < 2) continue;

        // Series with the same unit share a scale; the first unit is labelled
        // on the left, a second one on the right.
        std::vector<std::vector<double>> values(series[c].size());
        for (const Sample& s : samples_) {
            const double row[kCharts][2] = {{s.v, s.omega}, {s.eRight, s.eLeft}, {s.iRight, s.iLeft}};
            for (std::size_t k = 0; k < values.size(); ++k) values[k].push_back(row[c][k]);
        }
        std::vector<std::pair<double, double>> ranges(values.size());
        for (std::size_t k = 0; k < values.size(); ++k) {
            std::vector<double> all;
            for (std::size_t j = 0; j < values.size(); ++j)
                if (series[c][j].unit == series[c][k].unit) all.insert(all.end(), values[j].begin(), values[j].end());
            ranges[k] = rangeOf(all, series[c][k].minSpan);
        }
        const bool twoUnits = series[c][1].unit != series[c][0].unit;
        for (std::size_t k = 0; k < values.size(); ++k) {
            if (k == 1 && !twoUnits) break;
            const QString maxLabel = axisLabel(ranges[k].second, series[c][k].unit);
            const QString minLabel = axisLabel(ranges[k].first, series[c][k].unit);
            const int labelX = k == 0 ? 2 : area.right() + 4;
            p.setPen(twoUnits ? series[c][k].colour : palette().color(QPalette::WindowText));
            p.drawText(QPoint(labelX, area.top() + p.fontMetrics().ascent()), maxLabel);
            p.drawText(QPoint(labelX, area.bottom()), minLabel);
        }

        p.save();
        p.setClipRect(area);
        p.setRenderHint(QPainter::Antialiasing, true);
        const auto toX = [&](double t) { return area.left() + (t - tStart) / window_ * area.width(); };
        for (std::size_t k = 0; k < values.size(); ++k) {
            const auto [lo, hi] = ranges[k];
            const auto toY = [&](double y) { return area.bottom() - (y - lo) / (hi - lo) * area.height(); };
            if (lo < 0.0 && hi > 0.0 && k == 0) {  // the zero line
                p.setPen(QPen(QColor(200, 200, 200), 1, Qt::DashLine));
                p.drawLine(QPointF(area.left(), toY(0.0)), QPointF(area.right(), toY(0.0)));
            }
            QPainterPath path;
            path.moveTo(toX(samples_[0].t), toY(values[k][0]));
            for (std::size_t i = 1; i < samples_.size(); ++i) path.lineTo(toX(samples_[i].t), toY(values[k][i]));
            p.setPen(QPen(series[c][k].colour, 2.0));
            p.drawPath(path);
        }
        p.restore();
    }
}

}  // namespace vssim
