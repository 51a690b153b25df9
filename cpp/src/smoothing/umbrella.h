#pragma once
// Internal to the smoothing chapter (not installed): the umbrella operator U = D⁻¹L as compact
// rows, its explicit step, and the step loop shared by meshes and curves.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/smoothing/error_control.h>

#include <Eigen/SparseCore>

#include <functional>
#include <vector>

namespace meshsmith::smoothing::detail {

/// Row i of U without its diagonal (−1): u_ij = w_ij / Σ_j w_ij over columns[offsets[i] ..
/// offsets[i+1]). `moves[i]` is 0 for a vertex held in place (fixed, or whose weights sum to 0).
/// When every row's weights are equal (uniform weights, polylines), `weights` is empty and
/// `row_weight[i]` = 1/deg(i) stands for them: the explicit step then streams 4 bytes per
/// neighbour instead of 12.
struct Umbrella {
  std::vector<int> offsets;
  std::vector<int> columns;
  std::vector<double> weights;
  std::vector<double> row_weight;
  std::vector<char> moves;
  Eigen::Index size() const { return static_cast<Eigen::Index>(moves.size()); }
};

/// The umbrella operator of the Laplacian L (n×n, libigl's signs: L_ij = w_ij, L_ii = −Σ_j w_ij),
/// whose row i holds vertex i's weights. `L_rows` is L itself when L is symmetric, else Lᵀ
/// (CSC columns = rows of L). Vertices in `fixed` and vertices whose weights do not sum to a
/// positive number do not move. (Cot weights sum to Σ ½(cot B + cot C) = Σ ½|jk| / h_i > 0 over
/// the vertex's triangles, mean-value weights are positive: only degenerate neighbourhoods, whose
/// weights are 0, stay.)
/// \throw InputError naming `function` if an index of fixed is outside [0, n).
Umbrella umbrella_operator(const Eigen::SparseMatrix<double>& L_rows, const std::vector<int>& fixed,
                           const char* function);

/// \throw InputError naming `function` unless every index of fixed is in [0, n).
void validate_fixed(const std::vector<int>& fixed, Eigen::Index n, const char* function);

/// after = before + step·(U before) on the moving rows, = before on the others. Parallel.
void explicit_step(const Umbrella& U, double step, const VertexMatrix& before, VertexMatrix& after);

/// One step of a smoothing method: writes the positions after the step into `after`.
using Step = std::function<void(const VertexMatrix& before, VertexMatrix& after)>;
/// Restricts a step's displacement (direction projection): may rewrite `after` from `before`.
using Restriction = std::function<void(const VertexMatrix& before, VertexMatrix& after)>;

/// The error bound of a run: the original positions and, for a slab, their axes.
struct Bound {
  ErrorControl control;
  const VertexMatrix* original = nullptr;
  VertexMatrix axes;  // #V×3 unit normals or tangents (error_slab only)
  SlabAxis meaning = SlabAxis::normal;
};

/// Runs `iterations` rounds of `steps` (one step per round, or Taubin's λ and μ steps) from
/// `start`: after each step the restriction (if any), then the error bound. Reports progress once
/// per step under `stage`. Returns the final positions.
VertexMatrix run_steps(const VertexMatrix& start, int iterations, const std::vector<Step>& steps,
                       const Restriction& restriction, const Bound& bound, const Progress& progress,
                       const char* stage);

}  // namespace meshsmith::smoothing::detail
