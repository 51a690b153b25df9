// Bindings of the reconstruction chapter: marching cubes (dense and sparse), signed distances,
// screened Poisson (python/meshsmith/reconstruction/ documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/reconstruction/marching_cubes.h>

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
}

}  // namespace meshsmith::python
