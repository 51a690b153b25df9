// Bindings of quad extraction from a seamless parametrization (§5.2.2 step 4).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/quadrangulation/quad_extraction.h>

#include <pybind11/stl.h>

#include <string>

namespace meshsmith::python {

namespace {

using namespace meshsmith::quadrangulation;

/// UV: an (m, 3, 2) array-like of per-corner parameter positions, as a C-contiguous float64 array.
RealArray as_corner_uv(const py::object& object, Eigen::Index n_faces) {
  const py::array array = as_numeric_array(object, "UV", Elements::real);
  if (array.ndim() != 3 || array.shape(0) != n_faces || array.shape(1) != 3 || array.shape(2) != 2)
    throw InputError("UV must have shape (" + std::to_string(n_faces) + ", 3, 2) (one (u, v) per corner of each face), got " +
                     shape_of(array));
  return RealArray::ensure(array);
}

py::dict report_to_dict(const QuadExtractionReport& r) {
  py::dict d;
  d["flipped_triangles"] = r.flipped_triangles;
  d["degenerate_triangles"] = r.degenerate_triangles;
  d["non_seamless_edges"] = r.non_seamless_edges;
  d["non_integer_singularities"] = r.non_integer_singularities;
  d["untangled_vertices"] = r.untangled_vertices;
  d["singular_vertices"] = r.singular_vertices;
  d["singular_indices"] = r.singular_indices;
  d["squares_cut_by_boundary"] = r.squares_cut_by_boundary;
  d["squares_inconsistent"] = r.squares_inconsistent;
  d["quads_non_manifold"] = r.quads_non_manifold;
  d["euler_input"] = r.euler_input;
  d["euler_output"] = r.euler_output;
  d["mirrored"] = r.mirrored;
  d["complete"] = r.complete();
  return d;
}

}  // namespace

void bind_quadrangulation_extraction(py::module_& m) {
  m.def("extract_quads", [](const py::object& V, const py::object& F, const py::object& UV,
                            const py::object& callback) {
    const MeshArguments mesh(V, F);
    const RealArray uv = as_corner_uv(UV, mesh.F().rows());
    const Eigen::Map<const CornerUVMatrix> corners(uv.data(), 3 * mesh.F().rows(), 2);
    const Progress progress = make_progress(callback);
    QuadExtraction result = without_gil([&] { return extract_quads(mesh.V(), mesh.F(), corners, progress); });
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> node_face = result.node_face.cast<std::int64_t>();
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.Q),
                          to_numpy(std::move(result.node_uv)), to_numpy(std::move(node_face)),
                          report_to_dict(result.report));
  }, py::arg("V"), py::arg("F"), py::arg("UV"), py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
