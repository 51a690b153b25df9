// Bindings of the quadrangulation chapter (§5.2.2): cross fields, singularities, the cut graph, MIQ.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/quadrangulation/cross_field.h>
#include <meshsmith/quadrangulation/cut_graph.h>
#include <meshsmith/quadrangulation/miq.h>

#include <memory>
#include <string>
#include <vector>

namespace meshsmith::python {
namespace {

using namespace meshsmith::quadrangulation;

Eigen::VectorXd as_angles(const py::object& theta) {
  const RealArray array = as_real_vector(theta, "field");
  return Eigen::Map<const Eigen::VectorXd>(array.data(), array.shape(0));
}

py::array_t<std::int64_t> int64_vector(const std::vector<int>& values) {
  return indices_to_numpy(Eigen::Map<const Eigen::VectorXi>(values.data(), static_cast<Eigen::Index>(values.size())))
      .attr("reshape")(-1);
}

py::dict field_edges_dict(const FieldEdges& edges) {
  py::dict out;
  out["edges"] = indices_to_numpy(edges.edges);
  out["edge_faces"] = indices_to_numpy(edges.faces);
  out["connection"] = to_numpy(Eigen::VectorXd(edges.connection));
  out["period_jumps"] = indices_to_numpy(edges.period_jumps).attr("reshape")(-1);
  return out;
}

py::dict cut_dict(FieldCut cut) {
  py::dict out;
  out["V"] = to_numpy(std::move(cut.cut.V));
  out["F"] = indices_to_numpy(cut.cut.F);
  out["vertex_origin"] = indices_to_numpy(cut.cut.vertex_origin).attr("reshape")(-1);
  out["seam_edges"] = indices_to_numpy(cut.cut.seam_edges);
  out["singular_vertices"] = int64_vector(cut.singularities.vertices);
  out["singular_indices"] = int64_vector(cut.singularities.indices);
  out["combed_theta"] = to_numpy(std::move(cut.combed_theta));
  out["seam_jumps"] = indices_to_numpy(cut.seam_jumps).attr("reshape")(-1);
  return out;
}

/// `with shared_field_mesh():` holds a SharedFieldMesh for the block (quadrangulate's stages).
struct SharedFieldMeshScope {
  std::unique_ptr<SharedFieldMesh> scope;
};

}  // namespace

void bind_quadrangulation(py::module_& m) {
  py::class_<SharedFieldMeshScope>(m, "shared_field_mesh")
      .def(py::init<>())
      .def("__enter__", [](SharedFieldMeshScope& self) {
        if (!self.scope) self.scope = std::make_unique<SharedFieldMesh>();
        return &self;
      }, py::return_value_policy::reference)
      .def("__exit__", [](SharedFieldMeshScope& self, const py::args&) {
        self.scope.reset();
        return false;
      });
  m.def("cross_field", [](const py::object& V, const py::object& F, const std::string& align, double sharp_angle,
                          const py::object& constraint_faces, const py::object& constraint_directions,
                          double curvature_weight, double crease_weight, const std::string& rounding,
                          const py::object& callback) {
    const MeshArguments mesh(V, F);
    CrossFieldOptions options;
    options.align = parse_choice<FieldAlignment>(align, "align", {{"curvature", FieldAlignment::curvature},
                                                                  {"smooth", FieldAlignment::smooth},
                                                                  {"boundary", FieldAlignment::boundary}});
    options.rounding = parse_choice<FieldRounding>(rounding, "rounding", {{"none", FieldRounding::none},
                                                                          {"resolve", FieldRounding::resolve},
                                                                          {"greedy", FieldRounding::greedy}});
    options.sharp_angle_degrees = sharp_angle;
    options.curvature_weight = curvature_weight;
    options.crease_weight = crease_weight;
    if (!constraint_faces.is_none()) {
      const IndexArray faces = as_index_vector(constraint_faces, "constraints (faces)");
      options.constraint_faces.assign(faces.data(), faces.data() + faces.shape(0));
      const RealArray directions = as_real_matrix(constraint_directions, "constraints (directions)", 3);
      options.constraint_directions = map_vertices(directions);
    }
    const Progress progress = make_progress(callback);
    CrossField field = without_gil([&] { return cross_field(mesh.V(), mesh.F(), options, progress); });
    py::dict out = field_edges_dict(field.edges);
    out["theta"] = to_numpy(std::move(field.theta));
    out["directions"] = to_numpy(std::move(field.directions));
    out["constrained_faces"] = field.constrained_faces;
    out["energy"] = field.energy;
    out["initial_energy"] = field.initial_energy;
    out["changed_jumps"] = field.changed_jumps;
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("align") = "curvature", py::arg("sharp_angle") = 0.0,
     py::arg("constraint_faces") = py::none(), py::arg("constraint_directions") = py::none(),
     py::arg("curvature_weight") = 1e-3, py::arg("crease_weight") = 0.2, py::arg("rounding") = "none",
     py::arg("progress") = py::none(), "A cross field (§5.2.2 step 1); see meshsmith.quadrangulation.cross_field.");

  m.def("field_angles", [](const py::object& V, const py::object& F, const py::object& directions) {
    const MeshArguments mesh(V, F);
    const RealArray d = as_real_matrix(directions, "field", 3);
    return to_numpy(without_gil([&] { return field_angles(mesh.V(), mesh.F(), map_vertices(d)); }));
  }, py::arg("V"), py::arg("F"), py::arg("directions"));

  m.def("field_edges", [](const py::object& V, const py::object& F, const py::object& theta) {
    const MeshArguments mesh(V, F);
    const Eigen::VectorXd angles = as_angles(theta);
    return field_edges_dict(without_gil([&] { return field_edges(mesh.V(), mesh.F(), angles); }));
  }, py::arg("V"), py::arg("F"), py::arg("theta"));

  m.def("resolve_angles", [](const py::object& V, const py::object& F, const py::object& theta,
                             const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& jumps,
                             const py::array_t<bool, py::array::c_style | py::array::forcecast>& held) {
    const MeshArguments mesh(V, F);
    const Eigen::VectorXd angles = as_angles(theta);
    if (jumps.ndim() != 1 || held.ndim() != 1) throw InputError("resolve_angles: jumps and held must be 1-D arrays");
    std::vector<int> jump_values(static_cast<std::size_t>(jumps.size()));
    for (py::ssize_t k = 0; k < jumps.size(); ++k) {
      const std::int64_t value = jumps.data()[k];
      if (value < -(1 << 20) || value > (1 << 20)) throw InputError("resolve_angles: a period jump is out of range");
      jump_values[static_cast<std::size_t>(k)] = static_cast<int>(value);
    }
    std::vector<char> held_values(held.data(), held.data() + held.size());
    ResolvedAngles resolved = without_gil([&] { return resolve_angles(mesh.V(), mesh.F(), angles, jump_values, held_values); });
    py::dict out;
    out["theta"] = to_numpy(std::move(resolved.theta));
    out["period_jumps"] = indices_to_numpy(resolved.period_jumps).attr("reshape")(-1);
    out["singular_vertices"] = int64_vector(resolved.singularities.vertices);
    out["singular_indices"] = int64_vector(resolved.singularities.indices);
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("theta"), py::arg("jumps"), py::arg("held"));

  m.def("singularities", [](const py::object& V, const py::object& F, const py::object& theta) {
    const MeshArguments mesh(V, F);
    const Eigen::VectorXd angles = as_angles(theta);
    const Singularities found = without_gil([&] { return singularities(mesh.V(), mesh.F(), angles); });
    return py::make_tuple(int64_vector(found.vertices), int64_vector(found.indices));
  }, py::arg("V"), py::arg("F"), py::arg("theta"));

  m.def("cut_graph", [](const py::object& V, const py::object& F, const py::object& theta) {
    const MeshArguments mesh(V, F);
    const Eigen::VectorXd angles = as_angles(theta);
    return cut_dict(without_gil([&] { return cut_graph(mesh.V(), mesh.F(), angles); }));
  }, py::arg("V"), py::arg("F"), py::arg("theta"));

  m.def("miq", [](const py::object& V, const py::object& F, const py::object& theta, double target_edge_length,
                  double target_quads, bool round_singularities, bool round_translations, const py::object& repair_iterations,
                  double stiffening, double sharp_angle, bool reround, double conformal_scale, const py::object& callback) {
    const MeshArguments mesh(V, F);
    const Eigen::VectorXd angles = as_angles(theta);
    MiqOptions options;
    options.target_edge_length = target_edge_length;
    options.target_quads = target_quads;
    options.round_singularities = round_singularities;
    options.round_translations = round_translations;
    options.repair_iterations = integer_argument<int>(repair_iterations, "repair_iterations", 0, 1000);
    options.stiffening = stiffening;
    options.sharp_angle_degrees = sharp_angle;
    options.reround = reround;
    options.conformal_scale = conformal_scale;
    const Progress progress = make_progress(callback);
    MiqResult result = without_gil([&] { return miq(mesh.V(), mesh.F(), angles, options, progress); });
    py::dict out;
    out["uv"] = to_numpy(std::move(result.uv)).attr("reshape")(-1, 3, 2);
    out["flipped_before"] = result.flipped_before;
    out["flipped_after"] = result.flipped_after;
    out["integer_variables"] = result.integer_variables;
    out["rounding_residual"] = result.rounding_residual;
    out["repair_rounds"] = result.repair_rounds;
    out["feature_edges"] = result.feature_edges;
    out["separations"] = result.separations;
    out["separation_conflicts"] = result.separation_conflicts;
    out["released_feature_edges"] = result.released_feature_edges;
    out["release_rounds"] = result.release_rounds;
    out["flipped_unconstrained"] = result.flipped_unconstrained;
    out["rerounded_integers"] = result.rerounded_integers;
    out["target_edge_length"] = result.target_edge_length;
    out["log_scale_min"] = result.log_scale_min;
    out["log_scale_max"] = result.log_scale_max;
    out["cut"] = cut_dict(std::move(result.cut));
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("theta"), py::arg("target_edge_length") = 0.0,
     py::arg("target_quads") = 0.0, py::arg("round_singularities") = true, py::arg("round_translations") = true, py::arg("repair_iterations") = 10,
     py::arg("stiffening") = 5.0, py::arg("sharp_angle") = 0.0, py::arg("reround") = true,
     py::arg("conformal_scale") = 1.0, py::arg("progress") = py::none(),
     "Mixed-integer quadrangulation parametrization (§5.2.2 step 3); see meshsmith.quadrangulation.miq.");
}

}  // namespace meshsmith::python
