#pragma once
// Power diagrams (§2.1.4) in 2D and 3D: the regular triangulation of weighted sites and each
// site's power cell clipped to a box.
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::tessellation {

/// One power cell: a convex polygon (2D) or a convex polyhedron (3D).
struct PowerCell {
  /// 2D: k×2 polygon corners in counter-clockwise order. 3D: k×3 polyhedron corners.
  /// 0 rows when the cell is empty (hidden site, or cell outside the box).
  Eigen::MatrixXd vertices;
  /// 3D only: #F×3 triangles into `vertices`, outward-oriented (each planar face fanned). 2D: empty.
  FaceMatrix faces;
};

struct PowerDiagram {
  /// #S×3 triangles (CCW) in 2D or #S×4 positively oriented tetrahedra in 3D: the regular
  /// triangulation, indices into the sites. Empty when the sites are degenerate (collinear in
  /// 2D, coplanar in 3D, or fewer than d+1 visible sites).
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> triangulation;
  std::vector<PowerCell> cells;  ///< one per site, in input order
  std::vector<int> hidden;       ///< sites whose power cell is empty in R^d, increasing
};

/// Power diagram of weighted sites (§2.1.4; Aurenhammer 1987): the cell of site i is
/// { q in box : |q - p_i|^2 - w_i <= |q - p_j|^2 - w_j for all j }, w = squared radii.
/// The regular triangulation comes from CGAL (Regular_triangulation_2/3, exact predicates). Each
/// cell is built by clipping the box with the half-spaces of the site's neighbours in that
/// triangulation (of the lower-dimensional one for collinear/coplanar sites); the half-spaces are linear in
/// q, so clipping in double with a relative tolerance of 1e-12 of the box size is accurate to
/// about that tolerance (no cell is lost or duplicated: the tolerance only decides whether a
/// corner on a clipping plane is kept).
/// P: n×2 or n×3 sites, weights: n, bounds: 2d numbers (xmin, ymin, xmax, ymax[, zmin, zmax]).
/// \pre n >= 1, all finite, xmin < xmax etc.
/// \throw InputError for empty input, NaN/Inf, a wrong weight count or an empty box.
PowerDiagram power_diagram(const Eigen::Ref<const Eigen::MatrixXd>& P,
                           const Eigen::Ref<const Eigen::VectorXd>& weights,
                           const Eigen::Ref<const Eigen::VectorXd>& bounds);

}  // namespace meshsmith::tessellation
