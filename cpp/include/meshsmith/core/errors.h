#pragma once
/// \file errors.h
/// The exceptions every meshsmith function throws; the Python bindings map them to
/// meshsmith.InputError (a ValueError), meshsmith.SolverError (a RuntimeError) and
/// meshsmith.Cancelled.
#include <cstdio>
#include <stdexcept>
#include <string>

namespace meshsmith {

/// Bad input: wrong shape, NaN/Inf, index out of range, empty, or a precondition of the
/// algorithm that does not hold (manifold, disk topology, ...). The message names the element.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A numerical method failed on valid input (factorization not positive definite, no convergence).
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The caller's progress callback asked to stop.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A number for an error message, with 6 significant digits in either notation ("1e-300",
/// "0.25"), where std::to_string would print 1e-300 as "0.000000".
inline std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

}  // namespace meshsmith
