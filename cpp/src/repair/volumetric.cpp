// Volumetric repair (§2.4.2): rasterize (conservative triangle-box test, recursive subdivision),
// close by rho, flood-fill, make well-composed, dual contouring with QEF vertices, feature-aware
// smoothing, untangling; on a sparse grid of 8×8×8 bricks near the surface (default) or a dense
// voxel grid. include/meshsmith/repair/volumetric.h documents the steps and guarantees.
#include <meshsmith/repair/volumetric.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/decimation/decimate.h>
#include <meshsmith/geometry/distance.h>
#include <meshsmith/repair/self_intersections.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshsmith::repair {
namespace {

using Vec3 = Eigen::Vector3d;

// Grid cells and corners as one 64-bit key: 21 bits an axis.
constexpr int kAxisBits = 21;
constexpr std::int64_t kAxisMask = (std::int64_t(1) << kAxisBits) - 1;
constexpr std::int64_t kAxisLimit = kAxisMask - 1;  // cells an axis (corners go to n)
std::int64_t pack(std::int64_t i, std::int64_t j, std::int64_t k) { return (i << 42) | (j << 21) | k; }
void unpack(std::int64_t key, std::int64_t c[3]) {
  c[0] = key >> 42, c[1] = (key >> 21) & kAxisMask, c[2] = key & kAxisMask;
}

// Conservative separating-axis test (Akenine-Möller's 13 axes) of the triangle p against the
// closed cube of centre `centre` and half-edge hh: false only when an axis separates them by more
// than the floating-point error of the test, so a triangle that touches the cube (even at a
// corner) is never missed. The error bounds: q = p - centre (and centre itself, origin + h·index)
// are within 8u·scale of the exact values per coordinate (scale: the largest coordinate), so the
// cube is enlarged by that; a projection axis·q computed in doubles is within 3u·|axis|₁·max|q| of
// exact (the axis may be inexact: any axis separates, as long as both sides use the same one).
bool triangle_overlaps_box(const Vec3 p[3], const Vec3& centre, double hh) {
  constexpr double u = std::numeric_limits<double>::epsilon() / 2.0;
  double scale = centre.cwiseAbs().maxCoeff();
  Vec3 q[3];
  for (int c = 0; c < 3; ++c) {
    q[c] = p[c] - centre;
    scale = std::max(scale, p[c].cwiseAbs().maxCoeff());
  }
  const double H = hh * (1.0 + 8.0 * u) + 8.0 * u * scale;
  double M = 0.0;
  for (int c = 0; c < 3; ++c) M = std::max(M, q[c].cwiseAbs().maxCoeff());
  for (int a = 0; a < 3; ++a) {
    const double lo = std::min({q[0][a], q[1][a], q[2][a]}), hi = std::max({q[0][a], q[1][a], q[2][a]});
    if (lo > H || hi < -H) return false;
  }
  auto separated = [&](const Vec3& axis) {
    const double l1 = axis.cwiseAbs().sum();
    if (!(l1 > 0.0)) return false;
    const double s0 = axis.dot(q[0]), s1 = axis.dot(q[1]), s2 = axis.dot(q[2]);
    const double r = H * l1 * (1.0 + 8.0 * u) + 8.0 * u * l1 * (M + H);
    return std::min({s0, s1, s2}) > r || std::max({s0, s1, s2}) < -r;
  };
  if (separated((q[1] - q[0]).cross(q[2] - q[0]))) return false;
  for (int e = 0; e < 3; ++e) {
    const Vec3 edge = q[(e + 1) % 3] - q[e];
    for (int a = 0; a < 3; ++a) {
      if (separated(Vec3::Unit(a).cross(edge))) return false;
    }
  }
  return true;
}

// Calls mark(i, j, k) for every cell of edge h (cell (i,j,k) = origin + h·[i, i+1]×…) in
// [0, n) that the triangle p overlaps (conservatively): the cube of cells around the triangle's
// bounding box is split recursively into octants, and only octants the triangle overlaps are
// split further, so the cost follows the triangle's area in cells, not its bounding box's volume.
template <class Mark>
void rasterize_triangle(const Vec3 p[3], const Vec3& origin, double h, const std::int64_t n[3], Mark&& mark) {
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const double mn = std::min({p[0][a], p[1][a], p[2][a]}), mx = std::max({p[0][a], p[1][a], p[2][a]});
    lo[a] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((mn - origin[a]) / h)) - 1);
    hi[a] = std::min<std::int64_t>(n[a] - 1, static_cast<std::int64_t>(std::floor((mx - origin[a]) / h)) + 1);
    if (lo[a] > hi[a]) return;
  }
  std::int64_t size = 1;
  while (size < std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) + 1) size *= 2;
  struct Box { std::int64_t c[3]; std::int64_t s; };
  std::vector<Box> stack{{{lo[0], lo[1], lo[2]}, size}};
  while (!stack.empty()) {
    const Box b = stack.back();
    stack.pop_back();
    bool empty = false;
    for (int a = 0; a < 3; ++a) empty = empty || b.c[a] > hi[a] || b.c[a] + b.s - 1 < lo[a];
    if (empty) continue;
    const Vec3 centre = origin + h * Vec3(b.c[0] + 0.5 * b.s, b.c[1] + 0.5 * b.s, b.c[2] + 0.5 * b.s);
    if (!triangle_overlaps_box(p, centre, 0.5 * h * double(b.s))) continue;
    if (b.s == 1) {
      mark(b.c[0], b.c[1], b.c[2]);
      continue;
    }
    const std::int64_t half = b.s / 2;
    for (int o = 0; o < 8; ++o) {
      stack.push_back({{b.c[0] + ((o >> 2) & 1) * half, b.c[1] + ((o >> 1) & 1) * half, b.c[2] + (o & 1) * half}, half});
    }
  }
}

// The offsets (in cells) of the cells whose centres lie within r cells of a cell's centre.
// (Compared in float as the dense grid's distance transform does, so both give the same solid.)
std::vector<std::array<int, 3>> ball_offsets(double r) {
  std::vector<std::array<int, 3>> offsets;
  const int R = static_cast<int>(std::floor(r));
  const float r2 = static_cast<float>(r * r);
  for (int x = -R; x <= R; ++x) {
    for (int y = -R; y <= R; ++y) {
      for (int z = -R; z <= R; ++z) {
        if (static_cast<float>(x * x + y * y + z * z) <= r2) offsets.push_back({x, y, z});
      }
    }
  }
  return offsets;
}

// The grid (both grids: the same lattice, so they give the same solid): the bounding box padded
// by rho + 2 cells, with the lattice placed as before the sparse grid existed (centred on the box
// with that count), then one brick more on each side, and rounded up to whole bricks on the high
// side. counts: cells an axis; origin: the lowest corner.
constexpr int kBrickBits = 3, kBrick = 1 << kBrickBits, kBrickCells = kBrick * kBrick * kBrick;
struct GridPlacement {
  std::array<double, 3> counts;
  Vec3 origin;
};
GridPlacement grid_placement(const Vec3& lower, const Vec3& upper, double h, double r_cells) {
  const double pad = std::ceil(r_cells) + 2.0;
  const Vec3 centre = (lower + upper) / 2.0;
  GridPlacement g;
  for (int a = 0; a < 3; ++a) {
    const double centred = std::ceil((upper[a] - lower[a]) / h) + 1.0 + 2.0 * pad + 2.0 * kBrick;
    g.counts[a] = kBrick * std::ceil(centred / kBrick);
    g.origin[a] = centre[a] - 0.5 * centred * h;
  }
  return g;
}

// The boundary faces of a solid: one quad per cell face between a solid and an empty cell, its
// corners as grid-corner keys (pack), oriented outward.
struct Boundary {
  Vec3 origin = Vec3::Zero();  // the grid's lowest corner
  std::vector<std::array<std::int64_t, 4>> quads;
  // The face between cell c and cell c + e_d; a, b: whether they are solid.
  void add(const std::int64_t c[3], int d, bool a, bool b) {
    if (a == b) return;
    const int u = (d + 1) % 3, w = (d + 2) % 3;
    std::int64_t base[3] = {c[0], c[1], c[2]};
    base[d] += 1;
    std::int64_t step[3][3] = {};
    step[u][u] = 1, step[w][w] = 1;
    auto key = [&](int su, int sw) {
      return pack(base[0] + su * step[u][0] + sw * step[w][0], base[1] + su * step[u][1] + sw * step[w][1],
                  base[2] + su * step[u][2] + sw * step[w][2]);
    };
    std::array<std::int64_t, 4> q = {key(0, 0), key(1, 0), key(1, 1), key(0, 1)};
    if (!a) std::swap(q[1], q[3]);  // normal towards -d
    quads.push_back(q);
  }
};

// ---------------------------------------------------------------------------------------------
// Dense voxel grid (grid = dense).

struct VoxelGrid {
  std::int64_t n[3];
  Vec3 origin;
  double h;
  std::int64_t size() const { return n[0] * n[1] * n[2]; }
  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return (i * n[1] + j) * n[2] + k; }
  std::int64_t stride(int axis) const { return axis == 0 ? n[1] * n[2] : axis == 1 ? n[2] : 1; }
};

// Squared Euclidean distance (in voxels²) from every voxel centre to the nearest voxel of `set`
// (Felzenszwalb & Huttenlocher 2012: three separable lower-envelope passes).
std::vector<float> squared_distance_transform(const VoxelGrid& g, const std::vector<std::uint8_t>& set,
                                              const Progress& progress) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> d(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) d[i] = set[i] ? 0.0f : inf;
  std::int64_t longest = std::max({g.n[0], g.n[1], g.n[2]});
  std::vector<float> f(longest), out(longest);
  std::vector<double> z(longest + 1);
  std::vector<std::int64_t> v(longest);
  for (int axis = 0; axis < 3; ++axis) {
    progress.report(axis / 3.0, "distance transform");
    const std::int64_t len = g.n[axis], stride = g.stride(axis);
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (std::int64_t x = 0; x < g.n[a1]; ++x) {
      for (std::int64_t y = 0; y < g.n[a2]; ++y) {
        std::int64_t c[3];
        c[axis] = 0, c[a1] = x, c[a2] = y;
        const std::int64_t base = g.index(c[0], c[1], c[2]);
        bool any = false;
        for (std::int64_t q = 0; q < len; ++q) {
          f[q] = d[base + q * stride];
          any = any || f[q] < inf;
        }
        if (!any) continue;
        std::int64_t k = -1;
        for (std::int64_t q = 0; q < len; ++q) {
          if (f[q] == inf) continue;
          double s = 0.0;
          while (k >= 0) {
            s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * (q - v[k]));
            if (s <= z[k]) --k; else break;
          }
          ++k;
          v[k] = q;
          z[k] = k == 0 ? -std::numeric_limits<double>::infinity() : s;
          z[k + 1] = std::numeric_limits<double>::infinity();
        }
        std::int64_t j = 0;
        for (std::int64_t q = 0; q < len; ++q) {
          while (z[j + 1] < double(q)) ++j;
          const double dq = double(q - v[j]);
          out[q] = static_cast<float>(dq * dq + f[v[j]]);
        }
        for (std::int64_t q = 0; q < len; ++q) d[base + q * stride] = out[q];
      }
    }
  }
  return d;
}

// Voxels reached from voxel 0 through voxels where `blocked` is 0 (6-connected).
std::vector<std::uint8_t> flood_outside(const VoxelGrid& g, const std::vector<std::uint8_t>& blocked) {
  std::vector<std::uint8_t> reached(blocked.size(), 0);
  std::vector<std::int64_t> queue{0};
  reached[0] = 1;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::int64_t v = queue[head];
    const std::int64_t c[3] = {v / g.stride(0), (v / g.n[2]) % g.n[1], v % g.n[2]};
    for (int axis = 0; axis < 3; ++axis) {
      for (int step : {-1, 1}) {
        const std::int64_t t = c[axis] + step;
        if (t < 0 || t >= g.n[axis]) continue;
        const std::int64_t w = v + step * g.stride(axis);
        if (!reached[w] && !blocked[w]) {
          reached[w] = 1;
          queue.push_back(w);
        }
      }
    }
  }
  return reached;
}

// The cell a 2×2×2 block (corner c at bit c: x = bit 2, y = bit 1, z = bit 0; `bits` its solid
// cells, `count` how many) needs filled to remove a diagonal pair alone in one of its faces or an
// antipodal pair alone in the block (in the solid or its complement), or -1.
int well_composed_fill(int bits, int count) {
  int fill = -1;
  // Antipodal pairs c and 7-c.
  for (int c = 0; c < 4 && fill < 0; ++c) {
    const int pair = (1 << c) | (1 << (7 - c));
    if (count == 2 && bits == pair) fill = c ^ 1;           // a neighbour of corner c
    if (count == 6 && (bits & pair) == 0) fill = c;
  }
  // The block's six faces: corners with bit `axis` fixed to `side`.
  for (int axis = 0; axis < 3 && fill < 0; ++axis) {
    for (int side = 0; side < 2 && fill < 0; ++side) {
      int face[4], m = 0;
      for (int c = 0; c < 8; ++c) {
        if (((c >> (2 - axis)) & 1) == side) face[m++] = c;
      }
      // face[0..3] in binary order: (0,3) and (1,2) are the diagonals.
      const bool b0 = bits >> face[0] & 1, b1 = bits >> face[1] & 1, b2 = bits >> face[2] & 1,
                 b3 = bits >> face[3] & 1;
      if (b0 == b3 && b1 == b2 && b0 != b1) fill = b0 ? face[1] : face[0];
    }
  }
  return fill;
}

// Adds voxels to `solid` until no 2×2 square holds a diagonal pair alone and no 2×2×2 block holds
// an antipodal pair alone (in the solid or its complement). Returns the voxels added.
std::int64_t make_well_composed(const VoxelGrid& g, std::vector<std::uint8_t>& solid, const Progress& progress) {
  std::int64_t added = 0;
  const std::int64_t sx = g.stride(0), sy = g.stride(1);
  for (int sweep = 0;; ++sweep) {
    progress.report(std::min(0.9, sweep / 10.0), "well-composed");
    std::int64_t changed = 0;
    for (std::int64_t i = 0; i + 1 < g.n[0]; ++i) {
      for (std::int64_t j = 0; j + 1 < g.n[1]; ++j) {
        for (std::int64_t k = 0; k + 1 < g.n[2]; ++k) {
          const std::int64_t base = g.index(i, j, k);
          std::int64_t at[8];
          int bits = 0, count = 0;
          for (int c = 0; c < 8; ++c) {
            at[c] = base + ((c >> 2) & 1) * sx + ((c >> 1) & 1) * sy + (c & 1);
            if (solid[at[c]]) bits |= 1 << c, ++count;
          }
          if (count == 0 || count == 8) continue;
          const int fill = well_composed_fill(bits, count);
          if (fill >= 0) {
            solid[at[fill]] = 1;
            ++changed;
          }
        }
      }
    }
    added += changed;
    if (changed == 0) return added;
  }
}

// ---------------------------------------------------------------------------------------------
// Sparse grid (grid = sparse): cells are stored only in 8×8×8 bricks that hold a cell near the
// surface (occupied, within rho of it, eroded or changed by the manifold fix); every other brick is
// uniform, with one state byte in a coarse array of the bricks (1/512 of the cells), set by the
// flood fill: outside, or enclosed (solid).

enum : std::uint8_t { kOccupied = 1, kBlocked = 2, kOutside = 4, kSolid = 8, kEroded = 16 };

struct SparseGrid {
  std::int64_t n[3];   // cells an axis (multiples of kBrick)
  std::int64_t nb[3];  // bricks an axis
  Vec3 origin;
  double h = 0.0;
  std::int64_t max_cells = 0;
  std::vector<std::int32_t> brick_of;  // per brick: index of its stored cells, or -1 (uniform)
  std::vector<std::uint8_t> coarse;    // per brick: the state of all its cells while uniform
  std::vector<std::uint8_t> cells;     // kBrickCells per stored brick
  std::vector<std::int64_t> stored;    // the brick index of each stored brick

  std::int64_t brick(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return ((i >> kBrickBits) * nb[1] + (j >> kBrickBits)) * nb[2] + (k >> kBrickBits);
  }
  static std::size_t local(std::int64_t i, std::int64_t j, std::int64_t k) {
    return std::size_t(((i & (kBrick - 1)) << (2 * kBrickBits)) | ((j & (kBrick - 1)) << kBrickBits) | (k & (kBrick - 1)));
  }
  bool contains(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < n[0] && j < n[1] && k < n[2];
  }
  std::uint8_t state(std::int64_t i, std::int64_t j, std::int64_t k) const {
    const std::int64_t b = brick(i, j, k);
    const std::int32_t s = brick_of[b];
    return s < 0 ? coarse[b] : cells[std::size_t(s) * kBrickCells + local(i, j, k)];
  }
  std::uint8_t& at(std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::int64_t b = brick(i, j, k);
    std::int32_t s = brick_of[b];
    if (s < 0) s = store(b);
    return cells[std::size_t(s) * kBrickCells + local(i, j, k)];
  }
  std::int32_t store(std::int64_t b) {
    const auto s = static_cast<std::int64_t>(stored.size());
    if ((s + 1) * kBrickCells > max_cells || s + 1 >= std::numeric_limits<std::int32_t>::max()) {
      throw InputError("volumetric_repair: the sparse grid needs more than max_cells = " + std::to_string(max_cells) +
                       " cells near the surface (" + std::to_string(s) + " bricks of " + std::to_string(kBrickCells) +
                       " cells stored so far, cell edge epsilon/sqrt(3) = " + number_text(h) +
                       "); raise epsilon or max_cells");
    }
    stored.push_back(b);
    cells.resize(cells.size() + kBrickCells, coarse[b]);
    brick_of[b] = static_cast<std::int32_t>(s);
    return static_cast<std::int32_t>(s);
  }
  void brick_coordinates(std::int64_t b, std::int64_t c[3]) const {
    c[0] = b / (nb[1] * nb[2]), c[1] = (b / nb[2]) % nb[1], c[2] = b % nb[2];
  }
  // Calls f(i, j, k, state&) for every stored cell.
  template <class F>
  void for_stored(F&& f) {
    for (std::size_t s = 0; s < stored.size(); ++s) {
      std::int64_t c[3];
      brick_coordinates(stored[s], c);
      for (int l = 0; l < kBrickCells; ++l) {
        f(c[0] * kBrick + (l >> (2 * kBrickBits)), c[1] * kBrick + ((l >> kBrickBits) & (kBrick - 1)),
          c[2] * kBrick + (l & (kBrick - 1)), cells[s * kBrickCells + std::size_t(l)]);
      }
    }
  }
  // Solid cells: stored ones plus kBrickCells per uniform solid brick.
  std::int64_t count(std::uint8_t bit, bool set) const {
    std::int64_t total = 0;
    for (std::size_t b = 0; b < coarse.size(); ++b) {
      if (brick_of[b] < 0 && bool(coarse[b] & bit) == set) total += kBrickCells;
    }
    for (auto s : cells) total += bool(s & bit) == set;
    return total;
  }
};

// Sets kOutside on the cells reached from the grid's corner through cells without a `wall` bit
// (6-connected), clearing it elsewhere; uniform bricks are visited as one node each.
void sparse_flood_outside(SparseGrid& g, std::uint8_t wall) {
  for (auto& s : g.coarse) s &= std::uint8_t(~kOutside);
  for (auto& s : g.cells) s &= std::uint8_t(~kOutside);
  constexpr std::int64_t kUniform = std::int64_t(1) << 62;
  std::vector<std::int64_t> stack;
  auto visit = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::int64_t b = g.brick(i, j, k);
    const std::int32_t s = g.brick_of[b];
    std::uint8_t& state = s < 0 ? g.coarse[b] : g.cells[std::size_t(s) * kBrickCells + SparseGrid::local(i, j, k)];
    if (state & (kOutside | wall)) return;
    state |= kOutside;
    stack.push_back(s < 0 ? (kUniform | b) : pack(i, j, k));
  };
  visit(0, 0, 0);
  while (!stack.empty()) {
    const std::int64_t item = stack.back();
    stack.pop_back();
    if (item & kUniform) {
      std::int64_t c[3];
      g.brick_coordinates(item & ~kUniform, c);
      for (int axis = 0; axis < 3; ++axis) {
        for (int step : {-1, 1}) {
          std::int64_t d[3] = {c[0], c[1], c[2]};
          d[axis] += step;
          if (d[axis] < 0 || d[axis] >= g.nb[axis]) continue;
          // The cells of the neighbour brick's face towards this brick (one call if it is uniform).
          const int u = (axis + 1) % 3, w = (axis + 2) % 3;
          const bool uniform = g.brick_of[(d[0] * g.nb[1] + d[1]) * g.nb[2] + d[2]] < 0;
          const int span = uniform ? 1 : kBrick;
          for (int x = 0; x < span; ++x) {
            for (int y = 0; y < span; ++y) {
              std::int64_t cell[3];
              cell[axis] = d[axis] * kBrick + (step > 0 ? 0 : kBrick - 1);
              cell[u] = d[u] * kBrick + x, cell[w] = d[w] * kBrick + y;
              visit(cell[0], cell[1], cell[2]);
            }
          }
        }
      }
    } else {
      std::int64_t c[3];
      unpack(item, c);
      for (int axis = 0; axis < 3; ++axis) {
        for (int step : {-1, 1}) {
          std::int64_t d[3] = {c[0], c[1], c[2]};
          d[axis] += step;
          if (g.contains(d[0], d[1], d[2])) visit(d[0], d[1], d[2]);
        }
      }
    }
  }
}

// Sparse counterpart of make_well_composed: the 2×2×2 blocks that can hold both solid and empty
// cells are those with a cell in a stored brick (uniform bricks that touch are all solid or all
// empty: the flood fill would otherwise have crossed between them), so only blocks whose lowest
// corner lies in [8b - 1, 8b + 7] of a stored brick b are examined. Cells added to a uniform brick
// store it.
std::int64_t sparse_make_well_composed(SparseGrid& g, const Progress& progress) {
  std::int64_t added = 0;
  for (int sweep = 0;; ++sweep) {
    progress.report(std::min(0.9, sweep / 10.0), "well-composed");
    std::int64_t changed = 0;
    for (std::size_t s = 0; s < g.stored.size(); ++s) {
      std::int64_t bc[3];
      g.brick_coordinates(g.stored[s], bc);
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(0, bc[a] * kBrick - 1);
        hi[a] = std::min<std::int64_t>(g.n[a] - 2, bc[a] * kBrick + kBrick - 1);
      }
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
          for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
            int bits = 0, count = 0;
            for (int c = 0; c < 8; ++c) {
              if (g.state(i + ((c >> 2) & 1), j + ((c >> 1) & 1), k + (c & 1)) & kSolid) bits |= 1 << c, ++count;
            }
            if (count == 0 || count == 8) continue;
            const int fill = well_composed_fill(bits, count);
            if (fill >= 0) {
              g.at(i + ((fill >> 2) & 1), j + ((fill >> 1) & 1), k + (fill & 1)) |= kSolid;
              ++changed;
            }
          }
        }
      }
    }
    added += changed;
    if (changed == 0) return added;
  }
}

// The sparse pipeline up to the boundary faces (steps 1-3 of volumetric.h on stored bricks).
Boundary sparse_solid_boundary(const VertexRef& V, const FaceRef& F, const Vec3& lower, const Vec3& upper,
                               const VolumetricOptions& options, VolumetricReport& report, const Progress& progress) {
  const double h = options.epsilon / std::sqrt(3.0);
  const double r_cells = options.rho / h;
  SparseGrid g;
  g.h = h;
  g.max_cells = options.max_cells;
  const GridPlacement placement = grid_placement(lower, upper, h, r_cells);
  const std::array<double, 3>& counts = placement.counts;
  double bricks = 1.0;
  report.dense_cells = counts[0] * counts[1] * counts[2];
  for (int a = 0; a < 3; ++a) {
    if (!(counts[a] <= double(kAxisLimit))) {
      throw InputError("volumetric_repair: the grid would have " + number_text(counts[a]) +
                       " cells along axis " + std::to_string(a) + ", more than " + std::to_string(kAxisLimit) +
                       " (cell edge epsilon/sqrt(3) = " + number_text(h) + "); raise epsilon");
    }
    g.nb[a] = static_cast<std::int64_t>(counts[a]) / kBrick;
    g.n[a] = g.nb[a] * kBrick;
    bricks *= double(g.nb[a]);
  }
  if (!(bricks <= double(options.max_cells))) {
    throw InputError("volumetric_repair: the sparse grid's coarse array would have " + number_text(bricks) +
                     " bricks, more than max_cells = " + std::to_string(options.max_cells) + "; raise epsilon or max_cells");
  }
  g.origin = placement.origin;
  report.shape = {g.n[0], g.n[1], g.n[2]};
  report.cell_size = h;
  g.brick_of.assign(static_cast<std::size_t>(bricks), -1);
  g.coarse.assign(static_cast<std::size_t>(bricks), 0);

  // 1. Rasterize.
  std::vector<std::int64_t> occupied;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if ((f & 4095) == 0) progress.subrange(0.0, 0.2).report(double(f) / F.rows(), "rasterize");
    Vec3 p[3];
    for (int c = 0; c < 3; ++c) p[c] = V.row(F(f, c)).transpose();
    rasterize_triangle(p, g.origin, h, g.n, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
      std::uint8_t& s = g.at(i, j, k);
      if (s & kOccupied) return;
      s |= kOccupied;
      occupied.push_back(pack(i, j, k));
    });
  }
  report.occupied_cells = static_cast<std::int64_t>(occupied.size());
  sparse_flood_outside(g, kOccupied);
  const std::int64_t plain_inside = g.count(kOutside, false);

  // 2. Closing by rho: block the cells within rho of an occupied one (balls around the occupied
  // cells with an empty 6-neighbour: the nearest occupied cell of any cell is one of those),
  // flood-fill the outside, grow it back by rho (balls around the outside cells with a non-outside
  // 6-neighbour, likewise).
  progress.report(0.2, "closing");
  const auto ball = ball_offsets(r_cells);
  auto on_rim = [&](const std::int64_t c[3], std::uint8_t bit, bool set) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int step : {-1, 1}) {
        std::int64_t d[3] = {c[0], c[1], c[2]};
        d[axis] += step;
        if (g.contains(d[0], d[1], d[2]) && bool(g.state(d[0], d[1], d[2]) & bit) != set) return true;
      }
    }
    return false;
  };
  for (std::size_t o = 0; o < occupied.size(); ++o) {
    if ((o & 65535) == 0) progress.subrange(0.2, 0.35).report(double(o) / occupied.size(), "dilate");
    std::int64_t c[3];
    unpack(occupied[o], c);
    if (!on_rim(c, kOccupied, true)) {
      g.at(c[0], c[1], c[2]) |= kBlocked;
      continue;
    }
    for (const auto& b : ball) {
      const std::int64_t i = c[0] + b[0], j = c[1] + b[1], k = c[2] + b[2];
      if (g.contains(i, j, k)) g.at(i, j, k) |= kBlocked;
    }
  }
  std::vector<std::int64_t>().swap(occupied);
  sparse_flood_outside(g, kBlocked);
  if (r_cells > 0.0) {
    std::vector<std::int64_t> rim;
    g.for_stored([&](std::int64_t i, std::int64_t j, std::int64_t k, std::uint8_t& s) {
      if (s & kOutside) return;
      const std::int64_t c[3] = {i, j, k};
      for (int axis = 0; axis < 3; ++axis) {
        for (int step : {-1, 1}) {
          std::int64_t d[3] = {c[0], c[1], c[2]};
          d[axis] += step;
          if (g.contains(d[0], d[1], d[2]) && (g.state(d[0], d[1], d[2]) & kOutside)) rim.push_back(pack(d[0], d[1], d[2]));
        }
      }
    });
    std::sort(rim.begin(), rim.end());
    rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
    for (std::size_t o = 0; o < rim.size(); ++o) {
      if ((o & 65535) == 0) progress.subrange(0.35, 0.5).report(double(o) / rim.size(), "erode");
      std::int64_t c[3];
      unpack(rim[o], c);
      for (const auto& b : ball) {
        const std::int64_t i = c[0] + b[0], j = c[1] + b[1], k = c[2] + b[2];
        if (g.contains(i, j, k) && !(g.state(i, j, k) & (kOutside | kEroded))) g.at(i, j, k) |= kEroded;
      }
    }
  }
  for (std::size_t b = 0; b < g.coarse.size(); ++b) {
    if (!(g.coarse[b] & kOutside)) g.coarse[b] |= kSolid;
  }
  for (auto& s : g.cells) {
    if ((s & kOccupied) || !(s & (kOutside | kEroded))) s |= kSolid;
  }

  // 3. Well-composed solid without cavities.
  for (int round = 0; round < 64; ++round) {
    report.manifold_cells += sparse_make_well_composed(g, progress.subrange(0.5, 0.6));
    sparse_flood_outside(g, kSolid);
    std::int64_t filled = 0;
    for (std::size_t b = 0; b < g.coarse.size(); ++b) {
      if (!(g.coarse[b] & (kOutside | kSolid))) g.coarse[b] |= kSolid, filled += g.brick_of[b] < 0;
    }
    for (auto& s : g.cells) {
      if (!(s & (kOutside | kSolid))) s |= kSolid, ++filled;
    }
    if (filled == 0) break;
  }
  report.inside_cells = g.count(kSolid, true);
  report.closing_cells = report.inside_cells - plain_inside - report.manifold_cells;
  report.stored_cells = static_cast<std::int64_t>(g.cells.size());

  // The boundary faces: those with a cell in a stored brick (a face between two uniform bricks
  // separates two solid or two empty cells). Each face once: from its lower cell, or from its
  // upper cell when the lower one is in a uniform brick.
  progress.report(0.6, "boundary faces");
  Boundary boundary;
  boundary.origin = g.origin;
  g.for_stored([&](std::int64_t i, std::int64_t j, std::int64_t k, std::uint8_t& s) {
    const std::int64_t c[3] = {i, j, k};
    const bool solid = s & kSolid;
    for (int d = 0; d < 3; ++d) {
      std::int64_t up[3] = {i, j, k}, down[3] = {i, j, k};
      up[d] += 1, down[d] -= 1;
      if (up[d] < g.n[d]) boundary.add(c, d, solid, g.state(up[0], up[1], up[2]) & kSolid);
      if (down[d] >= 0 && g.brick_of[g.brick(down[0], down[1], down[2])] < 0) {
        boundary.add(down, d, g.state(down[0], down[1], down[2]) & kSolid, solid);
      }
    }
  });
  return boundary;
}


// The dense pipeline up to the boundary faces (steps 1-3 of volumetric.h on every voxel).
Boundary dense_solid_boundary(const VertexRef& V, const FaceRef& F, const Vec3& lower, const Vec3& upper,
                              const VolumetricOptions& options, VolumetricReport& report, const Progress& progress) {
  const double h = options.epsilon / std::sqrt(3.0);
  VoxelGrid g;
  g.h = h;
  const GridPlacement placement = grid_placement(lower, upper, h, options.rho / h);
  const std::array<double, 3>& counts = placement.counts;
  const double cells = counts[0] * counts[1] * counts[2];
  for (int a = 0; a < 3; ++a) g.n[a] = counts[a] < double(kAxisLimit) ? static_cast<std::int64_t>(counts[a]) : kAxisLimit + 1;
  report.dense_cells = cells;
  if (!(cells <= double(options.max_cells)) || std::max({g.n[0], g.n[1], g.n[2]}) > kAxisLimit) {
    throw InputError("volumetric_repair: the grid would have " + number_text(cells) + " cells (" +
                     number_text(double(g.n[0])) + " x " + number_text(double(g.n[1])) + " x " +
                     number_text(double(g.n[2])) + ", cell edge epsilon/sqrt(3) = " + number_text(h) +
                     "), more than max_cells = " + std::to_string(options.max_cells) + " or more than " +
                     std::to_string(kAxisLimit) + " along an axis; raise epsilon or max_cells");
  }
  g.origin = placement.origin;
  report.shape = {g.n[0], g.n[1], g.n[2]};
  report.cell_size = h;
  const std::int64_t N = g.size();
  report.stored_cells = N;

  // 1. Rasterize.
  std::vector<std::uint8_t> occupied(N, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if ((f & 4095) == 0) progress.subrange(0.0, 0.2).report(double(f) / F.rows(), "rasterize");
    Vec3 p[3];
    for (int c = 0; c < 3; ++c) p[c] = V.row(F(f, c)).transpose();
    rasterize_triangle(p, g.origin, h, g.n,
                       [&](std::int64_t i, std::int64_t j, std::int64_t k) { occupied[g.index(i, j, k)] = 1; });
  }
  for (auto o : occupied) report.occupied_cells += o;

  // 2. Closing by rho, flood fill.
  const double r_cells = options.rho / h;
  std::vector<std::uint8_t> outside = flood_outside(g, occupied);
  std::int64_t plain_inside = 0;
  for (auto o : outside) plain_inside += !o;
  std::vector<std::uint8_t> solid(N);
  if (r_cells > 0.0) {
    const float r2 = static_cast<float>(r_cells * r_cells);
    std::vector<float> d = squared_distance_transform(g, occupied, progress.subrange(0.2, 0.35));
    std::vector<std::uint8_t> blocked(N);
    for (std::int64_t v = 0; v < N; ++v) blocked[v] = d[v] <= r2;
    outside = flood_outside(g, blocked);
    d = squared_distance_transform(g, outside, progress.subrange(0.35, 0.5));
    for (std::int64_t v = 0; v < N; ++v) solid[v] = occupied[v] || d[v] > r2;
  } else {
    for (std::int64_t v = 0; v < N; ++v) solid[v] = !outside[v];
  }

  // 3. Well-composed solid without cavities.
  for (int round = 0; round < 64; ++round) {
    report.manifold_cells += make_well_composed(g, solid, progress.subrange(0.5, 0.6));
    std::vector<std::uint8_t> reached = flood_outside(g, solid);
    std::int64_t filled = 0;
    for (std::int64_t v = 0; v < N; ++v) {
      if (!reached[v] && !solid[v]) solid[v] = 1, ++filled;
    }
    if (filled == 0) break;
  }
  for (auto s : solid) report.inside_cells += s;
  report.closing_cells = report.inside_cells - plain_inside - report.manifold_cells;
  std::vector<std::uint8_t>().swap(outside);
  std::vector<std::uint8_t>().swap(occupied);

  progress.report(0.6, "boundary faces");
  Boundary boundary;
  boundary.origin = g.origin;
  for (std::int64_t i = 0; i < g.n[0]; ++i) {
    for (std::int64_t j = 0; j < g.n[1]; ++j) {
      for (std::int64_t k = 0; k < g.n[2]; ++k) {
        const std::int64_t v = g.index(i, j, k);
        const std::int64_t c[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          if (c[d] + 1 < g.n[d]) boundary.add(c, d, solid[v], solid[v + g.stride(d)]);
        }
      }
    }
  }
  return boundary;
}

// Steps 4-6 of volumetric.h: dual contouring of the boundary faces (one vertex per grid corner,
// at its clamped QEF minimizer), smoothing along the QEFs' null spaces, triangulation, untangling.
VolumetricResult contour(const VertexRef& V, const FaceRef& F, Boundary boundary, const VolumetricOptions& options,
                         VolumetricReport report, const Progress& progress) {
  VolumetricResult result;
  const double h = report.cell_size;
  const Vec3 origin = boundary.origin;
  progress.report(0.65, "dual contouring");
  std::vector<std::int64_t> keys;
  keys.reserve(boundary.quads.size() * 4);
  for (const auto& q : boundary.quads) keys.insert(keys.end(), q.begin(), q.end());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  keys.shrink_to_fit();
  const auto nv = static_cast<Eigen::Index>(keys.size());
  const auto nq = static_cast<Eigen::Index>(boundary.quads.size());
  if (nv >= std::numeric_limits<int>::max() / 2 || 2 * nq >= std::numeric_limits<int>::max()) {
    throw InputError("volumetric_repair: the output would exceed 2^31 elements; raise epsilon");
  }
  Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> Q(nq, 4);
  for (Eigen::Index q = 0; q < nq; ++q) {
    for (int c = 0; c < 4; ++c) {
      Q(q, c) = static_cast<int>(std::lower_bound(keys.begin(), keys.end(), boundary.quads[q][c]) - keys.begin());
    }
  }
  std::vector<std::array<std::int64_t, 4>>().swap(boundary.quads);
  VertexMatrix corner(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    std::int64_t c[3];
    unpack(keys[v], c);
    corner.row(v) = (origin + h * Vec3(double(c[0]), double(c[1]), double(c[2]))).transpose();
  }
  std::vector<std::int64_t>().swap(keys);

  // The QEFs and the smoothing in a scope of their own: their arrays (~250 bytes a vertex) are
  // freed before the untangling checks the mesh.
  VertexMatrix X = corner;
  {
    // Hermite data: the plane of the nearest input triangle to each quad's centre.
    VertexMatrix centres(nq, 3);
    for (Eigen::Index q = 0; q < nq; ++q) {
      centres.row(q) = 0.25 * (corner.row(Q(q, 0)) + corner.row(Q(q, 1)) + corner.row(Q(q, 2)) + corner.row(Q(q, 3)));
    }
    const geometry::SurfaceDistance surface(V, F);
    const geometry::ClosestPoints nearest = surface.closest_points(centres, progress.subrange(0.65, 0.75));
    std::vector<Eigen::Matrix3d> ata(nv, Eigen::Matrix3d::Zero());
    std::vector<Vec3> atb(nv, Vec3::Zero()), mass(nv, Vec3::Zero());
    std::vector<int> samples(nv, 0);
    for (Eigen::Index q = 0; q < nq; ++q) {
      if (nearest.distances[q] > 1.5 * h) continue;
      const int f = nearest.faces[q];
      const Vec3 a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
      Vec3 n = (b - a).cross(c - a);
      if (!(n.norm() > 0.0)) continue;
      n.normalize();
      const Vec3 p = nearest.points.row(q).transpose();
      for (int k = 0; k < 4; ++k) {
        const int v = Q(q, k);
        ata[v] += n * n.transpose();
        atb[v] += n * n.dot(p);
        mass[v] += p;
        ++samples[v];
      }
    }
    std::vector<Eigen::Matrix3d> free_directions(nv, Eigen::Matrix3d::Identity());
    // A vertex's cell: the 8 voxels around its corner (the occupied ones among them hold the input
    // surface, which may lie anywhere in them, since occupied voxels count as inside).
    auto clamp = [&](Eigen::Index v, const Vec3& x) {
      const Vec3 c = corner.row(v).transpose();
      return x.cwiseMax(c - Vec3::Constant(h)).cwiseMin(c + Vec3::Constant(h)).eval();
    };
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (samples[v] == 0) {
        ++report.unconstrained_vertices;
        continue;
      }
      const Vec3 m = mass[v] / samples[v];
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(ata[v]);
      const Vec3 rhs = atb[v] - ata[v] * m;
      const double largest = eig.eigenvalues().maxCoeff();
      Vec3 x = m;
      int rank = 0;
      Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
      for (int i = 0; i < 3; ++i) {
        const double l = eig.eigenvalues()[i];
        if (l > 0.02 * largest && l > 0.0) {
          const Vec3 e = eig.eigenvectors().col(i);
          x += e * (e.dot(rhs) / l);
          P -= e * e.transpose();
          ++rank;
        }
      }
      if (rank >= 2) ++report.sharp_vertices;
      free_directions[v] = P;
      X.row(v) = clamp(v, x).transpose();
    }

    // 7. Feature-aware smoothing along the QEF's null space.
    if (options.smoothing > 0) {
      std::vector<Eigen::Index> offsets(nv + 1, 0);
      for (Eigen::Index q = 0; q < nq; ++q) {
        for (int k = 0; k < 4; ++k) offsets[Q(q, k) + 1] += 2;
      }
      for (Eigen::Index v = 0; v < nv; ++v) offsets[v + 1] += offsets[v];
      std::vector<int> neighbours(offsets[nv]);
      std::vector<Eigen::Index> fill(offsets.begin(), offsets.end() - 1);
      for (Eigen::Index q = 0; q < nq; ++q) {
        for (int k = 0; k < 4; ++k) {
          const int v = Q(q, k);
          neighbours[fill[v]++] = Q(q, (k + 1) % 4);
          neighbours[fill[v]++] = Q(q, (k + 3) % 4);
        }
      }
      for (int round = 0; round < options.smoothing; ++round) {
        progress.subrange(0.75, 0.8).report(double(round) / options.smoothing, "smoothing");
        VertexMatrix next = X;
        for (Eigen::Index v = 0; v < nv; ++v) {
          Vec3 mean = Vec3::Zero();
          for (Eigen::Index e = offsets[v]; e < offsets[v + 1]; ++e) mean += X.row(neighbours[e]).transpose();
          mean /= double(offsets[v + 1] - offsets[v]);
          const Vec3 x = X.row(v).transpose();
          next.row(v) = clamp(v, x + 0.5 * free_directions[v] * (mean - x)).transpose();
        }
        X.swap(next);
      }
    }
  }

  // 8. Triangles along the shorter diagonal; undo self-intersections.
  result.F.resize(2 * nq, 3);
  for (Eigen::Index q = 0; q < nq; ++q) {
    const int a = Q(q, 0), b = Q(q, 1), c = Q(q, 2), d = Q(q, 3);
    if ((X.row(a) - X.row(c)).squaredNorm() <= (X.row(b) - X.row(d)).squaredNorm()) {
      result.F.row(2 * q) << a, b, c;
      result.F.row(2 * q + 1) << a, c, d;
    } else {
      result.F.row(2 * q) << a, b, d;
      result.F.row(2 * q + 1) << b, c, d;
    }
  }
  Q.resize(0, 4);
  // The first round checks every face; a later one only the faces near those whose vertices the
  // previous round moved (faces that did not change were checked already, and a face meeting a
  // changed one lies near it: a vertex stays within h of its grid corner along each axis and a
  // face's corners are adjacent grid corners, so the corners of two meeting faces differ by at
  // most 4 along each axis: buckets of 8×8×8 corners and their 26 neighbours cover them).
  std::vector<std::uint8_t> moved(nv, 0), changed;
  auto bucket_key = [&](Eigen::Index v, int dx, int dy, int dz) {
    const Vec3 c = (corner.row(v).transpose() - origin) / h;
    return pack(std::llround(c[0]) / 8 + 1 + dx, std::llround(c[1]) / 8 + 1 + dy, std::llround(c[2]) / 8 + 1 + dz);
  };
  for (int round = 0;; ++round) {
    progress.subrange(0.8, 1.0).report(std::min(0.95, round / 20.0), "untangle");
    EdgeMatrix pairs;
    if (round == 0) {
      pairs = self_intersections(X, result.F);
    } else {
      std::vector<std::int64_t> near;
      for (Eigen::Index f = 0; f < result.F.rows(); ++f) {
        if (!(changed[result.F(f, 0)] || changed[result.F(f, 1)] || changed[result.F(f, 2)])) continue;
        for (int c = 0; c < 3; ++c) {
          for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
              for (int dz = -1; dz <= 1; ++dz) near.push_back(bucket_key(result.F(f, c), dx, dy, dz));
            }
          }
        }
      }
      std::sort(near.begin(), near.end());
      near.erase(std::unique(near.begin(), near.end()), near.end());
      std::vector<Eigen::Index> subset;
      for (Eigen::Index f = 0; f < result.F.rows(); ++f) {
        for (int c = 0; c < 3; ++c) {
          if (std::binary_search(near.begin(), near.end(), bucket_key(result.F(f, c), 0, 0, 0))) {
            subset.push_back(f);
            break;
          }
        }
      }
      FaceMatrix Fs(static_cast<Eigen::Index>(subset.size()), 3);
      for (std::size_t i = 0; i < subset.size(); ++i) Fs.row(Eigen::Index(i)) = result.F.row(subset[i]);
      pairs = self_intersections(X, Fs);
      for (Eigen::Index p = 0; p < pairs.rows(); ++p) {
        pairs(p, 0) = static_cast<int>(subset[std::size_t(pairs(p, 0))]);
        pairs(p, 1) = static_cast<int>(subset[std::size_t(pairs(p, 1))]);
      }
    }
    if (pairs.rows() == 0) break;
    if (round >= 64) {
      X = corner;  // the voxel surface itself: embedded
      std::fill(moved.begin(), moved.end(), 1);
      break;
    }
    changed.assign(nv, 0);
    for (Eigen::Index p = 0; p < pairs.rows(); ++p) {
      for (int s = 0; s < 2; ++s) {
        for (int c = 0; c < 3; ++c) changed[result.F(pairs(p, s), c)] = 1;
      }
    }
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (!changed[v]) continue;
      moved[v] = 1;
      X.row(v) = round < 8 ? (0.5 * (X.row(v) + corner.row(v))).eval() : corner.row(v);
    }
  }
  for (auto m : moved) report.untangled_vertices += m;
  result.V = std::move(X);
  result.report = report;
  return result;
}

// Step 7 of volumetric.h: coarse output where the surface is flat. The fine mesh (closed,
// manifold, embedded) is simplified by the decimation chapter's QEM edge collapses up to a quadric
// error of (adaptive_error·ε)²; the link condition keeps it closed and manifold with its genus, and
// a result that self-intersects is redone from the fine mesh with a quarter of the bound (at most
// three times; then the fine mesh stays). Why collapses on the fine mesh and not octree
// simplification: volumetric.h.
void simplify(VolumetricResult& result, const VolumetricOptions& options, const Progress& progress) {
  VolumetricReport& report = result.report;
  report.fine_faces = result.F.rows();
  if (!(options.adaptive_error > 0.0) || result.F.rows() == 0) return;
  decimation::QemOptions qem;
  qem.max_error = options.adaptive_error * options.epsilon * options.adaptive_error * options.epsilon;
  qem.prevent_normal_flips = true;
  qem.keep_boundary = true;
  // Serial: with max_error as the only stop rule, the four-part parallel phase stalled here on
  // fandisk's fine mesh at extent/200 (still in it after 3 CPU-minutes, when it was stopped).
  qem.parallel = false;
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double lo = attempt == 0 ? 0.0 : 0.9 + 0.03 * (attempt - 1);
    const Progress step = progress.subrange(lo, attempt == 0 ? 0.9 : lo + 0.03);
    decimation::QemResult coarse = decimation::decimate_qem(result.V, result.F, qem, step.subrange(0.0, 0.8));
    step.report(0.8, "adaptive: self-intersection check");
    if (self_intersections(coarse.V, coarse.F).rows() == 0) {
      report.adaptive_bound = qem.max_error;
      report.adaptive_max_error = coarse.max_collapse_error;
      result.V = std::move(coarse.V);
      result.F = std::move(coarse.F);
      return;
    }
    ++report.adaptive_retries;
    qem.max_error /= 4.0;
  }
}

}  // namespace

VolumetricResult volumetric_repair(const VertexRef& V, const FaceRef& F, const VolumetricOptions& options,
                                   const Progress& progress) {
  validate_mesh(V, F);
  if (!std::isfinite(options.epsilon) || options.epsilon <= 0.0) {
    throw InputError("volumetric_repair: epsilon must be finite and > 0, got " + number_text(options.epsilon));
  }
  if (!std::isfinite(options.rho) || options.rho < 0.0) {
    throw InputError("volumetric_repair: rho must be finite and >= 0, got " + number_text(options.rho));
  }
  if (options.smoothing < 0) {
    throw InputError("volumetric_repair: smoothing must be >= 0, got " + std::to_string(options.smoothing));
  }
  if (!std::isfinite(options.adaptive_error) || options.adaptive_error < 0.0) {
    throw InputError("volumetric_repair: adaptive_error must be finite and >= 0, got " +
                     number_text(options.adaptive_error));
  }
  if (options.max_cells < 1) {
    throw InputError("volumetric_repair: max_cells must be >= 1, got " + std::to_string(options.max_cells));
  }
  if (F.rows() == 0) {
    throw InputError("volumetric_repair: F has no faces");
  }
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity()), upper = -lower;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      lower = lower.cwiseMin(V.row(F(f, c)).transpose());
      upper = upper.cwiseMax(V.row(F(f, c)).transpose());
    }
  }
  VolumetricReport report;
  const Progress solid_progress = progress.subrange(0.0, 0.6);
  Boundary boundary = options.dense ? dense_solid_boundary(V, F, lower, upper, options, report, solid_progress)
                                    : sparse_solid_boundary(V, F, lower, upper, options, report, solid_progress);
  const bool adaptive = options.adaptive_error > 0.0;
  VolumetricResult result =
      contour(V, F, std::move(boundary), options, report, progress.subrange(0.6, adaptive ? 0.9 : 1.0));
  simplify(result, options, progress.subrange(0.9, 1.0));
  progress.report(1.0, "done");
  return result;
}

}  // namespace meshsmith::repair
