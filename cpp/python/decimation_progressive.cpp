// Bindings of progressive meshes (§4.3).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/decimation/progressive_mesh.h>

#include <string>
#include <vector>

namespace meshsmith::python {
namespace {

using decimation::ProgressiveMesh;

py::tuple mesh_to_python(Mesh&& mesh) {
  return py::make_tuple(to_numpy(std::move(mesh.V)), indices_to_numpy(mesh.F));
}

/// A level of `pm`: an integer in [0, split_count].
Eigen::Index level_argument(const ProgressiveMesh& pm, const py::object& level) {
  return integer_argument<Eigen::Index>(level, "level", 0, pm.split_count());
}

}  // namespace

void bind_decimation_progressive(py::module_& m) {
  py::class_<ProgressiveMesh>(m, "ProgressiveMesh")
      .def_property_readonly("split_count", &ProgressiveMesh::split_count)
      .def_property_readonly("level", &ProgressiveMesh::level)
      .def("face_count", [](const ProgressiveMesh& pm, const py::object& level) {
        return pm.face_count(level_argument(pm, level));
      }, py::arg("level"))
      .def("vertex_count", [](const ProgressiveMesh& pm, const py::object& level) {
        return pm.vertex_count(level_argument(pm, level));
      }, py::arg("level"))
      .def("level_for_face_count", [](const ProgressiveMesh& pm, const py::object& n_faces) {
        // The core names the range of levels; this checks that n_faces is an integer at all.
        return pm.level_for_face_count(integer_argument<Eigen::Index>(n_faces, "n_faces"));
      }, py::arg("n_faces"))
      // The current level is mutable state: these two keep the GIL (they take milliseconds), so
      // Python threads sharing one ProgressiveMesh cannot race on it.
      .def("set_level", [](ProgressiveMesh& pm, const py::object& level) { pm.set_level(level_argument(pm, level)); },
           py::arg("level"))
      .def("current_mesh", [](const ProgressiveMesh& pm) { return mesh_to_python(pm.current_mesh()); })
      .def("selective_refinement", [](const ProgressiveMesh& pm, const py::object& selected, bool whole_stars) {
        const std::vector<char> flags = as_flag_vector(selected, "selected");
        return mesh_to_python(without_gil([&] { return pm.selective_refinement(flags, whole_stars); }));
      }, py::arg("selected"), py::arg("whole_stars") = false)
      .def_property_readonly("full_positions", [](const ProgressiveMesh& pm) {
        return to_numpy(VertexMatrix(pm.full_positions()));
      })
      .def("save", [](const ProgressiveMesh& pm, const std::string& path) {
        py::gil_scoped_release release;
        decimation::save_progressive_mesh(path, pm);
      }, py::arg("path"));

  m.def("progressive_mesh_from_collapses",
        [](const py::object& V, const py::object& F, const py::object& vertices, const py::object& removed_position,
           const py::object& kept_position_before, const py::object& kept_position_after,
           const py::object& callback) {
    const MeshArguments mesh(V, F);
    const IndexArray ids = as_index_matrix(vertices, "collapse vertices", 4);
    const RealArray removed = as_real_matrix(removed_position, "removed_position", 3);
    const RealArray before = as_real_matrix(kept_position_before, "kept_position_before", 3);
    const RealArray after = as_real_matrix(kept_position_after, "kept_position_after", 3);
    const py::ssize_t k = ids.shape(0);
    if (removed.shape(0) != k || before.shape(0) != k || after.shape(0) != k)
      throw InputError("progressive mesh: the collapse arrays have different lengths");
    std::vector<decimation::CollapseRecord> records(k);
    const auto id = ids.unchecked<2>();
    const auto r = removed.unchecked<2>(), b = before.unchecked<2>(), a = after.unchecked<2>();
    for (py::ssize_t i = 0; i < k; ++i) {
      records[i].removed = id(i, 0), records[i].kept = id(i, 1), records[i].left = id(i, 2), records[i].right = id(i, 3);
      for (int c = 0; c < 3; ++c) {
        records[i].removed_position(c) = r(i, c);
        records[i].kept_position_before(c) = b(i, c);
        records[i].kept_position_after(c) = a(i, c);
      }
    }
    const Progress progress = make_progress(callback);
    return without_gil([&] { return decimation::progressive_mesh_from_collapses(mesh.V(), mesh.F(), records, progress); });
  }, py::arg("V"), py::arg("F"), py::arg("vertices"), py::arg("removed_position"),
     py::arg("kept_position_before"), py::arg("kept_position_after"), py::arg("progress") = py::none(),
     "ProgressiveMesh from collapses in the order performed: vertices (k, 4) = removed, kept, left, right.");

  m.def("load_progressive_mesh", [](const std::string& path) {
    return without_gil([&] { return decimation::load_progressive_mesh(path); });
  }, py::arg("path"));
}

}  // namespace meshsmith::python
