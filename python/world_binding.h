// Defines vssim.World (and builtin_scenes) in the module.
#pragma once

#include <pybind11/pybind11.h>

namespace vssim::python {

void bindWorld(pybind11::module_& m);

}  // namespace vssim::python
