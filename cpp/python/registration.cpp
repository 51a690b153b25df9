// Bindings of the registration chapter (§2.3.1): Horn alignment, ICP, voxel reduction.
#include "bindings.h"
#include "convert.h"
#include "thread_limit.h"

#include <meshsmith/registration/align.h>
#include <meshsmith/registration/icp.h>

#include <cstdint>
#include <vector>
#include <string>

namespace meshsmith::python {

namespace {

using RowTransform = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;

py::array_t<double> transform_to_numpy(const registration::Transform& T) {
  RowTransform copy = T;
  return to_numpy(std::move(copy));
}

registration::Transform transform_argument(const py::handle& value, const char* name) {
  auto array = as_real_matrix(value, name, 4);
  if (array.shape(0) != 4)
    throw InputError(std::string(name) + " has shape " + shape_of(array) + ": expected a 4×4 transform");
  return Eigen::Map<const RowTransform>(array.data());
}

registration::IcpOptions icp_options(const std::string& method, const py::object& max_iterations, double tolerance,
                                     double max_distance, double trim, double voxel_size, double normal_angle,
                                     const py::object& normal_neighbours, double relative_rmse,
                                     double relative_fitness, const py::object& patience) {
  registration::IcpOptions options;
  options.method = parse_choice<registration::IcpMethod>(
      method, "method", {{"point_to_point", registration::IcpMethod::point_to_point},
                         {"point_to_plane", registration::IcpMethod::point_to_plane}});
  options.max_iterations = integer_argument<int>(max_iterations, "max_iterations", 1);
  options.tolerance = tolerance;
  options.max_distance = max_distance;
  options.trim = trim;
  options.voxel_size = voxel_size;
  options.normal_angle = normal_angle;
  options.normal_neighbours = integer_argument<int>(normal_neighbours, "normal_neighbours", 3, 10000);
  options.relative_rmse = relative_rmse;
  options.relative_fitness = relative_fitness;
  options.patience = integer_argument<int>(patience, "patience", 0, 1000000);
  return options;
}

}  // namespace

void bind_registration(py::module_& m) {
  m.def("align", [](const py::object& A, const py::object& B, const py::object& weights, bool scale) {
    auto a = as_real_matrix(A, "A", 3);
    auto b = as_real_matrix(B, "B", 3);
    RealArray w = weights.is_none() ? RealArray(0) : as_real_vector(weights, "weights");
    const Eigen::Map<const Eigen::VectorXd> w_view(w.data(), w.shape(0));
    auto T = without_gil([&] { return registration::align(map_vertices(a), map_vertices(b), w_view, scale); });
    return transform_to_numpy(T);
  }, py::arg("A"), py::arg("B"), py::arg("weights") = py::none(), py::arg("scale") = false,
     "4×4 transform mapping A onto B (Horn's quaternion method, §2.3.1).");

  m.def("icp", [](const py::object& source, const py::object& target, const py::object& target_normals,
                  const std::string& method, const py::object& max_iterations, double tolerance,
                  double max_distance, double trim, double voxel_size, const py::object& normal_neighbours,
                  const py::object& initial, const py::object& threads, const py::object& callback,
                  const py::object& source_normals, double normal_angle, double relative_rmse,
                  double relative_fitness, const py::object& patience) {
    auto s = as_real_matrix(source, "source", 3);
    auto t = as_real_matrix(target, "target", 3);
    auto normals_of = [](const py::object& value, const char* name) {
      return value.is_none() ? RealArray(std::vector<py::ssize_t>{0, 3}) : as_real_matrix(value, name, 3);
    };
    RealArray normals = normals_of(target_normals, "target_normals");
    RealArray s_normals = normals_of(source_normals, "source_normals");
    registration::IcpOptions options = icp_options(method, max_iterations, tolerance, max_distance, trim, voxel_size,
                                                   normal_angle, normal_neighbours, relative_rmse, relative_fitness,
                                                   patience);
    if (!initial.is_none()) options.initial = transform_argument(initial, "initial");
    Progress progress = make_progress(callback);
    auto result = with_threads(threads, [&] {
      const Eigen::Map<const VertexMatrix> n_view(normals.data(), normals.shape(0), 3);
      const Eigen::Map<const VertexMatrix> sn_view(s_normals.data(), s_normals.shape(0), 3);
      return registration::icp(map_vertices(s), map_vertices(t), sn_view, n_view, options, progress);
    });
    py::array_t<bool> inliers(static_cast<py::ssize_t>(result.inliers.size()));
    auto view = inliers.mutable_unchecked<1>();
    for (std::size_t i = 0; i < result.inliers.size(); ++i) view(py::ssize_t(i)) = result.inliers[i] != 0;
    py::array_t<double> history(static_cast<py::ssize_t>(result.rms_history.size()), result.rms_history.data());
    return py::make_tuple(transform_to_numpy(result.transform), result.rms, result.iterations, result.converged,
                          result.inlier_fraction, history, inliers, result.stop);
  }, py::arg("source"), py::arg("target"), py::arg("target_normals") = py::none(),
     py::arg("method") = "point_to_point", py::arg("max_iterations") = 50, py::arg("tolerance") = 1e-6,
     py::arg("max_distance") = 0.0, py::arg("trim") = 1.0, py::arg("voxel_size") = 0.0,
     py::arg("normal_neighbours") = 16, py::arg("initial") = py::none(), py::arg("threads") = py::none(),
     py::arg("progress") = py::none(), py::arg("source_normals") = py::none(), py::arg("normal_angle") = 0.0,
     py::arg("relative_rmse") = 1e-6, py::arg("relative_fitness") = 1e-6, py::arg("patience") = 10,
     "(transform, rms, iterations, converged, inlier_fraction, rms_history, inliers, stop) of rigid ICP (§2.3.1).");

  m.def("icp_multi", [](const py::sequence& scans, const std::string& method, const py::object& max_iterations,
                        double tolerance, double max_distance, double trim, double voxel_size, double normal_angle,
                        const py::object& normal_neighbours, const py::object& initial, const py::object& rounds,
                        double round_tolerance, const py::object& threads, const py::object& callback,
                        double relative_rmse, double relative_fitness, const py::object& patience,
                        const std::string& strategy, double overlap_distance, double min_overlap,
                        const py::object& edge_samples) {
    registration::IcpMultiOptions options;
    options.strategy = parse_choice<registration::MultiStrategy>(
        strategy, "strategy", {{"growing", registration::MultiStrategy::growing},
                               {"pose_graph", registration::MultiStrategy::pose_graph}});
    options.overlap_distance = overlap_distance;
    options.min_overlap = min_overlap;
    options.edge_samples = integer_argument<int>(edge_samples, "edge_samples", 3, 100000000);
    options.icp = icp_options(method, max_iterations, tolerance, max_distance, trim, voxel_size, normal_angle,
                              normal_neighbours, relative_rmse, relative_fitness, patience);
    options.rounds = integer_argument<int>(rounds, "rounds", 0, 1000);
    options.round_tolerance = round_tolerance;
    std::vector<VertexMatrix> points;
    points.reserve(py::len(scans));
    for (std::size_t i = 0; i < py::len(scans); ++i) {
      const std::string name = "scans[" + std::to_string(i) + "]";
      auto array = as_real_matrix(scans[i], name.c_str(), 3);
      points.emplace_back(map_vertices(array));
    }
    if (!initial.is_none()) {
      const py::sequence poses = py::reinterpret_borrow<py::sequence>(initial);
      for (std::size_t i = 0; i < py::len(poses); ++i) {
        const std::string name = "initial[" + std::to_string(i) + "]";
        options.initial.push_back(transform_argument(poses[i], name.c_str()));
      }
    }
    Progress progress = make_progress(callback);
    auto result = with_threads(threads, [&] { return registration::icp_multi(points, options, progress); });
    const auto k = static_cast<py::ssize_t>(result.transforms.size());
    py::array_t<double> transforms({k, py::ssize_t(4), py::ssize_t(4)});
    auto t_view = transforms.mutable_unchecked<3>();
    for (py::ssize_t i = 0; i < k; ++i)
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) t_view(i, r, c) = result.transforms[std::size_t(i)](r, c);
    py::array_t<bool> converged(k);
    auto c_view = converged.mutable_unchecked<1>();
    for (py::ssize_t i = 0; i < k; ++i) c_view(i) = result.scan_converged[std::size_t(i)] != 0;
    py::array_t<std::int64_t> edges({static_cast<py::ssize_t>(result.edges.size()), py::ssize_t(2)});
    auto e_view = edges.mutable_unchecked<2>();
    for (std::size_t e = 0; e < result.edges.size(); ++e)
      e_view(py::ssize_t(e), 0) = result.edges[e].first, e_view(py::ssize_t(e), 1) = result.edges[e].second;
    return py::make_tuple(transforms, py::array_t<double>(k, result.rms.data()),
                          py::array_t<double>(k, result.inlier_fraction.data()), converged, result.rounds,
                          result.converged, edges);
  }, py::arg("scans"), py::arg("method") = "point_to_point", py::arg("max_iterations") = 50,
     py::arg("tolerance") = 1e-6, py::arg("max_distance") = 0.0, py::arg("trim") = 1.0, py::arg("voxel_size") = 0.0,
     py::arg("normal_angle") = 0.0, py::arg("normal_neighbours") = 16, py::arg("initial") = py::none(),
     py::arg("rounds") = 10, py::arg("round_tolerance") = 1e-3, py::arg("threads") = py::none(), py::arg("progress") = py::none(),
     py::arg("relative_rmse") = 1e-6, py::arg("relative_fitness") = 1e-6, py::arg("patience") = 10,
     py::arg("strategy") = "growing", py::arg("overlap_distance") = 0.0, py::arg("min_overlap") = 0.2,
     py::arg("edge_samples") = 2000,
     "(transforms, rms, inlier_fraction, scan_converged, rounds, converged, edges) of multi-scan ICP (§2.3.1).");

  m.def("voxel_downsample", [](const py::object& P, double voxel_size) {
    auto points = as_real_matrix(P, "P", 3);
    auto out = without_gil([&] { return registration::voxel_downsample(map_vertices(points), voxel_size); });
    return to_numpy(std::move(out));
  }, py::arg("P"), py::arg("voxel_size"), "Centroids of the occupied voxels of P, in voxel order.");
}

}  // namespace meshsmith::python
