// Bindings of volumetric repair (§2.4.2): a thin wrapper over meshsmith::repair::volumetric_repair
// (python/meshsmith/repair/volumetric.py documents it for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/repair/volumetric.h>

#include <cstdint>

namespace meshsmith::python {

void bind_repair_volumetric(py::module_& m) {
  m.def("volumetric_repair", [](const py::object& V, const py::object& F, double epsilon, double rho,
                                const py::object& smoothing, const py::object& max_cells, bool dense,
                                double adaptive_error, const py::object& callback) {
    const MeshArguments mesh(V, F);
    repair::VolumetricOptions options;
    options.epsilon = epsilon;
    options.rho = rho;
    options.smoothing = integer_argument<int>(smoothing, "smoothing", 0);
    options.max_cells = integer_argument<std::int64_t>(max_cells, "max_cells", 1);
    options.dense = dense;
    options.adaptive_error = adaptive_error;
    const Progress progress = make_progress(callback);
    auto result = without_gil([&] { return repair::volumetric_repair(mesh.V(), mesh.F(), options, progress); });
    const auto& r = result.report;
    py::dict report;
    report["shape"] = py::make_tuple(r.shape[0], r.shape[1], r.shape[2]);
    report["cell_size"] = r.cell_size;
    report["dense_cells"] = r.dense_cells;
    report["stored_cells"] = r.stored_cells;
    report["occupied_cells"] = r.occupied_cells;
    report["inside_cells"] = r.inside_cells;
    report["closing_cells"] = r.closing_cells;
    report["manifold_cells"] = r.manifold_cells;
    report["sharp_vertices"] = r.sharp_vertices;
    report["unconstrained_vertices"] = r.unconstrained_vertices;
    report["untangled_vertices"] = r.untangled_vertices;
    report["fine_faces"] = r.fine_faces;
    report["adaptive_bound"] = r.adaptive_bound;
    report["adaptive_max_error"] = r.adaptive_max_error;
    report["adaptive_retries"] = r.adaptive_retries;
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F), report);
  }, py::arg("V"), py::arg("F"), py::arg("epsilon"), py::arg("rho") = 0.0, py::arg("smoothing") = 3,
     py::arg("max_cells") = std::int64_t(1) << 25, py::arg("dense") = false,
     py::arg("adaptive_error") = 0.0, py::arg("progress") = py::none(),
     "Volumetric repair (§2.4.2). Returns (V, F, report); see meshsmith.repair.volumetric_repair.");
}

}  // namespace meshsmith::python
