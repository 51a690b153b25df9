// Bindings of the smoothing chapter's fairing (python/meshsmith/smoothing/fairing.py documents it).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/smoothing/fairing.h>

#include <vector>

namespace meshsmith::python {

void bind_smoothing_fairing(py::module_& m) {
  m.def("bilaplacian", [](const py::object& V, const py::object& F, const py::object& fixed) {
    const MeshArguments mesh(V, F);
    const IndexArray indices = as_index_vector(fixed, "fixed");
    const std::vector<int> held(indices.data(), indices.data() + indices.shape(0));
    return to_numpy(without_gil([&] { return smoothing::bilaplacian(mesh.V(), mesh.F(), held); }));
  }, py::arg("V"), py::arg("F"), py::arg("fixed"));
}

}  // namespace meshsmith::python
