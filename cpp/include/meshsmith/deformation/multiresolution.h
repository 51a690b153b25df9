#pragma once
/// \file multiresolution.h
/// Multiresolution editing (§3.1.2 "Classical Multi-Resolution Modeling"; Kobbelt et al. 1998,
/// Botsch & Kobbelt 2004): a surface P is split into a smooth base P̄ (the bi-Laplacian fairing
/// of a region) and details P − P̄ expressed in local frames of the base, so that after the
/// base is edited into Q̄ the details are re-added in the frames of Q̄ (they turn with it).
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::deformation {

/// Details of a surface over a base, in the base's local frames.
struct DetailFrames {
  /// #V: the neighbour whose direction fixes each vertex's tangent; −1 where the base has no
  /// frame (a zero normal or tangent) or the vertex has no detail.
  Eigen::VectorXi neighbour;
  /// #V×3: (tangent, bitangent, normal) coefficients of the detail (0 without one).
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> coefficients;
  /// #V×3: the details in world coordinates, used where a frame is missing.
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> world;
};

/// The details V − base at the vertices with `with_detail[v]` (others: none) in the frames of
/// `base`: normal = base's angle-weighted vertex normal, tangent = the direction to the vertex's
/// first neighbour (in face order) projected off the normal, bitangent = normal × tangent.
/// V, base: #V×3; F: #F×3; with_detail: #V flags (empty: every vertex).
/// \throw InputError for invalid shapes, indices or NaN/Inf.
DetailFrames encode_details(const VertexRef& V, const VertexRef& base, const FaceRef& F,
                            const std::vector<char>& with_detail = {});

/// `base` + the details re-added in the frames of `base` (#V×3); where `base` has no frame at a
/// vertex, its world detail is added. \throw InputError for shapes that do not match `details`.
VertexMatrix decode_details(const VertexRef& base, const FaceRef& F, const DetailFrames& details);

/// The detail transfer of multiresolution editing: decode_details(edited_base, F,
/// encode_details(V, base, F)) — the details of V over `base` re-added on `edited_base`.
/// \throw InputError as encode_details, or if edited_base does not have #V rows.
VertexMatrix transfer_details(const VertexRef& V, const VertexRef& base, const FaceRef& F,
                              const VertexRef& edited_base);

}  // namespace meshsmith::deformation
