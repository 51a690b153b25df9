#pragma once
/// \file spectral.h
/// Spectral Morse–Smale quadrangulation (§5.2.1; Dong, Bremer, Garland, Pascucci and Hart,
/// "Spectral Surface Quadrangulation", SIGGRAPH 2006): a Laplacian eigenfunction, its
/// Morse–Smale complex (maxima, minima, saddles and the steepest lines between them), whose cells
/// are quads with max–saddle–min–saddle corners, each cell mapped harmonically onto the unit
/// square and sampled by an n×m grid whose counts agree across shared sides.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/quadrangulation/quad_extraction.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace meshsmith::quadrangulation {

/// How a vertex of a piecewise-linear function is classified from its one-ring (Banchoff's
/// criterion): the neighbours above and below it form 2k alternating wedges.
enum class CriticalType : int {
  regular = 0,  ///< k = 1
  minimum = 1,  ///< every neighbour above
  saddle = 2,   ///< k ≥ 2: a saddle of multiplicity k − 1 (a monkey saddle counts twice)
  maximum = 3,  ///< every neighbour below
};

/// The Morse–Smale complex of a vertex function on a closed triangle mesh, traced on its edges.
struct MorseSmaleComplex {
  Eigen::VectorXi vertex_type;          ///< #V CriticalType values
  Eigen::VectorXi saddle_multiplicity;  ///< #V: k − 1 at saddles, 0 elsewhere
  Eigen::Index maxima = 0, minima = 0;
  Eigen::Index saddles = 0;             ///< with multiplicity: maxima − saddles + minima = χ
  /// The separatrices: vertex paths from a saddle to a maximum (ascending) or a minimum
  /// (descending), along mesh edges, pairwise vertex-disjoint but at their ends (so they cannot
  /// cross).
  std::vector<std::vector<int>> lines;
  std::vector<char> line_ascending;     ///< per line: 1 ascending, 0 descending
  /// Lines that met another line (every step up, or down, taken) and went on beside it, by the
  /// shortest path through free vertices to the extremum that line ends at.
  Eigen::Index detours = 0;
  /// Lines walled in by others that went on through the gaps between them (the mesh edges
  /// crossing a gap split at their midpoints; spectral_quadrangulate only).
  Eigen::Index gap_routes = 0;
  Eigen::VectorXi face_patch;           ///< #F: the cell of each face (−1 when the complex is incomplete)
  /// #P×4: each cell's corners counter-clockwise (as the faces), a maximum first, then a saddle,
  /// the minimum, the other saddle.
  QuadMatrix patch_corners;
  QuadMatrix patch_sides;               ///< #P×4: the line from corner k to corner k+1
  /// Empty when every saddle has all its lines and every cell is a disk bounded by four lines
  /// with max–saddle–min–saddle corners; otherwise what failed first (the cells are then empty).
  std::string problem;
  bool complete() const { return problem.empty(); }
};

/// The Morse–Smale complex of f (one value per vertex; ties broken by vertex index, the
/// simulation of simplicity, so every vertex is a maximum, minimum, saddle or regular). From
/// every saddle, one line per wedge of its one-ring: steepest ascent (largest slope Δf/|Δx|)
/// from an upper wedge to a maximum, steepest descent from a lower wedge to a minimum, each step
/// to a neighbour that no other line uses and that is no saddle. A line that meets another (all its
/// steps taken: PL gradient lines merge in valleys and on ridges) goes on beside it, by the
/// shortest path through free vertices to the extremum the other line ends at (counted in
/// detours). A saddle whose wedge has no free vertex leaves the complex incomplete (problem says
/// where; refining the mesh gives it room).
/// V: #V×3, F: #F×3, f: #V finite values.
/// \pre (V, F) is a clean, connected, closed, oriented 2-manifold.
/// \throw InputError if it is not (naming the element), or f has the wrong size or a NaN.
/// Complexity: O(#V · valence²).
MorseSmaleComplex morse_smale_complex(const VertexRef& V, const FaceRef& F,
                                      const Eigen::Ref<const Eigen::VectorXd>& f);

struct SpectralOptions {
  Eigen::Index target_faces = 0;    ///< about this many quads (0: quads of twice the mean edge length)
  Eigen::Index target_patches = 0;  ///< about this many cells (0: one per ~25 quads, in [8, 240])
  Eigen::Index eigenvector = 0;     ///< the eigenvector's index (≥ 1; 0: chosen from target_patches)
  /// true: one seamless parametrization of all cells coupled by transition functions, extracted
  /// by extract_quads (a candidate whose extraction is incomplete falls back to the cells' maps);
  /// false: each cell mapped on its own and sampled by its n×m grid.
  bool coupled = false;
};

struct SpectralQuadrangulation {
  VertexMatrix V;                 ///< #Vq×3 quad-mesh vertices, on the input surface
  QuadMatrix Q;                   ///< #Q×4 quads, counter-clockwise like the input
  Eigen::VectorXi quad_patch;     ///< #Q: the cell each quad lies in
  QuadMatrix patch_corners;       ///< #P×4: each cell's corners as rows of V (max, saddle, min, saddle)
  Eigen::Index eigenvector = 0;   ///< the eigenvector used (index into the ascending spectrum)
  double eigenvalue = 0.0;        ///< its eigenvalue λ (−L u = λ M u), input units
  Eigen::Index maxima = 0, minima = 0, saddles = 0;  ///< of the complex (saddles with multiplicity)
  Eigen::Index multi_saddles = 0;  ///< saddle vertices of multiplicity > 1
  Eigen::Index saddle_vertices = 0;  ///< saddle vertices (cells = saddles + saddle_vertices)
  Eigen::Index refinements = 0;   ///< 1-to-4 subdivisions applied so that the lines had room
  Eigen::Index detours = 0;       ///< lines that went on beside another (MorseSmaleComplex::detours)
  Eigen::Index gap_routes = 0;    ///< of them, lines that went through gaps (MorseSmaleComplex::gap_routes)
  Eigen::Index candidates_tried = 0;  ///< eigenvectors whose complex was traced
  Eigen::Index traced_faces = 0;  ///< faces of the surfaces traced, summed over every trace (the search's work)
  /// Extrema of the eigenvector cancelled (with as many saddles) by the persistence-based
  /// simplification before the complex was traced.
  Eigen::Index cancelled_extrema = 0;
  int simplification_rounds = 0;  ///< its sweep rounds (−1: it did not converge, f was kept)
  /// Of cancelled_extrema, those cancelled because only two lines reached them (a layout corner
  /// of valence 2), the complex then traced again.
  Eigen::Index cancelled_two_cell_extrema = 0;
  Eigen::Index two_cell_extrema = 0;  ///< extrema of the complex used that only two lines reach
  bool coupled = true;            ///< the coupled map made the quads (asked for, and its extraction complete;
                                  ///< otherwise the cells were mapped one by one)
  Eigen::Index flipped_before = 0;  ///< coupled map: triangles with det ≤ 0 in (u, v) as first solved
  Eigen::Index flipped_after = 0;   ///< coupled map: the same after the stiffening repair
  int repair_rounds = 0;            ///< coupled map: stiffening rounds run
};

/// Spectral quadrangulation of a closed surface (§5.2.1). Computes the lowest eigenpairs of the
/// cotangent Laplacian with the Voronoi mass matrix (geometry::laplacian_eigenpairs); takes the
/// eigenvector given, or the ones whose complex has 2·#saddles cells (Euler's formula for a quad
/// complex) nearest target_patches, in that order, until one gives a complete complex (with up to
/// two 1-to-4 subdivisions of the mesh, the function linearly interpolated, when lines lack room).
/// Chords of the lines (mesh edges joining two non-consecutive vertices of one line) are split at
/// their midpoints. Each cell is mapped onto the unit square by a mean-value harmonic map (Floater:
/// bijective, the square being convex and no edge joining two vertices of one side), its corners at (0,0), (1,0), (1,1), (0,1) and its
/// sides by arc length; the sides are grouped into chains (opposite sides of a cell, shared sides
/// of two cells) and every chain gets one count n = max(1, round(mean length / h)), h =
/// √(area / target_faces): the n×m grids conform, giving a pure, manifold, consistently oriented
/// quad mesh with the input's Euler characteristic. The step h is then rescaled (a few rounds) so
/// that Σ n·m comes nearest target_faces.
/// V: #V×3, F: #F×3.
/// \pre (V, F) is a clean, connected, closed, oriented 2-manifold.
/// \throw InputError if it is not, or an option is out of range; SolverError if no candidate
/// eigenvector gives a complete complex (the message says why the last one failed); Cancelled.
SpectralQuadrangulation spectral_quadrangulate(const VertexRef& V, const FaceRef& F,
                                               const SpectralOptions& options = {},
                                               const Progress& progress = {});

}  // namespace meshsmith::quadrangulation
