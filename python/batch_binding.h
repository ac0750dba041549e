// vssim.BatchWorld: batch/ (n independent worlds on a pool of threads) for
// Python, with inputs and results as (n, ...) numpy arrays (docs/python.md).
#pragma once

#include <pybind11/pybind11.h>

namespace vssim::python {

void bindBatchWorld(pybind11::module_& m);

}  // namespace vssim::python
