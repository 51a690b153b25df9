#pragma once
/// \file dual_loops.h
/// Dual-loop quad layouts (§5.3 "Surface layouts": generate loops along the cross field, select
/// them until every region is a disk with at most one singularity, dualize the arrangement;
/// Campen, Bommes & Kobbelt 2012 "Dual loops meshing: quality quad layouts on manifolds").
///
/// A loop is a closed path of mesh edges that follows one direction of a cross field: the
/// shortest closed path through a seed vertex in an anisotropic metric (travel along the field
/// costs its length, travel across it `anisotropy` times more — the curriculum's "ellipse"
/// tracing), returning to the seed with the same direction class after the field's period jumps.
/// Loops never pass through a singular vertex, never share an edge, never revisit a vertex, and
/// cross each other only transversally at a vertex, with orthogonal direction classes (two
/// loops per crossing at most; loops of one family may cross where parallel_crossing_penalty ≥ 0). The loops cut the surface into regions; the arrangement's dual —
/// one vertex per region, one quad per crossing — is the coarse quad layout.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/quadrangulation/cross_field.h>
#include <meshsmith/quadrangulation/quad_extraction.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace meshsmith::quadrangulation {

struct DualLoopOptions {
  /// Target distance between neighbouring loops of one direction family, in input units (about
  /// the coarse quad edge length). Loops are added until no vertex is farther than
  /// 0.75·spacing from a loop of either family (besides the region conditions). ≤ 0:
  /// sqrt(surface area) / 4.
  double spacing = 0.0;
  double anisotropy = 4.0;            ///< cost of travel across the field ÷ along it (≥ 1)
  double max_deviation_degrees = 70;  ///< edges deviating more from the loop's direction are not taken, in (0, 90)
  int max_loops = 300;                ///< loops selected at most
  int max_failed_seeds = 2000;        ///< seeds whose trace gave no usable loop, at most (then the selection stops)
  /// Crossings of two loops of one family (not orthogonal): < 0 not allowed; ≥ 0 allowed at this
  /// extra cost × spacing (a looser layout whose quads at those crossings are sheared).
  double parallel_crossing_penalty = -1.0;
};

/// One selected loop: a closed edge path (vertices[k] → vertices[k+1], the last back to the first).
struct DualLoop {
  std::vector<int> vertices;
  std::vector<int> crossings;  ///< positions in `vertices` where another loop crosses it
  double length = 0.0;         ///< in input units
  int seed = -1;               ///< the seed vertex it was traced through
};

struct DualLoopReport {
  Eigen::Index loops = 0, crossings = 0, segments = 0, regions = 0;
  Eigen::Index parallel_crossings = 0;    ///< crossings of two loops of one family (0 unless allowed)
  std::vector<int> region_euler;          ///< #regions χ of each region (1: a disk)
  std::vector<int> region_singularities;  ///< #regions singular vertices inside each region
  std::vector<int> region_corners;        ///< #regions crossing corners on each region's boundary (its layout valence)
  Eigen::Index non_disk_regions = 0;      ///< regions with χ ≠ 1
  Eigen::Index multi_singular_regions = 0;///< regions with more than one singularity
  Eigen::Index degenerate_quads = 0;      ///< layout quads with a repeated vertex
  Eigen::Index non_manifold_edges = 0;    ///< layout edges not shared by exactly two quads in opposite directions
  Eigen::Index non_manifold_vertices = 0; ///< layout vertices whose quads do not form one fan
  Eigen::Index low_valence_vertices = 0;  ///< layout vertices of valence 2 (two quads sharing two edges)
  long long euler_input = 0, euler_layout = 0;
  Eigen::Index seeds_tried = 0, seeds_failed = 0;
  Eigen::Index seeds_unclosed = 0;     ///< of the failed: no closed path back to the seed in its class within the budget
  Eigen::Index seeds_overlapping = 0;  ///< of the failed: the shortest closed path revisits a vertex, and the
                                       ///< search with one class per vertex found no other
  double max_distance_to_loops = 0.0;  ///< over the vertices, the largest distance to the nearer loop family (input units)
  double spacing = 0.0;                ///< the spacing used (input units)
  std::string failure;                 ///< empty when complete; otherwise where and why the layout is not a valid dual
  bool regions_valid() const { return non_disk_regions == 0 && multi_singular_regions == 0; }
  bool complete() const {
    return regions_valid() && degenerate_quads == 0 && non_manifold_edges == 0 && non_manifold_vertices == 0 &&
           low_valence_vertices == 0 &&
           euler_layout == euler_input && crossings > 0;
  }
};

struct DualLoopLayout {
  std::vector<DualLoop> loops;
  Eigen::VectorXi region;  ///< #F region of each face (0 .. regions−1)
  /// #regions×3 layout vertices: a region's singular vertex, else its vertex farthest from the loops,
  /// else (every vertex of the region on a loop) the centroid of its largest face
  VertexMatrix Vq;
  Eigen::VectorXi Vq_vertex;  ///< #regions the input vertex each layout vertex sits at (for a centroid: that face's nearest corner)
  QuadMatrix Q;            ///< #crossings×4 layout quads (regions around each crossing, counter-clockwise)
  Eigen::VectorXi Q_vertex;   ///< #crossings the input vertex of each crossing (the layout face's centre)
  Singularities singularities;
  DualLoopReport report;
};

/// Traces and selects dual loops on the closed mesh (V, F) along the cross field `theta` (#F
/// angles, as CrossField::theta) and builds the dual quad layout of their arrangement (§5.3).
/// Selection is greedy: the next seed is the vertex (and direction family) farthest from the
/// loops of that family (geodesic distance along edges, capped by twice the distance to the
/// nearest singularity), restricted to the faulty regions while a region is not a disk or holds
/// more than one singularity; a traced loop pays a separation penalty near loops of its own
/// family. It stops when the regions are valid and the loops cover the surface at `spacing`, or
/// when max_loops / max_failed_seeds is reached (the report then says what is missing). Then a
/// loop at a layout vertex of valence 2 is dropped where that lowers the layout's faults (with
/// the selection run again, up to 4 × 3 times, where valence 2 is the only fault left).
/// V: #V×3, F: #F×3, theta: #F.
/// \pre a clean, connected, oriented, closed 2-manifold.
/// \throw InputError as cross_field, for a mesh with boundary, a theta that is not #F finite
///        values, or options out of range; Cancelled from `progress`.
/// Complexity: one Dijkstra over 4#V (vertex, direction class) states per seed tried; a region
/// flood fill per loop tried as a drop.
DualLoopLayout dual_loop_layout(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta,
                                const DualLoopOptions& options = {}, const Progress& progress = {});

}  // namespace meshsmith::quadrangulation
