#include "scene_binding.h"

#include <limits>
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

std::uint64_t seedArgument(const py::object& seed) {
    const py::object operator_ = py::module_::import("operator");
    if (py::isinstance<py::bool_>(seed) || !py::hasattr(seed, "__index__"))
        throw py::type_error("seed: expected a whole number >= 0, got " + py::str(py::type::of(seed)).cast<std::string>());
    const py::object value = operator_.attr("index")(seed);
    const py::object largest = py::int_(std::numeric_limits<std::uint64_t>::max());
    if (operator_.attr("lt")(value, py::int_(0)).cast<bool>() || operator_.attr("gt")(value, largest).cast<bool>())
        throw std::invalid_argument("seed: expected a whole number from 0 to 2^64 - 1, got " +
                                    py::repr(value).cast<std::string>());
    return value.cast<std::uint64_t>();
}

}  // namespace vssim::python
