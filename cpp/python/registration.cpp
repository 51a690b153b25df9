// Bindings of the registration chapter (§2.3.1): Horn alignment, ICP, voxel reduction.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/registration/align.h>
#include <meshsmith/registration/icp.h>

#include <oneapi/tbb/global_control.h>

#include <memory>
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
                  const py::object& initial, const py::object& threads, const py::object& callback) {
    auto s = as_real_matrix(source, "source", 3);
    auto t = as_real_matrix(target, "target", 3);
    RealArray normals = target_normals.is_none() ? RealArray(std::vector<py::ssize_t>{0, 3})
                                                 : as_real_matrix(target_normals, "target_normals", 3);
    registration::IcpOptions options;
    options.method = parse_choice<registration::IcpMethod>(
        method, "method", {{"point_to_point", registration::IcpMethod::point_to_point},
                           {"point_to_plane", registration::IcpMethod::point_to_plane}});
    options.max_iterations = integer_argument<int>(max_iterations, "max_iterations", 1);
    options.tolerance = tolerance;
    options.max_distance = max_distance;
    options.trim = trim;
    options.voxel_size = voxel_size;
    options.normal_neighbours = integer_argument<int>(normal_neighbours, "normal_neighbours", 3, 10000);
    if (!initial.is_none()) options.initial = transform_argument(initial, "initial");
    const int thread_count = threads.is_none() ? 0 : integer_argument<int>(threads, "threads", 1, 4096);
    Progress progress = make_progress(callback);
    auto result = without_gil([&] {
      std::unique_ptr<tbb::global_control> limit;
      if (thread_count > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      static_cast<std::size_t>(thread_count));
      const Eigen::Map<const VertexMatrix> n_view(normals.data(), normals.shape(0), 3);
      return registration::icp(map_vertices(s), map_vertices(t), n_view, options, progress);
    });
    py::array_t<bool> inliers(static_cast<py::ssize_t>(result.inliers.size()));
    auto view = inliers.mutable_unchecked<1>();
    for (std::size_t i = 0; i < result.inliers.size(); ++i) view(py::ssize_t(i)) = result.inliers[i] != 0;
    py::array_t<double> history(static_cast<py::ssize_t>(result.rms_history.size()), result.rms_history.data());
    return py::make_tuple(transform_to_numpy(result.transform), result.rms, result.iterations, result.converged,
                          result.inlier_fraction, history, inliers);
  }, py::arg("source"), py::arg("target"), py::arg("target_normals") = py::none(),
     py::arg("method") = "point_to_point", py::arg("max_iterations") = 50, py::arg("tolerance") = 1e-6,
     py::arg("max_distance") = 0.0, py::arg("trim") = 1.0, py::arg("voxel_size") = 0.0,
     py::arg("normal_neighbours") = 16, py::arg("initial") = py::none(), py::arg("threads") = py::none(),
     py::arg("progress") = py::none(),
     "(transform, rms, iterations, converged, inlier_fraction, rms_history, inliers) of rigid ICP (§2.3.1).");

  m.def("voxel_downsample", [](const py::object& P, double voxel_size) {
    auto points = as_real_matrix(P, "P", 3);
    auto out = without_gil([&] { return registration::voxel_downsample(map_vertices(points), voxel_size); });
    return to_numpy(std::move(out));
  }, py::arg("P"), py::arg("voxel_size"), "Centroids of the occupied voxels of P, in voxel order.");
}

}  // namespace meshsmith::python
