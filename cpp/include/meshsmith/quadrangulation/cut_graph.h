#pragma once
/// \file cut_graph.h
/// Cutting a surface with a cross field into a disk through every singularity, and combing the
/// field on the disk (§5.2.2 step 2 "Surface cutting": a dual spanning tree, then pruning, gives
/// the 2g homology generators; the singularities are joined to them, so that the field is
/// combable on the cut surface: its period jumps vanish across every edge not cut). The cut
/// itself is parametrization::cut_to_disk's.
#include <meshsmith/core/types.h>
#include <meshsmith/parametrization/cut_to_disk.h>
#include <meshsmith/quadrangulation/cross_field.h>

#include <Eigen/Core>

namespace meshsmith::quadrangulation {

struct FieldCut {
  parametrization::CutMesh cut;    ///< the disk: vertex copies, faces, seam edges (input edges i < j)
  Singularities singularities;     ///< of the input field (all on the seam or the boundary)
  Eigen::VectorXd combed_theta;    ///< #F θ_f + r_f·π/2 (r_f integer): period jump 0 across every uncut interior edge
  Eigen::VectorXi seam_jumps;      ///< #C period jump of combed_theta across each seam edge, from the face whose
                                   ///< side runs i → j to the other, in {−1, 0, 1, 2}
};

/// Cuts (V, F) into a disk through every singular vertex of the field `theta` (#F angles, as
/// CrossField::theta) and combs the field on it (breadth-first across the uncut edges).
/// V: #V×3, F: #F×3.
/// \pre a clean, connected, oriented 2-manifold.
/// \throw InputError as cross_field or for a theta that is not #F finite values; SolverError if
///        the combing finds a non-zero period jump across an uncut edge (a singularity off the cut).
FieldCut cut_graph(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta);

}  // namespace meshsmith::quadrangulation
