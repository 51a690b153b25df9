// Bindings of the geometry chapter (python/meshsmith/geometry.py documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/geometry/measures.h>

namespace meshsmith::python {

void bind_geometry(py::module_& m) {
  m.def("face_areas", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    auto areas = without_gil([&] { return geometry::face_areas(mesh.V(), mesh.F()); });
    return to_numpy(std::move(areas));
  }, py::arg("V"), py::arg("F"));

  m.def("surface_area", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    return without_gil([&] { return geometry::surface_area(mesh.V(), mesh.F()); });
  }, py::arg("V"), py::arg("F"));

  m.def("volume", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    return without_gil([&] { return geometry::volume(mesh.V(), mesh.F()); });
  }, py::arg("V"), py::arg("F"));

  bind_geometry_differential(m);  // geometry_differential.cpp: normals, Laplacians, curvature
  bind_geometry_metrics(m);       // geometry_metrics.cpp: distortion, distances
}

}  // namespace meshsmith::python
