// Bindings of dual-loop quad layouts (§5.3); see meshsmith.quadrangulation.dual_loop_layout.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/quadrangulation/dual_loops.h>

#include <cstdint>
#include <vector>

namespace meshsmith::python {

namespace {

using namespace meshsmith::quadrangulation;

py::array_t<std::int64_t> int64_list(const std::vector<int>& values) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(values.size()));
  auto view = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < values.size(); ++i) view(static_cast<py::ssize_t>(i)) = values[i];
  return out;
}

py::dict report_dict(const DualLoopReport& r) {
  py::dict d;
  d["loops"] = r.loops;
  d["crossings"] = r.crossings;
  d["parallel_crossings"] = r.parallel_crossings;
  d["segments"] = r.segments;
  d["regions"] = r.regions;
  d["region_euler"] = int64_list(r.region_euler);
  d["region_singularities"] = int64_list(r.region_singularities);
  d["region_corners"] = int64_list(r.region_corners);
  d["non_disk_regions"] = r.non_disk_regions;
  d["multi_singular_regions"] = r.multi_singular_regions;
  d["degenerate_quads"] = r.degenerate_quads;
  d["non_manifold_edges"] = r.non_manifold_edges;
  d["non_manifold_vertices"] = r.non_manifold_vertices;
  d["low_valence_vertices"] = r.low_valence_vertices;
  d["euler_input"] = r.euler_input;
  d["euler_layout"] = r.euler_layout;
  d["seeds_tried"] = r.seeds_tried;
  d["seeds_failed"] = r.seeds_failed;
  d["seeds_unclosed"] = r.seeds_unclosed;
  d["seeds_overlapping"] = r.seeds_overlapping;
  d["max_distance_to_loops"] = r.max_distance_to_loops;
  d["spacing"] = r.spacing;
  d["failure"] = r.failure;
  d["regions_valid"] = r.regions_valid();
  d["complete"] = r.complete();
  return d;
}

}  // namespace

void bind_quadrangulation_dual_loops(py::module_& m) {
  m.def("dual_loop_layout", [](const py::object& V, const py::object& F, const py::object& theta, double spacing,
                               double anisotropy, double max_deviation, const py::object& max_loops,
                               const py::object& max_failed_seeds, double parallel_crossing_penalty,
                               const py::object& callback) {
    const MeshArguments mesh(V, F);
    const RealArray angles = as_real_vector(theta, "field");
    const Eigen::VectorXd field = Eigen::Map<const Eigen::VectorXd>(angles.data(), angles.shape(0));
    DualLoopOptions options;
    options.spacing = spacing;
    options.anisotropy = anisotropy;
    options.max_deviation_degrees = max_deviation;
    options.max_loops = integer_argument<int>(max_loops, "max_loops", 1, 1 << 20);
    options.max_failed_seeds = integer_argument<int>(max_failed_seeds, "max_failed_seeds", 0, 1 << 24);
    options.parallel_crossing_penalty = parallel_crossing_penalty;
    const Progress progress = make_progress(callback);
    DualLoopLayout layout = without_gil([&] { return dual_loop_layout(mesh.V(), mesh.F(), field, options, progress); });
    py::list loops, crossings;
    py::list lengths, seeds;
    for (const DualLoop& loop : layout.loops) {
      loops.append(int64_list(loop.vertices));
      crossings.append(int64_list(loop.crossings));
      lengths.append(loop.length);
      seeds.append(loop.seed);
    }
    py::dict out;
    out["loops"] = loops;
    out["loop_crossings"] = crossings;
    out["loop_lengths"] = lengths;
    out["loop_seeds"] = seeds;
    out["region"] = indices_to_numpy(layout.region).attr("reshape")(-1);
    out["Vq"] = to_numpy(std::move(layout.Vq));
    out["Vq_vertex"] = indices_to_numpy(layout.Vq_vertex).attr("reshape")(-1);
    out["Q"] = indices_to_numpy(layout.Q);
    out["Q_vertex"] = indices_to_numpy(layout.Q_vertex).attr("reshape")(-1);
    out["singular_vertices"] = int64_list(layout.singularities.vertices);
    out["singular_indices"] = int64_list(layout.singularities.indices);
    out["report"] = report_dict(layout.report);
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("theta"), py::arg("spacing") = 0.0, py::arg("anisotropy") = 4.0,
     py::arg("max_deviation") = 70.0, py::arg("max_loops") = 300, py::arg("max_failed_seeds") = 2000,
     py::arg("parallel_crossing_penalty") = -1.0,
     py::arg("progress") = py::none(),
     "Dual-loop quad layout (§5.3); see meshsmith.quadrangulation.dual_loop_layout.");
}

}  // namespace meshsmith::python
