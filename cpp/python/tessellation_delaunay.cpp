// Bindings of the 2D tessellations: Delaunay, constrained Delaunay, Voronoi, Lawson flips and
// Delaunay refinement (meshsmith._core.tessellation; wrapped by meshsmith.tessellation).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/tessellation/delaunay.h>

#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace meshsmith::python {

namespace {

using tessellation::PointMatrix2;

Eigen::Map<const PointMatrix2> map_points(const RealArray& a) { return {a.data(), a.shape(0), 2}; }
Eigen::Map<const EdgeMatrix> map_pairs(const IndexArray& a) { return {a.data(), a.shape(0), 2}; }

py::tuple planar_mesh_to_python(tessellation::PlanarMesh&& mesh) {
  return py::make_tuple(to_numpy(std::move(mesh.V)), indices_to_numpy(mesh.F), mesh.steiner_count);
}

}  // namespace

void bind_tessellation_delaunay(py::module_& m) {
  m.def("delaunay", [](const py::object& P) {
        auto points = as_real_matrix(P, "P", 2);
        auto result = without_gil([&] { return tessellation::delaunay(map_points(points)); });
        py::array_t<std::int64_t> merged(result.merged.size());
        std::copy(result.merged.data(), result.merged.data() + result.merged.size(),
                  merged.mutable_data());
        return py::make_tuple(indices_to_numpy(result.F), merged);
      },
      py::arg("P"));

  m.def("constrained_delaunay", [](const py::object& P, const py::object& segments,
                                   const py::object& holes) {
        auto points = as_real_matrix(P, "P", 2);
        auto pairs = as_index_matrix(segments, "segments", 2);
        auto seeds = as_real_matrix(holes, "holes", 2);
        return planar_mesh_to_python(without_gil([&] {
          return tessellation::constrained_delaunay(map_points(points), map_pairs(pairs),
                                                    map_points(seeds));
        }));
      },
      py::arg("P"), py::arg("segments"), py::arg("holes"));

  m.def("refine", [](const py::object& P, const py::object& segments, const py::object& holes,
                     double min_angle, double max_area, const py::object& max_steiner_points,
                     const py::object& callback) {
        auto points = as_real_matrix(P, "P", 2);
        auto pairs = as_index_matrix(segments, "segments", 2);
        auto seeds = as_real_matrix(holes, "holes", 2);
        Progress progress = make_progress(callback);
        tessellation::RefineOptions options;
        options.min_angle_degrees = min_angle;
        options.max_area = max_area;
        options.max_steiner_points = integer_argument<int>(max_steiner_points, "max_steiner_points", 0);
        return planar_mesh_to_python(without_gil([&] {
          return tessellation::refine(map_points(points), map_pairs(pairs), map_points(seeds),
                                      options, progress);
        }));
      },
      py::arg("P"), py::arg("segments"), py::arg("holes"), py::arg("min_angle"),
      py::arg("max_area"), py::arg("max_steiner_points"), py::arg("progress") = py::none());

  m.def("flip_to_delaunay", [](const py::object& V, const py::object& F) {
        auto points = as_real_matrix(V, "V", 2);
        auto faces = as_index_matrix(F, "F", 3);
        auto result = without_gil(
            [&] { return tessellation::flip_to_delaunay(map_points(points), map_faces(faces)); });
        return py::make_tuple(indices_to_numpy(result.F), result.flip_count);
      },
      py::arg("V"), py::arg("F"));

  m.def("voronoi", [](const py::object& P, const std::array<double, 4>& bounds) {
        auto points = as_real_matrix(P, "P", 2);
        auto diagram =
            without_gil([&] { return tessellation::voronoi(map_points(points), Eigen::Vector4d(bounds.data())); });
        py::list cells;
        for (auto& cell : diagram.cells) cells.append(to_numpy(std::move(cell)));
        return py::make_tuple(to_numpy(std::move(diagram.vertices)), indices_to_numpy(diagram.edges),
                              to_numpy(std::move(diagram.directions)),
                              indices_to_numpy(diagram.edge_sites), cells,
                              indices_to_numpy(diagram.delaunay.F));
      },
      py::arg("P"), py::arg("bounds"));
}

}  // namespace meshsmith::python
