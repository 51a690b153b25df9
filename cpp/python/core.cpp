// Bindings of the core chapter: validation, defects, OpenMesh conversion, build information.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/core/build_info.h>
#include <meshsmith/core/mesh.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>

#include <pybind11/stl.h>

#include <thread>

namespace meshsmith::python {

void bind_core(py::module_& m) {
  m.def("validate_mesh", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    py::gil_scoped_release release;
    validate_mesh(mesh.V(), mesh.F());
  }, py::arg("V"), py::arg("F"));

  m.def("find_mesh_defects", [](const py::object& V, const py::object& F, double area_tolerance) {
    const MeshArguments mesh(V, F);
    MeshDefects defects;
    {
      py::gil_scoped_release release;
      validate_mesh(mesh.V(), mesh.F());
      defects = find_mesh_defects(mesh.V(), mesh.F(), area_tolerance);
    }
    py::dict out;
    out["degenerate_faces"] = py::array_t<int>(defects.degenerate_faces.size(), defects.degenerate_faces.data());
    out["zero_area_faces"] = py::array_t<int>(defects.zero_area_faces.size(), defects.zero_area_faces.data());
    out["duplicate_faces"] = py::array_t<int>(defects.duplicate_faces.size(), defects.duplicate_faces.data());
    out["unreferenced_vertices"] = py::array_t<int>(defects.unreferenced_vertices.size(), defects.unreferenced_vertices.data());
    out["summary"] = defects.summary();
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("area_tolerance") = 0.0);

  m.def("trimesh_roundtrip", [](const py::object& V, const py::object& F) {
    const MeshArguments mesh(V, F);
    auto result = without_gil([&] { return from_trimesh(to_trimesh(mesh.V(), mesh.F())); });
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F));
  }, py::arg("V"), py::arg("F"),
  "Builds the OpenMesh TriMesh of (V, F) and converts it back (checks manifoldness on the way).");

  m.def("progress_loop", [](int steps, double seconds_per_step, const py::object& callback) {
    // Exercises the progress plumbing exactly as a long algorithm does: GIL released, report()
    // from the loop, Ctrl-C and cancellation honoured. Returns the number of steps completed.
    Progress progress = make_progress(callback);
    py::gil_scoped_release release;
    int done = 0;
    for (; done < steps; ++done) {
      progress.report(static_cast<double>(done) / steps, "progress_loop");
      std::this_thread::sleep_for(std::chrono::duration<double>(seconds_per_step));
    }
    progress.report(1.0, "progress_loop");
    return done;
  }, py::arg("steps"), py::arg("seconds_per_step"), py::arg("callback") = py::none());

  // The exponent of core/normalization.h's frame for Python code that normalizes itself (the
  // curves): points / 2^exponent lie in (-1, 1).
  m.def("normalizing_exponent", [](const py::array_t<double, py::array::c_style | py::array::forcecast>& X) {
    if (X.ndim() != 2) throw InputError("normalizing_exponent: expected an (n, d) array");
    const Eigen::Map<const PointMatrix> points(X.data(), X.shape(0), X.shape(1));
    return normalizing_frame(points).exponent;
  });
  m.def("version", &version);
  m.def("dependency_versions", &dependency_versions);
}

}  // namespace meshsmith::python
