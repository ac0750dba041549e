// The synthetic overhead-camera image the TCP clients receive, drawn from
// each snapshot by the same CameraRenderer the server uses, scaled to the
// widget with its aspect ratio kept. Fed by the main window. A combo box
// above the image previews the camera presets: the scene's own camera (what
// clients receive), the ideal one or the realistic one (lens, light, noise,
// blur); the preview changes nothing the server sends.
#pragma once

#include <QImage>
#include <QWidget>
#include <optional>
#include <memory>
#include <opencv2/core.hpp>

#include "vssim/camera/camera_renderer.h"
#include "realtime/snapshot.h"

class QComboBox;

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

    // Which camera the view draws with.
    enum class Preview { Scene, Ideal, Realistic };
    void setPreview(Preview preview);
    Preview preview() const { return preview_; }
    QComboBox* previewBox() const { return previewBox_; }
    // The settings the view draws with now (the scene's, or a preset's).
    const CameraSettings& shownCamera() const;

    QSize sizeHint() const override { return {640, 480}; }

protected:
    void paintEvent(QPaintEvent* event) override;

private:
    void rebuildRenderer();
    QRect imageArea() const;  // below the combo box

    QComboBox* previewBox_ = nullptr;
    Preview preview_ = Preview::Scene;
    std::optional<Scene> scene_;
    std::optional<Snapshot> last_;  // redrawn when the preview changes
    std::unique_ptr<CameraRenderer> renderer_;  // null when the chosen camera cannot be drawn (problem_ says why)
    QString problem_;
    cv::Mat frame_;                  // BGR, reused between renderings
    std::vector<cv::Rect> patches_;  // unused here, render() fills them
    QImage image_;
};

}  // namespace vssim
