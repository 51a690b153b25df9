#pragma once
// Internal helpers of the tessellation chapter's 2D code. The predicates are implemented in
// delaunay_cgal.cpp with CGAL's filtered exact kernel, so callers need no CGAL header.
#include <meshsmith/tessellation/delaunay.h>

#include <vector>

namespace meshsmith::tessellation::detail {

/// Sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear. Exact.
int orientation(const double* a, const double* b, const double* c);

/// +1 if d is strictly inside the circle through the CCW triangle (a, b, c), -1 if strictly
/// outside, 0 if on it. Exact.
int side_of_circle(const double* a, const double* b, const double* c, const double* d);

/// \throw InputError naming `name` and the first row holding NaN or Inf.
void require_finite(const PointRef2& P, const char* name);

/// Representative of each point: the smallest index with exactly the same coordinates.
std::vector<int> merge_duplicates(const PointRef2& P);

/// Power of two that brings the largest |coordinate| of P into [0.5, 1): multiplying by it is
/// exact, so code that constructs points (circumcentres, intersections, Steiner points) can work on
/// scaled coordinates without overflow or underflow of squared lengths, and scale back exactly.
/// \throw InputError if the points span less than 1e-100 of their magnitude (squared lengths
///        would underflow).
double normalizing_scale(const PointRef2& P);

/// \throw InputError if fewer than 3 of the representatives are distinct.
void require_three_distinct(const std::vector<int>& representative);

}  // namespace meshsmith::tessellation::detail
