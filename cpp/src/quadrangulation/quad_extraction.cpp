// Quad extraction from a seamless parametrization (§5.2.2 step 4; QEx, Ebke et al. 2013).
//
// How it works. QEx traces the integer iso-lines through the triangles and across the seams; the
// hard part there is the degenerate cases (an iso-line through a vertex, along an edge, a grid point
// on an edge), which need the same answer from both sides of every seam. We build the same mesh from
// the faces of the grid instead of its lines, with predicates that are exact and chart-independent:
//
//  1. Transitions. For each interior edge, the rotation r·π/2 and integer translation t that map the
//     (u, v) of one side onto the other (r from the edge vectors' angle, t rounded).
//  2. Exact seamless map. Around each vertex the transitions are composed over its fan from one home
//     corner; the home position is rounded to a dyadic grid (2^-s) and every other corner of the vertex
//     is its exact image (rotations and integer translations are exact on dyadic numbers held as
//     int64). At a singular vertex the loop transition is a rotation, and the home is its fixed point,
//     which must be an integer point. Every seam then relates its two sides exactly, so an
//     orientation predicate (int64 coordinates, __int128 products) gives the same sign in every chart.
//  3. Cells. In each triangle's chart, every unit square whose open interior meets the open triangle
//     (separating-axis test with the triangle's edges; the bounding box gives the axis tests) is a cell.
//  4. Gluing. A cell (f, S) is glued to (g, T(S)) across edge f|g when the edge meets the open square
//     (so both sides of it lie in S). A breadth-first walk over the glue links, composing the
//     transitions, gives each square's preimage: one class of cells, with the transform from its root
//     chart into each member's chart (two paths giving different transforms: inconsistent). A cell
//     whose square meets a boundary edge is cut by the boundary; a link to a missing cell (flipped
//     triangle, seam mismatch) makes the class inconsistent. Either leaves the square out. Zero-area
//     (u, v) triangles (MIQ collapses some next to singularities) are crossed: the walk goes on to
//     the faces beyond them, and grid points on them get one node.
//  5. Corners. Each square's four corners (counter-clockwise in its root chart) are located, exactly,
//     in a member cell's closed triangle: inside a face, on an edge (keyed by the edge's smaller side
//     and the point in that side's chart) or at a vertex, so a grid node seen from several charts gets
//     one key and one index.
//  6. Validity. Quads on an edge used more than twice or twice in one direction, or at a vertex with
//     more than one fan, are removed (repeatedly) so the result is always manifold and oriented.
#include <meshsmith/quadrangulation/quad_extraction.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/topology/characteristics.h>
#include <meshsmith/topology/edge_incidence.h>
#include <meshsmith/topology/manifold.h>

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

namespace meshsmith::quadrangulation {

namespace {

using Int = std::int64_t;
using Wide = __int128;

struct Point {
  Int x = 0, y = 0;
  bool operator==(const Point& o) const { return x == o.x && y == o.y; }
  bool operator!=(const Point& o) const { return !(*this == o); }
};

/// x ↦ R^r x + t·2^s: a rotation by r quarter turns (counter-clockwise) and a translation by the
/// integer vector t (grid units). `shift` is s: points are held as integers in units of 2^-s.
struct Rigid {
  int r = 0;
  Int tx = 0, ty = 0;
  bool operator==(const Rigid& o) const { return r == o.r && tx == o.tx && ty == o.ty; }
  bool operator!=(const Rigid& o) const { return !(*this == o); }
};

Point rotate(Point p, int r) {
  switch (r & 3) {
    case 1: return {-p.y, p.x};
    case 2: return {-p.x, -p.y};
    case 3: return {p.y, -p.x};
    default: return p;
  }
}

Point apply(const Rigid& T, Point p, int shift) {
  const Point q = rotate(p, T.r);
  return {q.x + (T.tx << shift), q.y + (T.ty << shift)};
}

/// (a ∘ b)(x) = a(b(x)).
Rigid compose(const Rigid& a, const Rigid& b) {
  const Point t = rotate({b.tx, b.ty}, a.r);
  return {(a.r + b.r) & 3, t.x + a.tx, t.y + a.ty};
}

Rigid inverse(const Rigid& a) {
  const Point t = rotate({-a.tx, -a.ty}, -a.r);
  return {(4 - a.r) & 3, t.x, t.y};
}

int sign(Wide v) { return (v > 0) - (v < 0); }

/// Sign of the area of (a, b, c): exact for |coordinates| < 2^61.
int orient(Point a, Point b, Point c) {
  const Wide v = static_cast<Wide>(b.x - a.x) * (c.y - a.y) - static_cast<Wide>(b.y - a.y) * (c.x - a.x);
  return sign(v);
}

Int floor_div(Int a, int shift) { return a >> shift; }  // arithmetic shift: floor
Int ceil_div(Int a, int shift) { return -((-a) >> shift); }

/// Does the closed segment [p, q] meet the open square (i, i+1) × (j, j+1) (in units of 2^-s)?
/// Separating axes: the square's two and the segment's normal.
bool segment_meets_open_square(Point p, Point q, const std::array<Point, 4>& corners, Int x0, Int x1,
                               Int y0, Int y1) {
  if (std::max(p.x, q.x) <= x0 || std::min(p.x, q.x) >= x1) return false;
  if (std::max(p.y, q.y) <= y0 || std::min(p.y, q.y) >= y1) return false;
  bool any_positive = false, any_negative = false;
  for (const Point& c : corners) {
    const int o = orient(p, q, c);
    any_positive |= o > 0;
    any_negative |= o < 0;
  }
  return any_positive && any_negative;
}

std::array<Point, 4> square_corners(Int i, Int j, int shift) {
  return {Point{i << shift, j << shift}, Point{(i + 1) << shift, j << shift},
          Point{(i + 1) << shift, (j + 1) << shift}, Point{i << shift, (j + 1) << shift}};
}

/// The rotation and integer translation taking segment (pa, pb) onto (qa, qb), and how far off it is.
std::pair<Rigid, double> fit_transition(const Eigen::Vector2d& pa, const Eigen::Vector2d& pb,
                                        const Eigen::Vector2d& qa, const Eigen::Vector2d& qb) {
  const Eigen::Vector2d d = pb - pa, e = qb - qa;
  const double angle = std::atan2(d.x() * e.y() - d.y() * e.x(), d.dot(e));
  const int r = static_cast<int>(std::lround(angle / (M_PI / 2))) & 3;
  auto rot = [r](const Eigen::Vector2d& x) -> Eigen::Vector2d {
    switch (r) {
      case 1: return {-x.y(), x.x()};
      case 2: return -x;
      case 3: return {x.y(), -x.x()};
      default: return x;
    }
  };
  const Eigen::Vector2d t = 0.5 * ((qa - rot(pa)) + (qb - rot(pb)));
  Rigid T{r, static_cast<Int>(std::llround(t.x())), static_cast<Int>(std::llround(t.y()))};
  const Eigen::Vector2d tr(static_cast<double>(T.tx), static_cast<double>(T.ty));
  const double residual = std::max((rot(pa) + tr - qa).lpNorm<Eigen::Infinity>(),
                                   (rot(pb) + tr - qb).lpNorm<Eigen::Infinity>());
  return {T, residual};
}

struct Cell {
  int face;
  Int i, j;
  bool cut_by_boundary = false;
  bool broken = false;  // glued to a cell that does not exist
};

/// Key of a grid node: at a vertex (kind 0, id = vertex), on an edge (kind 1, id = the edge's smaller
/// side 3f + k, point in face f's chart), inside a face (kind 2, id = face) or on a zero-area (u, v)
/// triangle (kind 3, id = that face, point in its chart).
using NodeKey = std::tuple<int, int, Int, Int>;

}  // namespace

QuadExtraction extract_quads(const VertexRef& V, const FaceRef& F, const CornerUVRef& UV,
                             const Progress& progress) {
  validate_mesh(V, F);
  const Eigen::Index m = F.rows();
  if (UV.rows() != 3 * m)
    throw InputError("UV has " + std::to_string(UV.rows()) + " corner rows; expected 3 per face (" +
                     std::to_string(3 * m) + ")");
  double max_abs = 0.0;
  for (Eigen::Index c = 0; c < UV.rows(); ++c)
    for (int k = 0; k < 2; ++k) {
      const double value = UV(c, k);
      if (!std::isfinite(value))
        throw InputError("UV of face " + std::to_string(c / 3) + ", corner " + std::to_string(c % 3) +
                         " is not finite");
      max_abs = std::max(max_abs, std::abs(value));
    }
  if (max_abs >= std::ldexp(1.0, 40))
    throw InputError("UV holds |value| >= 2^40: scale the parametrization down");
  for (Eigen::Index f = 0; f < m; ++f)
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
      throw InputError("face " + std::to_string(f) + " repeats a vertex");
  const topology::EdgeIncidence incidence = topology::edge_incidence(F, V.rows());
  if (const EdgeMatrix bad = topology::non_manifold_edges(incidence); bad.rows() > 0) {
    const Eigen::RowVector2i e = bad.row(0);
    throw InputError("extract_quads needs a manifold mesh: edge (" + std::to_string(e(0)) + ", " +
                     std::to_string(e(1)) + ") has more than two faces");
  }
  {
    const std::vector<int> bad = topology::non_manifold_vertices(F, incidence);
    if (!bad.empty())
      throw InputError("extract_quads needs a manifold mesh: vertex " + std::to_string(bad.front()) +
                       " is non-manifold (split it with topology.split_non_manifold_vertices)");
  }
  progress.report(0.0, "extract quads: transitions");

  QuadExtraction out;
  QuadExtractionReport& report = out.report;
  report.euler_input = topology::euler_characteristic(F, incidence);

  // Read the map, mirrored when it is clockwise overall.
  auto corner = [m](Eigen::Index f, int k) { return static_cast<int>(3 * f + ((k % 3) + 3) % 3); };
  double signed_area = 0.0;
  for (Eigen::Index f = 0; f < m; ++f) {
    const Eigen::Vector2d a = UV.row(3 * f), b = UV.row(3 * f + 1), c = UV.row(3 * f + 2);
    signed_area += (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  }
  report.mirrored = signed_area < 0.0;
  auto uv = [&](int c) -> Eigen::Vector2d {
    return {UV(c, 0), report.mirrored ? -UV(c, 1) : UV(c, 1)};
  };

  // 1. Transitions: twin side and the map from a side's face chart into its twin's face chart.
  const int n_sides = static_cast<int>(3 * m);
  std::vector<int> twin(n_sides, -1);
  std::vector<Rigid> transition(n_sides);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) != 2) continue;
    const int s1 = incidence.edge_sides[incidence.edge_offsets[e]];
    const int s2 = incidence.edge_sides[incidence.edge_offsets[e] + 1];
    twin[s1] = s2;
    twin[s2] = s1;
    // side s1 runs a → b in its face; s2 runs b → a in the other.
    const Eigen::Vector2d pa = uv(s1), pb = uv(corner(s1 / 3, s1 % 3 + 1));
    const Eigen::Vector2d qb = uv(s2), qa = uv(corner(s2 / 3, s2 % 3 + 1));
    const auto [T, residual] = fit_transition(pa, pb, qa, qb);
    const double scale = std::max({1.0, pa.lpNorm<Eigen::Infinity>(), qa.lpNorm<Eigen::Infinity>()});
    if (!(residual <= 1e-6 * scale)) ++report.non_seamless_edges;
    transition[s1] = T;
    transition[s2] = inverse(T);
  }

  // 2. Exact seamless map on the dyadic grid 2^-shift.
  const int shift = std::clamp(50 - static_cast<int>(std::ceil(std::log2(max_abs + 2.0))), 0, 40);
  const double unit = std::ldexp(1.0, shift);
  std::vector<Point> U(n_sides);
  {
    std::vector<char> movable(V.rows(), 0);
    std::vector<std::vector<int>> corners_of(V.rows());
    for (int c = 0; c < n_sides; ++c) corners_of[F(c / 3, c % 3)].push_back(c);
    std::vector<Rigid> to_corner(n_sides);
    std::vector<char> seen(n_sides, 0);
    std::vector<int> queue;
    for (Eigen::Index w = 0; w < V.rows(); ++w) {
      const std::vector<int>& cs = corners_of[w];
      if (cs.empty()) continue;
      queue.assign(1, cs.front());
      seen[cs.front()] = 1;
      to_corner[cs.front()] = Rigid{};
      std::optional<Rigid> loop;
      bool mismatch = false;
      double angle_sum = 0.0;
      for (std::size_t q = 0; q < queue.size(); ++q) {
        const int c = queue[q];
        const int f = c / 3, k = c % 3;
        const Eigen::Vector2d d1 = uv(corner(f, k + 1)) - uv(c), d2 = uv(corner(f, k + 2)) - uv(c);
        angle_sum += std::atan2(d1.x() * d2.y() - d1.y() * d2.x(), d1.dot(d2));
        // The two sides of f at w: side k (w → next) and side k+2 (prev → w).
        for (const int s : {corner(f, k), corner(f, k + 2)}) {
          const int t = twin[s];
          if (t < 0) continue;
          const int g = t / 3;
          const int cg = F(g, t % 3) == w ? t : corner(g, t % 3 + 1);
          const Rigid T = compose(transition[s], to_corner[c]);
          if (!seen[cg]) {
            seen[cg] = 1;
            to_corner[cg] = T;
            queue.push_back(cg);
          } else if (T != to_corner[cg]) {
            const Rigid D = compose(inverse(to_corner[cg]), T);  // home chart → home chart
            if (D.r == 0) mismatch = true;
            else loop = D;
          }
        }
      }
      const int index = 4 - static_cast<int>(std::lround(angle_sum / (M_PI / 2)));
      const bool interior = std::all_of(cs.begin(), cs.end(), [&](int c) {
        return twin[c] >= 0 && twin[corner(c / 3, c % 3 + 2)] >= 0;
      });
      if (interior && index != 0) {
        report.singular_vertices.push_back(static_cast<int>(w));
        report.singular_indices.push_back(index);
      }
      if (mismatch) ++report.non_seamless_edges;
      const Eigen::Vector2d home = uv(cs.front());
      Point H{static_cast<Int>(std::llround(home.x() * unit)), static_cast<Int>(std::llround(home.y() * unit))};
      if (loop) {
        // Fixed point x = R x + t of the loop transition, rounded to the integer grid.
        const Rigid& D = *loop;
        Eigen::Matrix2d R;
        if (D.r == 1) R << 0, -1, 1, 0;
        else if (D.r == 2) R << -1, 0, 0, -1;
        else R << 0, 1, -1, 0;
        const Eigen::Vector2d x = (Eigen::Matrix2d::Identity() - R)
                                      .inverse() * Eigen::Vector2d(static_cast<double>(D.tx), static_cast<double>(D.ty));
        const Point X{static_cast<Int>(std::llround(x.x())), static_cast<Int>(std::llround(x.y()))};
        const Point Xs{X.x << shift, X.y << shift};
        if (apply(D, Xs, shift) == Xs) H = Xs;
        else ++report.non_integer_singularities;
      }
      for (const int c : cs) U[c] = apply(to_corner[c], H, shift);
      movable[w] = interior && !loop && !mismatch;
    }

    // Untangling: a free vertex of a clockwise triangle moves to the mean of its ring (read in its
    // home chart) when that leaves fewer non-positive triangles around it; a few rounds.
    auto area_sign = [&](int f) { return orient(U[3 * f], U[3 * f + 1], U[3 * f + 2]); };
    for (int round = 0; round < 8; ++round) {
      std::vector<int> candidates;
      for (Eigen::Index f = 0; f < m; ++f)
        if (area_sign(static_cast<int>(f)) < 0)
          for (int k = 0; k < 3; ++k)
            if (movable[F(f, k)]) candidates.push_back(F(f, k));
      if (candidates.empty()) break;
      std::sort(candidates.begin(), candidates.end());
      candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      bool moved = false;
      for (const int w : candidates) {
        const std::vector<int>& cs = corners_of[w];
        auto bad_around = [&] {
          int bad = 0;
          for (const int c : cs) bad += area_sign(c / 3) <= 0;
          return bad;
        };
        const int before = bad_around();
        Wide sx = 0, sy = 0;
        for (const int c : cs) {
          const Rigid back = inverse(to_corner[c]);
          for (const int o : {corner(c / 3, c % 3 + 1), corner(c / 3, c % 3 + 2)}) {
            const Point p = apply(back, U[o], shift);
            sx += p.x;
            sy += p.y;
          }
        }
        const Wide count = 2 * static_cast<Wide>(cs.size());
        const Point H{static_cast<Int>(sx / count), static_cast<Int>(sy / count)};
        std::vector<Point> old(cs.size());
        for (std::size_t i = 0; i < cs.size(); ++i) old[i] = U[cs[i]], U[cs[i]] = apply(to_corner[cs[i]], H, shift);
        if (bad_around() < before) {
          moved = true;
          ++report.untangled_vertices;
        } else {
          for (std::size_t i = 0; i < cs.size(); ++i) U[cs[i]] = old[i];
        }
      }
      if (!moved) break;
    }
  }
  progress.report(0.2, "extract quads: cells");

  // Vertices joined by an edge of zero length in (u, v) are one grid point: one node if it is on the grid.
  std::vector<int> same_point(V.rows());
  for (Eigen::Index v = 0; v < V.rows(); ++v) same_point[v] = static_cast<int>(v);
  auto representative = [&](int v) {
    while (same_point[v] != v) v = same_point[v] = same_point[same_point[v]];
    return v;
  };
  for (int c = 0; c < n_sides; ++c)
    if (U[c] == U[corner(c / 3, c % 3 + 1)]) {
      const int a = representative(F(c / 3, c % 3)), b = representative(F(c / 3, (c % 3 + 1) % 3));
      same_point[std::max(a, b)] = std::min(a, b);
    }

  // 3. Cells: (face, square) with overlapping interiors, sorted by (face, i, j).
  {
    // The grid's size, bounded before anything depends on it (a map scaled far too large would
    // otherwise run for hours): the unit squares of every face's bounding box.
    double squares = 0.0;
    for (Eigen::Index f = 0; f < m; ++f) {
      const Point A = U[3 * f], B = U[3 * f + 1], C = U[3 * f + 2];
      squares += static_cast<double>(ceil_div(std::max({A.x, B.x, C.x}), shift) - floor_div(std::min({A.x, B.x, C.x}), shift)) *
                 static_cast<double>(ceil_div(std::max({A.y, B.y, C.y}), shift) - floor_div(std::min({A.y, B.y, C.y}), shift));
    }
    if (squares > std::ldexp(1.0, 26))
      throw InputError("UV spans about " + std::to_string(static_cast<long long>(squares)) +
                       " unit squares over its triangles, more than 2^26: scale the parametrization down");
  }
  std::vector<Cell> cells;
  std::vector<int> face_cells(m + 1, 0);
  std::vector<int> face_sign(m, 0);
  for (Eigen::Index f = 0; f < m; ++f) {
    face_cells[f] = static_cast<int>(cells.size());
    const Point A = U[3 * f], B = U[3 * f + 1], C = U[3 * f + 2];
    face_sign[f] = orient(A, B, C);
    if (face_sign[f] == 0) { ++report.degenerate_triangles; continue; }
    if (face_sign[f] < 0) { ++report.flipped_triangles; continue; }
    const Int i0 = floor_div(std::min({A.x, B.x, C.x}), shift), i1 = ceil_div(std::max({A.x, B.x, C.x}), shift);
    const Int j0 = floor_div(std::min({A.y, B.y, C.y}), shift), j1 = ceil_div(std::max({A.y, B.y, C.y}), shift);
    const std::array<Point, 3> P{A, B, C};
    for (Int i = i0; i < i1; ++i)
      for (Int j = j0; j < j1; ++j) {
        const auto sq = square_corners(i, j, shift);
        bool separated = false;
        for (int k = 0; k < 3 && !separated; ++k)
          separated = std::all_of(sq.begin(), sq.end(),
                                  [&](const Point& c) { return orient(P[k], P[(k + 1) % 3], c) <= 0; });
        if (!separated) cells.push_back(Cell{static_cast<int>(f), i, j});
      }
    if (f % 4096 == 0) progress.report(0.2 + 0.3 * static_cast<double>(f) / static_cast<double>(m), "extract quads: cells");
  }
  face_cells[m] = static_cast<int>(cells.size());
  auto find_cell = [&](int f, Int i, Int j) -> int {
    const auto begin = cells.begin() + face_cells[f], end = cells.begin() + face_cells[f + 1];
    const auto it = std::lower_bound(begin, end, std::make_pair(i, j), [](const Cell& c, const std::pair<Int, Int>& key) {
      return std::make_pair(c.i, c.j) < key;
    });
    return (it != end && it->i == i && it->j == j) ? static_cast<int>(it - cells.begin()) : -1;
  };

  // 4. Glue links: cell → (neighbour cell, transform from this cell's chart to the neighbour's).
  // A zero-area triangle in (u, v) is a segment (or a point): a square crossing into one passes
  // through it to the faces beyond, so the walk continues across such faces (a flipped one breaks it).
  const int n_cells = static_cast<int>(cells.size());
  std::vector<std::vector<std::pair<int, Rigid>>> links(n_cells);
  std::vector<std::pair<int, Rigid>> through;  // (side entered, chart transform so far)
  std::vector<int> crossed_faces;
  for (int c = 0; c < n_cells; ++c) {
    Cell& cell = cells[c];
    const int f = cell.face;
    const auto sq = square_corners(cell.i, cell.j, shift);
    for (int k = 0; k < 3; ++k) {
      const int s = 3 * f + k;
      if (!segment_meets_open_square(U[s], U[corner(f, k + 1)], sq, sq[0].x, sq[2].x, sq[0].y, sq[2].y)) continue;
      if (twin[s] < 0) { cell.cut_by_boundary = true; continue; }
      through.assign(1, {s, transition[s]});
      crossed_faces.clear();
      for (std::size_t q = 0; q < through.size(); ++q) {
        const auto [side, T] = through[q];
        const int g = twin[side] / 3;
        // The square's doubled centre maps to the neighbour square's doubled centre.
        const Point centre = rotate({2 * cell.i + 1, 2 * cell.j + 1}, T.r);
        const Int ci = (centre.x + 2 * T.tx - 1) / 2, cj = (centre.y + 2 * T.ty - 1) / 2;
        if (face_sign[g] > 0) {
          const int other = find_cell(g, ci, cj);
          if (other < 0) cell.broken = true;
          else links[c].push_back({other, T});
          continue;
        }
        if (face_sign[g] < 0 || std::find(crossed_faces.begin(), crossed_faces.end(), g) != crossed_faces.end() ||
            crossed_faces.size() >= 64) {
          cell.broken = true;
          continue;
        }
        crossed_faces.push_back(g);
        const auto sg = square_corners(ci, cj, shift);
        for (int k2 = 0; k2 < 3; ++k2) {
          const int s2 = 3 * g + k2;
          if (s2 == twin[side]) continue;
          if (!segment_meets_open_square(U[s2], U[corner(g, k2 + 1)], sg, sg[0].x, sg[2].x, sg[0].y, sg[2].y)) continue;
          if (twin[s2] < 0) { cell.cut_by_boundary = true; continue; }
          through.push_back({s2, compose(transition[s2], T)});
        }
      }
    }
  }
  progress.report(0.6, "extract quads: squares");

  // 5. Classes (one per square's preimage) and their corners.
  std::vector<int> class_of(n_cells, -1);
  std::vector<Rigid> from_root(n_cells);
  std::map<NodeKey, int> node_index;
  std::vector<std::array<int, 4>> quads;
  std::vector<int> members;
  // Nodes are appended to growing vectors, then copied: conservativeResize per node is quadratic.
  std::vector<Eigen::RowVector3d> node_position;
  std::vector<std::array<double, 2>> node_uv;
  std::vector<int> node_face;
  auto locate = [&](int cell, Point p) -> int {
    const int f = cells[cell].face;
    const std::array<Point, 3> P{U[3 * f], U[3 * f + 1], U[3 * f + 2]};
    std::array<int, 3> o{};
    for (int k = 0; k < 3; ++k) {
      o[k] = orient(P[k], P[(k + 1) % 3], p);
      if (o[k] < 0) return -1;
    }
    const int zeros = (o[0] == 0) + (o[1] == 0) + (o[2] == 0);
    NodeKey key;
    int key_face = f;
    Point key_point = p;
    if (zeros >= 2) {
      // corner k is shared by sides k-1 and k: the one non-zero side is k+1.
      const int k = o[1] != 0 ? 0 : (o[2] != 0 ? 1 : 2);
      key = {0, representative(F(f, k)), 0, 0};
    } else if (zeros == 1) {
      const int k = o[0] == 0 ? 0 : (o[1] == 0 ? 1 : 2);
      int s = 3 * f + k;
      if (twin[s] >= 0 && face_sign[twin[s] / 3] == 0) {
        // On the edge of a zero-area (u, v) triangle: the same (u, v) point seen from the triangle's
        // other sides is the same node, so it is keyed in that triangle.
        key_point = apply(transition[s], p, shift);
        key_face = twin[s] / 3;
        key = {3, key_face, key_point.x, key_point.y};
      } else {
        if (twin[s] >= 0 && twin[s] < s) {
          key_point = apply(transition[s], p, shift);
          s = twin[s];
          key_face = s / 3;
        }
        key = {1, s, key_point.x, key_point.y};
      }
    } else {
      key = {2, f, p.x, p.y};
    }
    const auto [it, inserted] = node_index.emplace(key, static_cast<int>(node_position.size()));
    if (inserted) {
      Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
      if (std::get<0>(key) == 0) {
        x = V.row(std::get<1>(key));
      } else {
        const double area = static_cast<double>(static_cast<Wide>(P[1].x - P[0].x) * (P[2].y - P[0].y) -
                                                static_cast<Wide>(P[1].y - P[0].y) * (P[2].x - P[0].x));
        for (int k = 0; k < 3; ++k) {
          const Point a = P[(k + 1) % 3], b = P[(k + 2) % 3];
          const double weight = static_cast<double>(static_cast<Wide>(b.x - a.x) * (p.y - a.y) -
                                                    static_cast<Wide>(b.y - a.y) * (p.x - a.x)) / area;
          x += weight * V.row(F(f, k));
        }
      }
      node_position.push_back(x);
      node_uv.push_back({static_cast<double>(key_point.x >> shift), static_cast<double>(key_point.y >> shift)});
      node_face.push_back(key_face);
    }
    return it->second;
  };

  int n_classes = 0;
  for (int root = 0; root < n_cells; ++root) {
    if (class_of[root] >= 0) continue;
    const int id = n_classes++;
    members.assign(1, root);
    class_of[root] = id;
    from_root[root] = Rigid{};
    bool consistent = true, cut = false;
    for (std::size_t q = 0; q < members.size(); ++q) {
      const int c = members[q];
      consistent &= !cells[c].broken;
      cut |= cells[c].cut_by_boundary;
      for (const auto& [other, step] : links[c]) {
        const Rigid T = compose(step, from_root[c]);
        if (class_of[other] < 0) {
          class_of[other] = id;
          from_root[other] = T;
          members.push_back(other);
        } else if (class_of[other] != id || from_root[other] != T) {
          consistent = false;
        }
      }
    }
    if (cut) { ++report.squares_cut_by_boundary; continue; }
    if (!consistent) { ++report.squares_inconsistent; continue; }
    const auto sq = square_corners(cells[root].i, cells[root].j, shift);
    std::array<int, 4> quad{};
    bool found_all = true;
    for (int k = 0; k < 4 && found_all; ++k) {
      quad[k] = -1;
      for (const int c : members) {
        quad[k] = locate(c, apply(from_root[c], sq[k], shift));
        if (quad[k] >= 0) break;
      }
      found_all = quad[k] >= 0;
    }
    if (found_all) {
      std::array<int, 4> sorted = quad;
      std::sort(sorted.begin(), sorted.end());
      found_all = std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
    }
    if (!found_all) { ++report.squares_inconsistent; continue; }
    quads.push_back(quad);
    if (id % 4096 == 0) progress.report(0.6 + 0.3 * static_cast<double>(root) / std::max(1, n_cells), "extract quads: squares");
  }

  // 6. Remove quads until the rest is manifold and oriented.
  progress.report(0.9, "extract quads: validity");
  std::vector<char> kept(quads.size(), 1);
  for (int round = 0; round < 16; ++round) {
    std::map<std::pair<int, int>, std::vector<int>> edge_quads;  // undirected edge → quads on it
    std::map<std::pair<int, int>, int> directed;
    for (std::size_t q = 0; q < quads.size(); ++q) {
      if (!kept[q]) continue;
      for (int k = 0; k < 4; ++k) {
        const int a = quads[q][k], b = quads[q][(k + 1) % 4];
        edge_quads[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(q));
        ++directed[{a, b}];
      }
    }
    std::vector<int> remove;
    for (const auto& [edge, on] : edge_quads) {
      const bool bad = on.size() > 2 || directed[{edge.first, edge.second}] > 1 ||
                       directed[{edge.second, edge.first}] > 1;
      if (bad) remove.insert(remove.end(), on.begin(), on.end());
    }
    if (remove.empty()) {
      // Vertex fans: on the quads split into triangles (same vertices, edges, fans).
      FaceMatrix T(2 * static_cast<Eigen::Index>(std::count(kept.begin(), kept.end(), 1)), 3);
      std::vector<int> quad_of;
      Eigen::Index t = 0;
      for (std::size_t q = 0; q < quads.size(); ++q) {
        if (!kept[q]) continue;
        T.row(t++) << quads[q][0], quads[q][1], quads[q][2];
        T.row(t++) << quads[q][0], quads[q][2], quads[q][3];
        quad_of.push_back(static_cast<int>(q));
      }
      if (t == 0) break;
      const std::vector<int> pinched =
          topology::non_manifold_vertices(T, topology::edge_incidence(T, static_cast<Eigen::Index>(node_position.size())));
      if (pinched.empty()) break;
      std::vector<char> is_pinched(node_position.size(), 0);
      for (const int v : pinched) is_pinched[v] = 1;
      for (std::size_t i = 0; i < quad_of.size(); ++i)
        for (int k = 0; k < 4; ++k)
          if (is_pinched[quads[quad_of[i]][k]]) remove.push_back(quad_of[i]);
    }
    for (const int q : remove) {
      if (kept[q]) ++report.quads_non_manifold;
      kept[q] = 0;
    }
  }

  // Compact: only nodes that a kept quad uses, in order of first use.
  std::vector<int> new_index(node_position.size(), -1);
  Eigen::Index n_quads = std::count(kept.begin(), kept.end(), 1), n_nodes = 0;
  out.Q.resize(n_quads, 4);
  Eigen::Index row = 0;
  for (std::size_t q = 0; q < quads.size(); ++q) {
    if (!kept[q]) continue;
    for (int k = 0; k < 4; ++k) {
      int& v = new_index[quads[q][k]];
      if (v < 0) v = static_cast<int>(n_nodes++);
      out.Q(row, k) = v;
    }
    ++row;
  }
  out.V.resize(n_nodes, 3);
  out.node_uv.resize(n_nodes, 2);
  out.node_face.resize(n_nodes);
  for (std::size_t v = 0; v < node_position.size(); ++v) {
    const int w = new_index[v];
    if (w < 0) continue;
    out.V.row(w) = node_position[v];
    out.node_uv.row(w) << node_uv[v][0], report.mirrored ? -node_uv[v][1] : node_uv[v][1];
    out.node_face(w) = node_face[v];
  }
  if (n_quads > 0) {
    FaceMatrix T(2 * n_quads, 3);
    for (Eigen::Index q = 0; q < n_quads; ++q) {
      T.row(2 * q) << out.Q(q, 0), out.Q(q, 1), out.Q(q, 2);
      T.row(2 * q + 1) << out.Q(q, 0), out.Q(q, 2), out.Q(q, 3);
    }
    report.euler_output = topology::euler_characteristic(T, topology::edge_incidence(T, n_nodes));
  }
  progress.report(1.0, "extract quads");
  return out;
}

}  // namespace meshsmith::quadrangulation
