// The field seen from above, drawn from the engine's snapshots with QPainter
// on a QOpenGLWidget (GPU-composited; it never touches the engine). A person
// can select, drag and rotate robots, drag the ball, give a body a velocity
// by shift-dragging an arrow from it, zoom (wheel away from bodies) and pan
// (right or middle drag). Edits go out as signals; the main window turns
// them into engine requests and undo steps.
#pragma once

#include <QOpenGLWidget>
#include <QPixmap>
#include <QPointF>
#include <QTransform>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "realtime/snapshot.h"

namespace vssim {

class FieldView : public QOpenGLWidget {
    Q_OBJECT
public:
    // Arrow length to speed: dragging 0.1 m of arrow gives 1 m/s.
    static constexpr double kSpeedPerArrowMetre = 10.0;                      // (m/s) per m
    static constexpr double kRotateStep = 15.0 * 3.141592653589793 / 180.0;  // rad per wheel notch

    explicit FieldView(QWidget* parent = nullptr);

    void showSnapshot(std::shared_ptr<const Snapshot> snapshot);
    std::shared_ptr<const Snapshot> snapshot() const { return snapshot_; }
    void setSelectedRobot(int robot);
    int selectedRobot() const { return selected_; }
    void setShowTrails(bool on);
    void setShowVelocities(bool on);
    void resetView();

    // Field metres <-> widget pixels (for tests and the main window).
    QPointF toWidget(double x, double y) const;
    QPointF toField(const QPointF& widgetPoint) const;

signals:
    void robotSelected(int robot);  // -1: none
    // A body moved by the person (while dragging: many; `finished` on release).
    void robotPlaced(int robot, const vssim::RobotState& pose, bool finished);
    void ballPlaced(const vssim::BallState& ball, bool finished);
    // Drag started: the pose before it (for undo).
    void robotDragStarted(int robot, const vssim::RobotState& before);
    void ballDragStarted(const vssim::BallState& before);
    void keyChanged(int key, bool pressed);
    void focusLost();  // keys held now will never be seen released

protected:
    void paintGL() override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void keyReleaseEvent(QKeyEvent* event) override;
    void focusOutEvent(QFocusEvent* event) override;

private:
    enum class Drag { None, Robot, Ball, RobotArrow, BallArrow, Pan };
    void paintField(QPainter& p) const;
    void paintBodies(QPainter& p) const;
    QTransform worldToWidget() const;
    int robotAt(const QPointF& field) const;  // -1: none
    bool ballAt(const QPointF& field) const;
    RobotState clampInside(int robot, RobotState pose) const;
    BallState clampInside(BallState ball) const;

    std::shared_ptr<const Snapshot> snapshot_;
    int selected_ = -1;
    bool showTrails_ = true;
    bool showVelocities_ = true;
    // The static field, drawn for this transform and scene (paintGL).
    QPixmap fieldCache_;
    QTransform fieldCacheTransform_;
    std::shared_ptr<const Scene> fieldCacheScene_;
    double zoom_ = 1.0;
    QPointF pan_;  // m, the view centre's offset from the field centre
    static constexpr double kDragThresholdPx = 4.0;
    Drag drag_ = Drag::None;
    QPointF pressPixel_;  // where the button went down, widget px
    bool moved_ = false;  // the mouse travelled beyond kDragThresholdPx since
    int dragRobot_ = -1;
    QPointF dragOffset_;  // m: body centre minus the grab point
    QPointF dragLast_;    // widget px (pan) or field m (arrow end)
    RobotState dragRobotPose_;
    BallState dragBall_;
    std::vector<std::deque<QPointF>> trails_;  // per robot, then the ball; field m
    double trailTime_ = -1.0;
};

}  // namespace vssim
