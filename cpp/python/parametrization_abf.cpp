// Bindings of ABF and ABF++ (§5.1.3) and the angle-based layout.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/parametrization/abf.h>
#include <meshsmith/parametrization/angle_reconstruction.h>

#include <pybind11/stl.h>

#include <string>

namespace meshsmith::python {

namespace {

parametrization::AbfMethod abf_method(const std::string& name) {
  if (name == "abf++") return parametrization::AbfMethod::AbfPlusPlus;
  if (name == "abf") return parametrization::AbfMethod::Abf;
  throw InputError("abf: unknown method '" + name + "': expected 'abf++' or 'abf'");
}

}  // namespace

void bind_parametrization_abf(py::module_& m) {
  m.def("abf", [](const py::object& V, const py::object& F, const std::string& method, const py::object& max_iterations,
                  double tolerance, double minimum_angle, const py::object& callback) {
    const MeshArguments mesh(V, F);
    parametrization::AbfOptions options;
    options.method = abf_method(method);
    options.max_iterations = integer_argument<int>(max_iterations, "max_iterations", 0, 1 << 20);
    options.tolerance = tolerance;
    options.minimum_angle = minimum_angle;
    const Progress progress = make_progress(callback);
    auto result = without_gil([&] { return parametrization::abf(mesh.V(), mesh.F(), options, progress); });
    py::dict out;
    out["uv"] = to_numpy(std::move(result.uv));
    out["angles"] = to_numpy(std::move(result.angles));
    out["optimal_angles"] = to_numpy(std::move(result.optimal_angles));
    out["iterations"] = result.iterations;
    out["residual"] = result.residual;
    out["residual_history"] = to_numpy(Eigen::VectorXd(
        Eigen::Map<const Eigen::VectorXd>(result.residual_history.data(), result.residual_history.size())));
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("method") = "abf++", py::arg("max_iterations") = 30,
     py::arg("tolerance") = 1e-8, py::arg("minimum_angle") = 1e-4, py::arg("progress") = py::none());

  m.def("uv_from_angles", [](const py::object& F, const py::object& angles, const py::object& n_vertices_in,
                             const py::object& pinned, const py::object& pinned_uv) {
    const auto faces = as_index_matrix(F, "F", 3);
    const auto corner_angles = as_real_matrix(angles, "angles", 3);
    const auto face_view = map_faces(faces);
    if (face_view.rows() == 0) throw InputError("uv_from_angles: F is empty");
    const Eigen::Index n_vertices = n_vertices_in.is_none()
                                        ? Eigen::Index(face_view.maxCoeff()) + 1
                                        : integer_argument<Eigen::Index>(n_vertices_in, "n_vertices", 1,
                                                                         3 * face_view.rows());  // all used
    parametrization::AnglePins pins;  // default: the first edge of face 0, on (0, 0)–(1, 0)
    pins.vertices = {face_view(0, 0), face_view(0, 1)};
    pins.positions = {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 0.0)};
    if (!pinned.is_none()) {
      const auto pin_indices = as_index_vector(pinned, "pinned");
      if (pin_indices.shape(0) != 2) throw InputError("uv_from_angles: pinned must hold two vertex indices");
      pins.vertices = {pin_indices.data()[0], pin_indices.data()[1]};
    }
    if (!pinned_uv.is_none()) {
      const auto pin_positions = as_real_matrix(pinned_uv, "pinned_uv", 2);
      if (pin_positions.shape(0) != 2) throw InputError("uv_from_angles: pinned_uv must have shape (2, 2)");
      for (int p = 0; p < 2; ++p) pins.positions[p] = Eigen::Vector2d(pin_positions.at(p, 0), pin_positions.at(p, 1));
    }
    const Eigen::Map<const parametrization::AngleMatrix> angle_view(corner_angles.data(), corner_angles.shape(0), 3);
    auto uv = without_gil([&] { return parametrization::uv_from_angles(face_view, n_vertices, angle_view, pins); });
    return to_numpy(std::move(uv));
  }, py::arg("F"), py::arg("angles"), py::arg("n_vertices") = py::none(), py::arg("pinned") = py::none(),
     py::arg("pinned_uv") = py::none());
}

}  // namespace meshsmith::python
