// Bindings of the smoothing chapter (§3.0.1–3.0.2): Laplacian, Taubin and curve smoothing with
// error control. The Python package (meshsmith.smoothing) turns its keyword options into these.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/smoothing/curve_smoothing.h>
#include <meshsmith/smoothing/laplacian_smoothing.h>

#include <limits>
#include <string>
#include <vector>

namespace meshsmith::python {
namespace {

using namespace meshsmith::smoothing;

SmoothingWeights parse_weights(const std::string& name) {
  return parse_choice<SmoothingWeights>(name, "weights",
                                        {{"uniform", SmoothingWeights::uniform},
                                         {"cotan", SmoothingWeights::cotan},
                                         {"cotan_delaunay", SmoothingWeights::cotan_delaunay},
                                         {"mean_value", SmoothingWeights::mean_value}});
}

SmoothingDirection parse_direction(const std::string& name) {
  return parse_choice<SmoothingDirection>(name, "direction",
                                          {{"full", SmoothingDirection::full},
                                           {"normal", SmoothingDirection::normal},
                                           {"tangential", SmoothingDirection::tangential}});
}

/// bound: "none", "epsilon_ball" or "error_slab"; epsilon its size.
ErrorControl parse_error_control(const std::string& bound, double epsilon) {
  ErrorControl control;
  control.bound = parse_choice<ErrorBound>(bound, "bound",
                                           {{"none", ErrorBound::none},
                                            {"epsilon_ball", ErrorBound::epsilon_ball},
                                            {"error_slab", ErrorBound::error_slab}});
  control.epsilon = epsilon;
  return control;
}

std::vector<int> parse_fixed(const py::object& fixed) {
  if (fixed.is_none()) return {};
  const IndexArray indices = as_index_vector(fixed, "fixed");
  return std::vector<int>(indices.data(), indices.data() + indices.size());
}

int parse_iterations(const py::object& iterations) {
  return integer_argument<int>(iterations, "iterations", 0, std::numeric_limits<int>::max());
}

/// Fills the options both mesh methods share.
void shared_options(SmoothingOptions& options, const std::string& weights, const py::object& iterations,
                    const std::string& direction, const py::object& fixed, const std::string& bound, double epsilon) {
  options.weights = parse_weights(weights);
  options.iterations = parse_iterations(iterations);
  options.direction = parse_direction(direction);
  options.fixed = parse_fixed(fixed);
  options.error_control = parse_error_control(bound, epsilon);
}

}  // namespace

void bind_smoothing(py::module_& m) {
  m.def("laplacian_smoothing", [](const py::object& V, const py::object& F, const std::string& weights, double lam,
                                  const py::object& iterations, const std::string& direction, bool implicit,
                                  const py::object& fixed, const std::string& bound, double epsilon,
                                  const py::object& callback) {
    const MeshArguments mesh(V, F);
    LaplacianSmoothingOptions options;
    shared_options(options, weights, iterations, direction, fixed, bound, epsilon);
    options.lambda = lam;
    options.implicit = implicit;
    Progress progress = make_progress(callback);
    return to_numpy(without_gil([&] { return laplacian_smoothing(mesh.V(), mesh.F(), options, progress); }));
  }, py::arg("V"), py::arg("F"), py::arg("weights"), py::arg("lam"), py::arg("iterations"), py::arg("direction"),
     py::arg("implicit"), py::arg("fixed"), py::arg("bound"), py::arg("epsilon"), py::arg("progress") = py::none(),
     "Smoothed (n, 3) positions: explicit or implicit umbrella-operator steps (§3.0.2).");

  m.def("taubin_smoothing", [](const py::object& V, const py::object& F, const std::string& weights, double lam,
                               double mu, const py::object& iterations, const std::string& direction,
                               const py::object& fixed, const std::string& bound, double epsilon,
                               const py::object& callback) {
    const MeshArguments mesh(V, F);
    TaubinOptions options;
    shared_options(options, weights, iterations, direction, fixed, bound, epsilon);
    options.lambda = lam;
    options.mu = mu;
    Progress progress = make_progress(callback);
    return to_numpy(without_gil([&] { return taubin_smoothing(mesh.V(), mesh.F(), options, progress); }));
  }, py::arg("V"), py::arg("F"), py::arg("weights"), py::arg("lam"), py::arg("mu"), py::arg("iterations"),
     py::arg("direction"), py::arg("fixed"), py::arg("bound"), py::arg("epsilon"), py::arg("progress") = py::none(),
     "Smoothed (n, 3) positions: Taubin's lambda|mu steps (§3.0.1).");

  m.def("smooth_curve", [](const py::object& P, double lam, double mu, const py::object& iterations, bool closed,
                           const py::object& fixed, const std::string& bound, double epsilon,
                           const py::object& tangents, const py::object& callback) {
    const RealArray points = as_real_matrix(P, "P", 2, 3);
    const Eigen::Map<const PointMatrix> view(points.data(), points.shape(0), points.shape(1));
    CurveSmoothingOptions options;
    options.lambda = lam;
    options.mu = mu;
    options.iterations = parse_iterations(iterations);
    options.closed = closed;
    options.fixed = parse_fixed(fixed);
    options.error_control = parse_error_control(bound, epsilon);
    if (!tangents.is_none()) {
      const RealArray axes = as_real_matrix(tangents, "tangents", points.shape(1));
      options.tangents = Eigen::Map<const PointMatrix>(axes.data(), axes.shape(0), axes.shape(1));
    }
    Progress progress = make_progress(callback);
    PointMatrix result = without_gil([&] { return smooth_curve(view, options, progress); });
    return to_numpy(std::move(result));
  }, py::arg("P"), py::arg("lam"), py::arg("mu"), py::arg("iterations"), py::arg("closed"), py::arg("fixed"),
     py::arg("bound"), py::arg("epsilon"), py::arg("tangents"), py::arg("progress") = py::none(),
     "Smoothed (n, d) polyline: Laplacian or Taubin steps on the polygon's second differences (§3.0.1).");
}

}  // namespace meshsmith::python
