#pragma once
// Internal to the tessellation chapter: the CGAL constrained Delaunay triangulation shared by
// constrained_delaunay (delaunay_cgal.cpp) and Delaunay refinement (refinement_cgal.cpp).
#include "planar_detail.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <vector>

namespace meshsmith::tessellation::detail {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

/// What a CDT vertex remembers: its input index (-1 for vertices CGAL or the refinement
/// creates: crossings, Steiner points) and, for a Steiner point refinement put on a
/// constrained edge, the piece of input segment it lies on (-1 otherwise; see refinement_cgal.cpp).
struct VertexInfo {
  int value = -1;
  int piece = -1;
};
using CdtVertex = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
/// Faces carry the in-domain flag (is_in_domain / set_in_domain).
using CdtFace = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using CdtTds = CGAL::Triangulation_data_structure_2<CdtVertex, CdtFace>;
// Exact_predicates_tag: crossing constraints are split at intersection points constructed in
// double precision, while every predicate stays exact.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, CdtTds, CGAL::Exact_predicates_tag>;

/// Checks the PSLG arguments, merges duplicate points, builds the CDT with its constraints (the
/// convex hull edges when there are no segments) and marks its domain: a face is in it unless it
/// can be reached from the unbounded face or from a face holding a hole seed without crossing a
/// constrained edge (Triangle's convention). The CDT holds the points multiplied by the returned
/// power of two (normalizing_scale).
/// \throw InputError as constrained_delaunay() documents.
double build_domain(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes, Cdt& cdt);

/// Input points first (unchanged), then every vertex the CDT created, in the order of CGAL's
/// vertex iteration; the triangles in the domain. Renumbers the created vertices' info().value.
PlanarMesh extract_domain(const PointRef2& P, Cdt& cdt, double scale);

}  // namespace meshsmith::tessellation::detail
