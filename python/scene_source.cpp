#include "scene_source.h"

#include "io/scene_io.h"

namespace vssim::python {

std::optional<Scene> sceneFromArgument(const std::string& argument, std::string* error) {
    const QString name = QString::fromStdString(argument);
    const QString path = resolveScenePath(name);
    if (path.isEmpty()) {
        *error = sceneNotFoundMessage(name).toStdString();
        return std::nullopt;
    }
    QString why;
    std::optional<Scene> scene = loadSceneFile(path, &why);
    if (!scene) *error = why.toStdString();
    return scene;
}

std::optional<Scene> sceneFromJson(const std::string& json, std::string* error) {
    QString why;
    std::optional<Scene> scene = parseScene(QByteArray::fromStdString(json), &why);
    if (!scene) *error = "scene: " + why.toStdString();
    return scene;
}

}  // namespace vssim::python
