// Bindings of self-intersection detection (§2.4): a thin wrapper over
// meshsmith::repair::self_intersections (python/meshsmith/repair/intersections.py documents it).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/repair/self_intersections.h>

namespace meshsmith::python {

void bind_repair_intersections(py::module_& m) {
  m.def("self_intersections", [](const py::object& V, const py::object& F, const py::object& callback) {
    const MeshArguments mesh(V, F);
    const Progress progress = make_progress(callback);
    EdgeMatrix pairs = without_gil([&] { return repair::self_intersections(mesh.V(), mesh.F(), progress); });
    return indices_to_numpy(pairs);
  }, py::arg("V"), py::arg("F"), py::arg("progress") = py::none(),
     "Self-intersecting face pairs (k, 2); see meshsmith.repair.self_intersections.");
}

}  // namespace meshsmith::python
