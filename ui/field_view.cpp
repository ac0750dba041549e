#include "field_view.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <optional>

#include "vssim/camera/camera_colours.h"
#include "vssim/camera/camera_layout.h"
#include "realtime/engine_request.h"
#include "vssim/field.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

constexpr double kMargin = 0.08;  // m of view around the field
constexpr std::size_t kTrailPoints = 240;
// Simulated time between two snapshots above which their positions are not
// joined by a trail segment, s (at x1 and 30 Hz they are 33 ms apart).
constexpr double kMaxTrailGap = 0.1;

// A robot moves along its heading only: an arrow from its centre to `tip`
// (field m) sets the speed of its projection on the heading, m/s.
double arrowRobotSpeed(const RobotState& r, const QPointF& tip) {
    const QPointF d = tip - QPointF(r.x, r.y);
    return std::clamp(FieldView::kSpeedPerArrowMetre * (d.x() * std::cos(r.theta) + d.y() * std::sin(r.theta)),
                      -kMaxPlacedRobotSpeed, kMaxPlacedRobotSpeed);
}

// The ball's velocity set by an arrow from its centre to `tip`, m/s.
QPointF arrowBallVelocity(const BallState& b, const QPointF& tip) {
    QPointF v = FieldView::kSpeedPerArrowMetre * (tip - QPointF(b.x, b.y));
    const double speed = std::hypot(v.x(), v.y());
    if (speed > kMaxPlacedBallSpeed) v *= kMaxPlacedBallSpeed / speed;
    return v;
}

QColor qcolor(Bgr c) { return QColor(c.r, c.g, c.b); }

// A patch (camera_layout.h) in the robot's frame, m.
QRectF patchRect(const PatchRectangle& patch, double side) {
    return QRectF(patch.xMin * side, patch.yMin * side, (patch.xMax - patch.xMin) * side,
                  (patch.yMax - patch.yMin) * side);
}

// Where a body dragged to centre c may go: c itself when it fits, else c
// clamped to the floor's bounding box and then pushed, a few times, along the
// inward normal of the wall nearest to it until the body clears that wall
// (the corner triangles, the goals' side walls and posts). reach(n): how far
// the body reaches along unit direction n, m. Nullopt when it still does not
// fit.
template <typename Reach, typename Fits>
std::optional<Eigen::Vector2d> placeOnFloor(const Field& field, Eigen::Vector2d c, Reach reach, Fits fits) {
    if (fits(c)) return c;
    const double rx = reach(Eigen::Vector2d::UnitX()), ry = reach(Eigen::Vector2d::UnitY());
    c.x() = std::clamp(c.x(), std::min(field.lower.x() + rx, 0.0), std::max(field.upper.x() - rx, 0.0));
    c.y() = std::clamp(c.y(), std::min(field.lower.y() + ry, 0.0), std::max(field.upper.y() - ry, 0.0));
    constexpr double kClearance = 1e-9;  // m beyond touching
    for (int pass = 0; pass < 6 && !fits(c); ++pass) {
        const NearestWall nearest = nearestWall(field, c);
        if (nearest.wall < 0) break;
        const Wall& w = field.walls[nearest.wall];
        const double off = reach(w.normal) + kClearance - (c - w.a).dot(w.normal);  // how far too close, m
        if (off > 0.0) c += off * w.normal;
    }
    if (fits(c)) return c;
    return std::nullopt;
}

// Index of robot i among the robots of its team (its identity colour).
int identityIndex(const Scene& scene, int robot) {
    int n = 0;
    for (int i = 0; i < robot; ++i) n += scene.robots[i].team == scene.robots[robot].team;
    return n;
}

}  // namespace

FieldView::FieldView(QWidget* parent) : QOpenGLWidget(parent) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(false);
    setMinimumSize(320, 280);
    setToolTip(
        tr("Drag a robot or the ball to move it; mouse wheel over a robot turns it;\n"
           "Shift+drag from a body sets its velocity (0.1 m of arrow = 1 m/s);\n"
           "wheel elsewhere zooms, right or middle drag pans; double-click puts the ball there\n"
           "(off the floor: resets the view);\n"
           "W A S D or the arrow keys drive the selected robot, Esc lets it go;\n"
           "Space plays or pauses, Ctrl+Z / Ctrl+Shift+Z undo and redo a move,\n"
           "Ctrl+Right steps 30 ms (paused), Ctrl+R resets, Ctrl+Up / Ctrl+Down change the speed."));
}

void FieldView::showSnapshot(std::shared_ptr<const Snapshot> snapshot) {
    // The same snapshot again (paused, idle): nothing to redraw.
    if (!snapshot || snapshot == snapshot_) return;
    const std::size_t bodies = snapshot->robots.size() + 1;
    if (trails_.size() != bodies || snapshot->time < trailTime_) trails_.assign(bodies, {});
    const double elapsed = std::max(0.0, snapshot->time - trailTime_);  // s since the last snapshot
    trailTime_ = snapshot->time;
    for (std::size_t i = 0; i < bodies && !snapshot->fault; ++i) {  // no trail through NaN
        const QPointF p = i + 1 < bodies ? QPointF(snapshot->robots[i].x, snapshot->robots[i].y)
                                         : QPointF(snapshot->ball.x, snapshot->ball.y);
        auto& trail = trails_[i];
        // A jump far beyond what its speed explains: moved by hand, no streak.
        const double speed =
            i + 1 < bodies ? std::abs(snapshot->robots[i].v) : std::hypot(snapshot->ball.vx, snapshot->ball.vy);
        if (!trail.empty() && QLineF(trail.back(), p).length() > 0.02 + 2.0 * speed * elapsed) trail.clear();
        // Snapshots far apart in simulated time (a fast speed factor, max
        // mode): a chord between them would cut across the path actually
        // taken, so the trail breaks instead (a NaN point).
        if (!trail.empty() && elapsed > kMaxTrailGap && !std::isnan(trail.back().x()))
            trail.push_back(QPointF(std::nan(""), std::nan("")));
        const bool afterGap = trail.empty() || std::isnan(trail.back().x());
        if (afterGap || QLineF(trail.back(), p).length() > 0.002) trail.push_back(p);
        while (trail.size() > kTrailPoints) trail.pop_front();
    }
    snapshot_ = std::move(snapshot);
    if (selected_ >= static_cast<int>(snapshot_->robots.size())) setSelectedRobot(-1);
    update();
}

void FieldView::setSelectedRobot(int robot) {
    if (robot == selected_) return;
    selected_ = robot;
    emit robotSelected(robot);
    update();
}

void FieldView::setShowTrails(bool on) {
    showTrails_ = on;
    update();
}

void FieldView::setShowVelocities(bool on) {
    showVelocities_ = on;
    update();
}

void FieldView::resetView() {
    zoom_ = 1.0;
    pan_ = QPointF();
    update();
}

QTransform FieldView::worldToWidget() const {
    // The floor's bounding box, goals included (centred on the origin).
    double length = 1.5, width = 1.3;
    if (snapshot_ && snapshot_->scene) {
        const Field& field = snapshot_->scene->field;
        length = std::max(field.length, field.upper.x() - field.lower.x());
        width = std::max(field.width, field.upper.y() - field.lower.y());
    }
    // Fit the field and its margin, keeping the aspect ratio; y up.
    const double scale = zoom_ * std::min(this->width() / (length + 2 * kMargin), height() / (width + 2 * kMargin));
    QTransform t;
    t.translate(this->width() / 2.0, height() / 2.0);
    t.scale(scale, -scale);
    t.translate(-pan_.x(), -pan_.y());
    return t;
}

QPointF FieldView::toWidget(double x, double y) const { return worldToWidget().map(QPointF(x, y)); }

QPointF FieldView::toField(const QPointF& widgetPoint) const { return worldToWidget().inverted().map(widgetPoint); }

void FieldView::paintGL() {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing);
    if (!snapshot_ || !snapshot_->scene) {
        p.fillRect(rect(), qcolor(kOutsideColour));
        return;
    }
    // The field itself (floor, markings, walls) changes only with the view
    // or the scene: drawn once into a pixmap, which the GL paint engine keeps
    // as a texture, so a redraw paints one image and then the bodies.
    const QTransform transform = worldToWidget();
    const qreal ratio = devicePixelRatioF();
    if (fieldCache_.isNull() || fieldCacheTransform_ != transform || fieldCacheScene_ != snapshot_->scene ||
        fieldCache_.size() != size() * ratio) {
        fieldCache_ = QPixmap(size() * ratio);
        fieldCache_.setDevicePixelRatio(ratio);
        QPainter cache(&fieldCache_);
        cache.setRenderHint(QPainter::Antialiasing);
        cache.fillRect(rect(), qcolor(kOutsideColour));
        cache.setTransform(transform);
        paintField(cache);
        fieldCacheTransform_ = transform;
        fieldCacheScene_ = snapshot_->scene;
    }
    p.drawPixmap(0, 0, fieldCache_);
    if (snapshot_->fault) {  // the bodies' numbers are NaN or infinite: say why instead
        p.setPen(QColor(255, 120, 120));
        p.drawText(rect().adjusted(20, 20, -20, -20), Qt::AlignCenter | Qt::TextWordWrap,
                   tr("The simulation halted: %1.\nReset, or open a scene.").arg(snapshot_->fault->message()));
        return;
    }
    p.setTransform(transform);
    paintBodies(p);
}

void FieldView::paintField(QPainter& p) const {
    // As the camera draws it (field_background.h): the floor inside the chain
    // of walls, goals included; the markings; the walls along every segment.
    const Field& field = snapshot_->scene->field;
    const FieldDimensions& d = field.dimensions;
    QPolygonF floor;
    for (const Wall& w : field.walls) floor << QPointF(w.a.x(), w.a.y());
    p.setPen(Qt::NoPen);
    p.setBrush(qcolor(kFloorColour));
    p.drawPolygon(floor);
    const double hx = field.length / 2, hy = field.width / 2;
    QPen line(qcolor(kMarkingColour), 0.004);
    p.setPen(line);
    p.setBrush(Qt::NoBrush);
    p.drawLine(QPointF(0, -hy), QPointF(0, hy));
    if (d.centre_radius > 0.0) p.drawEllipse(QPointF(0, 0), d.centre_radius, d.centre_radius);
    for (const double side : {-1.0, 1.0}) {
        if (d.goal_area_depth > 0.0 && d.goal_area_width > 0.0) {
            const double front = side * (hx - d.goal_area_depth), half = d.goal_area_width / 2;
            p.drawPolyline(QPolygonF{QPointF(side * hx, -half), QPointF(front, -half), QPointF(front, half),
                                     QPointF(side * hx, half)});
        }
        auto cross = [&](double x, double y) {
            p.drawLine(QPointF(x - kMarkHalfArm, y), QPointF(x + kMarkHalfArm, y));
            p.drawLine(QPointF(x, y - kMarkHalfArm), QPointF(x, y + kMarkHalfArm));
        };
        if (d.penalty_mark > 0.0) cross(side * (hx - d.penalty_mark), 0.0);
        if (d.free_ball_x > 0.0)
            for (const double y : {-d.free_ball_y, d.free_ball_y}) cross(side * (hx - d.free_ball_x), y);
    }
    QPen wall(qcolor(kWallColour), 0.012);
    wall.setJoinStyle(Qt::MiterJoin);
    p.setPen(wall);
    p.drawPolygon(floor);  // the closed chain: joined corners, no gaps at the posts
}

void FieldView::paintBodies(QPainter& p) const {
    const Snapshot& s = *snapshot_;
    const Scene& scene = *s.scene;
    if (showTrails_) {
        for (std::size_t i = 0; i < trails_.size(); ++i) {
            const bool ball = i + 1 == trails_.size();
            // Half-way to white, so that blue shows on the dark floor.
            const QColor team = ball ? qcolor(kBallColour) : qcolor(teamColour(scene.robots[i].team));
            QColor c((team.red() + 255) / 2, (team.green() + 255) / 2, (team.blue() + 255) / 2, 150);
            p.setPen(QPen(c, 0.003));
            // Pieces between breaks; a piece of one point (refreshes far apart
            // in simulated time: x4, max) is drawn as a dot, so fast runs
            // leave a dotted trail rather than none.
            QPainterPath path;
            std::vector<QPointF> dots;
            int pieceLength = 0;
            for (const QPointF& point : trails_[i]) {
                if (std::isnan(point.x())) {
                    if (pieceLength == 1) dots.push_back(path.currentPosition());
                    pieceLength = 0;
                    continue;
                }
                pieceLength == 0 ? path.moveTo(point) : path.lineTo(point);
                ++pieceLength;
            }
            if (pieceLength == 1) dots.push_back(path.currentPosition());
            p.drawPath(path);
            p.setPen(QPen(c, 0.008, Qt::SolidLine, Qt::RoundCap));
            for (const QPointF& dot : dots) p.drawPoint(dot);
        }
    }
    for (std::size_t i = 0; i < s.robots.size() && i < scene.robots.size(); ++i) {
        const RobotState& r = s.robots[i];
        const double side = scene.robots[i].params.side;
        p.save();
        // Off the field (FIRASim's turnon false): a ghost where it was left.
        if (i < s.offField.size() && s.offField[i]) p.setOpacity(0.25);
        p.translate(r.x, r.y);
        p.rotate(r.theta * 180.0 / 3.141592653589793);
        // Body, team patch (rear), identity patch (front): as the camera draws them.
        p.setPen(Qt::NoPen);
        p.setBrush(qcolor(kRobotBodyColour));
        p.drawRect(QRectF(-side / 2, -side / 2, side, side));
        p.setBrush(qcolor(teamColour(scene.robots[i].team)));
        p.drawRect(patchRect(kTeamPatch, side));
        p.setBrush(qcolor(identityColour(identityIndex(scene, static_cast<int>(i)))));
        p.drawRect(patchRect(kIdentityPatch, side));
        // Heading mark: a white tick at the front edge.
        p.setPen(QPen(Qt::white, 0.004));
        p.drawLine(QPointF(0.5 * side, 0), QPointF(0.68 * side, 0));
        const bool manual = i < s.control.size() && s.control[i].controller == RobotController::Manual;
        if (static_cast<int>(i) == selected_ || manual) {
            p.setPen(QPen(manual ? QColor(255, 80, 80) : QColor(120, 200, 255), 0.005,
                          manual ? Qt::DashLine : Qt::SolidLine));
            p.setBrush(Qt::NoBrush);
            p.drawEllipse(QPointF(0, 0), 0.75 * side, 0.75 * side);
        }
        p.restore();
        if (showVelocities_ && std::abs(r.v) > 1e-3) {
            p.setPen(QPen(QColor(255, 255, 255, 180), 0.004));
            const double len = r.v / kSpeedPerArrowMetre;
            p.drawLine(QPointF(r.x, r.y), QPointF(r.x + len * std::cos(r.theta), r.y + len * std::sin(r.theta)));
        }
    }
    p.setPen(Qt::NoPen);
    p.setBrush(qcolor(kBallColour));
    p.drawEllipse(QPointF(s.ball.x, s.ball.y), scene.ball_params.radius, scene.ball_params.radius);
    if (showVelocities_ && std::hypot(s.ball.vx, s.ball.vy) > 1e-3) {
        p.setPen(QPen(QColor(255, 200, 120), 0.004));
        p.drawLine(QPointF(s.ball.x, s.ball.y),
                   QPointF(s.ball.x + s.ball.vx / kSpeedPerArrowMetre, s.ball.y + s.ball.vy / kSpeedPerArrowMetre));
    }
    // The arrow being dragged.
    if (drag_ == Drag::RobotArrow || drag_ == Drag::BallArrow) {
        const QPointF from = drag_ == Drag::BallArrow ? QPointF(s.ball.x, s.ball.y)
                                                      : QPointF(s.robots[dragRobot_].x, s.robots[dragRobot_].y);
        p.setPen(QPen(QColor(255, 255, 0), 0.006));
        p.drawLine(from, dragLast_);
        const QLineF line(from, dragLast_);
        if (line.length() > 1e-6) {  // an arrowhead, 2 cm long, at the tip
            const QPointF back = (from - dragLast_) / line.length() * 0.02;
            const QPointF side(-back.y() * 0.5, back.x() * 0.5);
            p.drawLine(dragLast_, dragLast_ + back + side);
            p.drawLine(dragLast_, dragLast_ + back - side);
        }
        // What the release will set, next to the tip, in pixels.
        const QPointF tip = worldToWidget().map(dragLast_);
        p.save();
        p.resetTransform();
        p.setPen(QColor(255, 255, 0));
        const double speed = drag_ == Drag::BallArrow ? QLineF(QPointF(), arrowBallVelocity(s.ball, dragLast_)).length()
                                                      : arrowRobotSpeed(s.robots[dragRobot_], dragLast_);
        p.drawText(tip + QPointF(8, -8), QString::asprintf("%.2f m/s", speed));
        p.restore();
    }
}

int FieldView::robotAt(const QPointF& f) const {
    if (!snapshot_ || !snapshot_->scene) return -1;
    for (int i = static_cast<int>(snapshot_->robots.size()) - 1; i >= 0; --i) {
        const RobotState& r = snapshot_->robots[i];
        const double side = snapshot_->scene->robots[i].params.side;
        // In the robot's frame, with a little slack for grabbing.
        const double dx = f.x() - r.x, dy = f.y() - r.y;
        const double along = dx * std::cos(r.theta) + dy * std::sin(r.theta);
        const double across = -dx * std::sin(r.theta) + dy * std::cos(r.theta);
        if (std::abs(along) <= 0.6 * side && std::abs(across) <= 0.6 * side) return i;
    }
    return -1;
}

bool FieldView::ballAt(const QPointF& f) const {
    if (!snapshot_ || !snapshot_->scene) return false;
    return std::hypot(f.x() - snapshot_->ball.x, f.y() - snapshot_->ball.y) <=
           1.5 * snapshot_->scene->ball_params.radius;
}

RobotState FieldView::clampInside(int robot, RobotState pose) const {
    const Scene& scene = *snapshot_->scene;
    const double side = scene.robots[robot].params.side;
    const Eigen::Vector2d u(std::cos(pose.theta), std::sin(pose.theta)), v(-u.y(), u.x());
    // How far the square reaches along a unit direction n.
    auto reach = [&](const Eigen::Vector2d& n) { return 0.5 * side * (std::abs(n.dot(u)) + std::abs(n.dot(v))); };
    auto fits = [&](const Eigen::Vector2d& c) { return robotInsideField(scene.field, side, c.x(), c.y(), pose.theta); };
    const std::optional<Eigen::Vector2d> c = placeOnFloor(scene.field, {pose.x, pose.y}, reach, fits);
    if (!c) return snapshot_->robots[robot];  // nowhere near: it stays where it is
    pose.x = c->x(), pose.y = c->y();
    return pose;
}

BallState FieldView::clampInside(BallState ball) const {
    const Scene& scene = *snapshot_->scene;
    const double r = scene.ball_params.radius;
    auto fits = [&](const Eigen::Vector2d& c) { return discInsideField(scene.field, r, c.x(), c.y()); };
    const std::optional<Eigen::Vector2d> c = placeOnFloor(
        scene.field, {ball.x, ball.y}, [r](const Eigen::Vector2d&) { return r; }, fits);
    if (!c) return BallState{snapshot_->ball.x, snapshot_->ball.y, ball.vx, ball.vy};
    ball.x = c->x(), ball.y = c->y();
    return ball;
}

void FieldView::mousePressEvent(QMouseEvent* event) {
    setFocus();
    if (!snapshot_) return;
    const QPointF f = toField(event->position());
    pressPixel_ = event->position();
    moved_ = false;
    if (event->button() == Qt::RightButton || event->button() == Qt::MiddleButton) {
        drag_ = Drag::Pan;
        dragLast_ = event->position();
        return;
    }
    if (event->button() != Qt::LeftButton) return;
    const bool arrow = event->modifiers() & Qt::ShiftModifier;
    const int robot = robotAt(f);
    if (robot >= 0) {
        setSelectedRobot(robot);
        dragRobot_ = robot;
        dragRobotPose_ = snapshot_->robots[robot];
        dragOffset_ = QPointF(dragRobotPose_.x, dragRobotPose_.y) - f;
        drag_ = arrow ? Drag::RobotArrow : Drag::Robot;
        dragLast_ = f;
        emit robotDragStarted(robot, dragRobotPose_);
    } else if (ballAt(f)) {
        dragBall_ = snapshot_->ball;
        dragOffset_ = QPointF(dragBall_.x, dragBall_.y) - f;
        drag_ = arrow ? Drag::BallArrow : Drag::Ball;
        dragLast_ = f;
        emit ballDragStarted(dragBall_);
    } else {
        setSelectedRobot(-1);
    }
}

void FieldView::mouseMoveEvent(QMouseEvent* event) {
    if (!snapshot_ || drag_ == Drag::None) return;
    const QPointF f = toField(event->position());
    // A click only selects: a body moves once the mouse has travelled a few pixels.
    if (!moved_ && QLineF(pressPixel_, event->position()).length() < kDragThresholdPx) return;
    moved_ = true;
    switch (drag_) {
        case Drag::Pan: {
            const QPointF before = toField(dragLast_);
            pan_ += before - f;
            dragLast_ = event->position();
            update();
            return;
        }
        case Drag::Robot: {
            RobotState pose = snapshot_->robots[dragRobot_];
            pose.x = f.x() + dragOffset_.x();
            pose.y = f.y() + dragOffset_.y();
            pose.theta = dragRobotPose_.theta;
            pose.v = 0;
            pose.omega = 0;
            emit robotPlaced(dragRobot_, clampInside(dragRobot_, pose), false);
            return;
        }
        case Drag::Ball: {
            BallState ball{f.x() + dragOffset_.x(), f.y() + dragOffset_.y(), 0.0, 0.0};
            emit ballPlaced(clampInside(ball), false);
            return;
        }
        case Drag::RobotArrow:
        case Drag::BallArrow:
            dragLast_ = f;
            update();
            return;
        case Drag::None: return;
    }
}

void FieldView::mouseReleaseEvent(QMouseEvent* event) {
    if (!snapshot_) return;
    const QPointF f = toField(event->position());
    const Drag drag = drag_;
    drag_ = Drag::None;
    if (!moved_ && QLineF(pressPixel_, event->position()).length() < kDragThresholdPx && drag != Drag::Pan) {
        update();  // a click: selected, nothing moved
        return;
    }
    switch (drag) {
        case Drag::Robot: {
            RobotState pose = dragRobotPose_;
            pose.x = f.x() + dragOffset_.x();
            pose.y = f.y() + dragOffset_.y();
            pose.v = 0;
            pose.omega = 0;
            emit robotPlaced(dragRobot_, clampInside(dragRobot_, pose), true);
            break;
        }
        case Drag::Ball:
            emit ballPlaced(clampInside(BallState{f.x() + dragOffset_.x(), f.y() + dragOffset_.y(), 0.0, 0.0}), true);
            break;
        case Drag::RobotArrow: {
            // A robot moves along its heading only: the arrow's projection on it.
            RobotState pose = snapshot_->robots[dragRobot_];
            pose.v = arrowRobotSpeed(pose, f);
            pose.omega = 0;
            emit robotPlaced(dragRobot_, pose, true);
            break;
        }
        case Drag::BallArrow: {
            BallState ball = snapshot_->ball;
            const QPointF v = arrowBallVelocity(ball, f);
            ball.vx = v.x();
            ball.vy = v.y();
            emit ballPlaced(ball, true);
            break;
        }
        case Drag::Pan:
        case Drag::None: break;
    }
    update();
}

void FieldView::mouseDoubleClickEvent(QMouseEvent* event) {
    // On the floor: the ball goes there, at rest (a referee placing it by
    // hand). Off the floor: the view is reset.
    if (!snapshot_ || event->button() != Qt::LeftButton) return;
    const QPointF f = toField(event->position());
    if (!onFloor(snapshot_->scene->field, {f.x(), f.y()})) {
        resetView();
        return;
    }
    emit ballDragStarted(snapshot_->ball);
    emit ballPlaced(clampInside(BallState{f.x(), f.y(), 0.0, 0.0}), true);
}

void FieldView::wheelEvent(QWheelEvent* event) {
    if (!snapshot_) return;
    const QPointF f = toField(event->position());
    const double notches = event->angleDelta().y() / 120.0;
    const int robot = robotAt(f);
    if (robot >= 0) {
        setSelectedRobot(robot);
        RobotState pose = snapshot_->robots[robot];
        emit robotDragStarted(robot, pose);
        pose.theta = std::remainder(pose.theta + notches * kRotateStep, 2 * 3.141592653589793);
        emit robotPlaced(robot, clampInside(robot, pose), true);
        return;
    }
    // Zoom about the cursor: the field point under it stays put.
    zoom_ = std::clamp(zoom_ * std::pow(1.2, notches), 0.5, 20.0);
    pan_ += f - toField(event->position());
    update();
}

void FieldView::keyPressEvent(QKeyEvent* event) {
    if (event->isAutoRepeat()) return;
    // Ctrl+Right (a disabled Step), Ctrl+S, ...: a shortcut meant, not driving.
    if (event->modifiers() & (Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier)) {
        event->ignore();
        return;
    }
    emit keyChanged(event->key(), true);
}

void FieldView::keyReleaseEvent(QKeyEvent* event) {
    if (event->isAutoRepeat()) return;
    emit keyChanged(event->key(), false);
}

}  // namespace vssim

namespace vssim {

void FieldView::focusOutEvent(QFocusEvent* event) {
    QOpenGLWidget::focusOutEvent(event);
    emit focusLost();
}

}  // namespace vssim
