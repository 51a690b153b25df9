#pragma once
/// \file clustering.h
/// Vertex clustering on a uniform grid (§4.1; Rossignac & Borrel 1993, Lindstrom 2000 for the
/// quadric representative): every vertex falls into a cubic cell, each occupied cell becomes one
/// representative vertex, a triangle survives iff its three corners lie in three different cells,
/// and duplicate triangles are removed. Fast and robust, but the result need not be manifold.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

namespace meshsmith::decimation {

/// Where the representative of a cell goes (§4.1).
enum class ClusterRepresentative {
  cell_center,  ///< the center of the cell: cheapest, largest error
  centroid,     ///< mean of the cell's vertices (low-pass filter)
  median,       ///< per-coordinate median of the cell's vertices (numpy's median: mean of the two
                ///< middle values for an even count)
  quadric,      ///< minimiser of the summed squared distances to the planes of the triangles at the
                ///< cell's vertices (§4.1.1, Quadric::minimizer with the pseudo-inverse, started at
                ///< the centroid); falls back to the centroid if the minimiser leaves the cell
};

struct ClusteringOptions {
  double cell_size = 0.0;  ///< edge length of the cubic cells (> 0); the grid starts at min(V)
  ClusterRepresentative representative = ClusterRepresentative::quadric;
};

struct ClusteringResult {
  VertexMatrix V;                 ///< #V'×3 representatives of the cells used by surviving triangles
  FaceMatrix F;                   ///< #F'×3 surviving triangles, orientation of their first input copy
  Eigen::VectorXi vertex_cluster; ///< #V: output vertex of each input vertex, −1 where none (an
                                  ///< unreferenced vertex, or a cell all of whose triangles vanished)
  bool is_manifold = false;       ///< topology::is_manifold(F)
  double cell_size = 0.0;         ///< the cell size used
};

/// Clusters the vertices of (V, F) on a grid of cubes of edge `options.cell_size` (§4.1).
/// V: #V×3 positions, F: #F×3 triangles. Unreferenced vertices are ignored.
/// \pre validate_mesh(V, F) passes (called here).
/// \throw InputError if it does not, if the cell size is not a positive finite number, or if it is
///        so small that a grid axis would need 2²¹ cells or more.
ClusteringResult cluster_vertices(const VertexRef& V, const FaceRef& F, const ClusteringOptions& options,
                                  const Progress& progress = {});

/// Number of occupied grid cells (of referenced vertices) for `cell_size`: the vertex count
/// clustering produces before the representatives of vanished cells are dropped.
/// \pre as cluster_vertices. \throw InputError as cluster_vertices.
Eigen::Index occupied_cell_count(const VertexRef& V, const FaceRef& F, double cell_size);

/// The cell size whose occupied-cell count is closest to `target_vertices` without exceeding it
/// when that is reachable (within 0.5% below is accepted), found by bisection on the logarithm of
/// the cell size (the count falls monotonically only in tendency, so the best size seen is
/// returned).
/// \pre as cluster_vertices. \throw InputError if target_vertices < 1.
double cell_size_for_vertex_count(const VertexRef& V, const FaceRef& F, Eigen::Index target_vertices);

}  // namespace meshsmith::decimation
