#include "convert.h"

#include <limits>

namespace meshsmith::python {

namespace {

/// repr(object) cut to `limit` characters, for messages about arbitrary user objects.
std::string short_repr(const py::handle& object, std::size_t limit = 60) {
  std::string text = py::repr(object);
  if (text.size() > limit) text = text.substr(0, limit - 3) + "...";
  return text;
}

std::string type_name(const py::handle& object) {
  return py::str(py::type::handle_of(object).attr("__qualname__"));
}

bool dtype_is(const py::array& array, Elements elements) {
  const char kind = array.dtype().kind();
  if (elements == Elements::flag) return kind == 'b';
  return kind == 'i' || kind == 'u' || (elements == Elements::real && kind == 'f');
}

const char* expected_elements(Elements elements) {
  switch (elements) {
    case Elements::real: return ": expected real numbers";
    case Elements::index: return ": expected integer indices";
    case Elements::flag: return ": expected booleans";
  }
  return "";
}

void check_matrix_shape(const py::array& array, const char* name, Eigen::Index columns_a,
                        Eigen::Index columns_b) {
  if (array.ndim() == 2 && (array.shape(1) == columns_a || array.shape(1) == columns_b)) return;
  const std::string expected = columns_a == columns_b
                                   ? "(n, " + std::to_string(columns_a) + ")"
                                   : "(n, " + std::to_string(columns_a) + ") or (n, " + std::to_string(columns_b) + ")";
  throw InputError(std::string(name) + " has shape " + shape_of(array) + ": expected " + expected);
}

void check_vector_shape(const py::array& array, const char* name) {
  if (array.ndim() != 1) throw InputError(std::string(name) + " has shape " + shape_of(array) + ": expected (n,)");
}

/// numpy conversion to the typed array, which can still fail (e.g. out of memory).
template <typename Typed>
Typed converted(const py::array& array, const char* name) {
  Typed typed = Typed::ensure(array);
  if (!typed) {
    throw InputError(std::string(name) + " could not be converted to " +
                     std::string(py::str(py::dtype::of<typename Typed::value_type>())));
  }
  return typed;
}

/// An integer array (dtype already checked) → int32, after checking every value fits: a wrapped
/// index would pass validation. Messages name the row: flat position / row_length.
IndexArray narrowed_indices(const py::array& array, const char* name, py::ssize_t row_length) {
  auto out_of_range = [&](py::ssize_t k, const std::string& value) {
    throw InputError(std::string(name) + "[" + std::to_string(k / row_length) + "] holds index " + value +
                     ", outside the 32-bit range");
  };
  constexpr auto int_max = std::numeric_limits<int>::max();
  const char kind = array.dtype().kind();
  if (kind == 'u' && array.dtype().itemsize() >= 4) {
    auto wide = converted<py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>>(array, name);
    for (py::ssize_t k = 0; k < wide.size(); ++k)
      if (wide.data()[k] > static_cast<std::uint64_t>(int_max)) out_of_range(k, std::to_string(wide.data()[k]));
  } else if (kind == 'i' && array.dtype().itemsize() > 4) {
    auto wide = converted<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>(array, name);
    for (py::ssize_t k = 0; k < wide.size(); ++k)
      if (wide.data()[k] < -int_max || wide.data()[k] > int_max) out_of_range(k, std::to_string(wide.data()[k]));
  }
  return converted<IndexArray>(array, name);
}

}  // namespace

std::string shape_of(const py::array& array) {
  std::string shape = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(array.shape(d));
  return shape + (array.ndim() == 1 ? ",)" : ")");
}

py::array as_numeric_array(const py::handle& object, const char* name, Elements elements) {
  if (object.is_none()) throw InputError(std::string(name) + " is None: expected an array");
  py::array array;
  if (py::isinstance<py::array>(object)) {
    array = py::reinterpret_borrow<py::array>(object);
  } else {
    // numpy.asarray itself, not py::array::ensure: ensure() swallows numpy's error and returns a
    // null handle, which is how ragged lists used to reach the dtype check and crash.
    try {
      array = py::module_::import("numpy").attr("asarray")(object);
    } catch (py::error_already_set& error) {
      // What numpy says about the nesting (ValueError, TypeError, OverflowError) is the
      // caller's bad input; MemoryError, KeyboardInterrupt and the like stay themselves.
      if (!error.matches(PyExc_ValueError) && !error.matches(PyExc_TypeError) && !error.matches(PyExc_OverflowError))
        throw;
      throw InputError(std::string(name) + " is not an array of numbers (" + type_name(object) +
                       " that numpy cannot convert: " + std::string(py::str(error.value())) + ")");
    }
  }
  if (!dtype_is(array, elements)) {
    throw InputError(std::string(name) + " has dtype " + std::string(py::str(array.dtype())) +
                     expected_elements(elements));
  }
  return array;
}

RealArray as_real_matrix(const py::handle& object, const char* name, Eigen::Index columns) {
  return as_real_matrix(object, name, columns, columns);
}

RealArray as_real_matrix(const py::handle& object, const char* name, Eigen::Index columns_a,
                         Eigen::Index columns_b) {
  const py::array array = as_numeric_array(object, name, Elements::real);
  check_matrix_shape(array, name, columns_a, columns_b);
  return converted<RealArray>(array, name);
}

RealArray as_real_vector(const py::handle& object, const char* name) {
  const py::array array = as_numeric_array(object, name, Elements::real);
  check_vector_shape(array, name);
  return converted<RealArray>(array, name);
}

IndexArray as_index_matrix(const py::handle& object, const char* name, Eigen::Index columns) {
  const py::array array = as_numeric_array(object, name, Elements::index);
  check_matrix_shape(array, name, columns, columns);
  return narrowed_indices(array, name, columns);
}

IndexArray as_index_vector(const py::handle& object, const char* name) {
  const py::array array = as_numeric_array(object, name, Elements::index);
  check_vector_shape(array, name);
  return narrowed_indices(array, name, 1);
}

std::vector<char> as_flag_vector(const py::handle& object, const char* name) {
  const py::array array = as_numeric_array(object, name, Elements::flag);
  check_vector_shape(array, name);
  const auto flags = converted<py::array_t<bool, py::array::c_style | py::array::forcecast>>(array, name);
  return std::vector<char>(flags.data(), flags.data() + flags.size());
}

namespace detail {

py::int_ checked_integer(const py::handle& value, const char* name, const py::int_& minimum,
                         const py::int_& maximum) {
  auto reject = [&] {
    return InputError(std::string(name) + " = " + short_repr(value) + ": expected an integer in [" +
                      std::string(py::str(minimum)) + ", " + std::string(py::str(maximum)) + "]");
  };
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) throw reject();  // floats, NaN, str, None
  const auto number = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
  if (!number) throw py::error_already_set();  // its own __index__ raised
  const int below = PyObject_RichCompareBool(number.ptr(), minimum.ptr(), Py_LT);
  const int above = PyObject_RichCompareBool(number.ptr(), maximum.ptr(), Py_GT);
  if (below < 0 || above < 0) throw py::error_already_set();
  if (below || above) throw reject();
  return number;
}

}  // namespace detail

Progress make_progress(const py::object& callback) {
  if (!callback.is_none() && !PyCallable_Check(callback.ptr())) {
    throw InputError("progress = " + short_repr(callback) +
                     ": expected a callable (fraction, stage) -> bool, or None");
  }
  py::object held = callback;  // keeps the callable alive for the lifetime of the Progress
  return Progress([held](double fraction, const std::string& stage) -> bool {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C → KeyboardInterrupt
    if (held.is_none()) return true;
    const py::object answer = held(fraction, stage);  // what it raises propagates as itself
    if (answer.is_none()) return true;
    if (PyBool_Check(answer.ptr())) return answer.ptr() == Py_True;
    if (py::isinstance(answer, py::module_::import("numpy").attr("bool_"))) return PyObject_IsTrue(answer.ptr()) == 1;
    throw InputError("the progress callback returned " + short_repr(answer) + " (" + type_name(answer) +
                     "): expected True (go on), False (cancel) or None");
  });
}

}  // namespace meshsmith::python
