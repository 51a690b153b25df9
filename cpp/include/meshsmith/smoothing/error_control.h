#pragma once
/// \file error_control.h
/// Error control for smoothing (§3.0.2 "Error Control"; Desbrun et al. 1999 use the same
/// bounds): every vertex stays in a region around its original position p*, enforced after
/// every step of every smoothing method of this chapter by projecting (not scaling) each
/// position onto its region.
#include <meshsmith/core/types.h>

namespace meshsmith::smoothing {

/// Which region a vertex may move in.
enum class ErrorBound {
  none,          ///< unconstrained
  epsilon_ball,  ///< isotropic: |p − p*| ≤ ε (the ε-ball of §3.0.2)
  error_slab,    ///< anisotropic: |n*ᵀ(p − p*)| ≤ ε along the original unit normal n*, free
                 ///< tangentially (the error slab of §3.0.2). For curves: the component of
                 ///< p − p* orthogonal to the original unit tangent t* is at most ε long.
};

/// An error bound and its size ε (in the units of the positions; > 0 unless bound is none).
struct ErrorControl {
  ErrorBound bound = ErrorBound::none;
  double epsilon = 0.0;
};

/// What the rows of `axes` in project_onto_error_bound mean for an error slab.
enum class SlabAxis {
  normal,   ///< surfaces: the bounded component is the one along the unit normal
  tangent,  ///< curves: the bounded component is the one orthogonal to the unit tangent
};

/// Projects every row of V onto its admissible region around original.row(i): the closest
/// point of the ε-ball (radial projection) or of the slab (the normal component clamped to
/// ±ε, the tangential one kept). The result satisfies the bound exactly as evaluated in double
/// precision from the stored positions — |V_i − p*_i| (the Euclidean norm of the rounded
/// difference) ≤ ε, or |Σ_k axes_ik (V_ik − p*_ik)| ≤ ε summed in k order — because the target
/// is ε(1 − 4·2⁻⁵²) and any row still outside after rounding is pulled in again. Rows with a zero
/// axis (a vertex without a normal) are bounded by the ε-ball instead. Parallel over rows.
/// V, original, axes: #V×3 (axes: unit rows; used by error_slab only). Rows already inside are
/// left bit for bit unchanged.
/// \pre V, original and axes have the same number of rows; control.epsilon > 0 unless none.
/// \throw InputError if the preconditions fail.
void project_onto_error_bound(const VertexRef& original, const VertexRef& axes, SlabAxis axis_meaning,
                              const ErrorControl& control, VertexMatrix& V);

/// \throw InputError naming `function` unless control is none or has a finite ε > 0.
void validate_error_control(const ErrorControl& control, const char* function);

}  // namespace meshsmith::smoothing
