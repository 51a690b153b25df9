// Bindings of graph-cut reconstruction and its Boykov–Kolmogorov max-flow (§2.2, §3.2).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/reconstruction/graph_cut.h>

#include <string>

namespace meshsmith::python {

void bind_reconstruction_graph_cut(py::module_& m) {
  m.def("max_flow", [](const py::object& node_count, const py::object& edges_in, const py::object& forward_in,
                       const py::object& backward_in, const py::object& source_in, const py::object& sink_in) {
    const auto n = integer_argument<std::int64_t>(node_count, "node_count", 0, std::int64_t(1) << 31);
    auto edges = as_index_matrix(edges_in, "edges", 2);
    auto forward = as_real_vector(forward_in, "capacities");
    auto backward = as_real_vector(backward_in, "reverse_capacities");
    auto source = as_real_vector(source_in, "source");
    auto sink = as_real_vector(sink_in, "sink");
    const Eigen::Index m_edges = edges.shape(0);
    if (forward.shape(0) != m_edges || backward.shape(0) != m_edges)
      throw InputError("capacities and reverse_capacities need one value per edge (" + std::to_string(m_edges) +
                       "), got " + shape_of(forward) + " and " + shape_of(backward));
    if (source.shape(0) != n || sink.shape(0) != n)
      throw InputError("source and sink need one value per node (" + std::to_string(n) + "), got " +
                       shape_of(source) + " and " + shape_of(sink));
    reconstruction::MaxFlow graph(n, m_edges);
    for (Eigen::Index e = 0; e < m_edges; ++e) graph.add_edge(edges.at(e, 0), edges.at(e, 1), forward.at(e), backward.at(e));
    for (std::int64_t u = 0; u < n; ++u) graph.add_terminal(u, source.at(u), sink.at(u));
    const double flow = without_gil([&] { return graph.solve(); });
    py::array_t<bool> side(static_cast<py::ssize_t>(n));
    auto view = side.mutable_unchecked<1>();
    for (std::int64_t u = 0; u < n; ++u) view(u) = graph.source_side(u);
    return py::make_tuple(flow, side);
  }, py::arg("node_count"), py::arg("edges"), py::arg("capacities"), py::arg("reverse_capacities"),
     py::arg("source"), py::arg("sink"));

  m.def("graph_cut", [](const py::object& P, const py::object& resolution, double crust, double exponent,
                        const py::object& inside, const py::object& callback) {
    auto samples = as_real_matrix(P, "P", 3);
    reconstruction::GraphCutOptions options;
    options.resolution = integer_argument<int>(resolution, "resolution", 2, 1024);
    options.crust = crust;
    options.exponent = exponent;
    if (!inside.is_none()) {
      auto seeds = as_real_matrix(inside, "inside", 3);
      if (seeds.shape(0) == 0) throw InputError("inside has no rows: expected at least one seed position, or None");
      options.inside = map_vertices(seeds);
    }
    Progress progress = make_progress(callback);
    auto result = without_gil([&] { return reconstruction::graph_cut(map_vertices(samples), options, progress); });
    py::dict out;
    out["V"] = to_numpy(std::move(result.V));
    out["F"] = indices_to_numpy(result.F);
    out["shape"] = py::make_tuple(result.shape[0], result.shape[1], result.shape[2]);
    out["origin"] = py::make_tuple(result.origin[0], result.origin[1], result.origin[2]);
    out["voxel_size"] = result.voxel_size;
    out["cut"] = result.cut;
    out["free_voxels"] = result.free_voxels;
    out["inside_voxels"] = result.inside_voxels;
    return out;
  }, py::arg("P"), py::arg("resolution"), py::arg("crust"), py::arg("exponent"), py::arg("inside"),
     py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
