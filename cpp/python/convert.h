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
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace meshsmith::python {

namespace py = pybind11;

/// C-contiguous arrays as the core reads them (forcecast: converted from any numeric dtype
/// after the checks below have ruled out the unsafe conversions).
using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int, py::array::c_style | py::array::forcecast>;

/// What the elements of an array argument must be: real numbers (float, signed or unsigned
/// integer dtypes), indices (integer dtypes only: a float or bool index is a bug upstream) or
/// flags (bool dtype only).
enum class Elements { real, index, flag };

/// THE conversion of an array argument: any array-like (an ndarray of any layout, read-only or
/// not, a list or tuple of numbers, an object with __array__) → numpy array, without copying
/// when it is one already. Every array argument of every binding goes through it, and so do the
/// Python modules' own checks (meshsmith._arguments calls it through meshsmith._core.core).
/// \throw InputError naming `name` for None, for anything numpy cannot turn into an array
///        (ragged nesting: "V is not an array of numbers (list that numpy cannot convert:
///        setting an array element with a sequence ...)"), and for a dtype that is not
///        `elements` (objects, strings, complex, bool, datetime, structured; floats for
///        indices). What an object's own __array__ raises (other than ValueError, TypeError or
///        OverflowError) and MemoryError propagate as themselves.
py::array as_numeric_array(const py::handle& object, const char* name, Elements elements);

/// "(3, 2)", "(4,)": the shape of an array as numpy prints it, for messages.
std::string shape_of(const py::array& array);

/// Any array-like of real numbers with shape (n, columns) → C-contiguous float64 array.
/// \throw InputError naming `name` as as_numeric_array, or for a wrong shape.
RealArray as_real_matrix(const py::handle& object, const char* name, Eigen::Index columns);

/// The same, for an (n, 2) or (n, 3) array: columns_a or columns_b columns.
RealArray as_real_matrix(const py::handle& object, const char* name, Eigen::Index columns_a,
                         Eigen::Index columns_b);

/// Any 1-D array-like of real numbers, shape (n,) → C-contiguous float64 array.
/// \throw InputError naming `name` as as_numeric_array, or for a shape other than (n,).
RealArray as_real_vector(const py::handle& object, const char* name);

/// Any array-like of integers with shape (n, columns) → C-contiguous int32 array. Booleans and
/// floats are rejected (a float index is a bug upstream), so are values outside int32.
IndexArray as_index_matrix(const py::handle& object, const char* name, Eigen::Index columns);

/// Any 1-D array-like of integers, shape (n,) → C-contiguous int32 array (checks as
/// as_index_matrix).
IndexArray as_index_vector(const py::handle& object, const char* name);

/// Any 1-D array-like of booleans, shape (n,) → one char (0 or 1) per element.
/// \throw InputError naming `name` as as_numeric_array, or for a shape other than (n,).
std::vector<char> as_flag_vector(const py::handle& object, const char* name);

namespace detail {
/// `value` as a Python int in [minimum, maximum] (see integer_argument).
py::int_ checked_integer(const py::handle& value, const char* name, const py::int_& minimum,
                         const py::int_& maximum);
}  // namespace detail

/// An integer option: a Python int, a numpy integer or anything with __index__ (not a bool, not
/// a float: 3.0 and NaN are rejected as `range` rejects them) in [minimum, maximum], checked
/// before any allocation depends on it. Bindings take integer options as py::object and convert
/// them here, so 2**40, 2**70 or NaN give one clear message instead of pybind11's TypeError.
/// \throw InputError "<name> = <value>: expected an integer in [minimum, maximum]".
template <typename Int>
Int integer_argument(const py::handle& value, const char* name,
                     Int minimum = std::numeric_limits<Int>::lowest(),
                     Int maximum = std::numeric_limits<Int>::max()) {
  static_assert(std::is_integral_v<Int>, "integer options only");
  return detail::checked_integer(value, name, py::int_(minimum), py::int_(maximum)).template cast<Int>();
}

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
/// released: the callback re-acquires it. Whatever the callback raises reaches the caller as
/// itself (the algorithm unwinds with it).
/// \throw InputError now if `callback` is neither None nor callable, and from report() if the
///        callback returns anything but True, False (Python or numpy booleans) or None.
Progress make_progress(const py::object& callback);

}  // namespace meshsmith::python
