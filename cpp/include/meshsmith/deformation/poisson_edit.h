#pragma once
/// \file poisson_edit.h
/// Poisson (gradient-domain) mesh editing (§3.1.2 "Poisson Editing"; Yu et al. 2004, Zayer et
/// al. 2005): the edited surface Q keeps the rest surface's Laplacian coordinates δ = ΔP,
/// turned by per-vertex rotations R_i, as well as the constraints allow:
///     min ‖ΔQ − R δ‖²_M  with Q held at the handle and fixed vertices,
/// whose normal equations are L M⁻¹ L Q = L R δ (L the cotan Laplacian, M the Voronoi mass
/// matrix, Δ = M⁻¹ L). With every R_i = I this is Δ²Q = Δ²P, the bi-Laplacian deformation.
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::deformation {

/// Poisson editing with the handle vertices at handle_positions and the fixed ones in place.
/// rotate = true: R_i = exp(w_i log R_h), where R_h is the rotation that best fits the handle's
/// move (Kabsch, about the handle's centroid) and w the bi-harmonic interpolant of 1 on the
/// handle and 0 on the fixed vertices, so details turn gradually from the fixed region to the
/// handle; rotate = false: R = I.
/// V: #V×3, F: #F×3, handle: #H distinct indices (non-empty), fixed: distinct indices not in
/// the handle, handle_positions: #H×3. Returns #V×3 (vertices used by no face keep V).
/// Cost: one factorization of the order-2 free block and three solves.
/// \throw InputError as HarmonicDeformer, or for handle_positions of the wrong shape or with
///        NaN/Inf; SolverError as KHarmonicSolver.
VertexMatrix poisson_edit(const VertexRef& V, const FaceRef& F, const std::vector<int>& handle,
                          const std::vector<int>& fixed, const VertexRef& handle_positions, bool rotate = true);

}  // namespace meshsmith::deformation
