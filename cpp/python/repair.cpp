// Bindings of the repair chapter: thin wrappers over meshsmith::repair (python/meshsmith/repair/
// documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/repair/orient.h>

#include <cstdint>

namespace meshsmith::python {

void bind_repair(py::module_& m) {
  m.def("orient_faces", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    auto oriented = without_gil([&] { return repair::orient_faces(mesh.V(), mesh.F()); });
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> flipped(static_cast<Eigen::Index>(oriented.flipped.size()));
    for (Eigen::Index k = 0; k < flipped.size(); ++k) flipped[k] = oriented.flipped[k];
    py::dict out;
    out["F"] = indices_to_numpy(oriented.F);
    out["flipped"] = to_numpy(std::move(flipped));
    out["components"] = oriented.components;
    out["closed_components"] = oriented.closed_components;
    out["non_orientable_components"] = oriented.non_orientable_components;
    return out;
  }, py::arg("V"), py::arg("F"));
}

}  // namespace meshsmith::python
