#pragma once
/// \file fill_holes.h
/// Hole filling (§2.4.1, Liepa 2003, "Filling holes in meshes"): each chosen boundary loop is
/// closed by the minimal-weight triangulation of the polygon it forms — weights compared
/// lexicographically, the largest dihedral angle first, then the total area — found by dynamic
/// programming, with the search space restricted to the faces of the 3D Delaunay triangulation of
/// the loop's vertices (Zou, Hu, Gu & Tai 2013, as CGAL does) or over every triangle (the exact
/// O(n³) version). The patch is then refined to the edge density around the hole (Liepa's √2
/// rule, splitting triangles at their centroids, with relaxing Delaunay flips) on the project's
/// halfedge mesh (core/mesh.h), and faired: its new vertices move to the solution of the
/// bi-Laplacian equation Δ²x = 0 (smoothing/fairing.h) with every other vertex held, so the patch
/// meets the surrounding surface with C¹ continuity.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <string>
#include <vector>

namespace meshsmith::repair {

/// Where the dynamic programme looks for triangles.
enum class HoleSearch {
  delaunay,  ///< faces of the 3D Delaunay triangulation of the loop; the exact search when it holds none
  exact,     ///< every triangle of loop vertices, O(n³) time and O(n²) memory
};

struct FillHolesOptions {
  /// Loop indices to fill (into topology::boundary_loops's order, longest first); empty: every
  /// loop that the size limits and keep_border let through.
  std::vector<int> holes;
  int max_hole_edges = 0;            ///< fill only loops of at most this many edges (0: no limit)
  double max_hole_diameter = 0.0;    ///< fill only loops whose vertices lie within this distance (0: no limit)
  /// Leave open, per connected component, its longest loop (by length) when it is at least
  /// kBorderRatio times longer than each other loop of the component (or the only one): the rim
  /// of a scan or the outline of an open surface.
  bool keep_border = false;
  HoleSearch search = HoleSearch::delaunay;
  bool refine = true;                ///< Liepa's √2 refinement with relaxing flips (at most 2^21 faces a patch)
  /// Bi-Laplacian fairing of the refined patch's new vertices (on the patch and the mesh faces
  /// at the loop's vertices, every vertex but the new ones held); nothing to do without refine.
  bool fair = true;
  double density = 1.4142135623730951;  ///< the refinement factor (Liepa's √2)
  /// Fill a hole together with its islands as one region: a loop of another component that lies
  /// inside a chosen loop (every vertex inside its polygon projected onto the plane of its
  /// Newell normal, within half the square root of its projected area of that plane, oriented
  /// against it, shorter) is joined to it by the shortest bridge edge between their vertices, and
  /// the joined polygon (the outer loop, a bridge, the island loop, the bridge back) is filled
  /// as one (an island's loop is then not kept by keep_border either). Off: every loop is filled
  /// on its own, so an island's patch and the hole's cross.
  bool islands = true;
};

/// The length ratio keep_border needs between the border and every other loop of its component.
constexpr double kBorderRatio = 2.0;

/// The exact search refuses loops longer than this (its table is O(n²) memory).
constexpr int kMaxExactHoleEdges = 2000;

/// One filled hole.
struct HolePatch {
  int loop = -1;                 ///< index of the loop in boundary_loops's order
  int loop_edges = 0;            ///< edges of the loop (= its vertices), its islands' not counted
  std::vector<int> islands;      ///< island loops filled with it (joined by bridge edges), ascending
  int faces = 0;                 ///< faces added
  int vertices = 0;              ///< vertices added (by refinement)
  bool delaunay = false;         ///< the Delaunay search space held the triangulation (else exact)
  int face_begin = 0;            ///< the patch's faces are output rows [face_begin, face_begin + faces)
  int vertex_begin = 0;          ///< its new vertices are output rows [vertex_begin, vertex_begin + vertices)
  /// The largest angle in degrees between the normals of two faces sharing an edge of the patch:
  /// its inner edges and the loop's edges, where it meets the mesh (0: flat; near 180: a fold-over).
  double max_dihedral_angle = 0.0;
  /// Mean length of the patch's inner edges over the mean length of the mesh edges at the loop's
  /// vertices (the surrounding ring); with no inner edge, of the patch's loop edges.
  double edge_length_ratio = 0.0;
};

/// A loop that was chosen but could not be filled, and why.
struct UnfilledHole {
  int loop = -1;
  std::string reason;
};

struct FillHolesResult {
  VertexMatrix V;                ///< the input vertices, then each patch's new ones
  FaceMatrix F;                  ///< the input faces in order, then each patch's faces
  std::vector<std::vector<int>> loops;   ///< every boundary loop of the input (boundary_loops order)
  std::vector<HolePatch> patches;        ///< in the order they were filled (ascending loop)
  std::vector<UnfilledHole> unfilled;    ///< chosen loops left open
  std::vector<int> kept_borders;         ///< loops left open by keep_border
};

/// Fills the holes of a triangle mesh. The faces of each patch are oriented like the faces around
/// the hole; the input's vertices and faces are kept unchanged, in order, and new elements are
/// appended. Each loop is filled independently, except that with options.islands a loop of an
/// island (a component floating inside a hole) is joined to the hole's loop by a bridge edge and
/// filled with it as one region (HolePatch::islands); a vertex where loops touch (a
/// pinched, non-manifold boundary vertex) is handled: no patch repeats a vertex within a face or
/// adds an edge the mesh already has, so the output has no new non-manifold edge.
/// V: #V×3, F: #F×3. Time per loop of n edges: O(n log n + t) for the Delaunay search (t the
/// Delaunay faces, about linear in n), O(n³) for the exact one; refinement is linear in the
/// faces it makes.
/// \pre the mesh is edge-manifold and oriented: every edge has at most two faces, traversed in
///      opposite directions (repair::clean gives such a mesh).
/// \throw InputError if validate_mesh fails, an edge has more than two faces or two faces in the
///        same direction, a loop index in options.holes is out of range, or an option is negative.
/// \throw SolverError as smoothing::bilaplacian; Cancelled from progress.
FillHolesResult fill_holes(const VertexRef& V, const FaceRef& F, const FillHolesOptions& options = {},
                           const Progress& progress = {});

}  // namespace meshsmith::repair
