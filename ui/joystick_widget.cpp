#include "joystick_widget.h"

#include <QMouseEvent>
#include <QPainter>
#include <algorithm>
#include <cmath>

namespace vssim {

namespace {

constexpr double kMargin = 2.0;         // px between the base and the widget's edge
constexpr double kKnobFraction = 0.28;  // knob radius / base radius

// Base radius, px: the largest circle that fits, less the margin.
double baseRadiusOf(const QWidget& w) { return std::max(1.0, std::min(w.width(), w.height()) / 2.0 - kMargin); }

}  // namespace

JoystickWidget::JoystickWidget(QWidget* parent) : QWidget(parent) {
    setMinimumSize(minimumSizeHint());
    setSizePolicy(QSizePolicy::Preferred, QSizePolicy::Preferred);
    setCursor(Qt::OpenHandCursor);
    setToolTip(tr("Drag the knob to drive: up is forward"));
}

QPointF JoystickWidget::centre() const { return {width() / 2.0, height() / 2.0}; }

double JoystickWidget::knobRadius() const { return baseRadiusOf(*this) * kKnobFraction; }

// The knob stays inside the base: its centre travels base - knob radius.
double JoystickWidget::travelRadius() const { return std::max(1.0, baseRadiusOf(*this) - knobRadius()); }

void JoystickWidget::moveKnobTo(const QPointF& px) {
    const QPointF offset = px - centre();
    const double r = travelRadius();
    double x = offset.x() / r;
    double y = -offset.y() / r;  // screen y points down
    const double length = std::hypot(x, y);
    if (length > 1.0) {  // clip to the unit disc, keeping the direction
        x /= length;
        y /= length;
    }
    const QPointF next(x, y);
    if (next == position_) return;
    position_ = next;
    update();
    emit moved(x, y);
}

void JoystickWidget::recentre() {
    position_ = QPointF(0.0, 0.0);
    update();
    emit moved(0.0, 0.0);
}

void JoystickWidget::mousePressEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton) {
        QWidget::mousePressEvent(event);
        return;
    }
    dragging_ = true;
    setCursor(Qt::ClosedHandCursor);
    moveKnobTo(event->position());
    event->accept();
}

void JoystickWidget::mouseMoveEvent(QMouseEvent* event) {
    if (!dragging_) {
        QWidget::mouseMoveEvent(event);
        return;
    }
    moveKnobTo(event->position());
    event->accept();
}

void JoystickWidget::mouseReleaseEvent(QMouseEvent* event) {
    if (!dragging_ || event->button() != Qt::LeftButton) {
        QWidget::mouseReleaseEvent(event);
        return;
    }
    dragging_ = false;
    setCursor(Qt::OpenHandCursor);
    recentre();
    event->accept();
}

void JoystickWidget::resizeEvent(QResizeEvent* event) {
    QWidget::resizeEvent(event);
    update();  // position_ is normalised: only the drawing changes
}

void JoystickWidget::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    const QPalette& pal = palette();
    const QPointF c = centre();
    const double base = baseRadiusOf(*this);
    const double travel = travelRadius();

    // Base and its full-deflection ring.
    p.setPen(QPen(pal.color(QPalette::Mid), 1.5));
    p.setBrush(pal.color(QPalette::Base));
    p.drawEllipse(c, base, base);
    p.setPen(QPen(pal.color(QPalette::Midlight), 1.0, Qt::DashLine));
    p.setBrush(Qt::NoBrush);
    p.drawEllipse(c, travel, travel);
    // Cross hairs: forward/back and turn.
    p.setPen(QPen(pal.color(QPalette::Mid), 1.0));
    p.drawLine(QPointF(c.x() - base, c.y()), QPointF(c.x() + base, c.y()));
    p.drawLine(QPointF(c.x(), c.y() - base), QPointF(c.x(), c.y() + base));
    // Forward marker at the top.
    const double tip = base - 4.0;
    const QPointF arrow[3] = {{c.x(), c.y() - tip}, {c.x() - 5.0, c.y() - tip + 7.0}, {c.x() + 5.0, c.y() - tip + 7.0}};
    p.setBrush(pal.color(QPalette::Mid));
    p.drawPolygon(arrow, 3);

    // Knob, at the position (screen y down).
    const QPointF knob(c.x() + position_.x() * travel, c.y() - position_.y() * travel);
    const QColor fill = isEnabled() ? pal.color(QPalette::Highlight) : pal.color(QPalette::Mid);
    p.setPen(QPen(fill.darker(140), 1.5));
    p.setBrush(dragging_ ? fill.lighter(115) : fill);
    const double kr = knobRadius();
    p.drawEllipse(knob, kr, kr);
}

}  // namespace vssim
