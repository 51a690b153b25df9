// Bindings of needle and cap removal (§2.4): a thin wrapper over
// meshsmith::repair::remove_needles_and_caps (python/meshsmith/repair/degenerate.py documents it).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/repair/degenerate_triangles.h>

#include <cstdint>

namespace meshsmith::python {

void bind_repair_degenerate(py::module_& m) {
  m.def("remove_needles_and_caps", [](const py::object& V, const py::object& F, double needle_ratio, double cap_angle,
                                      const py::object& max_passes) {
    const MeshArguments mesh(V, F);
    repair::NeedleCapOptions options;
    options.needle_ratio = needle_ratio;
    options.cap_angle = cap_angle;
    options.max_passes = integer_argument<int>(max_passes, "max_passes", 0, 1 << 20);
    auto result = without_gil([&] { return repair::remove_needles_and_caps(mesh.V(), mesh.F(), options); });
    auto as_array = [](const std::vector<int>& values) {
      Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> out(static_cast<Eigen::Index>(values.size()));
      for (std::size_t k = 0; k < values.size(); ++k) out[static_cast<Eigen::Index>(k)] = values[k];
      return to_numpy(std::move(out));
    };
    py::dict out;
    out["V"] = to_numpy(std::move(result.V));
    out["F"] = indices_to_numpy(result.F);
    out["vertex_map"] = as_array(result.vertex_map);
    out["face_map"] = as_array(result.face_map);
    out["collapses"] = result.collapses;
    out["flips"] = result.flips;
    out["remaining_needles"] = result.remaining_needles;
    out["remaining_caps"] = result.remaining_caps;
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("needle_ratio") = 10.0, py::arg("cap_angle") = 160.0,
     py::arg("max_passes") = 10, "Needle collapses and cap flips; see meshsmith.repair.remove_needles_and_caps.");
}

}  // namespace meshsmith::python
