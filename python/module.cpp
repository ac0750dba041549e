// The extension module vssim._vssim, which the package vssim re-exports
// (python/vssim/__init__.py, docs/python.md).
#include <pybind11/pybind11.h>

#include "batch_binding.h"
#include "world_binding.h"

PYBIND11_MODULE(_vssim, m) {
    m.doc() = "vssim in-process: one scene as vssim.World, n of them as vssim.BatchWorld (docs/python.md)";
    m.attr("__version__") = VSSIM_VERSION;
    vssim::python::bindWorld(m);
    vssim::python::bindBatchWorld(m);
}
