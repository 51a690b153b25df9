// Marching cubes (reconstruction/marching_cubes.h).
//
// How it works. The grid's cells are grouped into blocks of b³ cells; a block is contoured on
// its own from the (b+1)³ values at its corners (dense: copied from the array; sparse: returned
// by the field callback), in parallel, into a list of local vertices (each tagged with the key
// of its grid edge, 3·point + axis) and local triangles. The blocks' lists are then merged: the
// sorted distinct keys number the vertices (so the numbering, and the whole output, depends only
// on the grid values, not on the thread count or on which blocks were visited), and triangles
// come block by block in block order. The sparse variant visits the same blocks a dense run
// would find crossings in, for the pieces it reaches, so both give the same arrays.
//
// Inside a cell no case table is used: on each face the crossings are paired into directed
// segments (from the crossing where the face's counter-clockwise boundary walk, seen from
// outside the cell, goes from outside to inside, to one where it goes from inside to outside;
// on a face with four crossings the asymptotic decider pairs them: the two inside corners are
// joined across the face iff the product of their values exceeds that of the outside pair).
// Two cells sharing a face compute the same pairs in opposite directions, which makes the mesh
// crack-free and consistently oriented. Every crossing is the head of one segment and the tail
// of another, so the segments form closed loops on the cell's boundary, and each loop becomes a
// disc: the minimum-area triangulation of the loop polygon whose chords never join two vertices
// on a common cell face (such a chord could coincide with an edge of the neighbouring cell and
// would lie in the face); a loop without such a triangulation gets a centre vertex instead
// (counted in ContourMesh::centre_vertices). Each mesh edge then has two triangles (one on each
// side of a face segment, or two in a cell for a chord) and each vertex's link is one cycle
// through the (up to four) cells around its grid edge: a manifold. Interior ambiguities (two
// loops that a trilinear interpolant might join by a tunnel inside the cell) are always
// resolved as separate discs.
#include <meshsmith/reconstruction/marching_cubes.h>

#include <meshsmith/core/errors.h>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>

namespace meshsmith::reconstruction {
namespace {

using Int = std::int64_t;

/// The cell's combinatorics: corner c has offset (c & 1, c >> 1 & 1, c >> 2 & 1); edge e runs
/// along axis e / 4 from the corner whose other two offsets are the bits of e % 4.
struct CellTables {
  int corner_offset[8][3];
  int edge_axis[12];
  int edge_corner[12][2];  // lower and upper corner
  int edge_of[8][8];       // corner pair -> edge or -1
  int face_corner[6][4];   // counter-clockwise seen from outside
  int face_edge[6][4];     // edge from face_corner[i] to face_corner[i + 1]
  bool shares_face[12][12];

  CellTables() {
    for (int c = 0; c < 8; ++c)
      for (int a = 0; a < 3; ++a) corner_offset[c][a] = (c >> a) & 1;
    for (auto& row : edge_of)
      for (int& e : row) e = -1;
    for (int e = 0; e < 12; ++e) {
      const int axis = e / 4, u = (axis + 1) % 3, v = (axis + 2) % 3;
      const int low = (((e % 4) & 1) << std::min(u, v)) | (((e % 4) >> 1) << std::max(u, v));
      edge_axis[e] = axis;
      edge_corner[e][0] = low;
      edge_corner[e][1] = low | (1 << axis);
      edge_of[low][low | (1 << axis)] = edge_of[low | (1 << axis)][low] = e;
    }
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2, side = f % 2, u = (axis + 1) % 3, v = (axis + 2) % 3;  // e_u × e_v = e_axis
      const int square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int i = 0; i < 4; ++i) {
        const int* uv = square[side == 1 ? i : (4 - i) % 4];
        face_corner[f][i] = (side << axis) | (uv[0] << u) | (uv[1] << v);
      }
      for (int i = 0; i < 4; ++i) face_edge[f][i] = edge_of[face_corner[f][i]][face_corner[f][(i + 1) % 4]];
    }
    for (auto& row : shares_face)
      for (bool& s : row) s = false;
    for (int f = 0; f < 6; ++f)
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) shares_face[face_edge[f][i]][face_edge[f][j]] = true;
  }
};

const CellTables& cell_tables() {
  static const CellTables tables;
  return tables;
}

/// A block of cells: the first cell and the number of cells per axis (b, or fewer at the grid's end).
struct Block {
  Int key = 0;
  std::array<Int, 3> first{0, 0, 0};
  std::array<int, 3> cells{0, 0, 0};
  Int corner_count() const { return Int(cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1); }
};

struct BlockOutput {
  std::vector<Int> keys;           // per local vertex
  std::vector<double> positions;   // 3 per local vertex
  std::vector<int> triangles;      // 3 local indices per triangle
  std::vector<Int> neighbours;     // keys of other blocks sharing a crossed edge (sparse growth)
  Int centres = 0;
};

/// Block layout of a grid.
struct Blocking {
  Grid grid;
  int size;
  std::array<Int, 3> count;  // blocks per axis
  Blocking(const Grid& g, int b) : grid(g), size(b) {
    for (int a = 0; a < 3; ++a) count[a] = (g.shape[a] - 1 + b - 1) / b;
  }
  Int total() const { return count[0] * count[1] * count[2]; }
  Block block(Int key) const {
    Block block;
    block.key = key;
    const Int index[3] = {key / (count[1] * count[2]), (key / count[2]) % count[1], key % count[2]};
    for (int a = 0; a < 3; ++a) {
      block.first[a] = index[a] * size;
      block.cells[a] = static_cast<int>(std::min<Int>(size, grid.shape[a] - 1 - block.first[a]));
    }
    return block;
  }
  Int key_of_cell(const Int* cell) const {
    return ((cell[0] / size) * count[1] + cell[1] / size) * count[2] + cell[2] / size;
  }
};

/// Minimum-area triangulation of a loop polygon whose chords join no two vertices on a common
/// cell face; false if there is none. Appends local vertex indices to `triangles`.
bool triangulate_loop(int m, const int* edges, const int* vertices, const double* positions,
                      std::vector<int>& triangles) {
  const CellTables& t = cell_tables();
  if (m == 3) {
    triangles.insert(triangles.end(), {vertices[0], vertices[1], vertices[2]});
    return true;
  }
  auto allowed = [&](int i, int j) { return j == i + 1 || (i == 0 && j == m - 1) || !t.shares_face[edges[i]][edges[j]]; };
  auto area = [&](int i, int k, int j) {
    const double* a = positions + 3 * vertices[i];
    const double* b = positions + 3 * vertices[k];
    const double* c = positions + 3 * vertices[j];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  };
  constexpr double none = std::numeric_limits<double>::infinity();
  double cost[12][12];
  int split[12][12];
  for (int i = 0; i + 1 < m; ++i) cost[i][i + 1] = 0.0;
  for (int length = 2; length < m; ++length)
    for (int i = 0; i + length < m; ++i) {
      const int j = i + length;
      cost[i][j] = none;
      split[i][j] = -1;
      if (!allowed(i, j)) continue;
      for (int k = i + 1; k < j; ++k) {
        if (cost[i][k] == none || cost[k][j] == none) continue;
        const double c = cost[i][k] + cost[k][j] + area(i, k, j);
        if (c < cost[i][j]) cost[i][j] = c, split[i][j] = k;
      }
    }
  if (cost[0][m - 1] == none) return false;
  int stack[2 * 12][2];
  int top = 0;
  stack[top][0] = 0, stack[top][1] = m - 1, ++top;
  while (top > 0) {
    --top;
    const int i = stack[top][0], j = stack[top][1];
    if (j - i < 2) continue;
    const int k = split[i][j];
    triangles.insert(triangles.end(), {vertices[i], vertices[k], vertices[j]});
    stack[top][0] = i, stack[top][1] = k, ++top;
    stack[top][0] = k, stack[top][1] = j, ++top;
  }
  return true;
}

/// Contours one block from its corner values (C order over the block's (c+1)³ points).
void contour_block(const Blocking& blocking, const Block& block, const double* values, double iso,
                   bool want_neighbours, std::vector<int>& slots, BlockOutput& out) {
  const CellTables& t = cell_tables();
  const Grid& grid = blocking.grid;
  const Int ny = grid.shape[1], nz = grid.shape[2];
  const int px = block.cells[0] + 1, py = block.cells[1] + 1, pz = block.cells[2] + 1;
  slots.assign(static_cast<std::size_t>(px) * py * pz * 3, -1);
  auto local = [&](int i, int j, int k) { return (i * py + j) * pz + k; };

  auto vertex_of_edge = [&](int ci, int cj, int ck, int e) {
    const int* low = t.corner_offset[t.edge_corner[e][0]];
    const int axis = t.edge_axis[e];
    const int li = ci + low[0], lj = cj + low[1], lk = ck + low[2];
    const int point = local(li, lj, lk);
    int& slot = slots[static_cast<std::size_t>(point) * 3 + axis];
    if (slot >= 0) return slot;
    const int step[3] = {axis == 0 ? 1 : 0, axis == 1 ? 1 : 0, axis == 2 ? 1 : 0};
    const double v0 = values[point], v1 = values[local(li + step[0], lj + step[1], lk + step[2])];
    const double s = (iso - v0) / (v1 - v0);
    const Int g[3] = {block.first[0] + li, block.first[1] + lj, block.first[2] + lk};
    slot = static_cast<int>(out.keys.size());
    out.keys.push_back(((g[0] * ny + g[1]) * nz + g[2]) * 3 + axis);
    for (int a = 0; a < 3; ++a)
      out.positions.push_back(grid.origin[a] + grid.spacing[a] * (static_cast<double>(g[a]) + (a == axis ? s : 0.0)));
    if (want_neighbours) {  // the blocks of the (up to four) cells around this edge
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int du = -1; du <= 0; ++du)
        for (int dv = -1; dv <= 0; ++dv) {
          Int cell[3] = {g[0], g[1], g[2]};
          cell[u] += du, cell[v] += dv;
          if (cell[u] < 0 || cell[v] < 0 || cell[u] >= grid.shape[u] - 1 || cell[v] >= grid.shape[v] - 1 ||
              cell[axis] >= grid.shape[axis] - 1)
            continue;
          const Int key = blocking.key_of_cell(cell);
          if (key != block.key) out.neighbours.push_back(key);
        }
    }
    return slot;
  };

  for (int ci = 0; ci < block.cells[0]; ++ci)
    for (int cj = 0; cj < block.cells[1]; ++cj)
      for (int ck = 0; ck < block.cells[2]; ++ck) {
        double f[8];
        int inside = 0;
        for (int c = 0; c < 8; ++c) {
          f[c] = values[local(ci + (c & 1), cj + ((c >> 1) & 1), ck + (c >> 2))] - iso;
          if (f[c] < 0.0) inside |= 1 << c;
        }
        if (inside == 0 || inside == 255) continue;
        int next[12];
        for (int& n : next) n = -1;
        for (int face = 0; face < 6; ++face) {
          const int* q = t.face_corner[face];
          bool in[4];
          for (int i = 0; i < 4; ++i) in[i] = (inside >> q[i]) & 1;
          int entering[2], leaving[2], n_enter = 0, n_leave = 0;  // edges i: q[i] -> q[i+1]
          for (int i = 0; i < 4; ++i) {
            const bool a = in[i], b = in[(i + 1) % 4];
            if (!a && b) entering[n_enter++] = i;
            if (a && !b) leaving[n_leave++] = i;
          }
          if (n_enter == 1) {
            next[t.face_edge[face][entering[0]]] = t.face_edge[face][leaving[0]];
          } else if (n_enter == 2) {
            // Alternating corners: the asymptotic decider on f(q0)·f(q2) vs f(q1)·f(q3).
            const double even = f[q[0]] * f[q[2]], odd = f[q[1]] * f[q[3]];
            const bool inside_even = in[0];
            const bool inside_joined = inside_even ? even > odd : odd > even;
            for (int s = 0; s < 2; ++s) {
              const int i = entering[s];  // q[i] outside, q[i+1] inside
              // joined inside corners: the segment cuts off the outside corner q[i] (from edge i
              // to edge i-1); separate: it cuts off the inside corner q[i+1] (edge i to i+1).
              const int j = inside_joined ? (i + 3) % 4 : (i + 1) % 4;
              next[t.face_edge[face][i]] = t.face_edge[face][j];
            }
          }
        }
        bool used[12] = {false};
        int loop_number = 0;
        for (int start = 0; start < 12; ++start) {
          if (next[start] < 0 || used[start]) continue;
          int edges[12], vertices[12], m = 0;
          for (int e = start; !used[e]; e = next[e]) {
            used[e] = true;
            edges[m] = e;
            vertices[m] = vertex_of_edge(ci, cj, ck, e);
            ++m;
          }
          if (!triangulate_loop(m, edges, vertices, out.positions.data(), out.triangles)) {
            const Int g[3] = {block.first[0] + ci, block.first[1] + cj, block.first[2] + ck};
            const Int points = grid.shape[0] * ny * nz;
            const int centre = static_cast<int>(out.keys.size());
            out.keys.push_back(3 * points + ((g[0] * ny + g[1]) * nz + g[2]) * 4 + loop_number);
            double c[3] = {0, 0, 0};
            for (int i = 0; i < m; ++i)
              for (int a = 0; a < 3; ++a) c[a] += out.positions[3 * vertices[i] + a] / m;
            out.positions.insert(out.positions.end(), {c[0], c[1], c[2]});
            for (int i = 0; i < m; ++i) out.triangles.insert(out.triangles.end(), {vertices[i], vertices[(i + 1) % m], centre});
            ++out.centres;
          }
          ++loop_number;
        }
      }
}

/// Joins block outputs (in block-key order) into one mesh: vertices numbered by sorted key.
ContourMesh merge_blocks(std::vector<BlockOutput>& outputs) {
  std::vector<Int> keys;
  Int triangle_count = 0, centres = 0;
  for (const auto& out : outputs) {
    keys.insert(keys.end(), out.keys.begin(), out.keys.end());
    triangle_count += static_cast<Int>(out.triangles.size() / 3);
    centres += out.centres;
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  const Int limit = std::numeric_limits<int>::max();
  if (static_cast<Int>(keys.size()) > limit || triangle_count > limit)
    throw InputError("marching cubes: the surface has more than 2^31 - 1 vertices or triangles; use a coarser grid");
  ContourMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(keys.size()), 3);
  mesh.F.resize(triangle_count, 3);
  mesh.centre_vertices = centres;
  std::vector<Int> first_triangle(outputs.size() + 1, 0);
  for (std::size_t b = 0; b < outputs.size(); ++b)
    first_triangle[b + 1] = first_triangle[b] + static_cast<Int>(outputs[b].triangles.size() / 3);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<int> global;
    for (std::size_t b = r.begin(); b < r.end(); ++b) {
      const BlockOutput& out = outputs[b];
      global.resize(out.keys.size());
      for (std::size_t v = 0; v < out.keys.size(); ++v) {
        const auto index = std::lower_bound(keys.begin(), keys.end(), out.keys[v]) - keys.begin();
        global[v] = static_cast<int>(index);
        for (int a = 0; a < 3; ++a) mesh.V(index, a) = out.positions[3 * v + a];  // equal in every block
      }
      for (std::size_t i = 0; i < out.triangles.size() / 3; ++i)
        for (int c = 0; c < 3; ++c)
          mesh.F(first_triangle[b] + static_cast<Int>(i), c) = global[static_cast<std::size_t>(out.triangles[3 * i + c])];
    }
  });
  return mesh;
}

void check_iso(double iso) {
  if (!std::isfinite(iso)) throw InputError("iso = " + std::to_string(iso) + ": expected a finite number");
}

}  // namespace

void validate_grid(const Grid& grid) {
  const char* axis_name[3] = {"0", "1", "2"};
  for (int a = 0; a < 3; ++a) {
    if (grid.shape[a] < 2)
      throw InputError(std::string("grid shape[") + axis_name[a] + "] = " + std::to_string(grid.shape[a]) +
                       ": expected at least 2 points per axis");
    if (!(grid.spacing[a] > 0.0) || !std::isfinite(grid.spacing[a]))
      throw InputError(std::string("spacing[") + axis_name[a] + "] = " + std::to_string(grid.spacing[a]) +
                       ": expected a positive finite number");
    if (!std::isfinite(grid.origin[a]))
      throw InputError(std::string("origin[") + axis_name[a] + "] is not finite");
  }
  const Int limit = Int(1) << 40;
  if (grid.shape[0] > limit / grid.shape[1] || grid.shape[0] * grid.shape[1] > limit / grid.shape[2])
    throw InputError("grid of " + std::to_string(grid.shape[0]) + " x " + std::to_string(grid.shape[1]) + " x " +
                     std::to_string(grid.shape[2]) + " points: more than 2^40 points");
}

ContourMesh marching_cubes(const double* values, const Grid& grid, double iso, const Progress& progress) {
  validate_grid(grid);
  check_iso(iso);
  const Int ny = grid.shape[1], nz = grid.shape[2], n = grid.shape[0] * ny * nz;
  for (Int i = 0; i < n; ++i)
    if (!std::isfinite(values[i]))
      throw InputError("values[" + std::to_string(i / (ny * nz)) + ", " + std::to_string((i / nz) % ny) + ", " +
                       std::to_string(i % nz) + "] is " + std::to_string(values[i]) + ": expected finite numbers");
  const Blocking blocking(grid, 8);
  const Int total = blocking.total();
  std::vector<BlockOutput> outputs(static_cast<std::size_t>(total));
  constexpr Int chunk = 4096;
  for (Int begin = 0; begin < total; begin += chunk) {
    progress.report(0.9 * static_cast<double>(begin) / static_cast<double>(total), "marching cubes");
    tbb::parallel_for(tbb::blocked_range<Int>(begin, std::min(total, begin + chunk), 4), [&](const tbb::blocked_range<Int>& r) {
      std::vector<double> local;
      std::vector<int> slots;
      for (Int key = r.begin(); key < r.end(); ++key) {
        const Block block = blocking.block(key);
        local.resize(static_cast<std::size_t>(block.corner_count()));
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        std::size_t w = 0;
        for (int i = 0; i <= block.cells[0]; ++i)
          for (int j = 0; j <= block.cells[1]; ++j) {
            const double* row = values + ((block.first[0] + i) * ny + block.first[1] + j) * nz + block.first[2];
            for (int k = 0; k <= block.cells[2]; ++k) {
              local[w++] = row[k];
              lo = std::min(lo, row[k]), hi = std::max(hi, row[k]);
            }
          }
        if (hi < iso || lo >= iso) continue;
        contour_block(blocking, block, local.data(), iso, false, slots, outputs[static_cast<std::size_t>(key)]);
      }
    });
  }
  ContourMesh mesh = merge_blocks(outputs);
  mesh.blocks = total;
  mesh.evaluations = n;
  progress.report(1.0, "marching cubes");
  return mesh;
}

ContourMesh marching_cubes_sparse(const GridFunction& field, const Grid& grid, const VertexRef& seeds, double iso,
                                  const SparseOptions& options, const Progress& progress) {
  validate_grid(grid);
  check_iso(iso);
  if (options.block_size < 1 || options.block_size > 64)
    throw InputError("block_size = " + std::to_string(options.block_size) + ": expected an integer in [1, 64]");
  if (options.dilation < 0 || options.dilation > 16)
    throw InputError("dilation = " + std::to_string(options.dilation) + ": expected an integer in [0, 16]");
  if (seeds.rows() == 0) throw InputError("seeds is empty: expected at least one seed position");
  for (Eigen::Index r = 0; r < seeds.rows(); ++r)
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(seeds(r, a)))
        throw InputError("seeds[" + std::to_string(r) + ", " + std::to_string(a) + "] is not finite");
  const Blocking blocking(grid, options.block_size);

  std::vector<Int> wave;
  for (Eigen::Index r = 0; r < seeds.rows(); ++r) {
    Int cell[3];
    bool in_grid = true;
    for (int a = 0; a < 3; ++a) {
      const double x = (seeds(r, a) - grid.origin[a]) / grid.spacing[a];
      if (!(x >= 0.0) || x > static_cast<double>(grid.shape[a] - 1)) { in_grid = false; break; }
      cell[a] = std::min<Int>(static_cast<Int>(x), grid.shape[a] - 2);
    }
    if (!in_grid) continue;
    Int index[3] = {cell[0] / options.block_size, cell[1] / options.block_size, cell[2] / options.block_size};
    const int d = options.dilation;
    for (Int i = std::max<Int>(0, index[0] - d); i <= std::min(blocking.count[0] - 1, index[0] + d); ++i)
      for (Int j = std::max<Int>(0, index[1] - d); j <= std::min(blocking.count[1] - 1, index[1] + d); ++j)
        for (Int k = std::max<Int>(0, index[2] - d); k <= std::min(blocking.count[2] - 1, index[2] + d); ++k)
          wave.push_back((i * blocking.count[1] + j) * blocking.count[2] + k);
  }
  if (wave.empty()) throw InputError("no seed lies inside the grid");
  std::sort(wave.begin(), wave.end());
  wave.erase(std::unique(wave.begin(), wave.end()), wave.end());

  std::unordered_set<Int> visited(wave.begin(), wave.end());
  std::vector<std::pair<Int, BlockOutput>> found;
  Int evaluations = 0;
  using PointMatrix = Eigen::Matrix<Int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  constexpr std::size_t batch = 2048;
  while (!wave.empty()) {
    progress.report(0.9 * static_cast<double>(visited.size() - wave.size()) / static_cast<double>(visited.size()),
                    "marching cubes (sparse)");
    std::vector<Int> next_wave;
    for (std::size_t begin = 0; begin < wave.size(); begin += batch) {
      const std::size_t end = std::min(wave.size(), begin + batch);
      std::vector<Block> blocks;
      std::vector<Int> offset{0};
      for (std::size_t b = begin; b < end; ++b) {
        blocks.push_back(blocking.block(wave[b]));
        offset.push_back(offset.back() + blocks.back().corner_count());
      }
      PointMatrix points(offset.back(), 3);
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        Int row = offset[b];
        for (int i = 0; i <= blocks[b].cells[0]; ++i)
          for (int j = 0; j <= blocks[b].cells[1]; ++j)
            for (int k = 0; k <= blocks[b].cells[2]; ++k, ++row)
              points.row(row) << blocks[b].first[0] + i, blocks[b].first[1] + j, blocks[b].first[2] + k;
      }
      std::vector<double> values(static_cast<std::size_t>(offset.back()));
      field(points, values.data());
      evaluations += offset.back();
      for (std::size_t r = 0; r < values.size(); ++r)
        if (!std::isfinite(values[r]))
          throw InputError("the field returned " + std::to_string(values[r]) + " at grid point (" +
                           std::to_string(points(static_cast<Eigen::Index>(r), 0)) + ", " +
                           std::to_string(points(static_cast<Eigen::Index>(r), 1)) + ", " +
                           std::to_string(points(static_cast<Eigen::Index>(r), 2)) + "): expected finite values");
      std::vector<BlockOutput> outputs(blocks.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 4), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<int> slots;
        for (std::size_t b = r.begin(); b < r.end(); ++b)
          contour_block(blocking, blocks[b], values.data() + offset[b], iso, true, slots, outputs[b]);
      });
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        for (Int key : outputs[b].neighbours)
          if (visited.insert(key).second) next_wave.push_back(key);
        outputs[b].neighbours.clear();
        outputs[b].neighbours.shrink_to_fit();
        if (!outputs[b].keys.empty()) found.emplace_back(blocks[b].key, std::move(outputs[b]));
      }
    }
    if (static_cast<Int>(visited.size()) > options.max_blocks)
      throw InputError("marching_cubes_sparse visited more than max_blocks = " + std::to_string(options.max_blocks) +
                       " blocks: the level set is larger than expected (use a coarser grid or raise max_blocks)");
    std::sort(next_wave.begin(), next_wave.end());
    wave = std::move(next_wave);
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<BlockOutput> outputs;
  outputs.reserve(found.size());
  for (auto& entry : found) outputs.push_back(std::move(entry.second));
  ContourMesh mesh = merge_blocks(outputs);
  mesh.blocks = static_cast<Int>(visited.size());
  mesh.evaluations = evaluations;
  progress.report(1.0, "marching cubes (sparse)");
  return mesh;
}

}  // namespace meshsmith::reconstruction
