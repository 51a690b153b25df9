#pragma once
/// \file graph_cut.h
/// The unsigned route to a watertight surface (§2.2, §3.2 of the curriculum; Hornung & Kobbelt
/// 2006, "Robust reconstruction of watertight 3D models from non-uniformly sampled point clouds
/// without normal information"): no oriented normals, only an unsigned distance to the samples
/// on a voxel grid, and an s–t minimum cut of the grid graph between an outside seed and an
/// inside seed. The max-flow is Boykov & Kolmogorov's (2004) search-tree algorithm, written here.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <array>
#include <cstdint>
#include <vector>

namespace meshsmith::reconstruction {

/// An s–t graph with real capacities and Boykov–Kolmogorov max-flow (two search trees grown
/// from the terminals, augmentation along the path where they meet, orphans re-adopted; the
/// trees are reused between augmentations). Nodes 0..n-1; arcs are added in pairs.
/// Memory: 32 bytes per node; 24 bytes per edge until solve(), 48 from then on (the arcs in
/// compressed rows). At most 2^31 - 2 nodes and 2^30 - 1 edges.
/// Worst case O(n² m |cut|), in practice close to linear on grid graphs (the paper's
/// experiments; ours: see benchmarks/bench_reconstruction.py).
class MaxFlow {
 public:
  /// \throw InputError if nodes < 0 or nodes >= 2^31 - 1.
  explicit MaxFlow(std::int64_t nodes, std::int64_t edges_hint = 0);
  /// An edge u–v with capacity `forward` from u to v and `backward` from v to u (both >= 0).
  /// \throw InputError for a node out of range, u == v, a negative or non-finite capacity, or
  ///        the 2^30-th edge.
  void add_edge(std::int64_t u, std::int64_t v, double forward, double backward);
  /// Adds capacity from the source to u and from u to the sink (>= 0; accumulates).
  /// \throw InputError as add_edge.
  void add_terminal(std::int64_t u, double source, double sink);
  /// Runs the max-flow and returns its value. Later calls return the same value; edges or
  /// terminal capacities added after a solve() are added to the residual graph, and the next
  /// solve() returns the maximum flow of the whole graph.
  /// \throw Cancelled.
  double solve(const Progress& progress = {});
  /// After solve(): whether u is on the source side of the minimum cut (the nodes reachable from
  /// the source in the residual graph; the others are on the sink side).
  bool source_side(std::int64_t u) const;
  std::int64_t node_count() const { return static_cast<std::int64_t>(nodes_.size()) - 1; }

 private:
  struct Node {
    std::int32_t first = 0;           ///< arcs [first, next node's first) once in compressed rows
    std::int32_t parent = 0;          ///< arc to the parent, or kTerminal / kOrphan / kNone
    std::int32_t next_active = -1;    ///< FIFO of active nodes (-1: not queued; itself: last)
    std::int32_t stamp = 0;           ///< time its distance was last known valid
    std::int32_t distance = 0;        ///< arcs to the terminal along the parents (when stamped)
    std::int8_t tree = 0;             ///< 0 free, 1 source tree, 2 sink tree
    double terminal = 0.0;            ///< > 0: residual source → node; < 0: residual node → sink
  };
  struct Arc {
    std::int32_t head;    ///< node the arc points to
    std::int32_t sister;  ///< the reverse arc
    double residual;      ///< residual capacity
    double reverse;       ///< the sister's residual capacity (kept equal to it)
  };
  void to_rows();    ///< edge list → compressed rows (arcs_)
  void to_edges();   ///< compressed rows → edge list of residual capacities (before new edges)
  std::vector<Node> nodes_;                      ///< one more than node_count(): the rows' end
  std::vector<std::int32_t> edge_tail_, edge_head_;
  std::vector<double> edge_forward_, edge_backward_;
  std::vector<Arc> arcs_;
  double flow_ = 0.0;
  bool solved_ = false;
};

/// Options of graph_cut().
struct GraphCutOptions {
  int resolution = 64;    ///< cells along the samples' longest bounding-box edge, in [2, 1024]
  double crust = 2.0;     ///< crust half-width ÷ max(cell size, median sample spacing), in [0.5, 16]
  double exponent = 4.0;  ///< edge weight (d / crust width)^exponent + 1e-4, in [1, 16]
  VertexMatrix inside;    ///< optional inside seeds (positions, s×3); empty: found by a flood fill
};

/// The reconstructed surface and the cut.
struct GraphCutResult {
  VertexMatrix V;                      ///< #V×3
  FaceMatrix F;                        ///< #F×3, outward
  std::array<std::int64_t, 3> shape{};  ///< grid points per axis
  std::array<double, 3> origin{};       ///< position of grid point (0, 0, 0)
  double voxel_size = 0.0;              ///< grid spacing (the same on the three axes)
  double cut = 0.0;                     ///< value of the minimum cut (Σ weights of the cut edges)
  std::int64_t free_voxels = 0;         ///< grid points whose side the cut decided (graph nodes)
  std::int64_t inside_voxels = 0;       ///< grid points on the inside after the cut
};

/// Watertight reconstruction of the unoriented samples P (#P×3). On a grid of cubic cells
/// (`resolution` along the bounding box's longest edge, padded by the crust and two cells), the
/// unsigned distance d to the nearest sample (points::KdTree) is computed at every grid point.
/// The crust is the set of points with d < w = crust · max(cell, median sample spacing).
/// Without `inside` seeds, the grid points outside the crust reachable from the box's border
/// (6-connected) are the outside seed, those outside the crust and not reached the inside seed
/// — a fill that leaked through a gap between samples leaves only pockets near them, so until
/// the enclosed points include one at d >= 2w, w grows by 1.5 and the fill is redone
/// (InputError once 3w exceeds the largest d: a hole wider than the shape, or a shape thinner
/// than a cell; pass inside seeds or a finer resolution); with seeds, the border points are the
/// outside seed and the seeds' nearest grid points the inside one. Every other grid point is a
/// node of the graph, 6-neighbours joined by an edge of weight ((d_a + d_b) / 2w)^exponent +
/// 1e-4 (w the final crust width), so the minimum cut is a minimal surface weighted towards the samples. The surface is
/// the zero level set of d signed by the cut's side (negative inside), extracted by
/// marching_cubes: closed, edge-manifold and consistently outward, vertices within about half a
/// cell of the samples (the zero of the signed distance along each cut edge).
/// \pre #P >= 4 and P finite, not all on one line; options within the ranges above; at most
///      2^26 grid points; inside seeds finite, inside the grid and not on its border.
/// \throw InputError if a precondition fails (naming the row or option). \throw Cancelled.
/// Time O(grid points · log #P) for the distances plus the max-flow; memory O(grid points).
GraphCutResult graph_cut(const VertexRef& P, const GraphCutOptions& options = {}, const Progress& progress = {});

}  // namespace meshsmith::reconstruction
