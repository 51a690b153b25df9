// Screened Poisson reconstruction (reconstruction/poisson.h).
//
// Data structures. Every level works in the unit cube (the bounding cube mapped to [0, 1]³),
// n = 2^d cells per axis, cells grouped in blocks of 2³ (measured on the bunny at depth 8:
// blocks of 4³ made the finest band 1.5M nodes instead of 1.2M, and band 1 instead of 2 takes it
// to 0.8M at the same distances to the ground truth). A level keeps its band blocks (sorted
// keys, and a block table: dense up to depth 8, a hash map beyond), and for each band block the
// node ids of its 3³ corners, so that a cell's eight nodes are found with one lookup. Nodes are
// numbered in key order (through a dense table up to depth 7, by sorting beyond); the free
// ones (every cell around them that lies in the cube is a band cell) get a row of the system with
// 27 fixed slots (neighbour offsets in {−1, 0, 1}³), the others are Dirichlet nodes valued from
// the coarser level. The Q1 integrals are tensor products of 1-D integrals, truncated at the
// cube's faces (natural boundary conditions there).
//
// Cost (measured on pmp-bunny.xyz, depth 8, extraction depth 7, one thread, CPU seconds with
// MESHSMITH_POISSON_PROFILE=1, which prints each stage's wall and CPU time to stderr): of 0.5 s,
// the finest level's system 0.12 and solve 0.09 (12 CG iterations on 216k unknowns, memory
// bound: 27 slots of 12 bytes per row), sample depths 0.04, density 0.05, marching cubes 0.04,
// splatting 0.03, the coarser levels the rest.
//
// Determinism: splatting and the screening terms are accumulated sample by sample in input order
// on the calling thread; rows, matrix-vector products and evaluations are per item; the dot
// products of the conjugate gradients sum fixed chunks in a fixed order. Nothing depends on the
// number of threads.
#include <meshsmith/reconstruction/poisson.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/points/kd_tree.h>
#include <meshsmith/reconstruction/marching_cubes.h>

#include <Eigen/Eigenvalues>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <string>
#include <unordered_map>

namespace meshsmith::reconstruction {
namespace {

using Int = std::int64_t;
constexpr int B = 2;                          // cells per block edge
constexpr int C = B + 1;                      // corner nodes per block edge
constexpr int CORNERS = C * C * C;
constexpr std::int64_t DENSE_BLOCKS = std::int64_t(1) << 21;  // a dense block table up to 8 MB (depth 8)
constexpr std::int64_t DENSE_NODES = std::int64_t(1) << 22;   // a dense node table up to 16 MB (depth 7)

/// 1-D integrals of hat functions on nodes 0..n (unit spacing): ψ_i ψ_{i+o}, ψ_i' ψ_{i+o}',
/// ψ_{i+o} ψ_i', over the intervals next to node i that lie in [0, n].
struct Factors {
  double mass[3], stiffness[3], derivative[3];  // index o + 1
  Factors(Int i, Int n) {
    const bool left = i > 0, right = i < n;
    mass[0] = left ? 1.0 / 6 : 0.0, mass[2] = right ? 1.0 / 6 : 0.0;
    mass[1] = (left ? 1.0 / 3 : 0.0) + (right ? 1.0 / 3 : 0.0);
    stiffness[0] = left ? -1.0 : 0.0, stiffness[2] = right ? -1.0 : 0.0;
    stiffness[1] = (left ? 1.0 : 0.0) + (right ? 1.0 : 0.0);
    derivative[0] = left ? 0.5 : 0.0, derivative[2] = right ? -0.5 : 0.0;
    derivative[1] = (left ? 0.5 : 0.0) + (right ? -0.5 : 0.0);
  }
};

struct Level {
  int depth = 0;
  Int n = 0;       // cells per axis
  double h = 0.0;  // 1 / n
  Int blocks_per_axis = 0;
  std::vector<Int> block_keys;
  std::unordered_map<Int, int> block_index;  // when blocks_per_axis³ > DENSE_BLOCKS
  std::vector<int> block_dense;              // block per key (or -1) when blocks_per_axis³ <= DENSE_BLOCKS
  std::vector<std::array<int, CORNERS>> corner_id;
  std::vector<Int> node_key;        // sorted
  std::vector<int> row_of_node;     // free row or -1
  std::vector<int> node_of_row;
  Eigen::VectorXd value;            // χ per node
  std::vector<double> field;        // V per node, 3 doubles
  std::vector<double> deposit;      // W per node, 3 doubles (samples splatted at this level or coarser)

  Int node_key_of(Int i, Int j, Int k) const { return (i * (n + 1) + j) * (n + 1) + k; }
  int find_block(Int bi, Int bj, Int bk) const {
    const Int key = (bi * blocks_per_axis + bj) * blocks_per_axis + bk;
    if (!block_dense.empty()) return block_dense[static_cast<std::size_t>(key)];
    const auto it = block_index.find(key);
    return it == block_index.end() ? -1 : it->second;
  }
  /// find_block with a one-entry cache held by the caller (consecutive lookups mostly repeat).
  int find_block(Int bi, Int bj, Int bk, Int& cached_key, int& cached_index) const {
    const Int key = (bi * blocks_per_axis + bj) * blocks_per_axis + bk;
    if (!block_dense.empty()) return block_dense[static_cast<std::size_t>(key)];
    if (key != cached_key) {
      const auto it = block_index.find(key);
      cached_key = key;
      cached_index = it == block_index.end() ? -1 : it->second;
    }
    return cached_index;
  }
  /// The band cell holding unit position y: its block (or -1), the cell, the local coordinates.
  int locate(const double* y, Int* cell, double* t) const {
    for (int a = 0; a < 3; ++a) {
      const double x = y[a] * static_cast<double>(n);
      cell[a] = std::min<Int>(n - 1, std::max<Int>(0, static_cast<Int>(std::floor(x))));
      t[a] = std::min(1.0, std::max(0.0, x - static_cast<double>(cell[a])));
    }
    return find_block(cell[0] / B, cell[1] / B, cell[2] / B);
  }
  /// The 8 node ids of `cell` in block `block` (corner c: offsets c & 1, c >> 1 & 1, c >> 2).
  void cell_nodes(int block, const Int* cell, int* ids) const {
    const int li = static_cast<int>(cell[0] % B), lj = static_cast<int>(cell[1] % B), lk = static_cast<int>(cell[2] % B);
    const auto& table = corner_id[static_cast<std::size_t>(block)];
    for (int c = 0; c < 8; ++c) ids[c] = table[((li + (c & 1)) * C + lj + ((c >> 1) & 1)) * C + lk + (c >> 2)];
  }
};

void trilinear_weights(const double* t, double* w) {
  for (int c = 0; c < 8; ++c)
    w[c] = ((c & 1) ? t[0] : 1.0 - t[0]) * (((c >> 1) & 1) ? t[1] : 1.0 - t[1]) * ((c >> 2) ? t[2] : 1.0 - t[2]);
}

/// The 8 nodes and trilinear weights at unit position y on `level`; false outside its band.
bool interpolation(const Level& level, const double* y, int* ids, double* w) {
  Int cell[3];
  double t[3];
  const int block = level.locate(y, cell, t);
  if (block < 0) return false;
  level.cell_nodes(block, cell, ids);
  trilinear_weights(t, w);
  return true;
}

/// χ at unit position y, from level `top` down to the first level holding y in its band (the
/// coarsest holds every cell).
double evaluate_value(const std::vector<Level>& levels, int top, const double* y) {
  int ids[8];
  double w[8];
  for (int l = top; l >= 0; --l) {
    const Level& level = levels[static_cast<std::size_t>(l)];
    if (!interpolation(level, y, ids, w)) continue;
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) sum += w[c] * level.value[ids[c]];
    return sum;
  }
  return 0.0;
}

/// The level's deposit (3 components) at unit position y; 0 outside its band.
void evaluate_deposit(const Level& level, const double* y, double* out) {
  out[0] = out[1] = out[2] = 0.0;
  int ids[8];
  double w[8];
  if (!interpolation(level, y, ids, w)) return;
  for (int c = 0; c < 8; ++c)
    for (int a = 0; a < 3; ++a) out[a] += w[c] * level.deposit[3 * static_cast<std::size_t>(ids[c]) + a];
}

/// Sum of f(i) over [0, n) in fixed chunks, in a fixed order (thread-count independent).
template <typename Term>
double deterministic_sum(Int n, const Term& term) {
  constexpr Int chunk = 8192;
  const Int chunks = (n + chunk - 1) / chunk;
  std::vector<double> partial(static_cast<std::size_t>(chunks), 0.0);
  tbb::parallel_for(tbb::blocked_range<Int>(0, chunks, 1), [&](const tbb::blocked_range<Int>& r) {
    for (Int c = r.begin(); c < r.end(); ++c) {
      double s = 0.0;
      for (Int i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) s += term(i);
      partial[static_cast<std::size_t>(c)] = s;
    }
  });
  double total = 0.0;
  for (double p : partial) total += p;
  return total;
}

template <typename Body>
void parallel_rows(Int n, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<Int>(0, n, 1024), [&](const tbb::blocked_range<Int>& r) {
    for (Int i = r.begin(); i < r.end(); ++i) body(i);
  });
}


/// Crack-free iso-surface extraction on the leaves of the level hierarchy (adaptive mode).
///
/// The levels form an octree: with blocks of 2³ cells, a block of level d + 1 is a cell of level
/// d, so a band cell of level d is refined exactly when its block exists on level d + 1, and a
/// leaf otherwise. χ is continuous and trilinear on each leaf; on a leaf's boundary the nodes of
/// finer levels are Dirichlet nodes valued from the leaf (the leaf's children are not in the
/// finer bands), so along any axis-parallel edge of a leaf χ is one linear function and every
/// level sees the same values there. As in Kazhdan, Klein, Dalal & Hoppe (2007), "Unconstrained
/// isosurface extraction on arbitrary octrees", each leaf's polygon is closed from iso-segments
/// on the finest subdivision of its faces (the faces of the finer leaves across them) and of
/// those faces' edges (split wherever a finer cell touches the edge); a crossing is keyed by the
/// finest sub-edge it lies on, and its position computed from that sub-edge's two node values,
/// so the leaves on both sides of a face produce the same segments in opposite directions:
/// edge-manifold and closed wherever the surface stays inside the cube. Ambiguous face squares
/// are decided by the bilinear saddle value (asymptotic decider) computed from the square's
/// corners in a fixed order. A loop is triangulated with least area by chords that join vertices
/// on no common face of the leaf (such a chord belongs to this leaf only), or else around an
/// added centroid vertex.
class LeafExtractor {
 public:
  LeafExtractor(const std::vector<Level>& levels, double iso, const Eigen::RowVector3d& corner, double size)
      : levels_(levels), iso_(iso), corner_(corner), size_(size), top_(static_cast<int>(levels.size()) - 1) {}

  ContourMesh run(const Progress& progress) {
    for (int l = 0; l <= top_; ++l) {
      const Level& level = levels_[static_cast<std::size_t>(l)];
      progress.report(static_cast<double>(l) / (top_ + 1), "poisson: extraction");
      for (std::size_t b = 0; b < level.block_keys.size(); ++b) {
        const Int key = level.block_keys[b];
        const Int nb = level.blocks_per_axis;
        const Int origin[3] = {key / (nb * nb) * B, (key / nb) % nb * B, key % nb * B};
        for (int c = 0; c < 8; ++c) {
          const Int q[3] = {origin[0] + (c & 1), origin[1] + ((c >> 1) & 1), origin[2] + (c >> 2)};
          if (refined(l, q)) continue;
          int ids[8];
          level.cell_nodes(static_cast<int>(b), q, ids);
          int above = 0;
          for (int k = 0; k < 8; ++k) above += level.value[ids[k]] >= iso_ ? 1 : 0;
          if (above == 0 || above == 8) continue;
          leaf_polygons(l, q);
        }
      }
    }
    ContourMesh mesh;
    mesh.centre_vertices = centre_vertices_;
    mesh.V.resize(static_cast<Eigen::Index>(positions_.size()), 3);
    for (std::size_t v = 0; v < positions_.size(); ++v) mesh.V.row(static_cast<Eigen::Index>(v)) = positions_[v];
    mesh.F.resize(static_cast<Eigen::Index>(triangles_.size()), 3);
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      for (int a = 0; a < 3; ++a) mesh.F(static_cast<Eigen::Index>(t), a) = triangles_[t][static_cast<std::size_t>(a)];
    return mesh;
  }

  Int leaves_visited() const { return leaves_; }

 private:
  struct Crossing {
    std::uint64_t key;
    int vertex;
    int faces;  // bit 2·axis + side: the faces of the current leaf holding the vertex
  };
  struct Segment {
    int from, to;  // indices into the leaf's crossing list
  };
  struct SubEdge {
    int l;
    Int s[3];
  };

  const std::vector<Level>& levels_;
  double iso_;
  Eigen::RowVector3d corner_;
  double size_;
  int top_;
  Int leaves_ = 0;
  Int centre_vertices_ = 0;
  std::unordered_map<std::uint64_t, int> vertex_of_key_;
  std::vector<Eigen::RowVector3d> positions_;
  std::vector<std::array<int, 3>> triangles_;
  // Per leaf (reused).
  std::vector<Crossing> crossings_;
  std::vector<Segment> segments_;
  std::vector<SubEdge> cycle_;

  bool exists(int l, const Int* q) const {
    const Level& level = levels_[static_cast<std::size_t>(l)];
    for (int a = 0; a < 3; ++a)
      if (q[a] < 0 || q[a] >= level.n) return false;
    return level.find_block(q[0] / B, q[1] / B, q[2] / B) >= 0;
  }
  /// The cell q of level l (in the cube) has children: its block exists on level l + 1.
  bool refined(int l, const Int* q) const {
    if (l >= top_) return false;
    const Level& level = levels_[static_cast<std::size_t>(l)];
    for (int a = 0; a < 3; ++a)
      if (q[a] < 0 || q[a] >= level.n) return false;
    return levels_[static_cast<std::size_t>(l + 1)].find_block(q[0], q[1], q[2]) >= 0;
  }
  /// χ at node p of level l, from an existing cell of level l around it.
  double node_value(int l, const Int* p) const {
    const Level& level = levels_[static_cast<std::size_t>(l)];
    for (int c = 0; c < 8; ++c) {
      const Int q[3] = {p[0] - (c & 1), p[1] - ((c >> 1) & 1), p[2] - (c >> 2)};
      if (!exists(l, q)) continue;
      int ids[8];
      level.cell_nodes(level.find_block(q[0] / B, q[1] / B, q[2] / B), q, ids);
      return level.value[ids[c]];  // node p is corner c of cell q
    }
    return iso_;  // not reached: p is a corner of an existing cell
  }
  /// Appends the finest subdivision of the edge of level l along axis a from node s, in order.
  void subdivide(int l, int a, const Int* s, std::vector<SubEdge>& out) const {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    bool split = false;
    for (int o = 0; o < 4 && !split; ++o) {
      Int q[3] = {s[0], s[1], s[2]};
      q[b] -= o & 1, q[c] -= o >> 1;
      split = refined(l, q);
    }
    if (!split) {
      out.push_back({l, {s[0], s[1], s[2]}});
      return;
    }
    Int t[3] = {2 * s[0], 2 * s[1], 2 * s[2]};
    subdivide(l + 1, a, t, out);
    t[a] += 1;
    subdivide(l + 1, a, t, out);
  }
  std::uint64_t edge_key(const SubEdge& e, int a) const {
    return ((((static_cast<std::uint64_t>(a) * 16 + static_cast<std::uint64_t>(e.l)) * 2048 + static_cast<std::uint64_t>(e.s[0])) * 2048 +
             static_cast<std::uint64_t>(e.s[1])) * 2048) + static_cast<std::uint64_t>(e.s[2]);
  }
  /// The vertex of the crossing on sub-edge e (axis a): interpolated from its end values in
  /// increasing order, so every leaf computes the same position.
  int vertex(const SubEdge& e, int a, double low, double high) {
    const std::uint64_t key = edge_key(e, a);
    const auto found = vertex_of_key_.find(key);
    if (found != vertex_of_key_.end()) return found->second;
    const double t = std::min(1.0, std::max(0.0, (iso_ - low) / (high - low)));
    const double h = size_ / static_cast<double>(levels_[static_cast<std::size_t>(e.l)].n);
    Eigen::RowVector3d x;
    for (int k = 0; k < 3; ++k) x[k] = corner_[k] + h * (static_cast<double>(e.s[k]) + (k == a ? t : 0.0));
    const int id = static_cast<int>(positions_.size());
    positions_.push_back(x);
    vertex_of_key_.emplace(key, id);
    return id;
  }
  /// The faces of leaf (l, q) holding a point of sub-edge e along axis a (strictly inside it along a).
  int faces_of(int l, const Int* q, const SubEdge& e, int a) const {
    int mask = 0;
    const int shift = e.l - l;
    for (int k = 0; k < 3; ++k) {
      if (k == a) continue;
      if (e.s[k] == q[k] << shift) mask |= 1 << (2 * k);
      if (e.s[k] == (q[k] + 1) << shift) mask |= 1 << (2 * k + 1);
    }
    return mask;
  }

  /// The iso-segments of the face square of cell r of level l, normal axis n, side `side` (1:
  /// the cell's face at r[n] + 1), oriented for the leaf (l0, q0) whose outward normal there is
  /// +n if `outward_positive`: the leaf's loop runs counter-clockwise around the surface normal,
  /// which points to χ >= iso.
  void face_square(int l0, const Int* q0, int l, const Int* r, int n, int side, bool outward_positive) {
    const int u = (n + 1) % 3, v = (n + 2) % 3;
    Int base[3] = {r[0], r[1], r[2]};
    base[n] += side;
    // Corners counter-clockwise around +n: (0,0), (1,0), (1,1), (0,1) in (u, v); each edge of
    // the square from its lower node along u or v.
    auto corner_node = [&](int du, int dv, Int* p) {
      p[0] = base[0], p[1] = base[1], p[2] = base[2];
      p[u] += du, p[v] += dv;
    };
    Int p00[3], p10[3], p01[3], p11[3];
    corner_node(0, 0, p00), corner_node(1, 0, p10), corner_node(0, 1, p01), corner_node(1, 1, p11);
    const double a00 = node_value(l, p00) - iso_, a10 = node_value(l, p10) - iso_, a01 = node_value(l, p01) - iso_,
                 a11 = node_value(l, p11) - iso_;
    // The boundary cycle (around +n): sub-edges with their traversal direction.
    struct Step {
      SubEdge e;
      int axis;
      bool forward;
    };
    std::vector<Step> steps;
    auto add_edge = [&](const Int* from, int axis, bool forward) {
      cycle_.clear();
      subdivide(l, axis, from, cycle_);
      if (forward)
        for (const SubEdge& e : cycle_) steps.push_back({e, axis, true});
      else
        for (auto it = cycle_.rbegin(); it != cycle_.rend(); ++it) steps.push_back({*it, axis, false});
    };
    add_edge(p00, u, true);
    add_edge(p10, v, true);
    add_edge(p01, u, false);
    add_edge(p00, v, false);
    if (!outward_positive) {
      std::reverse(steps.begin(), steps.end());
      for (Step& s : steps) s.forward = !s.forward;
    }
    // Crossings in cycle order: leaving (χ >= iso to χ < iso along the traversal) or entering.
    struct Found {
      int index;  // into crossings_
      bool leaving;
    };
    std::vector<Found> found;
    for (const Step& s : steps) {
      Int hi[3] = {s.e.s[0], s.e.s[1], s.e.s[2]};
      hi[s.axis] += 1;
      const double low = node_value(s.e.l, s.e.s), high = node_value(s.e.l, hi);
      const bool low_above = low >= iso_, high_above = high >= iso_;
      if (low_above == high_above) continue;
      const int id = vertex(s.e, s.axis, low, high);
      crossings_.push_back({edge_key(s.e, s.axis), id, faces_of(l0, q0, s.e, s.axis)});
      const bool from_above = s.forward ? low_above : high_above;
      found.push_back({static_cast<int>(crossings_.size()) - 1, from_above});
    }
    const std::size_t k = found.size();
    if (k < 2) return;
    // Pair each leaving crossing with the next entering one (χ >= iso connected across the
    // square) or the previous one; the saddle value decides, from the corners in a fixed order.
    bool above_connected = true;
    if (k > 2) {
      const double denominator = a00 + a11 - a10 - a01;
      const double numerator = a00 * a11 - a10 * a01;
      above_connected = denominator == 0.0 || (numerator / denominator) >= 0.0;
    }
    for (std::size_t i = 0; i < k; ++i) {
      if (!found[i].leaving) continue;
      const std::size_t j = above_connected ? (i + 1) % k : (i + k - 1) % k;
      segments_.push_back({found[i].index, found[j].index});
    }
  }

  /// The faces of the finer leaves across face (n, side) of leaf (l0, q0), or the leaf's own.
  void gather_face(int l0, const Int* q0, int l, const Int* r, int n, int side, bool outward_positive) {
    // r: a cell of level l across the face (its face 1 - side touches the leaf's face).
    if (!refined(l, r)) {
      Int own[3] = {r[0], r[1], r[2]};
      own[n] -= side ? 1 : -1;  // back to the leaf side: the face is shared, take the leaf-side cell's face
      face_square(l0, q0, l, own, n, side, outward_positive);
      return;
    }
    const int u = (n + 1) % 3, v = (n + 2) % 3;
    for (int o = 0; o < 4; ++o) {
      Int child[3] = {2 * r[0], 2 * r[1], 2 * r[2]};
      child[n] += side ? 0 : 1;  // the children touching the face
      child[u] += o & 1, child[v] += o >> 1;
      gather_face(l0, q0, l + 1, child, n, side, outward_positive);
    }
  }

  void leaf_polygons(int l, const Int* q) {
    ++leaves_;
    crossings_.clear();
    segments_.clear();
    for (int n = 0; n < 3; ++n)
      for (int side = 0; side < 2; ++side) {
        Int r[3] = {q[0], q[1], q[2]};
        r[n] += side ? 1 : -1;
        const bool inside = r[n] >= 0 && r[n] < levels_[static_cast<std::size_t>(l)].n;
        if (inside && refined(l, r)) {
          gather_face(l, q, l, r, n, side, side == 1);
        } else {
          face_square(l, q, l, q, n, side, side == 1);
        }
      }
    // Chain the segments into loops (each crossing starts one segment and ends one).
    const std::size_t count = segments_.size();
    std::vector<char> used(count, 0);
    std::vector<int> loop;
    for (std::size_t first = 0; first < count; ++first) {
      if (used[first]) continue;
      loop.clear();
      std::size_t current = first;
      bool closed = false;
      for (std::size_t guard = 0; guard <= count; ++guard) {
        used[current] = 1;
        loop.push_back(segments_[current].from);
        const std::uint64_t next_key = crossings_[static_cast<std::size_t>(segments_[current].to)].key;
        if (next_key == crossings_[static_cast<std::size_t>(segments_[first].from)].key) {
          closed = true;
          break;
        }
        std::size_t next = count;
        for (std::size_t t = 0; t < count; ++t)
          if (!used[t] && crossings_[static_cast<std::size_t>(segments_[t].from)].key == next_key) {
            next = t;
            break;
          }
        if (next == count) break;
        current = next;
      }
      if (closed && loop.size() >= 3) triangulate(loop);
    }
  }

  void triangulate(const std::vector<int>& loop) {
    const std::size_t k = loop.size();
    auto vertex_of = [&](std::size_t i) { return crossings_[static_cast<std::size_t>(loop[i % k])].vertex; };
    auto faces = [&](std::size_t i) { return crossings_[static_cast<std::size_t>(loop[i % k])].faces; };
    if (k == 3) {
      triangles_.push_back({vertex_of(0), vertex_of(1), vertex_of(2)});
      return;
    }
    // The least-area triangulation by chords that join vertices on no common face of the leaf
    // (dynamic programming over the sub-polygons i..j, as in Kazhdan et al. 2007).
    if (k <= 16) {
      auto point = [&](std::size_t i) { return positions_[static_cast<std::size_t>(vertex_of(i))]; };
      auto chord = [&](std::size_t i, std::size_t j) { return j == i + 1 || (i == 0 && j == k - 1) || (faces(i) & faces(j)) == 0; };
      constexpr double none = std::numeric_limits<double>::infinity();
      std::vector<double> cost(k * k, 0.0);
      std::vector<int> split(k * k, -1);
      for (std::size_t length = 2; length < k; ++length)
        for (std::size_t i = 0; i + length < k; ++i) {
          const std::size_t j = i + length;
          double best = none;
          if (chord(i, j))
            for (std::size_t mid = i + 1; mid < j; ++mid) {
              const double c = cost[i * k + mid] + cost[mid * k + j];
              if (!(c < none)) continue;
              const double area = 0.5 * (point(mid) - point(i)).cross(point(j) - point(i)).norm();
              if (c + area < best) best = c + area, split[i * k + j] = static_cast<int>(mid);
            }
          cost[i * k + j] = best;
        }
      if (cost[k - 1] < none) {
        std::vector<std::array<std::size_t, 2>> stack{{0, k - 1}};
        while (!stack.empty()) {
          const auto [i, j] = stack.back();
          stack.pop_back();
          if (j < i + 2) continue;
          const auto mid = static_cast<std::size_t>(split[i * k + j]);
          triangles_.push_back({vertex_of(i), vertex_of(mid), vertex_of(j)});
          stack.push_back({i, mid});
          stack.push_back({mid, j});
        }
        return;
      }
    }
    Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
    for (std::size_t i = 0; i < k; ++i) centroid += positions_[static_cast<std::size_t>(vertex_of(i))];
    const int centre = static_cast<int>(positions_.size());
    ++centre_vertices_;
    positions_.push_back(centroid / static_cast<double>(k));
    for (std::size_t i = 0; i < k; ++i) triangles_.push_back({centre, vertex_of(i), vertex_of(i + 1)});
  }
};

}  // namespace

void validate_surface_samples(const VertexRef& P) {
  validate_vertices(P, "P");
  if (P.rows() < 4)
    throw InputError("P has " + std::to_string(P.rows()) + " points: expected at least 4 samples");
  // All points on a line (or one point) span no surface.
  const double extent = (P.colwise().maxCoeff() - P.colwise().minCoeff()).maxCoeff();
  const Eigen::RowVector3d mean = P.colwise().mean();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (Eigen::Index s = 0; s < P.rows(); ++s) covariance += (P.row(s) - mean).transpose() * (P.row(s) - mean);
  const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();
  if (!(extent > 0.0) || !(eigenvalues[1] > 1e-12 * eigenvalues[2]))
    throw InputError(extent > 0.0 ? "P: all points lie on one line: expected samples of a surface"
                                  : "P: all points coincide: expected samples of a surface");
}

PoissonResult poisson(const VertexRef& P, const VertexRef& N, const PoissonOptions& options, const Progress& progress) {
  validate_surface_samples(P);
  if (N.rows() != P.rows())
    throw InputError("N has " + std::to_string(N.rows()) + " rows and P " + std::to_string(P.rows()) +
                     ": expected one normal per sample");
  validate_vertices(N, "N");
  if (options.depth < 2 || options.depth > 10)
    throw InputError("depth = " + std::to_string(options.depth) + ": expected an integer in [2, 10]");
  if (!(options.screening >= 0.0) || !std::isfinite(options.screening))
    throw InputError("screening = " + std::to_string(options.screening) + ": expected a finite number >= 0");
  if (!(options.samples_per_node > 0.0) || !std::isfinite(options.samples_per_node))
    throw InputError("samples_per_node = " + std::to_string(options.samples_per_node) + ": expected a finite number > 0");
  if (!(options.scale >= 1.0) || !std::isfinite(options.scale))
    throw InputError("scale = " + std::to_string(options.scale) + ": expected a finite number >= 1");
  if (options.band < 1 || options.band > 16)
    throw InputError("band = " + std::to_string(options.band) + ": expected an integer in [1, 16]");
  if (options.refinement < 0 || options.refinement > 10)
    throw InputError("refinement = " + std::to_string(options.refinement) + ": expected an integer in [0, 10]");
  if (options.band_refinement < 0 || options.band_refinement > 10)
    throw InputError("band_refinement = " + std::to_string(options.band_refinement) + ": expected an integer in [0, 10]");
  if (options.extraction_depth != 0 && (options.extraction_depth < 2 || options.extraction_depth > options.depth))
    throw InputError("extraction_depth = " + std::to_string(options.extraction_depth) + ": expected 0 (automatic) or an integer in [2, depth = " +
                     std::to_string(options.depth) + "]");
  if (options.adaptive && options.band_refinement != 0)
    throw InputError("band_refinement applies to adaptive = false (the adaptive octree extracts on its leaves)");
  if (options.max_iterations < 1)
    throw InputError("max_iterations = " + std::to_string(options.max_iterations) + ": expected an integer >= 1");
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    throw InputError("tolerance = " + std::to_string(options.tolerance) + ": expected a finite number > 0");
  const Int m = P.rows();
  VertexMatrix normals(m, 3);
  for (Int s = 0; s < m; ++s) {
    const double length = N.row(s).norm();
    if (!(length > 0.0) || !std::isfinite(length))
      throw InputError("N[" + std::to_string(s) + "] has length " + std::to_string(length) +
                       ": expected a non-zero normal per sample");
    normals.row(s) = N.row(s) / length;
  }
  // The bounding cube.
  const Eigen::RowVector3d lower = P.colwise().minCoeff(), upper = P.colwise().maxCoeff();
  const double extent = (upper - lower).maxCoeff();
  const double size = options.scale * extent;
  const Eigen::RowVector3d corner = 0.5 * (lower + upper) - Eigen::RowVector3d::Constant(0.5 * size);
  VertexMatrix X(m, 3);  // unit-cube positions
  for (Int s = 0; s < m; ++s) X.row(s) = (P.row(s) - corner) / size;

  const char* profile_env = std::getenv("MESHSMITH_POISSON_PROFILE");
  const bool profile = profile_env != nullptr && *profile_env != '\0';
  auto stage_start = std::chrono::steady_clock::now();
  std::clock_t cpu_start = std::clock();
  auto stage = [&](const char* name) {
    if (!profile) return;
    const auto now = std::chrono::steady_clock::now();
    const std::clock_t cpu = std::clock();
    std::fprintf(stderr, "poisson stage %-22s %8.3f s wall %8.3f s cpu\n", name,
                 std::chrono::duration<double>(now - stage_start).count(),
                 static_cast<double>(cpu - cpu_start) / CLOCKS_PER_SEC);
    stage_start = now;
    cpu_start = cpu;
  };
  const int finest = options.depth, coarsest = std::max(2, std::min(options.coarse_depth, finest));
  const int depth_count = finest - coarsest + 1;
  auto cell_key = [&](Int s, int d) {
    const Int n = Int(1) << d;
    Int key = 0;
    for (int a = 0; a < 3; ++a) key = key * n + std::min<Int>(n - 1, static_cast<Int>(X(s, a) * static_cast<double>(n)));
    return key;
  };
  // Each sample's depth: the deepest level where the support of the node nearest to it (the 8
  // cells around that node) holds >= samples_per_node samples.
  std::vector<int> sample_depth(static_cast<std::size_t>(m), coarsest);
  std::vector<double> sample_area(static_cast<std::size_t>(m), 0.0);
  {
    // The samples' cell keys per level, sorted; each sample then counts the samples in its
    // node's support from the finest level down, stopping at the first level that holds enough.
    std::vector<std::vector<Int>> sorted(static_cast<std::size_t>(depth_count));
    tbb::parallel_for(0, depth_count, [&](int l) {
      auto& keys = sorted[static_cast<std::size_t>(l)];
      keys.resize(static_cast<std::size_t>(m));
      for (Int s = 0; s < m; ++s) keys[static_cast<std::size_t>(s)] = cell_key(s, coarsest + l);
      std::sort(keys.begin(), keys.end());
    });
    auto support_count = [&](Int s, int d) {
      const auto& keys = sorted[static_cast<std::size_t>(d - coarsest)];
      const Int n = Int(1) << d;
      Int node[3];
      for (int a = 0; a < 3; ++a) node[a] = static_cast<Int>(std::lround(X(s, a) * static_cast<double>(n)));
      Int total = 0;
      for (int c = 0; c < 8; ++c) {
        Int cell[3];
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          cell[a] = node[a] - ((c >> a) & 1);
          inside = inside && cell[a] >= 0 && cell[a] < n;
        }
        if (!inside) continue;
        const Int key = (cell[0] * n + cell[1]) * n + cell[2];
        const auto range = std::equal_range(keys.begin(), keys.end(), key);
        total += range.second - range.first;
      }
      return total;
    };
    parallel_rows(m, [&](Int s) {
      int depth = coarsest;
      Int count = 0;
      for (int d = finest; d >= coarsest; --d) {
        count = support_count(s, d);
        if (d == coarsest || static_cast<double>(count) >= options.samples_per_node) {
          depth = d;
          break;
        }
      }
      sample_depth[static_cast<std::size_t>(s)] = depth;
      const double h = std::ldexp(1.0, -depth);
      // The sample's share of the surface in the node's support (about 4 cells of area h² for a
      // surface through it).
      sample_area[static_cast<std::size_t>(s)] = 4.0 * h * h / static_cast<double>(std::max<Int>(1, count));
    });
  }
  // The extraction depth: as asked, or the deepest level at least half of the samples reach.
  int extract = options.extraction_depth > 0 ? std::max(coarsest, options.extraction_depth) : coarsest;
  {
    std::vector<Int> reaching(static_cast<std::size_t>(finest + 2), 0);  // samples of depth >= d
    for (Int s = 0; s < m; ++s) {
      ++reaching[static_cast<std::size_t>(sample_depth[static_cast<std::size_t>(s)])];
    }
    for (int d = finest; d >= coarsest; --d) reaching[static_cast<std::size_t>(d)] += reaching[static_cast<std::size_t>(d + 1)];
    if (options.extraction_depth == 0)
      for (int d = finest; d > coarsest; --d)
        if (2 * reaching[static_cast<std::size_t>(d)] >= m) {
          extract = d;
          break;
        }
  }
  // The levels: coarsest to extraction depth + band_refinement (at most the finest). Uniform
  // (adaptive = false): a sample's blocks are in the band of every level up to the extraction
  // depth, and of the deeper ones
  // that its own depth reaches (an adaptive refinement; measured on pmp-bunny.xyz at depth 8,
  // extraction depth 7: solving level 8 around the 37% of samples of depth 8 took 50% longer
  // and made the mean distance to the ground truth 1.6e-4 instead of 1.4e-4 × diagonal, as the
  // surface is extracted at depth 7 anyway, hence band_refinement = 0 by default).
  // Adaptive: a sample's blocks are in the band of the levels up to one beyond its own depth
  // only (at most e), so the octree is as deep as e only where the samples are dense enough,
  // coarser where they are sparser. (Up to its own depth only, measured on armadillo_low.xyz at
  // depth 8: mean distance from the samples to the mesh 3.95e-4 × diagonal instead of 3.01e-4
  // with every sample refined to e = 7; Open3D 3.23e-4.)
  auto in_band = [&](Int s, int d) {
    if (options.adaptive) return d <= extract && sample_depth[static_cast<std::size_t>(s)] + 1 >= d;
    return d <= extract || sample_depth[static_cast<std::size_t>(s)] >= d;
  };
  const int level_count = (options.adaptive ? extract : std::min(finest, extract + options.band_refinement)) - coarsest + 1;
  stage("sample depths");

  PoissonResult result;
  std::vector<Level> levels(static_cast<std::size_t>(level_count));
  double sample_mean = 0.0;
  for (int l = 0; l < level_count; ++l) {
    const double begin_fraction = 0.8 * (std::pow(4.0, l) - 1.0) / (std::pow(4.0, level_count) - 1.0);
    const double end_fraction = 0.8 * (std::pow(4.0, l + 1) - 1.0) / (std::pow(4.0, level_count) - 1.0);
    progress.report(begin_fraction, "poisson: band");
    Level& level = levels[static_cast<std::size_t>(l)];
    level.depth = coarsest + l;
    level.n = Int(1) << level.depth;
    level.h = 1.0 / static_cast<double>(level.n);
    level.blocks_per_axis = level.n / B;
    const Int nb = level.blocks_per_axis;
    // Band blocks: all of them on the coarsest level; else the blocks within band + 1 cells of a
    // sample in_band at this level (the adaptivity of an octree: where samples are sparser, χ
    // is the coarser level's; the part of V beyond the band acts through the coarser solution,
    // as boundary values).
    if (l == 0) {
      level.block_keys.resize(static_cast<std::size_t>(nb * nb * nb));
      for (Int k = 0; k < nb * nb * nb; ++k) level.block_keys[static_cast<std::size_t>(k)] = k;
    } else {
      // Marked in a dense table and collected in key order, or (beyond DENSE_BLOCKS) sorted.
      const bool dense = nb * nb * nb <= DENSE_BLOCKS;
      std::vector<char> marked(dense ? static_cast<std::size_t>(nb * nb * nb) : 0, 0);
      for (Int s = 0; s < m; ++s) {
        if (!in_band(s, level.depth)) continue;  // not refined here
        const double reach = (options.band + 1) * level.h;
        Int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
          const double block_size = B * level.h;
          lo[a] = std::max<Int>(0, static_cast<Int>(std::floor((X(s, a) - reach) / block_size)));
          hi[a] = std::min<Int>(nb - 1, static_cast<Int>(std::floor((X(s, a) + reach) / block_size)));
        }
        for (Int i = lo[0]; i <= hi[0]; ++i)
          for (Int j = lo[1]; j <= hi[1]; ++j)
            for (Int k = lo[2]; k <= hi[2]; ++k) {
              if (dense)
                marked[static_cast<std::size_t>((i * nb + j) * nb + k)] = 1;
              else
                level.block_keys.push_back((i * nb + j) * nb + k);
            }
      }
      if (dense) {
        for (Int key = 0; key < nb * nb * nb; ++key)
          if (marked[static_cast<std::size_t>(key)]) level.block_keys.push_back(key);
      } else {
        std::sort(level.block_keys.begin(), level.block_keys.end());
        level.block_keys.erase(std::unique(level.block_keys.begin(), level.block_keys.end()), level.block_keys.end());
      }
    }
    const auto block_count = level.block_keys.size();
    if (nb * nb * nb <= DENSE_BLOCKS) {
      level.block_dense.assign(static_cast<std::size_t>(nb * nb * nb), -1);
      for (std::size_t b = 0; b < block_count; ++b) level.block_dense[static_cast<std::size_t>(level.block_keys[b])] = static_cast<int>(b);
    } else {
      level.block_index.reserve(block_count);
      for (std::size_t b = 0; b < block_count; ++b) level.block_index.emplace(level.block_keys[b], static_cast<int>(b));
    }
    // Nodes: the corners of band blocks, numbered in sorted key order.
    auto block_origin = [&](std::size_t b, Int* first) {
      const Int key = level.block_keys[b];
      first[0] = key / (nb * nb) * B, first[1] = (key / nb) % nb * B, first[2] = key % nb * B;
    };
    // Up to DENSE_NODES grid nodes, a dense table numbers them (a scan in key order); beyond,
    // the keys are sorted and looked up by binary search. Both give the same numbering.
    const Int side = level.n + 1;
    const bool dense_nodes = side * side * side <= DENSE_NODES;
    std::vector<int> node_table(dense_nodes ? static_cast<std::size_t>(side * side * side) : 0, -1);
    auto for_each_corner = [&](std::size_t b, const auto& body) {
      Int first[3];
      block_origin(b, first);
      int w = 0;
      for (int i = 0; i < C; ++i)
        for (int j = 0; j < C; ++j)
          for (int k = 0; k < C; ++k, ++w) body(w, level.node_key_of(first[0] + i, first[1] + j, first[2] + k));
    };
    if (dense_nodes) {
      for (std::size_t b = 0; b < block_count; ++b)
        for_each_corner(b, [&](int, Int key) { node_table[static_cast<std::size_t>(key)] = 0; });
      int next = 0;
      for (Int key = 0; key < side * side * side; ++key)
        if (node_table[static_cast<std::size_t>(key)] == 0) {
          node_table[static_cast<std::size_t>(key)] = next++;
          level.node_key.push_back(key);
        }
    } else {
      level.node_key.reserve(block_count * CORNERS);
      for (std::size_t b = 0; b < block_count; ++b) for_each_corner(b, [&](int, Int key) { level.node_key.push_back(key); });
      std::sort(level.node_key.begin(), level.node_key.end());
      level.node_key.erase(std::unique(level.node_key.begin(), level.node_key.end()), level.node_key.end());
    }
    const Int nodes = static_cast<Int>(level.node_key.size());
    if (nodes > Int(1) << 30) throw InputError("poisson: the band has more than 2^30 nodes; use a smaller depth");
    level.corner_id.resize(block_count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, block_count, 64), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t b = r.begin(); b < r.end(); ++b)
        for_each_corner(b, [&](int w, Int key) {
          level.corner_id[b][static_cast<std::size_t>(w)] =
              dense_nodes ? node_table[static_cast<std::size_t>(key)]
                          : static_cast<int>(std::lower_bound(level.node_key.begin(), level.node_key.end(), key) -
                                             level.node_key.begin());
        });
    });
    node_table = {};
    auto node_coordinates = [&](Int id, Int* x) {
      const Int key = level.node_key[static_cast<std::size_t>(id)];
      x[0] = key / (side * side), x[1] = (key / side) % side, x[2] = key % side;
    };
    stage("level: band and nodes");
    // Free nodes: every incident cell inside the cube is a band cell.
    level.row_of_node.assign(static_cast<std::size_t>(nodes), -1);
    std::vector<char> is_free(static_cast<std::size_t>(nodes), 0);
    parallel_rows(nodes, [&](Int id) {
      Int x[3];
      node_coordinates(id, x);
      bool free = true;
      Int cached_key = -1;
      int cached_index = -1;
      for (int c = 0; c < 8 && free; ++c) {
        Int cell[3];
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          cell[a] = x[a] - (((c >> a) & 1) ? 1 : 0);
          inside = inside && cell[a] >= 0 && cell[a] < level.n;
        }
        if (inside && level.find_block(cell[0] / B, cell[1] / B, cell[2] / B, cached_key, cached_index) < 0) free = false;
      }
      is_free[static_cast<std::size_t>(id)] = free;
    });
    for (Int id = 0; id < nodes; ++id)
      if (is_free[static_cast<std::size_t>(id)]) {
        level.row_of_node[static_cast<std::size_t>(id)] = static_cast<int>(level.node_of_row.size());
        level.node_of_row.push_back(static_cast<int>(id));
      }
    const Int rows = static_cast<Int>(level.node_of_row.size());

    stage("level: free nodes");
    // The normal field: the coarser deposits prolonged (exact: the Q1 spaces are nested), plus
    // the samples splatted here (deposited here if this is their depth).
    level.field.assign(static_cast<std::size_t>(3 * nodes), 0.0);
    level.deposit.assign(static_cast<std::size_t>(3 * nodes), 0.0);
    if (l > 0) {
      const Level& coarser = levels[static_cast<std::size_t>(l - 1)];
      parallel_rows(nodes, [&](Int id) {
        Int x[3];
        node_coordinates(id, x);
        const double y[3] = {static_cast<double>(x[0]) * level.h, static_cast<double>(x[1]) * level.h,
                             static_cast<double>(x[2]) * level.h};
        evaluate_deposit(coarser, y, &level.deposit[3 * static_cast<std::size_t>(id)]);
      });
      level.field = level.deposit;
    }
    const double inverse_volume = std::pow(static_cast<double>(level.n), 3);
    for (Int s = 0; s < m; ++s) {
      if (sample_depth[static_cast<std::size_t>(s)] < level.depth) continue;
      const double y[3] = {X(s, 0), X(s, 1), X(s, 2)};
      double w[8];
      int ids[8];
      interpolation(level, y, ids, w);  // the sample's cell is a band cell
      const bool deposit_here = sample_depth[static_cast<std::size_t>(s)] == level.depth;
      for (int c = 0; c < 8; ++c)
        for (int a = 0; a < 3; ++a) {
          const double v = w[c] * sample_area[static_cast<std::size_t>(s)] * normals(s, a) * inverse_volume;
          level.field[3 * static_cast<std::size_t>(ids[c]) + a] += v;
          if (deposit_here) level.deposit[3 * static_cast<std::size_t>(ids[c]) + a] += v;
        }
    }

    stage("level: splatting");
    // Boundary values and the initial guess from the coarser level.
    level.value = Eigen::VectorXd::Zero(nodes);
    if (l > 0)
      parallel_rows(nodes, [&](Int id) {
        Int x[3];
        node_coordinates(id, x);
        const double y[3] = {static_cast<double>(x[0]) * level.h, static_cast<double>(x[1]) * level.h,
                             static_cast<double>(x[2]) * level.h};
        level.value[id] = evaluate_value(levels, l - 1, y);
      });

    stage("level: prolong chi");
    // Rows: 27 slots (offset (ox, oy, oz) in slot (ox+1)·9 + (oy+1)·3 + oz+1), column = node id.
    std::vector<int> column(static_cast<std::size_t>(27 * rows), -1);
    std::vector<double> entry(static_cast<std::size_t>(27 * rows), 0.0);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows);
    parallel_rows(rows, [&](Int r) {
      const Int id = level.node_of_row[static_cast<std::size_t>(r)];
      Int x[3];
      node_coordinates(id, x);
      const Factors fx(x[0], level.n), fy(x[1], level.n), fz(x[2], level.n);
      double b = 0.0;
      // The node ids of the (up to 8) incident band cells, looked up once each: cell x - 1 + bit
      // a of `incident` along axis a.
      int incident_ids[8][8];
      bool incident_known[8] = {false, false, false, false, false, false, false, false};
      for (int ox = -1; ox <= 1; ++ox)
        for (int oy = -1; oy <= 1; ++oy)
          for (int oz = -1; oz <= 1; ++oz) {
            const Int y[3] = {x[0] + ox, x[1] + oy, x[2] + oz};
            if (y[0] < 0 || y[1] < 0 || y[2] < 0 || y[0] > level.n || y[1] > level.n || y[2] > level.n) continue;
            const double mx = fx.mass[ox + 1], my = fy.mass[oy + 1], mz = fz.mass[oz + 1];
            const double k = level.h * (fx.stiffness[ox + 1] * my * mz + mx * fy.stiffness[oy + 1] * mz +
                                        mx * my * fz.stiffness[oz + 1]);
            const double g[3] = {fx.derivative[ox + 1] * my * mz, mx * fy.derivative[oy + 1] * mz,
                                 mx * my * fz.derivative[oz + 1]};
            if (k == 0.0 && g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0) continue;
            // The neighbour's id: a corner of a band cell holding both nodes.
            Int cell[3];
            for (int a = 0; a < 3; ++a) {
              const int o = a == 0 ? ox : (a == 1 ? oy : oz);
              cell[a] = o < 0 ? x[a] - 1 : (o > 0 ? x[a] : (x[a] < level.n ? x[a] : x[a] - 1));
            }
            const int incident = (cell[0] == x[0] ? 1 : 0) | (cell[1] == x[1] ? 2 : 0) | (cell[2] == x[2] ? 4 : 0);
            int* ids = incident_ids[incident];
            if (!incident_known[incident]) {
              level.cell_nodes(level.find_block(cell[0] / B, cell[1] / B, cell[2] / B), cell, ids);
              incident_known[incident] = true;
            }
            const int corner = (y[0] - cell[0]) | ((y[1] - cell[1]) << 1) | ((y[2] - cell[2]) << 2);
            const int j = ids[corner];
            const int slot = (ox + 1) * 9 + (oy + 1) * 3 + oz + 1;
            column[static_cast<std::size_t>(27 * r + slot)] = j;
            entry[static_cast<std::size_t>(27 * r + slot)] = k;
            const double* v = &level.field[3 * static_cast<std::size_t>(j)];
            b += level.h * level.h * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2]);
          }
      rhs[r] = b;
    });
    // Screening: α 2^d a_s φ_i(p_s) φ_j(p_s), sample by sample (the samples refined to this level).
    const double alpha = options.screening * static_cast<double>(level.n);
    for (Int s = 0; s < m; ++s) {
      if (sample_depth[static_cast<std::size_t>(s)] + options.refinement < level.depth || !in_band(s, level.depth)) continue;
      const double y[3] = {X(s, 0), X(s, 1), X(s, 2)};
      double w[8];
      int ids[8];
      if (!interpolation(level, y, ids, w)) continue;  // not reached: the sample's cell is a band cell
      const double weight = alpha * sample_area[static_cast<std::size_t>(s)];
      for (int a = 0; a < 8; ++a) {
        const int r = level.row_of_node[static_cast<std::size_t>(ids[a])];
        if (r < 0) continue;
        for (int c = 0; c < 8; ++c) {
          const int slot = (((c & 1) - (a & 1)) + 1) * 9 + ((((c >> 1) & 1) - ((a >> 1) & 1)) + 1) * 3 + ((c >> 2) - (a >> 2)) + 1;
          column[static_cast<std::size_t>(27 * r + slot)] = ids[c];
          entry[static_cast<std::size_t>(27 * r + slot)] += weight * w[a] * w[c];
        }
      }
    }
    // Dirichlet columns to the right-hand side; free columns to row indices.
    parallel_rows(rows, [&](Int r) {
      for (int slot = 0; slot < 27; ++slot) {
        int& j = column[static_cast<std::size_t>(27 * r + slot)];
        if (j < 0) continue;
        const int row = level.row_of_node[static_cast<std::size_t>(j)];
        if (row < 0) {
          rhs[r] -= entry[static_cast<std::size_t>(27 * r + slot)] * level.value[j];
          j = -1;
        } else {
          j = row;
        }
      }
    });
    auto multiply = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
      parallel_rows(rows, [&](Int r) {
        double sum = 0.0;
        for (int slot = 0; slot < 27; ++slot) {
          const int j = column[static_cast<std::size_t>(27 * r + slot)];
          if (j >= 0) sum += entry[static_cast<std::size_t>(27 * r + slot)] * in[j];
        }
        out[r] = sum;
      });
    };
    Eigen::VectorXd diagonal(rows);
    for (Int r = 0; r < rows; ++r) {
      const double d = entry[static_cast<std::size_t>(27 * r + 13)];
      diagonal[r] = d > 0.0 ? 1.0 / d : 1.0;
    }
    stage("level: system");
    // Conjugate gradients, Jacobi-preconditioned, from the coarser solution.
    Eigen::VectorXd x(rows), residual(rows), z(rows), direction(rows), product(rows);
    for (Int r = 0; r < rows; ++r) x[r] = level.value[level.node_of_row[static_cast<std::size_t>(r)]];
    multiply(x, product);
    residual = rhs - product;
    const double rhs_norm = std::sqrt(deterministic_sum(rows, [&](Int i) { return rhs[i] * rhs[i]; }));
    const double scale_norm = rhs_norm > 0.0 ? rhs_norm : 1.0;
    z = residual.cwiseProduct(diagonal);
    direction = z;
    double rz = deterministic_sum(rows, [&](Int i) { return residual[i] * z[i]; });
    PoissonLevel report;
    report.depth = level.depth;
    report.unknowns = rows;
    report.boundary = nodes - rows;
    double residual_norm = std::sqrt(deterministic_sum(rows, [&](Int i) { return residual[i] * residual[i]; }));
    const int iterations = l == 0 ? 4 * options.max_iterations : options.max_iterations;
    int it = 0;
    for (; it < iterations && residual_norm > options.tolerance * scale_norm; ++it) {
      if (it % 8 == 0)
        progress.report(begin_fraction + (end_fraction - begin_fraction) * it / iterations, "poisson: solve");
      multiply(direction, product);
      const double curvature = deterministic_sum(rows, [&](Int i) { return direction[i] * product[i]; });
      if (!(curvature > 0.0)) break;
      const double step = rz / curvature;
      parallel_rows(rows, [&](Int i) {
        x[i] += step * direction[i];
        residual[i] -= step * product[i];
        z[i] = residual[i] * diagonal[i];
      });
      const double rz_next = deterministic_sum(rows, [&](Int i) { return residual[i] * z[i]; });
      const double beta = rz_next / rz;
      rz = rz_next;
      parallel_rows(rows, [&](Int i) { direction[i] = z[i] + beta * direction[i]; });
      residual_norm = std::sqrt(deterministic_sum(rows, [&](Int i) { return residual[i] * residual[i]; }));
    }
    stage("level: solve");
    report.iterations = it;
    report.residual = residual_norm / scale_norm;
    result.levels.push_back(report);
    for (Int r = 0; r < rows; ++r) level.value[level.node_of_row[static_cast<std::size_t>(r)]] = x[r];
    level.field.clear();
    level.field.shrink_to_fit();
    if (l > 0) {
      levels[static_cast<std::size_t>(l - 1)].deposit.clear();
      levels[static_cast<std::size_t>(l - 1)].deposit.shrink_to_fit();
    }
  }
  // The iso-value: the mean of χ over the samples.
  const int top = level_count - 1;
  {
    std::vector<double> at_samples(static_cast<std::size_t>(m));
    parallel_rows(m, [&](Int s) {
      const double y[3] = {X(s, 0), X(s, 1), X(s, 2)};
      at_samples[static_cast<std::size_t>(s)] = evaluate_value(levels, top, y);
    });
    for (double v : at_samples) sample_mean += v;
    sample_mean /= static_cast<double>(m);
  }
  result.iso = sample_mean;

  stage("iso-value");
  // Marching cubes on the grid of the extraction depth, following the surface from the samples.
  result.extraction_depth = extract;
  const Int n = Int(1) << extract;
  Grid grid;
  grid.shape = {n + 1, n + 1, n + 1};
  const double h = size / static_cast<double>(n);
  for (int a = 0; a < 3; ++a) grid.origin[a] = corner[a], grid.spacing[a] = h;
  const GridFunction chi = [&](const Eigen::Ref<const Eigen::Matrix<Int, Eigen::Dynamic, 3, Eigen::RowMajor>>& points, double* out) {
    parallel_rows(points.rows(), [&](Int r) {
      const double y[3] = {static_cast<double>(points(r, 0)) / static_cast<double>(n),
                           static_cast<double>(points(r, 1)) / static_cast<double>(n),
                           static_cast<double>(points(r, 2)) / static_cast<double>(n)};
      out[r] = evaluate_value(levels, top, y);
    });
  };
  ContourMesh mesh = options.adaptive
                         ? LeafExtractor(levels, sample_mean, corner, size).run(progress.subrange(0.8, 0.95))
                         : marching_cubes_sparse(chi, grid, P, sample_mean, SparseOptions{}, progress.subrange(0.8, 0.95));
  stage("marching cubes");
  result.V = std::move(mesh.V);
  result.F = std::move(mesh.F);
  // Density: samples within 2 cells (of the extraction grid) of each vertex.
  result.density = Eigen::VectorXd::Zero(result.V.rows());
  if (result.V.rows() > 0) {
    const points::KdTree tree(P);
    const points::RadiusResult near = tree.query_radius(result.V, 2.0 * h, progress.subrange(0.95, 1.0));
    for (Eigen::Index v = 0; v < result.V.rows(); ++v)
      result.density[v] = static_cast<double>(near.offsets[static_cast<std::size_t>(v) + 1] - near.offsets[static_cast<std::size_t>(v)]);
  }
  stage("density");
  progress.report(1.0, "poisson");
  return result;
}

}  // namespace meshsmith::reconstruction
