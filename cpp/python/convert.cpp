#include "convert.h"

#include <limits>

namespace meshsmith::python {

namespace {

py::array as_array(const py::handle& object, const char* name) {
  if (object.is_none()) throw InputError(std::string(name) + " is None: expected an array");
  try {
    return py::array::ensure(object);
  } catch (const py::error_already_set&) {
  }
  throw InputError(std::string(name) + " is not convertible to an array");
}

void check_shape(const py::array& array, const char* name, Eigen::Index columns) {
  const bool ok = array.ndim() == 2 && array.shape(1) == columns;
  if (!ok) {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < array.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(array.shape(d));
    shape += array.ndim() == 1 ? ",)" : ")";
    throw InputError(std::string(name) + " has shape " + shape + ": expected (n, " + std::to_string(columns) + ")");
  }
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

}  // namespace

RealArray as_real_matrix(const py::handle& object, const char* name,
                                                       Eigen::Index columns) {
  py::array array = as_array(object, name);
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw InputError(std::string(name) + " has dtype " + std::string(py::str(array.dtype())) +
                     ": expected real numbers");
  }
  check_shape(array, name, columns);
  return converted<RealArray>(array, name);
}

IndexArray as_index_matrix(const py::handle& object, const char* name,
                                                     Eigen::Index columns) {
  py::array array = as_array(object, name);
  const char kind = array.dtype().kind();
  if (kind != 'i' && kind != 'u') {
    throw InputError(std::string(name) + " has dtype " + std::string(py::str(array.dtype())) +
                     ": expected integer indices");
  }
  check_shape(array, name, columns);
  // Check the range before narrowing to int32: a wrapped index would pass validation.
  auto out_of_range = [&](py::ssize_t k, const std::string& value) {
    throw InputError(std::string(name) + "[" + std::to_string(k / columns) + "] holds index " + value +
                     ", outside the 32-bit range");
  };
  constexpr auto int_max = std::numeric_limits<int>::max();
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

Progress make_progress(const py::object& callback) {
  py::object held = callback;  // keeps the callable alive for the lifetime of the Progress
  return Progress([held](double fraction, const std::string& stage) -> bool {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C → KeyboardInterrupt
    if (held.is_none()) return true;
    py::object answer = held(fraction, stage);
    return answer.is_none() || answer.cast<bool>();
  });
}

}  // namespace meshsmith::python
