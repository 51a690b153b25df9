// Input checks and duplicate merging shared by the 2D tessellation functions.
#include "planar_detail.h"

#include <meshsmith/core/normalization.h>

#include <meshsmith/core/errors.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace meshsmith::tessellation::detail {

void require_finite(const PointRef2& P, const char* name) {
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (!std::isfinite(P(i, 0)) || !std::isfinite(P(i, 1)))
      throw InputError(std::string(name) + ": row " + std::to_string(i) + " is not finite");
}

std::vector<int> merge_duplicates(const PointRef2& P) {
  const int n = static_cast<int>(P.rows());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    if (P(a, 0) != P(b, 0)) return P(a, 0) < P(b, 0);
    if (P(a, 1) != P(b, 1)) return P(a, 1) < P(b, 1);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> representative(n);
  for (int k = 0; k < n; ++k) {
    const int i = order[k];
    const bool same_as_previous =
        k > 0 && P(i, 0) == P(order[k - 1], 0) && P(i, 1) == P(order[k - 1], 1);
    // Equal points are consecutive and sorted by index, so the first of a run is the smallest.
    representative[i] = same_as_previous ? representative[order[k - 1]] : i;
  }
  return representative;
}

double normalizing_scale(const PointRef2& P) {
  const double magnitude = P.rows() ? P.cwiseAbs().maxCoeff() : 0.0;
  if (magnitude == 0) return 1.0;
  const int exponent = normalizing_frame(P).exponent;  // magnitude in [2^(exponent-1), 2^exponent)
  const double extent = (P.colwise().maxCoeff() - P.colwise().minCoeff()).maxCoeff();
  if (extent < 1e-100 * magnitude)
    throw InputError("P: the points span " + std::to_string(extent) +
                     ", too small relative to their magnitude for constructed points");
  return std::ldexp(1.0, -exponent);
}

void require_three_distinct(const std::vector<int>& representative) {
  int distinct = 0;
  for (std::size_t i = 0; i < representative.size() && distinct < 3; ++i)
    distinct += representative[i] == static_cast<int>(i);
  if (distinct < 3)
    throw InputError("P: a triangulation needs at least 3 distinct points, got " +
                     std::to_string(distinct));
}

}  // namespace meshsmith::tessellation::detail
