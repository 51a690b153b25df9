// Bindings of vertex clustering (§4.1).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/decimation/clustering.h>

#include <string>

namespace meshsmith::python {
namespace {

decimation::ClusterRepresentative parse_representative(const std::string& name) {
  using decimation::ClusterRepresentative;
  return parse_choice<ClusterRepresentative>(name, "representative",
                                             {{"center", ClusterRepresentative::cell_center},
                                              {"centroid", ClusterRepresentative::centroid},
                                              {"median", ClusterRepresentative::median},
                                              {"quadric", ClusterRepresentative::quadric}});
}

}  // namespace

void bind_decimation_clustering(py::module_& m) {
  m.def("cluster_vertices", [](const py::object& V, const py::object& F, double cell_size,
                               const std::string& representative, const py::object& callback) {
    const MeshArguments mesh(V, F);
    decimation::ClusteringOptions options;
    options.cell_size = cell_size;
    options.representative = parse_representative(representative);
    Progress progress = make_progress(callback);
    auto result = without_gil([&] { return decimation::cluster_vertices(mesh.V(), mesh.F(), options, progress); });
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F),
                          indices_to_numpy(result.vertex_cluster), result.is_manifold, result.cell_size);
  }, py::arg("V"), py::arg("F"), py::arg("cell_size"), py::arg("representative"),
     py::arg("progress") = py::none(),
     "(V, F, vertex_cluster, is_manifold, cell_size) of vertex clustering on a uniform grid (§4.1).");

  m.def("cell_size_for_vertex_count", [](const py::object& V, const py::object& F, const py::object& target_in) {
    const MeshArguments mesh(V, F);
    const auto target = integer_argument<Eigen::Index>(target_in, "target_vertices", 1);
    return without_gil([&] { return decimation::cell_size_for_vertex_count(mesh.V(), mesh.F(), target); });
  }, py::arg("V"), py::arg("F"), py::arg("target_vertices"));

  m.def("occupied_cell_count", [](const py::object& V, const py::object& F, double cell_size) {
    const MeshArguments mesh(V, F);
    return without_gil([&] { return decimation::occupied_cell_count(mesh.V(), mesh.F(), cell_size); });
  }, py::arg("V"), py::arg("F"), py::arg("cell_size"));
}

}  // namespace meshsmith::python
