// Bindings of incremental QEM decimation (§4.2).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/decimation/decimate.h>

#include <pybind11/stl.h>

#include <string>

namespace meshsmith::python {
namespace {

using namespace meshsmith::decimation;

CollapseOperator parse_operator(const std::string& name) {
  return parse_choice<CollapseOperator>(name, "operator",
                                        {{"edge", CollapseOperator::edge}, {"halfedge", CollapseOperator::halfedge}});
}

CollapseCost parse_cost(const std::string& name) {
  return parse_choice<CollapseCost>(name, "cost",
                                    {{"quadric", CollapseCost::quadric},
                                     {"plane_distance", CollapseCost::plane_distance},
                                     {"volume_change", CollapseCost::volume_change}});
}

/// Multiple-choice decimation draws this many edges per step at most (Wu & Kobbelt use 8): the
/// draw buffer is allocated up front.
constexpr int kMaxCandidates = 1 << 16;

/// The collapse records as arrays: removed, kept, left, right (k,) and the three positions (k, 3).
py::dict collapse_arrays(const std::vector<CollapseRecord>& records) {
  const auto k = static_cast<Eigen::Index>(records.size());
  Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> vertices(k, 4);
  VertexMatrix removed_position(k, 3), kept_before(k, 3), kept_after(k, 3);
  for (Eigen::Index i = 0; i < k; ++i) {
    const CollapseRecord& r = records[i];
    vertices.row(i) << r.removed, r.kept, r.left, r.right;
    removed_position.row(i) = r.removed_position.transpose();
    kept_before.row(i) = r.kept_position_before.transpose();
    kept_after.row(i) = r.kept_position_after.transpose();
  }
  py::dict out;
  const char* names[] = {"removed", "kept", "left", "right"};
  for (int c = 0; c < 4; ++c) out[names[c]] = indices_to_numpy(vertices.col(c)).attr("reshape")(-1);
  out["removed_position"] = to_numpy(std::move(removed_position));
  out["kept_position_before"] = to_numpy(std::move(kept_before));
  out["kept_position_after"] = to_numpy(std::move(kept_after));
  return out;
}

}  // namespace

void bind_decimation_qem(py::module_& m) {
  m.def("decimate_qem", [](const py::object& V, const py::object& F, const py::object& target_faces, double max_error,
                           const std::string& collapse, const std::string& cost, const py::object& candidates,
                           const py::object& seed, bool prevent_normal_flips, double max_normal_deviation_deg,
                           double min_triangle_quality, const py::object& max_valence, bool keep_boundary,
                           bool record_collapses, bool parallel, const py::object& callback) {
    const MeshArguments mesh(V, F);
    QemOptions options;
    options.target_faces = integer_argument<Eigen::Index>(target_faces, "target_faces", 0);
    options.max_error = max_error;
    options.collapse = parse_operator(collapse);
    options.cost = parse_cost(cost);
    options.candidates = integer_argument<int>(candidates, "candidates", 0, kMaxCandidates);
    options.seed = integer_argument<std::uint64_t>(seed, "seed");
    options.prevent_normal_flips = prevent_normal_flips;
    options.max_normal_deviation_deg = max_normal_deviation_deg;
    options.min_triangle_quality = min_triangle_quality;
    options.max_valence = integer_argument<int>(max_valence, "max_valence", 0);
    options.keep_boundary = keep_boundary;
    options.record_collapses = record_collapses;
    options.parallel = parallel;
    const Progress progress = make_progress(callback);
    QemResult result = without_gil([&] { return decimate_qem(mesh.V(), mesh.F(), options, progress); });
    py::dict report;
    report["vertex_origin"] = indices_to_numpy(result.vertex_origin).attr("reshape")(-1);
    report["max_error"] = result.max_collapse_error;
    report["max_error_normalized"] = result.max_collapse_error_normalized;
    report["max_error_exponent"] = result.max_collapse_error_exponent;
    report["target_reached"] = result.target_reached;
    report["collapse_count"] = result.collapse_count;
    report["split_vertex_origin"] = indices_to_numpy(result.split_vertex_origin).attr("reshape")(-1);
    if (record_collapses) report["collapses"] = collapse_arrays(result.collapses);
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F), report);
  }, py::arg("V"), py::arg("F"), py::arg("target_faces") = 0, py::arg("max_error") = 0.0,
     py::arg("operator") = "edge", py::arg("cost") = "quadric", py::arg("candidates") = 0, py::arg("seed") = 0,
     py::arg("prevent_normal_flips") = true, py::arg("max_normal_deviation_deg") = 0.0,
     py::arg("min_triangle_quality") = 0.0, py::arg("max_valence") = 0, py::arg("keep_boundary") = true,
     py::arg("record_collapses") = false, py::arg("parallel") = true, py::arg("progress") = py::none(),
     "Incremental QEM decimation (§4.2). Returns (V, F, report); see meshsmith.decimation.decimate.");
}

}  // namespace meshsmith::python
