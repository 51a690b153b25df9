// Bindings of the topology chapter: thin wrappers over meshsmith::topology (python/meshsmith/topology.py
// documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/topology/boundary.h>
#include <meshsmith/topology/characteristics.h>
#include <meshsmith/topology/components.h>
#include <meshsmith/topology/edge_incidence.h>
#include <meshsmith/topology/manifold.h>

#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <string>

namespace meshsmith::python {

namespace {

using Int64Vector = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>;

template <typename Container>
py::array_t<std::int64_t> int64_vector(const Container& values) {
  Int64Vector out(static_cast<Eigen::Index>(values.size()));
  for (Eigen::Index k = 0; k < out.size(); ++k) out[k] = values[k];
  return to_numpy(std::move(out));
}

/// None → -1 ("max index + 1" in the core); otherwise a non-negative integer.
Eigen::Index vertex_count_argument(const py::object& n_vertices) {
  if (n_vertices.is_none()) return -1;
  return integer_argument<Eigen::Index>(n_vertices, "n_vertices", 0, std::numeric_limits<int>::max());
}

}  // namespace

void bind_topology(py::module_& m) {
  m.def("edges", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    auto result = without_gil([&] { return topology::edges(map_faces(faces)); });
    return indices_to_numpy(result);
  }, py::arg("F"));

  m.def("boundary_loops", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    auto loops = without_gil([&] { return topology::boundary_loops(map_faces(faces)); });
    py::list out;
    for (const auto& loop : loops) out.append(int64_vector(loop));
    return out;
  }, py::arg("F"));

  m.def("connected_components", [](const py::object& F, const py::object& n_vertices,
                                    const std::string& connectivity) {
    auto faces = as_index_matrix(F, "F", 3);
    const Eigen::Index n = vertex_count_argument(n_vertices);
    if (connectivity != "vertex" && connectivity != "edge")
      throw InputError("connectivity must be 'vertex' or 'edge', got '" + connectivity + "'");
    const auto joined_by = connectivity == "edge" ? topology::Connectivity::Edge : topology::Connectivity::Vertex;
    auto components = without_gil([&] { return topology::connected_components(map_faces(faces), n, joined_by); });
    return py::make_tuple(components.count, int64_vector(components.face_labels),
                          int64_vector(components.vertex_labels));
  }, py::arg("F"), py::arg("n_vertices") = py::none(), py::arg("connectivity") = "vertex");

  m.def("euler_characteristic", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    return without_gil([&] { return topology::euler_characteristic(map_faces(faces)); });
  }, py::arg("F"));

  m.def("genus_per_component", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    auto genera = without_gil([&] { return topology::genus_per_component(map_faces(faces)); });
    return int64_vector(genera);
  }, py::arg("F"));

  m.def("non_manifold_edges", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    auto result = without_gil([&] { return topology::non_manifold_edges(map_faces(faces)); });
    return indices_to_numpy(result);
  }, py::arg("F"));

  m.def("non_manifold_vertices", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    auto result = without_gil([&] { return topology::non_manifold_vertices(map_faces(faces)); });
    return int64_vector(result);
  }, py::arg("F"));

  m.def("is_manifold", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    return without_gil([&] { return topology::is_manifold(map_faces(faces)); });
  }, py::arg("F"));

  m.def("is_oriented", [](const py::object& F) {
    auto faces = as_index_matrix(F, "F", 3);
    return without_gil([&] { return topology::is_oriented(map_faces(faces)); });
  }, py::arg("F"));

  m.def("split_non_manifold_vertices", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    auto split = without_gil([&] { return topology::split_non_manifold_vertices(mesh.V(), mesh.F()); });
    return py::make_tuple(to_numpy(std::move(split.V)), indices_to_numpy(split.F),
                          int64_vector(split.origin));
  }, py::arg("V"), py::arg("F"));

  m.def("mesh_info", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    auto info = without_gil([&] { return topology::mesh_info(mesh.V(), mesh.F()); });
    py::dict out;
    out["n_vertices"] = info.n_vertices;
    out["n_faces"] = info.n_faces;
    out["n_edges"] = info.n_edges;
    out["n_components"] = info.n_components;
    out["n_boundary_loops"] = info.n_boundary_loops;
    out["n_boundary_edges"] = info.n_boundary_edges;
    out["euler_characteristic"] = info.euler_characteristic;
    out["genus"] = info.genus ? py::object(py::int_(*info.genus)) : py::object(py::none());
    out["is_manifold"] = info.is_manifold;
    out["is_oriented"] = info.is_oriented;
    out["n_non_manifold_edges"] = info.n_non_manifold_edges;
    out["n_non_manifold_vertices"] = info.n_non_manifold_vertices;
    out["n_unreferenced_vertices"] = info.n_unreferenced_vertices;
    return out;
  }, py::arg("V"), py::arg("F"));
}

}  // namespace meshsmith::python
