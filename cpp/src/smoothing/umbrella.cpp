// The umbrella operator and the step loop (umbrella.h).
//
// The explicit step is the whole cost of Laplacian and Taubin smoothing, so U is stored as plain
// compact rows (offsets, columns, weights: 12 bytes per neighbour), the positions row-major, and
// each row's weighted sum is taken in its stored (ascending column) order, in parallel over rows
// with TBB: every output row is written by one task from fixed inputs, so the result does not
// depend on the thread count.
#include "umbrella.h"

#include <meshsmith/core/errors.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <string>
#include <utility>

namespace meshsmith::smoothing::detail {

void validate_fixed(const std::vector<int>& fixed, Eigen::Index n, const char* function) {
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    if (fixed[k] < 0 || fixed[k] >= n) {
      throw InputError(std::string(function) + ": fixed[" + std::to_string(k) + "] = " + std::to_string(fixed[k]) +
                       " is outside [0, " + std::to_string(n) + ")");
    }
  }
}

Umbrella umbrella_operator(const Eigen::SparseMatrix<double>& L_rows, const std::vector<int>& fixed,
                           const char* function) {
  const Eigen::Index n = L_rows.outerSize();
  validate_fixed(fixed, n, function);
  Umbrella U;
  U.moves.assign(n, 1);
  for (int v : fixed) U.moves[v] = 0;
  U.offsets.assign(n + 1, 0);
  U.columns.reserve(L_rows.nonZeros());
  U.weights.reserve(L_rows.nonZeros());
  const int* outer = L_rows.outerIndexPtr();
  const int* inner = L_rows.innerIndexPtr();
  const double* values = L_rows.valuePtr();
  for (Eigen::Index i = 0; i < n; ++i) {
    double total = 0.0;
    for (int k = outer[i]; k < outer[i + 1]; ++k)
      if (inner[k] != i) total += values[k];
    if (!(total > 0.0)) U.moves[i] = 0;
    if (U.moves[i]) {
      for (int k = outer[i]; k < outer[i + 1]; ++k) {
        if (inner[k] == i || values[k] == 0.0) continue;
        U.columns.push_back(inner[k]);
        U.weights.push_back(values[k] / total);
      }
    }
    U.offsets[i + 1] = static_cast<int>(U.columns.size());
  }
  bool equal = true;
  U.row_weight.assign(n, 0.0);
  for (Eigen::Index i = 0; i < n && equal; ++i) {
    if (U.offsets[i] == U.offsets[i + 1]) continue;
    U.row_weight[i] = U.weights[U.offsets[i]];
    for (int k = U.offsets[i]; k < U.offsets[i + 1]; ++k) equal = equal && U.weights[k] == U.row_weight[i];
  }
  if (equal) {
    U.weights.clear();
    U.weights.shrink_to_fit();
  } else {
    U.row_weight.clear();
  }
  return U;
}

void explicit_step(const Umbrella& U, double step, const VertexMatrix& before, VertexMatrix& after) {
  const Eigen::Index n = U.size();
  const double* p = before.data();
  double* q = after.data();
  const bool equal_weights = !U.row_weight.empty();
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 2048), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index i = range.begin(); i != range.end(); ++i) {
      const double* pi = p + 3 * i;
      double* qi = q + 3 * i;
      if (!U.moves[i]) {
        qi[0] = pi[0], qi[1] = pi[1], qi[2] = pi[2];
        continue;
      }
      double x = 0.0, y = 0.0, z = 0.0;
      if (equal_weights) {
        for (int k = U.offsets[i]; k < U.offsets[i + 1]; ++k) {
          const double* pj = p + 3 * static_cast<Eigen::Index>(U.columns[k]);
          x += pj[0];
          y += pj[1];
          z += pj[2];
        }
        const double w = U.row_weight[i];
        x *= w, y *= w, z *= w;
      } else {
        for (int k = U.offsets[i]; k < U.offsets[i + 1]; ++k) {
          const double w = U.weights[k];
          const double* pj = p + 3 * static_cast<Eigen::Index>(U.columns[k]);
          x += w * pj[0];
          y += w * pj[1];
          z += w * pj[2];
        }
      }
      // Σ_j u_ij = 1, so (U p)_i = Σ_j u_ij p_j − p_i.
      qi[0] = pi[0] + step * (x - pi[0]);
      qi[1] = pi[1] + step * (y - pi[1]);
      qi[2] = pi[2] + step * (z - pi[2]);
    }
  });
}

VertexMatrix run_steps(const VertexMatrix& start, int iterations, const std::vector<Step>& steps,
                       const Restriction& restriction, const Bound& bound, const Progress& progress,
                       const char* stage) {
  VertexMatrix current = start, next(start.rows(), 3);
  const double total = static_cast<double>(iterations) * static_cast<double>(steps.size());
  double done = 0.0;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    for (const Step& step : steps) {
      progress.report(done / total, stage);
      step(current, next);
      if (restriction) restriction(current, next);
      if (bound.control.bound != ErrorBound::none) {
        project_onto_error_bound(*bound.original, bound.axes, bound.meaning, bound.control, next);
      }
      std::swap(current, next);
      done += 1.0;
    }
  }
  progress.report(1.0, stage);
  return current;
}

}  // namespace meshsmith::smoothing::detail
