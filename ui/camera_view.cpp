#include "camera_view.h"

#include <QComboBox>
#include <QPainter>
#include <opencv2/imgproc.hpp>

namespace vssim {

CameraView::CameraView(QWidget* parent) : QWidget(parent) {
    setMinimumSize(160, 120);
    previewBox_ = new QComboBox(this);
    previewBox_->addItem(tr("The scene's camera (what clients receive)"));
    previewBox_->addItem(tr("Preview: ideal camera"));
    previewBox_->addItem(tr("Preview: realistic camera (lens, light, noise, blur)"));
    previewBox_->setToolTip(
        tr("Which camera this view draws with. The previews change nothing the clients receive: a scene's "
           "\"camera\" key sets that (docs/scenes.md)."));
    previewBox_->move(0, 0);
    connect(previewBox_, qOverload<int>(&QComboBox::currentIndexChanged), this,
            [this](int index) { setPreview(static_cast<Preview>(index)); });
}

CameraView::~CameraView() = default;

const CameraSettings& CameraView::shownCamera() const {
    static const CameraSettings ideal = idealCamera();  // before setScene(), or for a camera that cannot be drawn
    return renderer_ ? renderer_->settings() : ideal;
}

void CameraView::setScene(const Scene& scene) {
    scene_ = scene;
    last_.reset();
    rebuildRenderer();
    image_ = QImage();
    update();
}

void CameraView::setPreview(Preview preview) {
    if (previewBox_->currentIndex() != static_cast<int>(preview)) {
        previewBox_->setCurrentIndex(static_cast<int>(preview));  // comes back here through the signal
        return;
    }
    if (preview == preview_) return;
    preview_ = preview;
    rebuildRenderer();
    if (last_) showSnapshot(*last_);
}

void CameraView::rebuildRenderer() {
    if (!scene_) return;
    problem_.clear();
    const CameraSettings camera = preview_ == Preview::Ideal       ? idealCamera()
                                  : preview_ == Preview::Realistic ? realisticCamera()
                                                                   : scene_->camera;
    try {
        renderer_ = std::make_unique<CameraRenderer>(*scene_, camera);
    } catch (const std::exception& e) {
        // E.g. the realistic preview of a scene whose robots reach the camera's 2 m.
        renderer_.reset();
        problem_ = QString::fromStdString(e.what());
        image_ = QImage();
        update();
    }
}

void CameraView::showSnapshot(const Snapshot& s) {
    if (!renderer_ || static_cast<int>(s.robots.size()) != renderer_->bodyCount() - 1) return;
    last_ = s;
    WorldState state;
    state.step = s.step;
    state.time = s.time;
    state.robots = s.robots;
    state.voltages = s.voltages;
    state.voltages.resize(s.robots.size());
    state.ball = s.ball;
    state.offField = s.offField;  // robots off the field are not in the picture, as in the clients' camera
    // The frame number seeds the sensor noise: the snapshot's camera instant, as the server's.
    renderer_->render(state, frame_, patches_, static_cast<std::uint64_t>(std::max<std::int64_t>(0, s.frame)));

    cv::Mat rgb;
    cv::cvtColor(frame_, rgb, cv::COLOR_BGR2RGB);
    image_ = QImage(rgb.data, rgb.cols, rgb.rows, static_cast<qsizetype>(rgb.step), QImage::Format_RGB888).copy();
    update();
}

QRect CameraView::imageArea() const {
    const int top = previewBox_->sizeHint().height();
    return QRect(0, top, width(), std::max(0, height() - top));
}

void CameraView::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    previewBox_->resize(std::min(width(), previewBox_->sizeHint().width()), previewBox_->sizeHint().height());
    const QRect area = imageArea();
    if (image_.isNull()) {
        p.setPen(Qt::white);
        p.drawText(area, Qt::AlignCenter | Qt::TextWordWrap,
                   problem_.isEmpty() ? tr("no camera image") : tr("cannot draw this camera: %1").arg(problem_));
        return;
    }
    const QSize shown = image_.size().scaled(area.size(), Qt::KeepAspectRatio);
    const QRect target(QPoint(area.left() + (area.width() - shown.width()) / 2,
                              area.top() + (area.height() - shown.height()) / 2),
                       shown);
    p.setRenderHint(QPainter::SmoothPixmapTransform, true);
    p.drawImage(target, image_);
}

}  // namespace vssim
