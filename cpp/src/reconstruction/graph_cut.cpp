// Graph-cut reconstruction from unoriented samples, and Boykov–Kolmogorov max-flow (graph_cut.h).
#include <meshsmith/reconstruction/graph_cut.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/points/kd_tree.h>
#include <meshsmith/reconstruction/marching_cubes.h>
#include <meshsmith/reconstruction/poisson.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

namespace meshsmith::reconstruction {

namespace {
using Int = std::int64_t;
constexpr Int kNone = -3, kOrphan = -2, kTerminal = -1;  // parent_ values that are not arcs
constexpr Int kFar = std::numeric_limits<Int>::max() / 4;

void check_capacity(double value, const char* what) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw InputError(std::string(what) + " capacity = " + std::to_string(value) + ": expected a finite number >= 0");
}
}  // namespace

MaxFlow::MaxFlow(Int nodes, Int edges_hint) {
  if (nodes < 0) throw InputError("MaxFlow: negative node count " + std::to_string(nodes));
  const auto n = static_cast<std::size_t>(nodes);
  first_.assign(n, -1), parent_.assign(n, kNone), next_active_.assign(n, 0), stamp_.assign(n, 0);
  distance_.assign(n, 0), tree_.assign(n, 0), terminal_.assign(n, 0.0);
  const auto arcs = static_cast<std::size_t>(std::max<Int>(0, 2 * edges_hint));
  head_.reserve(arcs), next_.reserve(arcs), residual_.reserve(arcs);
}

void MaxFlow::add_edge(Int u, Int v, double forward, double backward) {
  const Int n = node_count();
  if (u < 0 || u >= n || v < 0 || v >= n || u == v)
    throw InputError("edge (" + std::to_string(u) + ", " + std::to_string(v) + "): expected two different nodes in [0, " +
                     std::to_string(n) + ")");
  check_capacity(forward, "forward");
  check_capacity(backward, "backward");
  const Int a = static_cast<Int>(head_.size());
  head_.push_back(v), next_.push_back(first_[static_cast<std::size_t>(u)]), residual_.push_back(forward);
  head_.push_back(u), next_.push_back(first_[static_cast<std::size_t>(v)]), residual_.push_back(backward);
  first_[static_cast<std::size_t>(u)] = a, first_[static_cast<std::size_t>(v)] = a + 1;
  solved_ = false;
}

void MaxFlow::add_terminal(Int u, double source, double sink) {
  if (u < 0 || u >= node_count())
    throw InputError("terminal node " + std::to_string(u) + ": expected a node in [0, " + std::to_string(node_count()) + ")");
  check_capacity(source, "source");
  check_capacity(sink, "sink");
  // Only the difference matters: min(source, sink) flows straight through u.
  double& t = terminal_[static_cast<std::size_t>(u)];
  const double s = source + std::max(t, 0.0), k = sink + std::max(-t, 0.0);
  flow_ += std::min(s, k) - std::min(std::max(t, 0.0), std::max(-t, 0.0));
  t = s - k;
  solved_ = false;
}

bool MaxFlow::source_side(Int u) const {
  if (u < 0 || u >= node_count()) throw InputError("node " + std::to_string(u) + " out of range");
  return tree_[static_cast<std::size_t>(u)] == 1;
}

double MaxFlow::solve(const Progress& progress) {
  if (solved_) return flow_;
  const Int n = node_count();
  auto at = [](auto& vector, Int i) -> auto& { return vector[static_cast<std::size_t>(i)]; };
  std::deque<Int> active, orphans;
  std::vector<std::int8_t> queued(static_cast<std::size_t>(n), 0);
  auto activate = [&](Int u) {
    if (!at(queued, u)) at(queued, u) = 1, active.push_back(u);
  };
  for (Int u = 0; u < n; ++u) {
    const double t = at(terminal_, u);
    at(tree_, u) = t > 0.0 ? 1 : t < 0.0 ? 2 : 0;
    at(parent_, u) = t != 0.0 ? kTerminal : kNone;
    at(stamp_, u) = 0, at(distance_, u) = 1;
    if (t != 0.0) activate(u);
  }
  Int time = 0, augmentations = 0;
  auto make_orphan = [&](Int u) { at(parent_, u) = kOrphan, orphans.push_back(u); };
  // The residual capacity of the arc a in the direction a tree of kind `tree` grows along it.
  auto open = [&](Int a, std::int8_t tree) { return tree == 1 ? at(residual_, a) > 0.0 : at(residual_, a ^ 1) > 0.0; };

  while (true) {
    while (!active.empty() && at(tree_, active.front()) == 0) at(queued, active.front()) = 0, active.pop_front();
    if (active.empty()) break;
    const Int i = active.front();
    const std::int8_t tree = at(tree_, i);
    Int meeting = -1;  // an arc from a source-tree node to a sink-tree node
    for (Int a = at(first_, i); a != -1; a = at(next_, a)) {
      if (!open(a, tree)) continue;
      const Int j = at(head_, a);
      const std::int8_t other = at(tree_, j);
      if (other == 0) {
        at(tree_, j) = tree, at(parent_, j) = a ^ 1, at(stamp_, j) = at(stamp_, i);
        at(distance_, j) = at(distance_, i) + 1;
        activate(j);
      } else if (other != tree) {
        meeting = tree == 1 ? a : a ^ 1;
        break;
      } else if (at(stamp_, j) <= at(stamp_, i) && at(distance_, j) > at(distance_, i)) {
        at(parent_, j) = a ^ 1, at(stamp_, j) = at(stamp_, i), at(distance_, j) = at(distance_, i) + 1;
      }
    }
    ++time;
    if (meeting == -1) {
      at(queued, i) = 0, active.pop_front();
      continue;
    }
    // Augment along source → tail(meeting) → head(meeting) → sink.
    const Int tail = at(head_, meeting ^ 1), head = at(head_, meeting);
    double bottleneck = at(residual_, meeting);
    for (Int u = tail;;) {
      const Int pa = at(parent_, u);
      if (pa == kTerminal) { bottleneck = std::min(bottleneck, at(terminal_, u)); break; }
      bottleneck = std::min(bottleneck, at(residual_, pa ^ 1));
      u = at(head_, pa);
    }
    for (Int u = head;;) {
      const Int pa = at(parent_, u);
      if (pa == kTerminal) { bottleneck = std::min(bottleneck, -at(terminal_, u)); break; }
      bottleneck = std::min(bottleneck, at(residual_, pa));
      u = at(head_, pa);
    }
    at(residual_, meeting) -= bottleneck, at(residual_, meeting ^ 1) += bottleneck;
    for (Int u = tail;;) {
      const Int pa = at(parent_, u);
      if (pa == kTerminal) {
        if ((at(terminal_, u) -= bottleneck) <= 0.0) at(terminal_, u) = 0.0, make_orphan(u);
        break;
      }
      const Int up = at(head_, pa);
      at(residual_, pa) += bottleneck;
      if ((at(residual_, pa ^ 1) -= bottleneck) <= 0.0) at(residual_, pa ^ 1) = 0.0, make_orphan(u);
      u = up;
    }
    for (Int u = head;;) {
      const Int pa = at(parent_, u);
      if (pa == kTerminal) {
        if ((at(terminal_, u) += bottleneck) >= 0.0) at(terminal_, u) = 0.0, make_orphan(u);
        break;
      }
      const Int up = at(head_, pa);
      at(residual_, pa ^ 1) += bottleneck;
      if ((at(residual_, pa) -= bottleneck) <= 0.0) at(residual_, pa) = 0.0, make_orphan(u);
      u = up;
    }
    flow_ += bottleneck;
    // Adoption: each orphan looks for a parent in its tree with an open arc and a path to the terminal.
    ++time;
    while (!orphans.empty()) {
      const Int u = orphans.front();
      orphans.pop_front();
      const std::int8_t t = at(tree_, u);
      Int best = -1, best_distance = kFar;
      for (Int a = at(first_, u); a != -1; a = at(next_, a)) {
        if (!open(a ^ 1, t)) continue;  // the arc from the candidate parent towards u (source tree) or u → it (sink tree)
        const Int j = at(head_, a);
        if (at(tree_, j) != t || at(parent_, j) == kNone) continue;
        Int d = 0, k = j;
        while (true) {
          if (at(stamp_, k) == time) { d += at(distance_, k); break; }
          const Int pk = at(parent_, k);
          ++d;
          if (pk == kTerminal) { at(stamp_, k) = time, at(distance_, k) = 1; break; }
          if (pk == kOrphan) { d = kFar; break; }
          k = at(head_, pk);
        }
        if (d >= kFar) continue;
        if (d < best_distance) best = a, best_distance = d;
        for (k = j; at(stamp_, k) != time; k = at(head_, at(parent_, k))) at(stamp_, k) = time, at(distance_, k) = d--;
      }
      if (best != -1) {
        at(parent_, u) = best, at(stamp_, u) = time, at(distance_, u) = best_distance + 1;
        continue;
      }
      for (Int a = at(first_, u); a != -1; a = at(next_, a)) {
        const Int j = at(head_, a);
        if (at(tree_, j) != t) continue;
        const Int pj = at(parent_, j);
        if (pj == kNone) continue;
        if (open(a ^ 1, t)) activate(j);
        if (pj >= 0 && at(head_, pj) == u) make_orphan(j);
      }
      at(tree_, u) = 0, at(parent_, u) = kNone;
    }
    if (++augmentations % 4096 == 0) progress.report(0.5, "max-flow");
  }
  solved_ = true;
  return flow_;
}

namespace {

/// The checks of graph_cut's options. \throw InputError.
void validate_options(const GraphCutOptions& options) {
  if (options.resolution < 2 || options.resolution > 1024)
    throw InputError("resolution = " + std::to_string(options.resolution) + ": expected an integer in [2, 1024]");
  if (!(options.crust >= 0.5 && options.crust <= 16.0))
    throw InputError("crust = " + std::to_string(options.crust) + ": expected a number in [0.5, 16]");
  if (!(options.exponent >= 1.0 && options.exponent <= 16.0))
    throw InputError("exponent = " + std::to_string(options.exponent) + ": expected a number in [1, 16]");
  if (options.inside.rows() > 0) validate_vertices(options.inside, "inside");
}

}  // namespace

GraphCutResult graph_cut(const VertexRef& P, const GraphCutOptions& options, const Progress& progress) {
  validate_surface_samples(P);
  validate_options(options);
  const points::KdTree tree(P);
  // Sample spacing: the median distance to the nearest other sample.
  double spacing = 0.0;
  {
    const auto nearest = tree.query_self(1);
    std::vector<double> d(nearest.distances.data(), nearest.distances.data() + nearest.distances.size());
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    spacing = d[d.size() / 2];
  }
  const Eigen::RowVector3d lower = P.colwise().minCoeff(), upper = P.colwise().maxCoeff();
  const double h = (upper - lower).maxCoeff() / options.resolution;
  const double width = options.crust * std::max(h, spacing);
  if (!(h > 0.0) || !std::isfinite(h) || !std::isfinite(width) || !(width / h <= 1e6))
    throw InputError("graph_cut: the samples' extent or spacing is outside the double range (or the spacing is over "
                     "a million cells): rescale P");
  const double margin_cells = std::ceil(width / h) + 2.0;
  GraphCutResult result;
  result.voxel_size = h;
  double points_total = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double count = std::ceil((upper[a] - lower[a]) / h - 1e-9) + 1.0 + 2.0 * margin_cells;
    points_total *= count;
    result.shape[static_cast<std::size_t>(a)] = static_cast<Int>(std::min(count, 1e9));
    result.origin[static_cast<std::size_t>(a)] = lower[a] - margin_cells * h;
  }
  if (points_total > double(Int(1) << 26))
    throw InputError("graph_cut: the grid would have " + std::to_string(static_cast<long long>(points_total)) +
                     " points (more than 2^26): lower the resolution or the crust (the sample spacing " +
                     std::to_string(spacing) + " sets the crust's width when it exceeds the cell size)");
  const Int nx = result.shape[0], ny = result.shape[1], nz = result.shape[2], count = nx * ny * nz;
  auto index = [&](Int i, Int j, Int k) { return (i * ny + j) * nz + k; };
  auto position = [&](Int i, Int j, Int k, int axis) {
    const Int c[3] = {i, j, k};
    return result.origin[static_cast<std::size_t>(axis)] + static_cast<double>(c[axis]) * h;
  };

  // Unsigned distance at every grid point, one slab of constant i at a time.
  std::vector<double> field(static_cast<std::size_t>(count));
  {
    VertexMatrix Q(ny * nz, 3);
    for (Int i = 0; i < nx; ++i) {
      for (Int j = 0; j < ny; ++j)
        for (Int k = 0; k < nz; ++k) {
          const Int r = j * nz + k;
          Q(r, 0) = position(i, j, k, 0), Q(r, 1) = position(i, j, k, 1), Q(r, 2) = position(i, j, k, 2);
        }
      const auto nearest = tree.query(Q, 1);
      std::copy(nearest.distances.data(), nearest.distances.data() + ny * nz, field.begin() + index(i, 0, 0));
      progress.report(0.4 * static_cast<double>(i + 1) / static_cast<double>(nx), "unsigned distance");
    }
  }
  auto on_border = [&](Int i, Int j, Int k) {
    return i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
  };
  // Seeds: 1 outside (source), 2 inside (sink), 0 decided by the cut.
  std::vector<std::int8_t> label(static_cast<std::size_t>(count), 0);
  auto at = [](auto& vector, Int i) -> auto& { return vector[static_cast<std::size_t>(i)]; };
  const Int steps[3] = {ny * nz, nz, 1};
  double threshold = width;  // the crust: grid points with d < threshold
  if (options.inside.rows() == 0) {
    // The flood fill leaks into the inside through gaps between samples wider than the crust
    // (random samples have gaps several times their median spacing); a leak leaves only pockets
    // near the samples enclosed. Until the enclosed region holds a point twice as far from the
    // samples as the crust is wide, the crust widens by 1.5 and the fill is redone.
    double largest = 0.0;
    for (Int p = 0; p < count; ++p) largest = std::max(largest, at(field, p));
    std::vector<Int> stack;
    while (true) {
      std::fill(label.begin(), label.end(), std::int8_t(0));
      for (Int i = 0; i < nx; ++i)
        for (Int j = 0; j < ny; ++j)
          for (Int k = 0; k < nz; ++k)
            if (on_border(i, j, k)) at(label, index(i, j, k)) = 1, stack.push_back(index(i, j, k));
      while (!stack.empty()) {  // flood fill of the points outside the crust from the border
        const Int p = stack.back();
        stack.pop_back();
        const Int i = p / (ny * nz), j = (p / nz) % ny, k = p % nz;
        const Int c[3] = {i, j, k}, n[3] = {nx, ny, nz};
        for (int a = 0; a < 3; ++a) {
          if (c[a] > 0 && at(label, p - steps[a]) == 0 && at(field, p - steps[a]) >= threshold)
            at(label, p - steps[a]) = 1, stack.push_back(p - steps[a]);
          if (c[a] < n[a] - 1 && at(label, p + steps[a]) == 0 && at(field, p + steps[a]) >= threshold)
            at(label, p + steps[a]) = 1, stack.push_back(p + steps[a]);
        }
      }
      double deepest = 0.0;
      for (Int p = 0; p < count; ++p)
        if (at(label, p) == 0 && at(field, p) >= threshold) deepest = std::max(deepest, at(field, p));
      if (deepest >= 2.0 * threshold) break;
      if (2.0 * threshold * 1.5 > largest)
        throw InputError("graph_cut: no grid point outside the crust is enclosed by it (the samples leave a gap "
                         "wider than the crust, or the shape is thinner than a cell): raise crust or resolution, "
                         "or give inside seeds");
      threshold *= 1.5;
      progress.report(0.42, "seeds");
    }
    for (Int p = 0; p < count; ++p)
      if (at(label, p) == 0 && at(field, p) >= threshold) at(label, p) = 2;
  } else {
    for (Int i = 0; i < nx; ++i)
      for (Int j = 0; j < ny; ++j)
        for (Int k = 0; k < nz; ++k)
          if (on_border(i, j, k)) at(label, index(i, j, k)) = 1;
    for (Int s = 0; s < options.inside.rows(); ++s) {
      Int c[3];
      for (int a = 0; a < 3; ++a) {
        const double g = std::round((options.inside(s, a) - result.origin[static_cast<std::size_t>(a)]) / h);
        const Int n = result.shape[static_cast<std::size_t>(a)];
        if (!(g >= 1.0 && g <= static_cast<double>(n - 2)))
          throw InputError("inside[" + std::to_string(s) + "] lies outside the grid's interior: expected a point "
                           "inside the samples' bounding box");
        c[a] = static_cast<Int>(g);
      }
      at(label, index(c[0], c[1], c[2])) = 2;
    }
  }
  progress.report(0.45, "seeds");

  // The graph on the undecided grid points.
  std::vector<std::int32_t> node(static_cast<std::size_t>(count), -1);
  Int nodes = 0;
  for (Int p = 0; p < count; ++p)
    if (at(label, p) == 0) {
      if (nodes >= std::numeric_limits<std::int32_t>::max()) throw InputError("graph_cut: too many graph nodes");
      at(node, p) = static_cast<std::int32_t>(nodes++);
    }
  MaxFlow graph(nodes, 3 * nodes);
  double constant = 0.0;
  const double scale = 1.0 / (2.0 * threshold);
  for (Int i = 0; i < nx; ++i) {
    for (Int j = 0; j < ny; ++j)
      for (Int k = 0; k < nz; ++k) {
        const Int p = index(i, j, k), c[3] = {i, j, k}, n[3] = {nx, ny, nz};
        for (int a = 0; a < 3; ++a) {
          if (c[a] + 1 >= n[a]) continue;
          const Int q = p + steps[a];
          const std::int8_t lp = at(label, p), lq = at(label, q);
          if (lp != 0 && lq != 0) {
            if (lp != lq) constant += std::pow((at(field, p) + at(field, q)) * scale, options.exponent) + 1e-4;
            continue;
          }
          const double weight = std::pow((at(field, p) + at(field, q)) * scale, options.exponent) + 1e-4;
          if (lp == 0 && lq == 0) graph.add_edge(at(node, p), at(node, q), weight, weight);
          else if (lp == 0) graph.add_terminal(at(node, p), lq == 1 ? weight : 0.0, lq == 2 ? weight : 0.0);
          else graph.add_terminal(at(node, q), lp == 1 ? weight : 0.0, lp == 2 ? weight : 0.0);
        }
      }
    progress.report(0.45 + 0.1 * static_cast<double>(i + 1) / static_cast<double>(nx), "graph");
  }
  result.free_voxels = nodes;
  result.cut = graph.solve(progress.subrange(0.55, 0.9)) + constant;

  // The unsigned distance signed by the cut (negative inside), contoured at 0.
  const double tiny = 1e-9 * h;
  for (Int p = 0; p < count; ++p) {
    const std::int8_t l = at(label, p);
    const bool inside = l == 2 || (l == 0 && !graph.source_side(at(node, p)));
    if (inside) at(field, p) = -std::max(at(field, p), tiny), ++result.inside_voxels;
  }
  std::vector<std::int8_t>().swap(label);
  std::vector<std::int32_t>().swap(node);
  Grid grid;
  grid.shape = result.shape;
  grid.origin = result.origin;
  grid.spacing = {h, h, h};
  ContourMesh mesh = marching_cubes(field.data(), grid, 0.0, progress.subrange(0.9, 1.0));
  result.V = std::move(mesh.V);
  result.F = std::move(mesh.F);
  progress.report(1.0, "graph cut");
  return result;
}

}  // namespace meshsmith::reconstruction
