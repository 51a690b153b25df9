// Bindings of the core chapter: validation, defects, OpenMesh conversion, build information.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/core/build_info.h>
#include <meshsmith/core/mesh.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>

#include <pybind11/stl.h>

#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

namespace meshsmith::python {

namespace {

/// The process-wide cap on TBB's worker threads (DESIGN.md, "Threads"): MESHSMITH_NUM_THREADS or
/// meshsmith.core.set_num_threads. A per-call `threads=` adds its own global_control; TBB obeys the
/// smallest active one, so a call can only lower the cap. Never destroyed (TBB may be gone at exit).
tbb::global_control* process_thread_cap = nullptr;

}  // namespace

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

  m.def("progress_loop", [](const py::object& steps_in, double seconds_per_step, const py::object& callback) {
    const int steps = integer_argument<int>(steps_in, "steps", 0);
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

  // The argument conversions of the bindings, for the checks the Python modules make themselves
  // (meshsmith._arguments): one rule, one set of messages.
  m.def("numeric_array", [](const py::object& value, const std::string& name, const std::string& elements) {
    return as_numeric_array(value, name.c_str(),
                            parse_choice<Elements>(elements, "elements", {{"real", Elements::real},
                                                                          {"index", Elements::index},
                                                                          {"flag", Elements::flag}}));
  }, py::arg("value"), py::arg("name"), py::arg("elements"),
  "value as a numpy array of any shape whose dtype is `elements` ('real', 'index' or 'flag'), not converted.");
  m.def("real_array", [](const py::object& value, const std::string& name, const py::object& columns) -> py::array {
    if (columns.is_none()) return as_real_vector(value, name.c_str());
    const auto pair = py::isinstance<py::tuple>(columns) ? columns.cast<std::pair<Eigen::Index, Eigen::Index>>()
                                                         : std::pair{columns.cast<Eigen::Index>(), columns.cast<Eigen::Index>()};
    return as_real_matrix(value, name.c_str(), pair.first, pair.second);
  }, py::arg("value"), py::arg("name"), py::arg("columns") = py::none(),
  "float64 C-contiguous array of shape (n,) (columns None), (n, columns) or (n, a) / (n, b) (columns (a, b)).");
  m.def("index_array", [](const py::object& value, const std::string& name, const py::object& columns) -> py::array {
    if (columns.is_none()) return as_index_vector(value, name.c_str());
    return as_index_matrix(value, name.c_str(), columns.cast<Eigen::Index>());
  }, py::arg("value"), py::arg("name"), py::arg("columns") = py::none(),
  "int32 C-contiguous array of shape (n,) (columns None) or (n, columns).");
  m.def("flag_array", [](const py::object& value, const std::string& name) {
    const std::vector<char> flags = as_flag_vector(value, name.c_str());
    py::array_t<bool> out(static_cast<py::ssize_t>(flags.size()));
    std::copy(flags.begin(), flags.end(), out.mutable_data());
    return out;
  }, py::arg("value"), py::arg("name"), "bool array of shape (n,).");
  m.def("integer_option", [](const py::object& value, const std::string& name, const py::int_& minimum,
                             const py::int_& maximum) {
    return detail::checked_integer(value, name.c_str(), minimum, maximum);
  }, py::arg("value"), py::arg("name"), py::arg("minimum"), py::arg("maximum"),
  "value as an int in [minimum, maximum]; InputError naming `name` and the range otherwise.");

  m.def("check_progress", [](const py::object& callback) { make_progress(callback); }, py::arg("callback"),
        "InputError unless callback is None or callable (as every binding's progress argument).");

  // The exponent of core/normalization.h's frame for Python code that normalizes itself (the
  // curves): points / 2^exponent lie in (-1, 1).
  m.def("normalizing_exponent", [](const py::array_t<double, py::array::c_style | py::array::forcecast>& X) {
    if (X.ndim() != 2) throw InputError("normalizing_exponent: expected an (n, d) array");
    const Eigen::Map<const PointMatrix> points(X.data(), X.shape(0), X.shape(1));
    return normalizing_frame(points).exponent;
  });
  m.def("set_thread_limit", [](const py::object& count) {
    const int limit = count.is_none() ? 0 : integer_argument<int>(count, "count", 1, 65536);
    delete process_thread_cap;
    process_thread_cap = nullptr;
    if (limit > 0)
      process_thread_cap = new tbb::global_control(tbb::global_control::max_allowed_parallelism,
                                                   static_cast<std::size_t>(limit));
  }, py::arg("count"), "Cap TBB's threads at count (None: no cap). InputError unless 1 <= count <= 65536.");
  m.def("thread_limit", [] {
    return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  }, "The number of threads meshsmith's parallel loops may use now.");
  m.def("version", &version);
  m.def("dependency_versions", &dependency_versions);
}

}  // namespace meshsmith::python
