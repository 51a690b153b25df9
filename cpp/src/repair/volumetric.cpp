// Volumetric repair (§2.4.2): rasterize, close by rho, flood-fill, make well-composed, dual
// contouring with QEF vertices, feature-aware smoothing, untangling. include/meshsmith/repair/
// volumetric.h documents the steps and guarantees.
#include <meshsmith/repair/volumetric.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
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

struct VoxelGrid {
  std::int64_t n[3];
  Vec3 origin;
  double h;
  std::int64_t size() const { return n[0] * n[1] * n[2]; }
  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return (i * n[1] + j) * n[2] + k; }
  std::int64_t stride(int axis) const { return axis == 0 ? n[1] * n[2] : axis == 1 ? n[2] : 1; }
};

// Separating-axis test of a triangle (corners relative to the box centre) against the cube of
// half-edge hh, with tolerance tol on the side of overlap.
bool triangle_overlaps_box(const Vec3 p[3], double hh, double tol) {
  for (int a = 0; a < 3; ++a) {
    const double lo = std::min({p[0][a], p[1][a], p[2][a]}), hi = std::max({p[0][a], p[1][a], p[2][a]});
    if (lo > hh + tol || hi < -hh - tol) return false;
  }
  auto separated = [&](const Vec3& axis) {
    const double l1 = axis.cwiseAbs().sum();
    if (l1 == 0.0) return false;
    const double s0 = axis.dot(p[0]), s1 = axis.dot(p[1]), s2 = axis.dot(p[2]);
    const double r = hh * l1 + tol * l1;
    return std::min({s0, s1, s2}) > r || std::max({s0, s1, s2}) < -r;
  };
  if (separated((p[1] - p[0]).cross(p[2] - p[0]))) return false;
  for (int e = 0; e < 3; ++e) {
    const Vec3 edge = p[(e + 1) % 3] - p[e];
    for (int a = 0; a < 3; ++a) {
      if (separated(Vec3::Unit(a).cross(edge))) return false;
    }
  }
  return true;
}

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
  if (options.max_cells < 1) {
    throw InputError("volumetric_repair: max_cells must be >= 1, got " + std::to_string(options.max_cells));
  }
  VolumetricResult result;
  VolumetricReport& report = result.report;
  if (F.rows() == 0) {
    throw InputError("volumetric_repair: F has no faces");
  }

  // 1. The grid.
  const double h = options.epsilon / std::sqrt(3.0);
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity()), upper = -lower;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      lower = lower.cwiseMin(V.row(F(f, c)).transpose());
      upper = upper.cwiseMax(V.row(F(f, c)).transpose());
    }
  }
  const double pad_cells = std::ceil(options.rho / h) + 2.0;
  VoxelGrid g;
  g.h = h;
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double count = std::ceil((upper[a] - lower[a]) / h) + 1.0 + 2.0 * pad_cells;
    cells *= count;
    g.n[a] = count < 1e15 ? static_cast<std::int64_t>(count) : std::int64_t(1) << 50;
  }
  if (!(cells <= double(options.max_cells))) {
    throw InputError("volumetric_repair: the grid would have " + number_text(cells) + " cells (" +
                     number_text(double(g.n[0])) + " x " + number_text(double(g.n[1])) + " x " +
                     number_text(double(g.n[2])) + ", cell edge epsilon/sqrt(3) = " + number_text(h) +
                     "), more than max_cells = " + std::to_string(options.max_cells) +
                     "; raise epsilon or max_cells");
  }
  const Vec3 centre = (lower + upper) / 2.0;
  for (int a = 0; a < 3; ++a) g.origin[a] = centre[a] - 0.5 * double(g.n[a]) * h;
  report.shape = {g.n[0], g.n[1], g.n[2]};
  report.cell_size = h;
  const std::int64_t N = g.size();

  // 2. Rasterize.
  std::vector<std::uint8_t> occupied(N, 0);
  const double tol = 1e-9 * h;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if ((f & 4095) == 0) progress.subrange(0.0, 0.2).report(double(f) / F.rows(), "rasterize");
    Vec3 p[3];
    for (int c = 0; c < 3; ++c) p[c] = V.row(F(f, c)).transpose();
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double mn = std::min({p[0][a], p[1][a], p[2][a]}), mx = std::max({p[0][a], p[1][a], p[2][a]});
      lo[a] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((mn - g.origin[a]) / h - 1e-6)));
      hi[a] = std::min<std::int64_t>(g.n[a] - 1, static_cast<std::int64_t>(std::floor((mx - g.origin[a]) / h + 1e-6)));
    }
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
        for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
          const std::int64_t v = g.index(i, j, k);
          if (occupied[v]) continue;
          const Vec3 c = g.origin + h * Vec3(i + 0.5, j + 0.5, k + 0.5);
          const Vec3 q[3] = {p[0] - c, p[1] - c, p[2] - c};
          if (triangle_overlaps_box(q, 0.5 * h, tol)) occupied[v] = 1;
        }
      }
    }
  }
  for (auto o : occupied) report.occupied_cells += o;

  // 3. Closing by rho, flood fill.
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

  // 4. Well-composed solid without cavities.
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

  // 5. Boundary quads (one per voxel face between the solid and the outside), corners as keys.
  const std::int64_t cy = g.n[2] + 1, cx = (g.n[1] + 1) * cy;
  std::vector<std::array<std::int64_t, 4>> quads;
  std::vector<Vec3> quad_centres;
  for (std::int64_t i = 0; i < g.n[0]; ++i) {
    for (std::int64_t j = 0; j < g.n[1]; ++j) {
      for (std::int64_t k = 0; k < g.n[2]; ++k) {
        const std::int64_t v = g.index(i, j, k);
        const std::int64_t c[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          if (c[d] + 1 >= g.n[d]) continue;
          const bool a = solid[v], b = solid[v + g.stride(d)];
          if (a == b) continue;
          const int u = (d + 1) % 3, w = (d + 2) % 3;
          std::int64_t base[3] = {i, j, k};
          base[d] += 1;
          const std::int64_t step[3] = {cx, cy, 1};
          const std::int64_t k0 = base[0] * cx + base[1] * cy + base[2];
          std::array<std::int64_t, 4> q = {k0, k0 + step[u], k0 + step[u] + step[w], k0 + step[w]};
          if (!a) std::swap(q[1], q[3]);  // normal towards -d
          quads.push_back(q);
          Vec3 m = g.origin + h * Vec3(i + 0.5, j + 0.5, k + 0.5);
          m[d] += 0.5 * h;
          quad_centres.push_back(m);
        }
      }
    }
  }
  std::vector<std::uint8_t>().swap(solid);
  progress.report(0.65, "dual contouring");
  std::vector<std::int64_t> keys;
  keys.reserve(quads.size() * 4);
  for (const auto& q : quads) keys.insert(keys.end(), q.begin(), q.end());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  const auto nv = static_cast<Eigen::Index>(keys.size());
  const auto nq = static_cast<Eigen::Index>(quads.size());
  if (nv >= std::numeric_limits<int>::max() / 2 || 2 * nq >= std::numeric_limits<int>::max()) {
    throw InputError("volumetric_repair: the output would exceed 2^31 elements; raise epsilon");
  }
  Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> Q(nq, 4);
  for (Eigen::Index q = 0; q < nq; ++q) {
    for (int c = 0; c < 4; ++c) {
      Q(q, c) = static_cast<int>(std::lower_bound(keys.begin(), keys.end(), quads[q][c]) - keys.begin());
    }
  }
  VertexMatrix corner(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    const std::int64_t key = keys[v];
    corner.row(v) = (g.origin + h * Vec3(double(key / cx), double((key / cy) % (g.n[1] + 1)), double(key % cy))).transpose();
  }

  // 6. Hermite data: the plane of the nearest input triangle to each quad's centre.
  VertexMatrix centres(nq, 3);
  for (Eigen::Index q = 0; q < nq; ++q) centres.row(q) = quad_centres[q].transpose();
  std::vector<Vec3>().swap(quad_centres);
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
  VertexMatrix X = corner;
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
  std::vector<std::uint8_t> moved(nv, 0);
  for (int round = 0;; ++round) {
    progress.subrange(0.8, 1.0).report(std::min(0.95, round / 20.0), "untangle");
    const EdgeMatrix pairs = self_intersections(X, result.F);
    if (pairs.rows() == 0) break;
    if (round >= 64) {
      X = corner;  // the voxel surface itself: embedded
      std::fill(moved.begin(), moved.end(), 1);
      break;
    }
    std::vector<std::uint8_t> hit(nv, 0);
    for (Eigen::Index p = 0; p < pairs.rows(); ++p) {
      for (int s = 0; s < 2; ++s) {
        for (int c = 0; c < 3; ++c) hit[result.F(pairs(p, s), c)] = 1;
      }
    }
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (!hit[v]) continue;
      moved[v] = 1;
      X.row(v) = round < 8 ? (0.5 * (X.row(v) + corner.row(v))).eval() : corner.row(v);
    }
  }
  for (auto m : moved) report.untangled_vertices += m;
  result.V = std::move(X);
  progress.report(1.0, "done");
  return result;
}

}  // namespace meshsmith::repair
