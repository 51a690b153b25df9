// Bindings of the geometry chapter's discrete differential geometry. Sparse matrices go out as
// (data, indices, indptr, n) with zero-copy arrays on the Eigen matrix's own buffers; the Python
// wrapper turns them into scipy.sparse.csc_matrix.
#include "bindings.h"

#include "convert.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/geometry/curvature.h>
#include <meshsmith/geometry/laplacian.h>
#include <meshsmith/geometry/normals.h>
#include <meshsmith/geometry/spectral.h>

#include <algorithm>
#include <limits>
#include <string>
#include <utility>

namespace meshsmith::python {

namespace {

using namespace meshsmith::geometry;

py::tuple sparse_to_python(Eigen::SparseMatrix<double>&& matrix) {
  matrix.makeCompressed();
  auto* owned = new Eigen::SparseMatrix<double>(std::move(matrix));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<Eigen::SparseMatrix<double>*>(p); });
  const py::ssize_t nnz = owned->nonZeros(), n = owned->outerSize();
  py::array_t<double> data({nnz}, {sizeof(double)}, owned->valuePtr(), free_when_done);
  py::array_t<int> indices({nnz}, {sizeof(int)}, owned->innerIndexPtr(), free_when_done);
  py::array_t<int> indptr({n + 1}, {sizeof(int)}, owned->outerIndexPtr(), free_when_done);
  return py::make_tuple(data, indices, indptr, owned->rows(), owned->cols());
}

py::array_t<double> vector_to_numpy(Eigen::VectorXd&& vector) { return to_numpy(std::move(vector)); }

NormalWeighting parse_weighting(const std::string& name) {
  return parse_choice<NormalWeighting>(name, "weighting",
                                       {{"uniform", NormalWeighting::uniform},
                                        {"area", NormalWeighting::area},
                                        {"angle", NormalWeighting::angle}});
}

MassMatrixType parse_mass(const std::string& name, const char* argument) {
  return parse_choice<MassMatrixType>(name, argument,
                                      {{"barycentric", MassMatrixType::barycentric}, {"voronoi", MassMatrixType::voronoi}});
}

/// 'full_turn': 2π at boundary vertices, as libigl; 'half_turn': π.
BoundaryAngle parse_boundary(const std::string& name) {
  return parse_choice<BoundaryAngle>(name, "boundary",
                                     {{"full_turn", BoundaryAngle::full_turn}, {"half_turn", BoundaryAngle::half_turn}});
}

PrincipalCurvatureMethod parse_principal(const std::string& name) {
  return parse_choice<PrincipalCurvatureMethod>(name, "method",
                                                {{"quadric_fit", PrincipalCurvatureMethod::quadric_fit},
                                                 {"shape_operator", PrincipalCurvatureMethod::shape_operator},
                                                 {"mean_gaussian", PrincipalCurvatureMethod::mean_gaussian}});
}

// Converts (V, F), releases the GIL and runs `compute(V_view, F_view)`.
template <typename Compute>
auto with_mesh(const py::object& V, const py::object& F, Compute&& compute) {
  const MeshArguments mesh(V, F);
  return without_gil([&] { return compute(mesh.V(), mesh.F()); });
}

}  // namespace

void bind_geometry_differential(py::module_& m) {
  m.def("face_normals", [](const py::object& V, const py::object& F) {
    return to_numpy(with_mesh(V, F, [](const auto& v, const auto& f) { return face_normals(v, f); }));
  }, py::arg("V"), py::arg("F"));

  m.def("vertex_normals", [](const py::object& V, const py::object& F, const std::string& weighting) {
    const NormalWeighting w = parse_weighting(weighting);
    return to_numpy(with_mesh(V, F, [w](const auto& v, const auto& f) { return vertex_normals(v, f, w); }));
  }, py::arg("V"), py::arg("F"), py::arg("weighting") = "angle");

  m.def("cotan_laplacian", [](const py::object& V, const py::object& F, bool intrinsic_delaunay) {
    return sparse_to_python(with_mesh(V, F, [intrinsic_delaunay](const auto& v, const auto& f) {
      return intrinsic_delaunay ? intrinsic_delaunay_cotan_laplacian(v, f) : cotan_laplacian(v, f);
    }));
  }, py::arg("V"), py::arg("F"), py::arg("intrinsic_delaunay") = false);

  m.def("mean_value_laplacian", [](const py::object& V, const py::object& F) {
    return sparse_to_python(with_mesh(V, F, [](const auto& v, const auto& f) { return mean_value_laplacian(v, f); }));
  }, py::arg("V"), py::arg("F"));

  m.def("uniform_laplacian", [](const py::object& F, const py::object& n_in, bool normalized) {
    auto faces = as_index_matrix(F, "F", 3);
    // None: the largest index + 1 (at least 1, so a negative index gets the core's message).
    const auto view = map_faces(faces);
    const Eigen::Index n = n_in.is_none() ? std::max<Eigen::Index>(view.size() ? view.maxCoeff() + 1 : 1, 1)
                                          : integer_argument<Eigen::Index>(n_in, "n", 1, std::numeric_limits<int>::max());
    auto L = without_gil([&] { return uniform_laplacian(view, n, normalized); });
    return sparse_to_python(std::move(L));
  }, py::arg("F"), py::arg("n") = py::none(), py::arg("normalized") = false);

  m.def("mass_matrix", [](const py::object& V, const py::object& F, const std::string& kind) {
    const MassMatrixType type = parse_mass(kind, "kind");
    return sparse_to_python(with_mesh(V, F, [type](const auto& v, const auto& f) { return mass_matrix(v, f, type); }));
  }, py::arg("V"), py::arg("F"), py::arg("kind") = "voronoi");

  m.def("vertex_areas", [](const py::object& V, const py::object& F, const std::string& kind) {
    const MassMatrixType type = parse_mass(kind, "kind");
    return vector_to_numpy(with_mesh(V, F, [type](const auto& v, const auto& f) { return vertex_areas(v, f, type); }));
  }, py::arg("V"), py::arg("F"), py::arg("kind") = "voronoi");

  m.def("gaussian_curvature", [](const py::object& V, const py::object& F, const std::string& boundary,
                                 bool pointwise, const std::string& area) {
    GaussianCurvatureOptions options;
    options.boundary = parse_boundary(boundary);
    options.pointwise = pointwise;
    options.area = parse_mass(area, "area");
    return vector_to_numpy(with_mesh(V, F, [&options](const auto& v, const auto& f) { return gaussian_curvature(v, f, options); }));
  }, py::arg("V"), py::arg("F"), py::arg("boundary") = "full_turn", py::arg("pointwise") = false,
     py::arg("area") = "voronoi");

  m.def("mean_curvature", [](const py::object& V, const py::object& F, const std::string& area) {
    const MassMatrixType type = parse_mass(area, "area");
    MeanCurvature result = with_mesh(V, F, [type](const auto& v, const auto& f) { return mean_curvature(v, f, type); });
    return py::make_tuple(vector_to_numpy(std::move(result.H)), to_numpy(std::move(result.Hn)));
  }, py::arg("V"), py::arg("F"), py::arg("area") = "voronoi");

  m.def("principal_curvatures", [](const py::object& V, const py::object& F, const std::string& method) {
    const PrincipalCurvatureMethod chosen = parse_principal(method);
    PrincipalCurvatures result = with_mesh(V, F, [chosen](const auto& v, const auto& f) { return principal_curvatures(v, f, chosen); });
    return py::make_tuple(vector_to_numpy(std::move(result.k1)), vector_to_numpy(std::move(result.k2)),
                          to_numpy(std::move(result.d1)), to_numpy(std::move(result.d2)));
  }, py::arg("V"), py::arg("F"), py::arg("method") = "quadric_fit");

  m.def("laplacian_eigenpairs", [](const py::object& V, const py::object& F, const py::object& k_in,
                                   const std::string& mass, const py::object& callback) {
    const auto k = integer_argument<Eigen::Index>(k_in, "k", 1, std::numeric_limits<int>::max());
    const MassMatrixType type = parse_mass(mass, "mass");
    Progress progress = make_progress(callback);
    LaplacianEigenpairs result = with_mesh(V, F, [&](const auto& v, const auto& f) {
      return laplacian_eigenpairs(v, f, k, type, progress);
    });
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vectors = result.vectors;
    return py::make_tuple(vector_to_numpy(std::move(result.values)), to_numpy(std::move(vectors)));
  }, py::arg("V"), py::arg("F"), py::arg("k"), py::arg("mass") = "voronoi", py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
