#pragma once
// Bindings of the geometry chapter's discrete differential geometry (normals, Laplacians, mass
// matrices, curvatures, Laplacian eigenpairs); called from bind_geometry.
#include <pybind11/pybind11.h>

namespace meshsmith::python {
void bind_geometry_differential(pybind11::module_& m);
}  // namespace meshsmith::python
