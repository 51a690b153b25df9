#pragma once
// Conversions between numpy arrays and the core's Eigen types, shared by every binding file.
// All argument checking that depends on Python objects (array-likeness, dtype, shape) happens
// here, once, so the Python modules stay thin and the messages are the same everywhere.
#include <meshsmith/core/errors.h>
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <initializer_list>
#include <string>
#include <utility>

namespace meshsmith::python {

namespace py = pybind11;

/// C-contiguous arrays as the core reads them (forcecast: converted from any numeric dtype
/// after the checks below have ruled out the unsafe conversions).
using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int, py::array::c_style | py::array::forcecast>;

/// Any array-like of real numbers with shape (n, columns) → C-contiguous float64 array.
/// \throw InputError naming `name` for a wrong shape, a non-numeric dtype or a non-array.
RealArray as_real_matrix(const py::handle& object, const char* name,
                                                       Eigen::Index columns);

/// Any array-like of integers with shape (n, columns) → C-contiguous int32 array. Booleans and
/// floats are rejected (a float index is a bug upstream), so are values outside int32.
IndexArray as_index_matrix(const py::handle& object, const char* name,
                                                     Eigen::Index columns);

/// The enumerator that the string option `value` names among `choices` — one rule, and one message,
/// for every string option of the bindings.
/// \throw InputError "<argument> = '<value>': expected 'a', 'b' or 'c'" for any other value.
template <typename Enum>
Enum parse_choice(const std::string& value, const std::string& argument,
                  std::initializer_list<std::pair<const char*, Enum>> choices) {
  for (const auto& [name, choice] : choices)
    if (value == name) return choice;
  std::string expected;
  std::size_t k = 0;
  for (const auto& choice : choices) {
    expected += std::string(k == 0 ? "'" : (k + 1 == choices.size() ? " or '" : ", '")) + choice.first + "'";
    ++k;
  }
  throw InputError(argument + " = '" + value + "': expected " + expected);
}

/// Read-only Eigen views on arrays produced by as_real_matrix / as_index_matrix (no copy).
inline Eigen::Map<const VertexMatrix> map_vertices(const RealArray& a) {
  return {a.data(), a.shape(0), 3};
}
inline Eigen::Map<const FaceMatrix> map_faces(const IndexArray& a) {
  return {a.data(), a.shape(0), 3};
}

/// The (V, F) arguments of a binding, checked and converted once; V() and F() are zero-copy views
/// that stay valid while this object lives.
struct MeshArguments {
  MeshArguments(const py::handle& V, const py::handle& F)
      : vertices(as_real_matrix(V, "V", 3)), faces(as_index_matrix(F, "F", 3)) {}
  Eigen::Map<const VertexMatrix> V() const { return map_vertices(vertices); }
  Eigen::Map<const FaceMatrix> F() const { return map_faces(faces); }
  RealArray vertices;
  IndexArray faces;
};

/// Runs `work()` with the GIL released and returns its result; `work` must not touch Python
/// objects (the arrays behind MeshArguments' views are fine: they are kept alive by the caller).
template <typename Work>
auto without_gil(Work&& work) {
  py::gil_scoped_release release;
  return work();
}

/// Moves a row-major Eigen matrix into a numpy array without copying its data.
template <typename Matrix>
py::array_t<typename Matrix::Scalar> to_numpy(Matrix&& matrix) {
  using Stored = std::decay_t<Matrix>;
  static_assert(Stored::IsRowMajor || Stored::ColsAtCompileTime == 1, "row-major matrices only");
  auto* owned = new Stored(std::forward<Matrix>(matrix));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<Stored*>(p); });
  using Scalar = typename Stored::Scalar;
  if constexpr (Stored::ColsAtCompileTime == 1) {
    return py::array_t<Scalar>({owned->rows()}, {sizeof(Scalar)}, owned->data(), free_when_done);
  } else {
    return py::array_t<Scalar>({owned->rows(), owned->cols()},
                               {sizeof(Scalar) * owned->cols(), sizeof(Scalar)}, owned->data(),
                               free_when_done);
  }
}

/// Index matrices go out as int64 (DESIGN.md: "int64 out").
template <typename Derived>
py::array_t<std::int64_t> indices_to_numpy(const Eigen::MatrixBase<Derived>& indices) {
  py::array_t<std::int64_t> out({indices.rows(), indices.cols()});
  auto view = out.template mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < indices.rows(); ++r)
    for (Eigen::Index c = 0; c < indices.cols(); ++c) view(r, c) = indices(r, c);
  return out;
}

/// A Progress that forwards to a Python callable `(fraction, stage) -> bool | None` (None or
/// `callback is None` means "go on"; False cancels) and that checks for Ctrl-C on every call,
/// so long C++ loops stop promptly on KeyboardInterrupt. Call the algorithm with the GIL
/// released: the callback re-acquires it.
Progress make_progress(const py::object& callback);

}  // namespace meshsmith::python
