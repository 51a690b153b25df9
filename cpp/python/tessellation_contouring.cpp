// Bindings of the contouring half of the tessellation chapter: power diagrams (§2.1.4) and
// Voronoi filtering / medial axis / local feature size (§2.1.2, §2.1.3).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/tessellation/power_diagram.h>
#include <meshsmith/tessellation/voronoi_filtering.h>

#include <string>

namespace meshsmith::python {

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// An (n, 2) or (n, 3) real array (`allowed` picks which) → row-major copy.
RowMatrix as_points(const py::handle& object, const char* name, bool allow_2d, bool allow_3d) {
  const RealArray real = as_real_matrix(object, name, allow_2d ? 2 : 3, allow_3d ? 3 : 2);
  return Eigen::Map<const RowMatrix>(real.data(), real.shape(0), real.shape(1));
}

/// A 1-D real array → Eigen vector (copy).
Eigen::VectorXd as_vector(const py::handle& object, const char* name) {
  const RealArray real = as_real_vector(object, name);
  return Eigen::Map<const Eigen::VectorXd>(real.data(), real.shape(0));
}

template <typename Derived>
py::array_t<double> real_to_numpy(const Eigen::MatrixBase<Derived>& m) {
  RowMatrix copy = m;
  return to_numpy(std::move(copy));
}

}  // namespace

void bind_tessellation_contouring(py::module_& m) {
  m.def("power_diagram", [](const py::object& P_in, const py::object& w_in, const py::object& b_in) {
    const RowMatrix P = as_points(P_in, "P", true, true);
    const Eigen::VectorXd weights = as_vector(w_in, "weights");
    const Eigen::VectorXd bounds = as_vector(b_in, "bounds");
    auto diagram = without_gil([&] { return tessellation::power_diagram(P, weights, bounds); });
    py::list cells;
    for (const auto& cell : diagram.cells) {
      if (P.cols() == 2)
        cells.append(real_to_numpy(cell.vertices));
      else
        cells.append(py::make_tuple(real_to_numpy(cell.vertices), indices_to_numpy(cell.faces)));
    }
    Eigen::VectorXi hidden = Eigen::Map<const Eigen::VectorXi>(diagram.hidden.data(),
                                                               static_cast<Eigen::Index>(diagram.hidden.size()));
    return py::make_tuple(indices_to_numpy(diagram.triangulation), cells,
                          indices_to_numpy(hidden).attr("ravel")());
  }, py::arg("P"), py::arg("weights"), py::arg("bounds"));

  m.def("crust", [](const py::object& samples_in) {
    const RowMatrix samples = as_points(samples_in, "samples", true, false);
    EdgeMatrix E = without_gil([&] { return tessellation::crust(samples); });
    return indices_to_numpy(E);
  }, py::arg("samples"));

  m.def("medial_axis", [](const py::object& samples_in) {
    const RowMatrix samples = as_points(samples_in, "samples", true, false);
    auto axis = without_gil([&] { return tessellation::medial_axis(samples); });
    return py::make_tuple(real_to_numpy(axis.vertices), indices_to_numpy(axis.edges));
  }, py::arg("samples"));

  m.def("local_feature_size", [](const py::object& samples_in) {
    const RowMatrix samples = as_points(samples_in, "samples", true, false);
    Eigen::VectorXd lfs = without_gil([&] { return tessellation::local_feature_size(samples); });
    return to_numpy(std::move(lfs));
  }, py::arg("samples"));

  m.def("sampling_ratio", [](const py::object& samples_in) {
    const RowMatrix samples = as_points(samples_in, "samples", true, false);
    return without_gil([&] { return tessellation::sampling_ratio(samples); });
  }, py::arg("samples"));

  m.def("crust_3d", [](const py::object& points_in, double cocone_angle, const py::object& max_hole_edges,
                       const py::object& callback) {
    const RowMatrix points = as_points(points_in, "points", false, true);
    tessellation::CoconeOptions options;
    options.cocone_angle = cocone_angle;
    options.max_hole_edges = integer_argument<int>(max_hole_edges, "max_hole_edges", 0, 1 << 20);  // 4x fits an int
    const Progress progress = make_progress(callback);
    Mesh mesh = without_gil([&] { return tessellation::crust_3d(points, options, progress); });
    return py::make_tuple(to_numpy(std::move(mesh.V)), indices_to_numpy(mesh.F));
  }, py::arg("points"), py::arg("cocone_angle"), py::arg("max_hole_edges"), py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
