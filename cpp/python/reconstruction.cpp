// Bindings of the reconstruction chapter: marching cubes (dense and sparse), signed distances,
// screened Poisson (python/meshsmith/reconstruction/ documents them for users).
#include "bindings.h"
#include "convert.h"
#include "thread_limit.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/reconstruction/marching_cubes.h>
#include <meshsmith/reconstruction/poisson.h>
#include <meshsmith/reconstruction/signed_distance.h>

#include <string>

namespace meshsmith::python {

namespace {

/// A 3-vector option (origin, spacing) as three doubles.
std::array<double, 3> triple(const py::handle& object, const char* name) {
  auto array = as_real_vector(object, name);
  if (array.shape(0) != 3) throw InputError(std::string(name) + " has shape " + shape_of(array) + ": expected 3 numbers");
  return {array.at(0), array.at(1), array.at(2)};
}

py::dict contour_to_python(reconstruction::ContourMesh&& mesh) {
  py::dict out;
  out["V"] = to_numpy(std::move(mesh.V));
  out["F"] = indices_to_numpy(mesh.F);
  out["centre_vertices"] = mesh.centre_vertices;
  out["blocks"] = mesh.blocks;
  out["evaluations"] = mesh.evaluations;
  return out;
}

}  // namespace

void bind_reconstruction(py::module_& m) {
  m.def("marching_cubes", [](const py::object& values_in, const py::object& origin, const py::object& spacing,
                             double iso, const py::object& callback) {
    py::array checked = as_numeric_array(values_in, "values", Elements::real);
    if (checked.ndim() != 3)
      throw InputError("values has shape " + shape_of(checked) + ": expected a 3-D array (nx, ny, nz)");
    RealArray values = RealArray::ensure(checked);
    reconstruction::Grid grid;
    for (int a = 0; a < 3; ++a) grid.shape[a] = values.shape(a);
    grid.origin = triple(origin, "origin");
    grid.spacing = triple(spacing, "spacing");
    Progress progress = make_progress(callback);
    return contour_to_python(without_gil([&] { return reconstruction::marching_cubes(values.data(), grid, iso, progress); }));
  }, py::arg("values"), py::arg("origin"), py::arg("spacing"), py::arg("iso"), py::arg("progress") = py::none());

  m.def("marching_cubes_sparse", [](const py::object& field, const py::object& shape_in, const py::object& origin,
                                    const py::object& spacing, const py::object& seeds_in, double iso,
                                    const py::object& block_size, const py::object& dilation,
                                    const py::object& callback) {
    if (!PyCallable_Check(field.ptr())) throw InputError("field is not callable: expected a function of (m, 3) positions");
    reconstruction::Grid grid;
    auto shape = as_index_vector(shape_in, "shape");
    if (shape.shape(0) != 3) throw InputError("shape has shape " + shape_of(shape) + ": expected 3 integers");
    for (int a = 0; a < 3; ++a) grid.shape[a] = shape.at(a);
    grid.origin = triple(origin, "origin");
    grid.spacing = triple(spacing, "spacing");
    auto seeds = as_real_matrix(seeds_in, "seeds", 3);
    reconstruction::SparseOptions options;
    options.block_size = integer_argument<int>(block_size, "block_size", 1, 64);
    options.dilation = integer_argument<int>(dilation, "dilation", 0, 16);
    Progress progress = make_progress(callback);
    const reconstruction::GridFunction evaluate = [&](const auto& points, double* out) {
      py::gil_scoped_acquire acquire;
      VertexMatrix positions(points.rows(), 3);
      for (Eigen::Index r = 0; r < points.rows(); ++r)
        for (int a = 0; a < 3; ++a) positions(r, a) = grid.origin[a] + grid.spacing[a] * static_cast<double>(points(r, a));
      py::object result = field(to_numpy(std::move(positions)));
      auto values = as_real_vector(result, "field(points)");
      if (values.shape(0) != points.rows())
        throw InputError("field returned " + std::to_string(values.shape(0)) + " values for " +
                         std::to_string(points.rows()) + " points: expected one per point");
      std::copy(values.data(), values.data() + points.rows(), out);
    };
    return contour_to_python(without_gil([&] {
      return reconstruction::marching_cubes_sparse(evaluate, grid, map_vertices(seeds), iso, options, progress);
    }));
  }, py::arg("field"), py::arg("shape"), py::arg("origin"), py::arg("spacing"), py::arg("seeds"), py::arg("iso"),
     py::arg("block_size"), py::arg("dilation"), py::arg("progress") = py::none());

  m.def("tangent_plane_sdf", [](const py::object& P, const py::object& N, const py::object& Q, const py::object& k_in,
                                const py::object& callback) {
    auto samples = as_real_matrix(P, "P", 3);
    auto normals = as_real_matrix(N, "N", 3);
    auto queries = as_real_matrix(Q, "Q", 3);
    const int k = integer_argument<int>(k_in, "k", 1);
    Progress progress = make_progress(callback);
    return to_numpy(without_gil([&] {
      return reconstruction::tangent_plane_sdf(map_vertices(samples), map_vertices(normals), map_vertices(queries), k,
                                               progress);
    }));
  }, py::arg("P"), py::arg("N"), py::arg("Q"), py::arg("k"), py::arg("progress") = py::none());

  m.def("winding_number", [](const py::object& V, const py::object& F, const py::object& Q, double accuracy,
                             const py::object& callback) {
    const MeshArguments mesh(V, F);
    auto queries = as_real_matrix(Q, "Q", 3);
    Progress progress = make_progress(callback);
    return to_numpy(without_gil([&] {
      const reconstruction::WindingNumber winding(mesh.V(), mesh.F(), accuracy);
      return winding.at(map_vertices(queries), progress);
    }));
  }, py::arg("V"), py::arg("F"), py::arg("Q"), py::arg("accuracy"), py::arg("progress") = py::none());

  m.def("mesh_sdf", [](const py::object& V, const py::object& F, const py::object& Q, const py::object& callback) {
    const MeshArguments mesh(V, F);
    auto queries = as_real_matrix(Q, "Q", 3);
    Progress progress = make_progress(callback);
    auto result = without_gil([&] { return reconstruction::mesh_sdf(mesh.V(), mesh.F(), map_vertices(queries), progress); });
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> face = result.face.cast<std::int64_t>();
    py::dict out;
    out["distance"] = to_numpy(std::move(result.distance));
    out["face"] = to_numpy(std::move(face));
    out["point"] = to_numpy(std::move(result.point));
    out["winding"] = to_numpy(std::move(result.winding));
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("Q"), py::arg("progress") = py::none());

  m.def("poisson", [](const py::object& P, const py::object& N, const py::object& depth, double screening,
                      double samples_per_node, double scale, const py::object& coarse_depth, const py::object& band,
                      const py::object& refinement, const py::object& max_iterations, double tolerance,
                      const py::object& extraction_depth, const py::object& band_refinement, const py::object& threads,
                      bool adaptive, const py::object& callback) {
    auto samples = as_real_matrix(P, "P", 3);
    auto normals = as_real_matrix(N, "N", 3);
    reconstruction::PoissonOptions options;
    options.depth = integer_argument<int>(depth, "depth", 2, 10);
    options.screening = screening;
    options.samples_per_node = samples_per_node;
    options.scale = scale;
    options.coarse_depth = integer_argument<int>(coarse_depth, "coarse_depth", 2, 10);
    options.band = integer_argument<int>(band, "band", 1, 16);
    options.refinement = integer_argument<int>(refinement, "refinement", 0, 10);
    options.max_iterations = integer_argument<int>(max_iterations, "max_iterations", 1, 1 << 20);
    options.tolerance = tolerance;
    options.extraction_depth = extraction_depth.is_none() ? 0 : integer_argument<int>(extraction_depth, "extraction_depth", 2, 10);
    options.band_refinement = integer_argument<int>(band_refinement, "band_refinement", 0, 10);
    options.adaptive = adaptive;
    Progress progress = make_progress(callback);
    auto result = with_threads(threads, [&] {  // the result does not depend on the thread count
      return reconstruction::poisson(map_vertices(samples), map_vertices(normals), options, progress);
    });
    const auto count = static_cast<Eigen::Index>(result.levels.size());
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> depths(count), unknowns(count), iterations(count);
    Eigen::VectorXd residuals(count);
    for (Eigen::Index l = 0; l < count; ++l) {
      const auto& level = result.levels[static_cast<std::size_t>(l)];
      depths[l] = level.depth, unknowns[l] = level.unknowns, iterations[l] = level.iterations;
      residuals[l] = level.residual;
    }
    py::dict out;
    out["V"] = to_numpy(std::move(result.V));
    out["F"] = indices_to_numpy(result.F);
    out["density"] = to_numpy(std::move(result.density));
    out["iso"] = result.iso;
    out["extraction_depth"] = result.extraction_depth;
    out["level_depths"] = to_numpy(std::move(depths));
    out["level_unknowns"] = to_numpy(std::move(unknowns));
    out["level_iterations"] = to_numpy(std::move(iterations));
    out["level_residuals"] = to_numpy(std::move(residuals));
    return out;
  }, py::arg("P"), py::arg("N"), py::arg("depth"), py::arg("screening"), py::arg("samples_per_node"), py::arg("scale"),
     py::arg("coarse_depth"), py::arg("band"), py::arg("refinement"), py::arg("max_iterations"), py::arg("tolerance"),
     py::arg("extraction_depth") = py::none(), py::arg("band_refinement") = 0, py::arg("threads") = py::none(),
     py::arg("adaptive") = false, py::arg("progress") = py::none());
}

}  // namespace meshsmith::python
