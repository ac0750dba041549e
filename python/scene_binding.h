// A scene from Python: a path (str or os.PathLike), a built-in scene name,
// or a dict in the scene-file format (docs/scenes.md). Errors raise
// ValueError with the loader's message (it names the key), TypeError for
// anything else.
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>

#include "vssim/scene.h"

namespace vssim::python {

Scene loadScene(const pybind11::object& scene);

// A world's seed from Python: a whole number 0 to 2^64 - 1 (a Python or numpy
// int). ValueError for a negative or too large one, TypeError for anything
// else (a bool or a float included).
std::uint64_t seedArgument(const pybind11::object& seed);

}  // namespace vssim::python
