#include "camera_view.h"

#include <QPainter>
#include <opencv2/imgproc.hpp>

namespace vssim {

CameraView::CameraView(QWidget* parent) : QWidget(parent) { setMinimumSize(160, 120); }

CameraView::~CameraView() = default;

void CameraView::setScene(const Scene& scene) {
    renderer_ = std::make_unique<CameraRenderer>(scene);
    image_ = QImage();
    update();
}

void CameraView::showSnapshot(const Snapshot& s) {
    if (!renderer_ || static_cast<int>(s.robots.size()) != renderer_->bodyCount() - 1) return;
    WorldState state;
    state.step = s.step;
    state.time = s.time;
    state.robots = s.robots;
    state.voltages = s.voltages;
    state.voltages.resize(s.robots.size());
    state.ball = s.ball;
    state.offField = s.offField;  // robots off the field are not in the picture, as in the clients' camera
    renderer_->render(state, frame_, patches_);

    cv::Mat rgb;
    cv::cvtColor(frame_, rgb, cv::COLOR_BGR2RGB);
    image_ = QImage(rgb.data, rgb.cols, rgb.rows, static_cast<qsizetype>(rgb.step), QImage::Format_RGB888).copy();
    update();
}

void CameraView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    if (image_.isNull()) {
        p.setPen(Qt::white);
        p.drawText(rect(), Qt::AlignCenter, tr("no camera image"));
        return;
    }
    const QSize shown = image_.size().scaled(size(), Qt::KeepAspectRatio);
    const QRect target(QPoint((width() - shown.width()) / 2, (height() - shown.height()) / 2), shown);
    p.setRenderHint(QPainter::SmoothPixmapTransform, true);
    p.drawImage(target, image_);
}

}  // namespace vssim
