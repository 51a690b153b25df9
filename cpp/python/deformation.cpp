// Bindings of the deformation chapter: k-harmonic interpolation, handle-based deformation and
// ARAP (python/meshsmith/deformation/ documents them for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/deformation/arap.h>
#include <meshsmith/deformation/harmonic_deformer.h>
#include <meshsmith/deformation/multiresolution.h>
#include <meshsmith/deformation/poisson_edit.h>

#include <optional>
#include <string>
#include <vector>

namespace meshsmith::python {

namespace {

using deformation::ArapDeformer;
using deformation::HarmonicDeformer;

/// A 1-D array-like of vertex indices → std::vector<int> (dtype and range checks as for F).
std::vector<int> vertex_list(const py::object& object, const char* name) {
  const IndexArray indices = as_index_vector(object, name);
  return std::vector<int>(indices.data(), indices.data() + indices.shape(0));
}

/// An (n, 3) array-like of positions, copied.
VertexMatrix positions_argument(const py::object& object, const char* name) {
  const RealArray array = as_real_matrix(object, name, 3);
  return map_vertices(array);
}

Eigen::Matrix4d affine_argument(const py::object& object) {
  const RealArray array = as_real_matrix(object, "T", 4);
  if (array.shape(0) != 4) throw InputError("T has shape " + shape_of(array) + ", expected (4, 4)");
  return Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(array.data());
}

int order_argument(const py::object& order) { return integer_argument<int>(order, "order", 1, 3); }

}  // namespace

void bind_deformation(py::module_& m) {
  m.def("harmonic", [](const py::object& V, const py::object& F, const py::object& b, const py::object& bc,
                       const py::object& order_in) {
    const MeshArguments mesh(V, F);
    const std::vector<int> vertices = vertex_list(b, "b");
    const py::array values_array = as_numeric_array(bc, "bc", Elements::real);
    if (values_array.ndim() != 2) {
      throw InputError("bc has shape " + shape_of(values_array) + ", expected (#b, c)");
    }
    const RealArray values = RealArray::ensure(values_array);
    const int order = order_argument(order_in);
    const Eigen::MatrixXd bc_matrix =
        Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            values.data(), values.shape(0), values.shape(1));
    const Eigen::MatrixXd X =
        without_gil([&] { return deformation::harmonic(mesh.V(), mesh.F(), vertices, bc_matrix, order); });
    return to_numpy(Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>(X));
  }, py::arg("V"), py::arg("F"), py::arg("b"), py::arg("bc"), py::arg("order") = 2);

  py::class_<HarmonicDeformer>(m, "HarmonicDeformer")
      .def(py::init([](const py::object& V, const py::object& F, const py::object& handle, const py::object& fixed,
                       const py::object& order_in, bool details) {
             const MeshArguments mesh(V, F);
             const std::vector<int> handle_vertices = vertex_list(handle, "handle");
             const std::vector<int> fixed_vertices = vertex_list(fixed, "fixed");
             const int order = order_argument(order_in);
             py::gil_scoped_release release;
             return std::make_unique<HarmonicDeformer>(mesh.V(), mesh.F(), handle_vertices, fixed_vertices, order,
                                                       details);
           }),
           py::arg("V"), py::arg("F"), py::arg("handle"), py::arg("fixed"), py::arg("order") = 2,
           py::arg("details") = false)
      .def("deform", [](const HarmonicDeformer& deformer, const py::object& positions) {
        const VertexMatrix P = positions_argument(positions, "handle_positions");
        return to_numpy(without_gil([&] { return deformer.deform(P); }));
      }, py::arg("handle_positions"))
      .def("transform", [](const HarmonicDeformer& deformer, const py::object& T) {
        const Eigen::Matrix4d matrix = affine_argument(T);
        return to_numpy(without_gil([&] { return deformer.transform(matrix); }));
      }, py::arg("T"))
      .def_property_readonly("handle", [](const HarmonicDeformer& d) {
        return indices_to_numpy(Eigen::Map<const Eigen::VectorXi>(d.handle().data(), d.handle().size()));
      })
      .def_property_readonly("fixed", [](const HarmonicDeformer& d) {
        return indices_to_numpy(Eigen::Map<const Eigen::VectorXi>(d.fixed().data(), d.fixed().size()));
      })
      .def_property_readonly("order", &HarmonicDeformer::order)
      .def_property_readonly("details", &HarmonicDeformer::details);

  py::class_<ArapDeformer>(m, "ArapDeformer")
      .def(py::init([](const py::object& V, const py::object& F, const py::object& handles) {
             const MeshArguments mesh(V, F);
             const std::vector<int> handle_vertices = vertex_list(handles, "handles");
             py::gil_scoped_release release;
             return std::make_unique<ArapDeformer>(mesh.V(), mesh.F(), handle_vertices);
           }),
           py::arg("V"), py::arg("F"), py::arg("handles"))
      .def("solve", [](const ArapDeformer& deformer, const py::object& positions, const py::object& iterations_in,
                       const py::object& initial, const py::object& callback) {
        const VertexMatrix P = positions_argument(positions, "positions");
        const int iterations = integer_argument<int>(iterations_in, "iterations", 0);
        std::optional<VertexMatrix> start;
        if (!initial.is_none()) start = positions_argument(initial, "initial");
        Progress progress = make_progress(callback);
        return to_numpy(without_gil([&] {
          if (!start) return deformer.solve(P, iterations, nullptr, progress);
          const VertexRef start_view(*start);
          return deformer.solve(P, iterations, &start_view, progress);
        }));
      }, py::arg("positions"), py::arg("iterations"), py::arg("initial") = py::none(),
         py::arg("progress") = py::none())
      .def("energy", [](const ArapDeformer& deformer, const py::object& U) {
        const VertexMatrix positions = positions_argument(U, "U");
        return without_gil([&] { return deformer.energy(positions); });
      }, py::arg("U"))
      .def_property_readonly("handles", [](const ArapDeformer& d) {
        return indices_to_numpy(Eigen::Map<const Eigen::VectorXi>(d.handles().data(), d.handles().size()));
      });

  m.def("poisson_edit", [](const py::object& V, const py::object& F, const py::object& handle, const py::object& fixed,
                           const py::object& positions, bool rotate) {
    const MeshArguments mesh(V, F);
    const std::vector<int> handle_vertices = vertex_list(handle, "handle");
    const std::vector<int> fixed_vertices = vertex_list(fixed, "fixed");
    const VertexMatrix P = positions_argument(positions, "handle_positions");
    return to_numpy(without_gil([&] {
      return deformation::poisson_edit(mesh.V(), mesh.F(), handle_vertices, fixed_vertices, P, rotate);
    }));
  }, py::arg("V"), py::arg("F"), py::arg("handle"), py::arg("fixed"), py::arg("handle_positions"),
     py::arg("rotate") = true);

  m.def("transfer_details", [](const py::object& V, const py::object& base, const py::object& F,
                               const py::object& edited_base) {
    const MeshArguments mesh(V, F);
    const VertexMatrix B = positions_argument(base, "base"), E = positions_argument(edited_base, "edited_base");
    return to_numpy(without_gil([&] { return deformation::transfer_details(mesh.V(), B, mesh.F(), E); }));
  }, py::arg("V"), py::arg("base"), py::arg("F"), py::arg("edited_base"));

  m.def("arap_energy", [](const py::object& V, const py::object& F, const py::object& U) {
    const MeshArguments mesh(V, F);
    const VertexMatrix positions = positions_argument(U, "U");
    return without_gil([&] { return deformation::arap_energy(mesh.V(), mesh.F(), positions); });
  }, py::arg("V"), py::arg("F"), py::arg("U"));
}

}  // namespace meshsmith::python
