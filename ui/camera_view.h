// The synthetic overhead-camera image the TCP clients receive, drawn from
// each snapshot by the same CameraRenderer the server uses, scaled to the
// widget with its aspect ratio kept. Fed by the main window.
#pragma once

#include <QImage>
#include <QWidget>
#include <memory>
#include <opencv2/core.hpp>

#include "camera/camera_renderer.h"
#include "realtime/snapshot.h"

namespace vssim {

class CameraView : public QWidget {
    Q_OBJECT
public:
    explicit CameraView(QWidget* parent = nullptr);
    ~CameraView() override;

    // The scene whose robots and ball are drawn (rebuilds the renderer).
    void setScene(const Scene& scene);
    // Renders the snapshot's robots and ball. Ignored before setScene() or
    // when the robot count differs from the scene's.
    void showSnapshot(const Snapshot& s);
    // The last rendering, RGB888 (null before the first).
    QImage image() const { return image_; }

    QSize sizeHint() const override { return {640, 480}; }

protected:
    void paintEvent(QPaintEvent* event) override;

private:
    std::unique_ptr<CameraRenderer> renderer_;
    cv::Mat frame_;                  // BGR, reused between renderings
    std::vector<cv::Rect> patches_;  // unused here, render() fills them
    QImage image_;
};

}  // namespace vssim
