#pragma once
// Binding function of the points chapter (module.cpp calls it with meshsmith._core.points).
#include <pybind11/pybind11.h>

namespace meshsmith::python {
void bind_points(pybind11::module_& m);
}  // namespace meshsmith::python
