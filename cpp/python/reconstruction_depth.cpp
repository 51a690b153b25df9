// Bindings of depth images (§2.3): back-projection, grid meshes, the 2D scanline case.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/reconstruction/depth_images.h>

#include <string>
#include <vector>

namespace meshsmith::python {

namespace {

/// An (h, w) array of real numbers (NaN allowed: invalid pixels) → C-contiguous float64.
RealArray depth_argument(const py::handle& object) {
  py::array array = as_numeric_array(object, "depth", Elements::real);
  if (array.ndim() != 2)
    throw InputError("depth has shape " + shape_of(array) + ": expected an (h, w) image");
  return RealArray::ensure(array);
}

Eigen::Map<const reconstruction::DepthImage> map_depth(const RealArray& a) {
  return {a.data(), a.shape(0), a.shape(1)};
}

std::vector<char> mask_argument(const py::object& mask) {
  return mask.is_none() ? std::vector<char>() : as_flag_vector(mask, "mask");
}

reconstruction::PinholeCamera camera(double fx, double fy, double cx, double cy, double depth_scale) {
  return {fx, fy, cx, cy, depth_scale};
}

}  // namespace

void bind_reconstruction_depth(py::module_& m) {
  m.def("depth_to_points", [](const py::object& depth, double fx, double fy, double cx, double cy,
                              const py::object& mask, double depth_scale) {
    RealArray d = depth_argument(depth);
    const std::vector<char> flags = mask_argument(mask);
    auto result = without_gil([&] {
      return reconstruction::depth_to_points(map_depth(d), camera(fx, fy, cx, cy, depth_scale), flags);
    });
    return py::make_tuple(to_numpy(std::move(result.points)), to_numpy(std::move(result.pixels)));
  }, py::arg("depth"), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("mask") = py::none(),
     py::arg("depth_scale") = 1.0, "(points, pixels) of the pinhole back-projection of the valid pixels (§2.3).");

  m.def("depth_to_mesh", [](const py::object& depth, double fx, double fy, double cx, double cy,
                            const py::object& mask, double depth_scale, double max_jump) {
    RealArray d = depth_argument(depth);
    const std::vector<char> flags = mask_argument(mask);
    auto result = without_gil([&] {
      return reconstruction::depth_to_mesh(map_depth(d), camera(fx, fy, cx, cy, depth_scale), max_jump, flags);
    });
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F), to_numpy(std::move(result.pixels)));
  }, py::arg("depth"), py::arg("fx"), py::arg("fy"), py::arg("cx"), py::arg("cy"), py::arg("mask") = py::none(),
     py::arg("depth_scale") = 1.0, py::arg("max_jump") = 0.05,
     "(V, F, pixels) of the pixel-grid mesh of a depth image, cut at depth discontinuities (§2.3).");

  m.def("scanline_to_points", [](const py::object& depths, const py::object& center, const py::object& direction,
                                 double opening_angle, double max_jump) {
    RealArray d = as_real_vector(depths, "depths");
    RealArray c = as_real_vector(center, "center");
    RealArray v = as_real_vector(direction, "direction");
    if (c.shape(0) != 2) throw InputError("center has shape " + shape_of(c) + ": expected (2,)");
    if (v.shape(0) != 2) throw InputError("direction has shape " + shape_of(v) + ": expected (2,)");
    const Eigen::Map<const Eigen::VectorXd> d_view(d.data(), d.shape(0));
    const Eigen::Vector2d c_vec(c.data()[0], c.data()[1]), v_vec(v.data()[0], v.data()[1]);
    auto result = without_gil([&] {
      return reconstruction::scanline_to_points(d_view, c_vec, v_vec, opening_angle, max_jump);
    });
    py::array_t<std::int64_t> samples(static_cast<py::ssize_t>(result.samples.size()), result.samples.data());
    return py::make_tuple(to_numpy(std::move(result.points)), samples, indices_to_numpy(result.segments));
  }, py::arg("depths"), py::arg("center"), py::arg("direction"), py::arg("opening_angle"), py::arg("max_jump") = 0.05,
     "(points, samples, segments) of a 1D depth camera's scanline (§2.3, the 2D case).");
}

}  // namespace meshsmith::python
