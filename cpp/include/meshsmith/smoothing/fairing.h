#pragma once
/// \file fairing.h
/// Bi-Laplacian fairing (§3.0.2 "Physical Interpretation": the thin plate Δ²f = 0 with a C¹
/// boundary condition; Botsch & Kobbelt 2004): the free vertices move to the solution of
/// Δ²x = 0 (the order-2 system of deformation/harmonic_deformer.h, cotan Laplacian and Voronoi
/// mass matrix) while the held ones keep their positions.
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::smoothing {

/// The faired positions: every vertex on a boundary edge and every neighbour of one (the
/// boundary ring: holding both gives C¹ continuity there), and the vertices in `fixed`, keep
/// their positions; every other vertex used by a face solves (L M⁻¹ L x)_i = 0. Vertices used by
/// no face keep their positions.
/// V: #V×3, F: #F×3, fixed: distinct vertex indices (may be empty on a mesh with a boundary).
/// Returns #V×3. Cost: one sparse Cholesky factorization and one solve with 3 right-hand sides.
/// \pre every connected component holds a held vertex (a closed component needs `fixed` ones).
/// \throw InputError for invalid V, F, an index of `fixed` out of range or repeated, or a
///        component with nothing held (naming one of its vertices); SolverError as
///        deformation::KHarmonicSolver.
VertexMatrix bilaplacian(const VertexRef& V, const FaceRef& F, const std::vector<int>& fixed);

}  // namespace meshsmith::smoothing
