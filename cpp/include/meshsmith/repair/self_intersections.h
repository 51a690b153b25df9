#pragma once
/// \file self_intersections.h
/// Self-intersecting face pairs of a triangle mesh (§2.4, mesh repair: detecting what cleaning
/// must resolve), with CGAL's exact predicates on an AABB tree of the faces.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

namespace meshsmith::repair {

/// The pairs (f, g), f < g, of faces that intersect other than along what they share: faces with
/// no common vertex that touch or cross; faces with one common vertex that meet elsewhere (an edge
/// of one crosses the other); faces with a common edge that fold onto each other (coplanar, on the
/// same side of the edge); faces on the same three vertices (duplicates). Rows sorted
/// lexicographically. Candidates are the pairs of faces whose closed bounding boxes meet
/// (CGAL::box_self_intersection_d, a streamed segment-tree sweep), decided in parallel with CGAL's
/// exact predicates (Epick: filtered, exact), so the answer depends neither on rounding nor on the
/// thread count. Degenerate faces (collinear or repeated corners: what
/// repair::clean removes) take no part.
/// V: #V×3, F: #F×3. Time O(#F log #F + k) for k candidate pairs.
/// \throw InputError if validate_mesh fails; Cancelled from progress.
EdgeMatrix self_intersections(const VertexRef& V, const FaceRef& F, const Progress& progress = {});

}  // namespace meshsmith::repair
