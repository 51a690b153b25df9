#pragma once
/// \file bijectivity.h
/// Is a piecewise-linear parametrization a bijection onto its image? (§5.2.2 local injectivity,
/// det(B − A, C − A) > 0 for every triangle; §5.1.1 a consistent parametrization.)
///
/// A map of a topological disk whose triangles all keep one orientation (none flipped, none
/// degenerate) and whose boundary polygon is simple is globally injective: the number of
/// pre-images of a point is the winding number of the boundary polygon around it, 0 or 1. The
/// test is therefore: (1) every UV triangle strictly counter-clockwise, or every one strictly
/// clockwise; (2) no two boundary edges meet except consecutive edges at their shared vertex,
/// and those do not fold back onto each other. All decisions use exact orientation predicates
/// (CGAL's filtered exact predicates), so nearly flat or nearly touching cases are decided
/// correctly. Boundary edges are paired by a box-intersection sweep, O(b log² b).
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>

#include <utility>
#include <vector>

namespace meshsmith::parametrization {

/// Why a map is or is not bijective.
struct BijectivityReport {
  bool bijective = false;
  int orientation = 0;                        ///< +1 all counter-clockwise, -1 all clockwise, 0 mixed or degenerate
  std::vector<int> degenerate_faces;          ///< faces with collinear UV corners, ascending
  std::vector<int> minority_faces;            ///< faces oriented against the majority (the flipped ones), ascending
  std::vector<std::pair<int, int>> crossing_boundary_edges;  ///< pairs of boundary edges (as 3f + k side
                                              ///< ids) that intersect; at most 100 are listed
  bool boundary_simple() const { return crossing_boundary_edges.empty(); }
};

/// Checks the parametrization UV of the triangles F as described above.
/// UV: #V×2 parameter positions, F: #F×3 triangles (a boundary edge is a side no other face
/// shares; for several boundary loops every loop must be simple and no two may meet — a
/// component nested inside another one's image is not detected).
/// \pre F indexes UV; UV is finite.
/// \throw InputError if F is empty, indexes outside UV, or UV holds a NaN/Inf.
BijectivityReport check_bijectivity(const geometry::ParameterRef& UV, const FaceRef& F);

/// check_bijectivity(UV, F).bijective.
bool is_bijective(const geometry::ParameterRef& UV, const FaceRef& F);

}  // namespace meshsmith::parametrization
