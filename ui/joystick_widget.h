// An on-screen joystick for machines without a gamepad: a round base with a
// knob the user drags with the mouse (left button). The knob springs back to
// the centre when released.
#pragma once

#include <QPointF>
#include <QWidget>

namespace vssim {

class JoystickWidget : public QWidget {
    Q_OBJECT
public:
    explicit JoystickWidget(QWidget* parent = nullptr);

    // Knob position, x right positive, y UP positive, inside the unit disc
    // (dimensionless); (0, 0) when not dragged.
    QPointF position() const { return position_; }

    // Geometry, in widget pixels: the centre of the base, and how far the
    // knob's centre travels from it for a full deflection (|position| = 1).
    QPointF centre() const;
    double travelRadius() const;

    QSize minimumSizeHint() const override { return {120, 120}; }
    QSize sizeHint() const override { return {160, 160}; }

signals:
    // The knob moved to (x, y): x right positive, y up positive, with
    // x^2 + y^2 <= 1. Emitted on press and while dragging (when the value
    // changes), and (0, 0) on release.
    void moved(double x, double y);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void resizeEvent(QResizeEvent* event) override;

private:
    double knobRadius() const;           // px
    void moveKnobTo(const QPointF& px);  // widget pixels -> position_, emits
    void recentre();                     // back to (0, 0), emits

    QPointF position_;
    bool dragging_ = false;
};

}  // namespace vssim
