// Bindings of boundary maps, harmonic/Tutte, stretch-minimizing, LSCM, cut to disk (§5.1.1–5.1.2).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/core/validation.h>
#include <meshsmith/parametrization/bijectivity.h>
#include <meshsmith/parametrization/boundary_map.h>
#include <meshsmith/parametrization/cut_to_disk.h>
#include <meshsmith/parametrization/harmonic.h>
#include <meshsmith/parametrization/lscm.h>
#include <meshsmith/parametrization/stretch.h>

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace meshsmith::python {

namespace {

using geometry::ParameterMatrix;
using namespace meshsmith::parametrization;

/// A 1-D array-like of vertex indices → std::vector<int> (dtype and range checks as for F).
std::vector<int> as_indices(const py::object& object, const char* name) {
  const IndexArray indices = as_index_vector(object, name);
  return std::vector<int>(indices.data(), indices.data() + indices.shape(0));
}

/// An (n, 2) array-like of parameter positions, copied.
ParameterMatrix as_parameters(const py::object& object, const char* name) {
  const auto array = as_real_matrix(object, name, 2);
  return Eigen::Map<const ParameterMatrix>(array.data(), array.shape(0), 2);
}

BoundaryShape parse_shape(const std::string& name) {
  return parse_choice<BoundaryShape>(name, "shape", {{"circle", BoundaryShape::circle}, {"square", BoundaryShape::square}});
}

HarmonicWeights parse_weights(const std::string& name) {
  return parse_choice<HarmonicWeights>(name, "weights",
                                       {{"uniform", HarmonicWeights::uniform},
                                        {"cotan", HarmonicWeights::cotan},
                                        {"mean_value", HarmonicWeights::mean_value}});
}

py::array_t<std::int64_t> vector_to_int64(const std::vector<int>& values) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

/// The boundary map the Python arguments describe: the longest loop on `shape` (boundary None),
/// the given loop on `shape` (boundary_uv None), or the given positions.
BoundaryMap boundary_from_arguments(const MeshArguments& mesh, const py::object& boundary,
                                    const py::object& boundary_uv, BoundaryShape shape) {
  if (boundary.is_none()) {
    if (!boundary_uv.is_none()) throw InputError("boundary_uv is given without boundary");
    return without_gil([&] { return map_boundary(mesh.V(), mesh.F(), shape); });
  }
  const std::vector<int> indices = as_indices(boundary, "boundary");
  if (boundary_uv.is_none()) {
    return without_gil([&] {
      validate_mesh(mesh.V(), mesh.F());  // map_boundary_loop reads V only; (V, F) is the argument
      return map_boundary_loop(mesh.V(), indices, shape);
    });
  }
  return BoundaryMap{indices, as_parameters(boundary_uv, "boundary_uv")};
}

}  // namespace

void bind_parametrization_maps(py::module_& m) {
  m.def("map_boundary", [](const py::object& V, const py::object& F, const std::string& shape,
                           const py::object& boundary) {
    const MeshArguments mesh(V, F);
    BoundaryMap map = boundary_from_arguments(mesh, boundary, py::none(), parse_shape(shape));
    return py::make_tuple(vector_to_int64(map.indices), to_numpy(std::move(map.uv)));
  }, py::arg("V"), py::arg("F"), py::arg("shape") = "circle", py::arg("boundary") = py::none());

  m.def("harmonic", [](const py::object& V, const py::object& F, const py::object& boundary,
                       const py::object& boundary_uv, const std::string& weights, const std::string& shape) {
    const MeshArguments mesh(V, F);
    const HarmonicWeights w = parse_weights(weights);
    const BoundaryShape s = parse_shape(shape);
    if (boundary.is_none() && boundary_uv.is_none()) {
      return to_numpy(without_gil([&] { return harmonic(mesh.V(), mesh.F(), HarmonicOptions{w, s}); }));
    }
    const BoundaryMap map = boundary_from_arguments(mesh, boundary, boundary_uv, s);
    return to_numpy(without_gil([&] { return harmonic(mesh.V(), mesh.F(), map, w); }));
  }, py::arg("V"), py::arg("F"), py::arg("boundary") = py::none(), py::arg("boundary_uv") = py::none(),
     py::arg("weights") = "uniform", py::arg("shape") = "circle");

  m.def("stretch_minimizing", [](const py::object& V, const py::object& F, const py::object& iterations,
                                 const std::string& weights,
                                 const std::string& shape, const py::object& callback) {
    const MeshArguments mesh(V, F);
    const StretchOptions options{integer_argument<int>(iterations, "iterations", 0, 1 << 20), parse_weights(weights),
                                 parse_shape(shape)};
    Progress progress = make_progress(callback);
    StretchResult result = without_gil([&] { return stretch_minimizing(mesh.V(), mesh.F(), options, progress); });
    py::dict out;
    out["uv"] = to_numpy(std::move(result.uv));
    out["stretch"] = py::array_t<double>(static_cast<py::ssize_t>(result.stretch.size()), result.stretch.data());
    out["best_iteration"] = result.best_iteration;
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("iterations") = 10, py::arg("weights") = "mean_value",
     py::arg("shape") = "circle", py::arg("progress") = py::none());

  m.def("lscm", [](const py::object& V, const py::object& F, const py::object& pinned, const py::object& pinned_uv) {
    const MeshArguments mesh(V, F);
    if (pinned.is_none() != pinned_uv.is_none()) throw InputError("give both pinned and pinned_uv, or neither");
    if (pinned.is_none()) return to_numpy(without_gil([&] { return lscm(mesh.V(), mesh.F()); }));
    const PinnedVertices pins{as_indices(pinned, "pinned"), as_parameters(pinned_uv, "pinned_uv")};
    return to_numpy(without_gil([&] { return lscm(mesh.V(), mesh.F(), pins); }));
  }, py::arg("V"), py::arg("F"), py::arg("pinned") = py::none(), py::arg("pinned_uv") = py::none());

  m.def("default_lscm_pins", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    PinnedVertices pins = without_gil([&] { return default_lscm_pins(mesh.V(), mesh.F()); });
    return py::make_tuple(vector_to_int64(pins.indices), to_numpy(std::move(pins.uv)));
  }, py::arg("V"), py::arg("F"));

  m.def("lscm_spectral", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    return to_numpy(without_gil([&] { return lscm_spectral(mesh.V(), mesh.F()); }));
  }, py::arg("V"), py::arg("F"));

  m.def("cut_to_disk", [](const py::object& V, const py::object& F, const py::object& through) {
    const MeshArguments mesh(V, F);
    const std::vector<int> vertices = through.is_none() ? std::vector<int>{} : as_indices(through, "through");
    CutMesh cut = without_gil([&] { return cut_to_disk(mesh.V(), mesh.F(), vertices); });
    py::dict out;
    out["V"] = to_numpy(std::move(cut.V));
    out["F"] = indices_to_numpy(cut.F);
    out["vertex_origin"] = indices_to_numpy(cut.vertex_origin).attr("reshape")(-1);
    out["seam_edges"] = indices_to_numpy(cut.seam_edges);
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("through") = py::none());

  m.def("check_bijectivity", [](const py::object& UV, const py::object& F) {
    const ParameterMatrix uv = as_parameters(UV, "UV");
    const auto faces = as_index_matrix(F, "F", 3);
    const auto report = without_gil([&] { return check_bijectivity(uv, map_faces(faces)); });
    py::dict out;
    out["bijective"] = report.bijective;
    out["orientation"] = report.orientation;
    out["degenerate_faces"] = vector_to_int64(report.degenerate_faces);
    out["flipped_faces"] = vector_to_int64(report.minority_faces);
    std::vector<int> crossing;
    for (const auto& [s, t] : report.crossing_boundary_edges) crossing.push_back(s), crossing.push_back(t);
    out["crossing_boundary_sides"] = vector_to_int64(crossing).attr("reshape")(-1, 2);
    return out;
  }, py::arg("UV"), py::arg("F"));
}

}  // namespace meshsmith::python
