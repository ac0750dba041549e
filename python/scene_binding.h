// A scene from Python: a path (str or os.PathLike), a built-in scene name,
// or a dict in the scene-file format (docs/scenes.md). Errors raise
// ValueError with the loader's message (it names the key), TypeError for
// anything else.
#pragma once

#include <pybind11/pybind11.h>

#include "vssim/scene.h"

namespace vssim::python {

Scene loadScene(const pybind11::object& scene);

}  // namespace vssim::python
