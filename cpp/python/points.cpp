// Bindings of the points chapter: kd-tree kNN / radius queries, PCA normals, normal orientation.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/points/kd_tree.h>
#include <meshsmith/points/normals.h>

#include <vector>

namespace meshsmith::python {

namespace {

py::tuple knn_to_python(points::KnnResult&& result) {
  return py::make_tuple(to_numpy(std::move(result.indices)), to_numpy(std::move(result.distances)));
}

template <typename T>
py::array_t<T> vector_to_numpy(const std::vector<T>& values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

/// The neighbour count `k` (the core checks it against the number of points).
int neighbour_count(const py::object& k) { return integer_argument<int>(k, "k", 1); }

}  // namespace

void bind_points(py::module_& m) {
  py::class_<points::KdTree>(m, "KdTree")
      .def(py::init([](const py::object& P, const py::object& leaf_size_in) {
             auto positions = as_real_matrix(P, "P", 3);
             const int leaf_size = integer_argument<int>(leaf_size_in, "leaf_size", 1);
             py::gil_scoped_release release;
             return std::make_unique<points::KdTree>(map_vertices(positions), leaf_size);
           }),
           py::arg("P"), py::arg("leaf_size") = 10)
      .def("__len__", &points::KdTree::size)
      .def_property_readonly("points", [](const points::KdTree& tree) {
        VertexMatrix copy = tree.points();
        return to_numpy(std::move(copy));
      })
      .def("query", [](const points::KdTree& tree, const py::object& k_in, const py::object& Q, const py::object& callback) {
             const int k = neighbour_count(k_in);
             Progress progress = make_progress(callback);
             if (Q.is_none()) {
               points::KnnResult result;
               {
                 py::gil_scoped_release release;
                 result = tree.query_self(k, progress);
               }
               return knn_to_python(std::move(result));
             }
             auto queries = as_real_matrix(Q, "Q", 3);
             points::KnnResult result;
             {
               py::gil_scoped_release release;
               result = tree.query(map_vertices(queries), k, progress);
             }
             return knn_to_python(std::move(result));
           },
           py::arg("k"), py::arg("Q") = py::none(), py::arg("progress") = py::none())
      .def("query_radius", [](const points::KdTree& tree, const py::object& Q, double radius,
                              const py::object& callback) {
             auto queries = as_real_matrix(Q, "Q", 3);
             Progress progress = make_progress(callback);
             points::RadiusResult result;
             {
               py::gil_scoped_release release;
               result = tree.query_radius(map_vertices(queries), radius, progress);
             }
             return py::make_tuple(vector_to_numpy(result.offsets), vector_to_numpy(result.indices),
                                   vector_to_numpy(result.distances));
           },
           py::arg("Q"), py::arg("radius"), py::arg("progress") = py::none())
      .def("estimate_normals", [](const points::KdTree& tree, const py::object& k_in, double radius,
                                  const py::object& callback) {
             const int k = neighbour_count(k_in);
             Progress progress = make_progress(callback);
             points::NormalEstimate estimate;
             {
               py::gil_scoped_release release;
               estimate = points::estimate_normals(tree, {k, radius}, progress);
             }
             return py::make_tuple(to_numpy(std::move(estimate.normals)),
                                   to_numpy(std::move(estimate.surface_variation)));
           },
           py::arg("k") = 16, py::arg("radius") = 0.0, py::arg("progress") = py::none());

  m.def("knn", [](const py::object& P, const py::object& k_in, const py::object& Q, const py::object& callback) {
    auto positions = as_real_matrix(P, "P", 3);
    const int k = neighbour_count(k_in);
    Progress progress = make_progress(callback);
    points::KnnResult result;
    if (Q.is_none()) {
      py::gil_scoped_release release;
      result = points::knn(map_vertices(positions), k, progress);
    } else {
      auto queries = as_real_matrix(Q, "Q", 3);
      py::gil_scoped_release release;
      result = points::knn(map_vertices(positions), map_vertices(queries), k, progress);
    }
    return knn_to_python(std::move(result));
  }, py::arg("P"), py::arg("k"), py::arg("Q") = py::none(), py::arg("progress") = py::none());

  m.def("estimate_normals", [](const py::object& P, const py::object& k_in, double radius, const py::object& callback) {
    auto positions = as_real_matrix(P, "P", 3);
    const int k = neighbour_count(k_in);
    Progress progress = make_progress(callback);
    points::NormalEstimate estimate;
    {
      py::gil_scoped_release release;
      estimate = points::estimate_normals(map_vertices(positions), {k, radius}, progress);
    }
    return py::make_tuple(to_numpy(std::move(estimate.normals)),
                          to_numpy(std::move(estimate.surface_variation)));
  }, py::arg("P"), py::arg("k") = 16, py::arg("radius") = 0.0, py::arg("progress") = py::none());

  m.def("orient_normals", [](const py::object& P, const py::object& N, const py::object& k_in, double alpha,
                             double beta, const py::object& axis_in, const py::object& callback) {
    auto positions = as_real_matrix(P, "P", 3);
    auto normals = as_real_matrix(N, "N", 3);
    const int k = neighbour_count(k_in);
    const int axis = integer_argument<int>(axis_in, "axis", 0, 2);
    Progress progress = make_progress(callback);
    VertexMatrix oriented;
    {
      py::gil_scoped_release release;
      oriented = points::orient_normals(map_vertices(positions), map_vertices(normals),
                                        {k, alpha, beta, axis}, progress);
    }
    return to_numpy(std::move(oriented));
  }, py::arg("P"), py::arg("N"), py::arg("k") = 16, py::arg("alpha") = 0.1, py::arg("beta") = 0.9,
     py::arg("axis") = 2, py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
