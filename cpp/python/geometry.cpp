// Bindings of the geometry chapter (python/meshsmith/geometry.py documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/geometry/measures.h>

namespace meshsmith::python {

void bind_geometry(py::module_& m) {
  m.def("face_areas", [](const py::object& V, const py::object& F) {
    auto vertices = as_real_matrix(V, "V", 3);
    auto faces = as_index_matrix(F, "F", 3);
    Eigen::VectorXd areas;
    {
      py::gil_scoped_release release;
      areas = geometry::face_areas(map_vertices(vertices), map_faces(faces));
    }
    return to_numpy(std::move(areas));
  }, py::arg("V"), py::arg("F"));

  m.def("surface_area", [](const py::object& V, const py::object& F) {
    auto vertices = as_real_matrix(V, "V", 3);
    auto faces = as_index_matrix(F, "F", 3);
    py::gil_scoped_release release;
    return geometry::surface_area(map_vertices(vertices), map_faces(faces));
  }, py::arg("V"), py::arg("F"));

  m.def("volume", [](const py::object& V, const py::object& F) {
    auto vertices = as_real_matrix(V, "V", 3);
    auto faces = as_index_matrix(F, "F", 3);
    py::gil_scoped_release release;
    return geometry::volume(map_vertices(vertices), map_faces(faces));
  }, py::arg("V"), py::arg("F"));
}

}  // namespace meshsmith::python
