// Bindings of the geometry chapter's metrics: parametrization distortion and surface distances
// (python/meshsmith/_metrics.py documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/geometry/distance.h>
#include <meshsmith/geometry/distortion.h>

#include <pybind11/stl.h>

namespace meshsmith::python {

namespace {

template <typename T>
py::array_t<T> vector_to_numpy(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

py::dict distortion_to_python(geometry::TriangleDistortion&& d) {
  py::dict out;
  const auto m = d.jacobians.rows();
  auto jacobians = to_numpy(std::move(d.jacobians));
  out["jacobians"] = jacobians.reshape({static_cast<py::ssize_t>(m), py::ssize_t(2), py::ssize_t(2)});
  out["singular_values"] = to_numpy(std::move(d.singular_values));
  out["isometric"] = to_numpy(std::move(d.isometric));
  out["conformal"] = to_numpy(std::move(d.conformal));
  out["area"] = to_numpy(std::move(d.area));
  out["stretch_l2"] = to_numpy(std::move(d.stretch_l2));
  out["stretch_linf"] = to_numpy(std::move(d.stretch_linf));
  out["flipped"] = to_numpy(std::move(d.flipped)).attr("astype")("bool");
  out["surface_areas"] = to_numpy(std::move(d.surface_areas));
  out["parameter_areas"] = to_numpy(std::move(d.parameter_areas));
  out["vertex_isometric"] = to_numpy(std::move(d.vertex_isometric));
  out["vertex_conformal"] = to_numpy(std::move(d.vertex_conformal));
  out["vertex_area"] = to_numpy(std::move(d.vertex_area));
  out["vertex_stretch_l2"] = to_numpy(std::move(d.vertex_stretch_l2));
  out["vertex_stretch_linf"] = to_numpy(std::move(d.vertex_stretch_linf));
  out["global_stretch_l2"] = d.global_stretch_l2;
  out["normalized_global_stretch_l2"] = d.normalized_global_stretch_l2;
  out["global_stretch_linf"] = d.global_stretch_linf;
  out["flipped_faces"] = vector_to_numpy(d.flipped_faces).attr("astype")("int64");
  out["degenerate_parameter_faces"] = vector_to_numpy(d.degenerate_parameter_faces).attr("astype")("int64");
  out["degenerate_surface_faces"] = vector_to_numpy(d.degenerate_surface_faces).attr("astype")("int64");
  return out;
}

}  // namespace

void bind_geometry_metrics(py::module_& m) {
  m.def("triangle_distortion", [](const py::object& V, const py::object& F, const py::object& UV) {
    const MeshArguments mesh(V, F);
    const auto parameters = as_real_matrix(UV, "UV", 2);
    const Eigen::Map<const geometry::ParameterMatrix> uv(parameters.data(), parameters.shape(0), 2);
    auto result = without_gil([&] { return geometry::triangle_distortion(mesh.V(), mesh.F(), uv); });
    return distortion_to_python(std::move(result));
  }, py::arg("V"), py::arg("F"), py::arg("UV"));

  py::class_<geometry::SurfaceDistance>(m, "SurfaceDistance")
      .def(py::init([](const py::object& V, const py::object& F, const py::object& leaf_size_in) {
             const MeshArguments mesh(V, F);
             const int leaf_size = integer_argument<int>(leaf_size_in, "leaf_size", 1);
             return without_gil([&] {
               return std::make_unique<geometry::SurfaceDistance>(mesh.V(), mesh.F(), leaf_size);
             });
           }),
           py::arg("V"), py::arg("F"), py::arg("leaf_size") = 4)
      .def_property_readonly("face_count", &geometry::SurfaceDistance::face_count)
      .def("closest_points", [](const geometry::SurfaceDistance& tree, const py::object& Q,
                                const py::object& callback) {
             const auto queries = as_real_matrix(Q, "Q", 3);
             Progress progress = make_progress(callback);
             auto result = without_gil([&] { return tree.closest_points(map_vertices(queries), progress); });
             Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> faces = result.faces.cast<std::int64_t>();
             return py::make_tuple(to_numpy(std::move(result.distances)), to_numpy(std::move(faces)),
                                   to_numpy(std::move(result.points)));
           },
           py::arg("Q"), py::arg("progress") = py::none())
      .def("distances", [](const geometry::SurfaceDistance& tree, const py::object& Q, const py::object& callback) {
             const auto queries = as_real_matrix(Q, "Q", 3);
             Progress progress = make_progress(callback);
             auto result = without_gil([&] { return tree.distances(map_vertices(queries), progress); });
             return to_numpy(std::move(result));
           },
           py::arg("Q"), py::arg("progress") = py::none());

  auto surface_distance = [](auto function) {
    return [function](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB,
                      const py::object& samples_per_face, const py::object& seed, const py::object& callback) {
      // Named conversions (not MeshArguments) so a message says which of the four arrays is bad.
      const auto va = as_real_matrix(VA, "VA", 3), vb = as_real_matrix(VB, "VB", 3);
      const auto fa = as_index_matrix(FA, "FA", 3), fb = as_index_matrix(FB, "FB", 3);
      Progress progress = make_progress(callback);
      const geometry::SurfaceSampling sampling{integer_argument<int>(samples_per_face, "samples_per_face", 0),
                                               integer_argument<std::uint64_t>(seed, "seed")};
      const auto d = without_gil([&] {
        return function(map_vertices(va), map_faces(fa), map_vertices(vb), map_faces(fb), sampling, progress);
      });
      return py::make_tuple(d.symmetric, d.a_to_b, d.b_to_a);
    };
  };
  m.def("hausdorff_distance", surface_distance([](auto&&... args) { return geometry::hausdorff_distance(args...); }),
        py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::arg("samples_per_face") = 0,
        py::arg("seed") = 0, py::arg("progress") = py::none());
  m.def("mean_surface_distance",
        surface_distance([](auto&&... args) { return geometry::mean_surface_distance(args...); }),
        py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::arg("samples_per_face") = 0,
        py::arg("seed") = 0, py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
