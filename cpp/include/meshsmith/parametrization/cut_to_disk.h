#pragma once
/// \file cut_to_disk.h
/// Cutting a closed or higher-genus surface open into a topological disk along a cut graph, so
/// that every disk parametrization (harmonic, LSCM, ABF) runs on it (§5.2.2 step 2 "Surface
/// cutting": grow a spanning tree of triangles across edges, then keep the edges the dual tree
/// never crossed and prune their dangling branches; the 2g loops left, joined to the boundary,
/// are the cut. Erickson & Whittlesey 2005, Gu, Gortler & Hoppe 2002 "Geometry images").
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::parametrization {

/// A mesh cut open along a seam. Vertices on the seam are duplicated: one copy per side.
struct CutMesh {
  VertexMatrix V;                ///< #Vc×3 positions; V.row(i) == input V.row(vertex_origin[i])
  FaceMatrix F;                  ///< #F×3, face f uses the copies of the input face f's corners
  Eigen::VectorXi vertex_origin; ///< #Vc: the input vertex each output vertex copies; the first
                                 ///< #V entries are 0..#V-1 (every vertex keeps its index once,
                                 ///< extra copies are appended in the order of their originals)
  EdgeMatrix seam_edges;         ///< #C×2 input edges (i < j, lexicographic) that were cut open
};

/// Cuts (V, F) into one topological disk (one boundary loop, Euler characteristic 1).
///  - A disk is returned unchanged (empty seam).
///  - Otherwise faces are joined by a breadth-first spanning tree of the dual graph grown from
///    face 0 that never crosses an edge of the shortest-path tree (Dijkstra on edge lengths) from
///    vertex 0 — from all boundary vertices at once on a mesh with boundary — (tree–cotree); the edges it does not cross (boundary edges included) form a graph
///    whose vertices of degree one are pruned repeatedly. The interior edges that survive — the
///    2g handle loops, each an edge closed by two shortest paths, and the paths joining the
///    boundary loops — are the seam.
///  - A closed genus-0 mesh prunes to nothing: it is cut along the shortest edge path between two
///    far-apart vertices (the ends of a double sweep of Dijkstra's algorithm on edge lengths).
/// V: #V×3, F: #F×3 triangles.
/// \pre a clean, connected, oriented 2-manifold: no repeated-index or zero-area face, no unused
///      vertex (the checks of every parametrization in this chapter).
/// \throw InputError naming the first offending face, vertex or edge otherwise.
CutMesh cut_to_disk(const VertexRef& V, const FaceRef& F);

/// The same cut, made to pass through every vertex of `through` as well (the singularities of a
/// cross field for MIQ, §5.2.2 step 2: "the cut graph must contain all singularities"): each
/// listed vertex not already on the seam or the boundary is joined to it by its shortest edge
/// path (one Dijkstra sweep from the seam and boundary vertices; the paths form a forest hung
/// on the seam, so the result stays a disk). On a closed genus-0 mesh the first listed vertex
/// starts the seam (the path to its farthest vertex when it is the only one). A disk is cut too
/// when `through` lists an interior vertex. An empty `through` gives cut_to_disk(V, F).
/// \pre as cut_to_disk.
/// 	hrow InputError as cut_to_disk, or naming an entry of `through` outside [0, #V).
CutMesh cut_to_disk(const VertexRef& V, const FaceRef& F, const std::vector<int>& through);

}  // namespace meshsmith::parametrization
