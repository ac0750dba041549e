#include "scene_binding.h"

#include <optional>
#include <stdexcept>
#include <string>

#include "scene_source.h"

namespace py = pybind11;

namespace vssim::python {

Scene loadScene(const py::object& scene) {
    std::string error;
    std::optional<Scene> loaded;
    if (py::isinstance<py::dict>(scene)) {
        const std::string json =
            py::module_::import("json").attr("dumps")(scene, py::arg("allow_nan") = false).cast<std::string>();
        loaded = sceneFromJson(json, &error);
    } else if (py::isinstance<py::str>(scene) || py::hasattr(scene, "__fspath__")) {
        const std::string path = py::module_::import("os").attr("fsdecode")(scene).cast<std::string>();
        loaded = sceneFromArgument(path, &error);
    } else {
        throw py::type_error("scene: expected a path, a built-in scene name or a dict, got " +
                             py::str(py::type::of(scene)).cast<std::string>());
    }
    if (!loaded) throw std::invalid_argument(error);
    return std::move(*loaded);
}

}  // namespace vssim::python
