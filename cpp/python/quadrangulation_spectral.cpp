// Bindings of spectral Morse–Smale quadrangulation (§5.2.1).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/quadrangulation/spectral.h>

#include <string>

namespace meshsmith::python {

namespace {

using namespace meshsmith::quadrangulation;

py::dict complex_dict(MorseSmaleComplex C) {
  py::dict out;
  out["vertex_type"] = indices_to_numpy(C.vertex_type).attr("reshape")(-1);
  out["saddle_multiplicity"] = indices_to_numpy(C.saddle_multiplicity).attr("reshape")(-1);
  out["maxima"] = C.maxima;
  out["minima"] = C.minima;
  out["saddles"] = C.saddles;
  py::list lines;
  for (const auto& line : C.lines) {
    lines.append(indices_to_numpy(Eigen::Map<const Eigen::VectorXi>(line.data(), static_cast<Eigen::Index>(line.size())))
                     .attr("reshape")(-1));
  }
  out["lines"] = lines;
  py::list ascending;
  for (const char a : C.line_ascending) ascending.append(static_cast<bool>(a));
  out["line_ascending"] = ascending;
  out["detours"] = C.detours;
  out["face_patch"] = indices_to_numpy(C.face_patch).attr("reshape")(-1);
  out["patch_corners"] = indices_to_numpy(C.patch_corners);
  out["patch_sides"] = indices_to_numpy(C.patch_sides);
  out["problem"] = C.problem;
  return out;
}

}  // namespace

void bind_quadrangulation_spectral(py::module_& m) {
  m.def("morse_smale_complex", [](const py::object& V, const py::object& F, const py::object& f) {
    const MeshArguments mesh(V, F);
    const RealArray values = as_real_vector(f, "f");
    const Eigen::VectorXd function = Eigen::Map<const Eigen::VectorXd>(values.data(), values.shape(0));
    return complex_dict(without_gil([&] { return morse_smale_complex(mesh.V(), mesh.F(), function); }));
  }, py::arg("V"), py::arg("F"), py::arg("f"),
     "The Morse–Smale complex of a vertex function (§5.2.1); see meshsmith.quadrangulation.morse_smale_complex.");

  m.def("spectral_quadrangulate", [](const py::object& V, const py::object& F, const py::object& target_faces,
                                     const py::object& target_patches, const py::object& eigenvector,
                                     bool coupled, const py::object& callback) {
    const MeshArguments mesh(V, F);
    SpectralOptions options;
    options.coupled = coupled;
    if (!target_faces.is_none()) options.target_faces = integer_argument<Eigen::Index>(target_faces, "target_faces", 1, Eigen::Index(1) << 24);
    if (!target_patches.is_none()) options.target_patches = integer_argument<Eigen::Index>(target_patches, "target_patches", 1, 100000);
    if (!eigenvector.is_none())
      options.eigenvector = integer_argument<Eigen::Index>(eigenvector, "eigenvector", 1, std::max<Eigen::Index>(1, mesh.V().rows() - 2));
    const Progress progress = make_progress(callback);
    SpectralQuadrangulation r = without_gil([&] { return spectral_quadrangulate(mesh.V(), mesh.F(), options, progress); });
    py::dict out;
    out["V"] = to_numpy(std::move(r.V));
    out["Q"] = indices_to_numpy(r.Q);
    out["quad_patch"] = indices_to_numpy(r.quad_patch).attr("reshape")(-1);
    out["patch_corners"] = indices_to_numpy(r.patch_corners);
    out["eigenvector"] = r.eigenvector;
    out["eigenvalue"] = r.eigenvalue;
    out["maxima"] = r.maxima;
    out["minima"] = r.minima;
    out["saddles"] = r.saddles;
    out["multi_saddles"] = r.multi_saddles;
    out["saddle_vertices"] = r.saddle_vertices;
    out["refinements"] = r.refinements;
    out["detours"] = r.detours;
    out["gap_routes"] = r.gap_routes;
    out["candidates_tried"] = r.candidates_tried;
    out["traced_faces"] = r.traced_faces;
    out["cancelled_extrema"] = r.cancelled_extrema;
    out["simplification_rounds"] = r.simplification_rounds;
    out["cancelled_two_cell_extrema"] = r.cancelled_two_cell_extrema;
    out["two_cell_extrema"] = r.two_cell_extrema;
    out["coupled"] = r.coupled;
    out["flipped_before"] = r.flipped_before;
    out["flipped_after"] = r.flipped_after;
    out["repair_rounds"] = r.repair_rounds;
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("target_faces") = py::none(), py::arg("target_patches") = py::none(),
     py::arg("eigenvector") = py::none(), py::arg("coupled") = false, py::arg("progress") = py::none(),
     "Spectral Morse–Smale quadrangulation (§5.2.1); see meshsmith.quadrangulation.spectral_quadrangulate.");
}

}  // namespace meshsmith::python
