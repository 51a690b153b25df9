// Graph-cut reconstruction from unoriented samples, and Boykov–Kolmogorov max-flow (graph_cut.h).
#include <meshsmith/reconstruction/graph_cut.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/points/kd_tree.h>
#include <meshsmith/reconstruction/marching_cubes.h>
#include <meshsmith/reconstruction/poisson.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::reconstruction {

// Max-flow: Boykov & Kolmogorov, "An experimental comparison of min-cut/max-flow algorithms for
// energy minimization in vision", PAMI 2004. The layout follows what made Kolmogorov's own code
// fast: one 32-byte record per node (all it needs in the inner loops in one cache line), the arcs
// of a node contiguous (compressed rows, built once at solve(); each arc knows its sister and
// keeps a copy of the sister's residual, so the sink tree's growth and the source tree's
// adoption, which test the reverse direction, read the node's own row and not the neighbours'), the
// active nodes in an intrusive FIFO through the node records, the orphans in a FIFO, and the
// "timestamp / distance" heuristic: a node's distance to its terminal is trusted when its stamp
// equals the current time, so the adoption's walk towards the root stops at the first node
// already checked in this round, and the growth re-parents a node onto a path that is known to
// be shorter (stamp no newer, distance smaller).

namespace {
using Int = std::int64_t;
constexpr std::int32_t kNone = -3, kOrphan = -2, kTerminal = -1;  // parent values that are not arcs
constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
constexpr Int kMaxNodes = (Int(1) << 31) - 2, kMaxEdges = (Int(1) << 30) - 1;

void check_capacity(double value, const char* what) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw InputError(std::string(what) + " capacity = " + std::to_string(value) + ": expected a finite number >= 0");
}
}  // namespace

MaxFlow::MaxFlow(Int nodes, Int edges_hint) {
  if (nodes < 0 || nodes > kMaxNodes)
    throw InputError("MaxFlow: node count " + std::to_string(nodes) + ": expected 0 to 2^31 - 2");
  nodes_.resize(static_cast<std::size_t>(nodes) + 1);
  const auto edges = static_cast<std::size_t>(std::clamp<Int>(edges_hint, 0, kMaxEdges));
  edge_tail_.reserve(edges), edge_head_.reserve(edges), edge_forward_.reserve(edges), edge_backward_.reserve(edges);
}

void MaxFlow::add_edge(Int u, Int v, double forward, double backward) {
  const Int n = node_count();
  if (u < 0 || u >= n || v < 0 || v >= n || u == v)
    throw InputError("edge (" + std::to_string(u) + ", " + std::to_string(v) + "): expected two different nodes in [0, " +
                     std::to_string(n) + ")");
  check_capacity(forward, "forward");
  check_capacity(backward, "backward");
  if (!arcs_.empty()) to_edges();
  if (static_cast<Int>(edge_tail_.size()) >= kMaxEdges)
    throw InputError("MaxFlow: more than 2^30 - 1 edges");
  edge_tail_.push_back(static_cast<std::int32_t>(u)), edge_head_.push_back(static_cast<std::int32_t>(v));
  edge_forward_.push_back(forward), edge_backward_.push_back(backward);
  solved_ = false;
}

void MaxFlow::add_terminal(Int u, double source, double sink) {
  if (u < 0 || u >= node_count())
    throw InputError("terminal node " + std::to_string(u) + ": expected a node in [0, " + std::to_string(node_count()) + ")");
  check_capacity(source, "source");
  check_capacity(sink, "sink");
  // Only the difference matters: min(source, sink) flows straight through u.
  double& t = nodes_[static_cast<std::size_t>(u)].terminal;
  const double s = source + std::max(t, 0.0), k = sink + std::max(-t, 0.0);
  flow_ += std::min(s, k) - std::min(std::max(t, 0.0), std::max(-t, 0.0));
  t = s - k;
  solved_ = false;
}

bool MaxFlow::source_side(Int u) const {
  if (u < 0 || u >= node_count()) throw InputError("node " + std::to_string(u) + " out of range");
  return nodes_[static_cast<std::size_t>(u)].tree == 1;
}

void MaxFlow::to_rows() {
  const std::size_t n = static_cast<std::size_t>(node_count()), m = edge_tail_.size();
  for (Node& node : nodes_) node.first = 0;
  for (std::size_t e = 0; e < m; ++e) ++nodes_[std::size_t(edge_tail_[e]) + 1].first, ++nodes_[std::size_t(edge_head_[e]) + 1].first;
  for (std::size_t u = 0; u < n; ++u) nodes_[u + 1].first += nodes_[u].first;
  arcs_.resize(2 * m);
  // Each row in reverse order of addition (the order Kolmogorov's linked lists scan arcs in:
  // on grid graphs it finds shorter augmenting paths than the order of addition, measured).
  std::vector<std::int32_t> fill(n);
  for (std::size_t u = 0; u < n; ++u) fill[u] = nodes_[u + 1].first;
  for (std::size_t e = 0; e < m; ++e) {
    const std::int32_t u = edge_tail_[e], v = edge_head_[e];
    const std::int32_t a = --fill[std::size_t(u)], b = --fill[std::size_t(v)];
    arcs_[std::size_t(a)] = {v, b, edge_forward_[e], edge_backward_[e]};
    arcs_[std::size_t(b)] = {u, a, edge_backward_[e], edge_forward_[e]};
  }
  std::vector<std::int32_t>().swap(edge_tail_), std::vector<std::int32_t>().swap(edge_head_);
  std::vector<double>().swap(edge_forward_), std::vector<double>().swap(edge_backward_);
}

void MaxFlow::to_edges() {
  const std::size_t n = static_cast<std::size_t>(node_count());
  for (std::size_t u = 0; u < n; ++u)
    for (std::int32_t a = nodes_[u].first; a < nodes_[u + 1].first; ++a) {
      const Arc& arc = arcs_[std::size_t(a)];
      if (a > arc.sister) continue;  // each pair once, from the arc stored first
      edge_tail_.push_back(static_cast<std::int32_t>(u)), edge_head_.push_back(arc.head);
      edge_forward_.push_back(arc.residual), edge_backward_.push_back(arc.reverse);
    }
  std::vector<Arc>().swap(arcs_);
}

double MaxFlow::solve(const Progress& progress) {
  if (solved_) return flow_;
  if (arcs_.empty()) to_rows();
  const std::int32_t n = static_cast<std::int32_t>(node_count());
  Node* const node = nodes_.data();
  Arc* const arc = arcs_.data();
  // The FIFO of active nodes, linked through Node::next_active.
  std::int32_t active_first = -1, active_last = -1;
  auto activate = [&](std::int32_t u) {
    if (node[u].next_active != -1) return;
    node[u].next_active = u;
    if (active_last >= 0) node[active_last].next_active = u;
    else active_first = u;
    active_last = u;
  };
  auto next_active = [&]() -> std::int32_t {  // the first queued node still in a tree, dequeued
    while (active_first >= 0) {
      const std::int32_t u = active_first, after = node[u].next_active;
      active_first = after == u ? -1 : after;
      if (active_first < 0) active_last = -1;
      node[u].next_active = -1;
      if (node[u].tree != 0) return u;
    }
    return -1;
  };
  for (std::int32_t u = 0; u < n; ++u) {
    Node& x = node[u];
    x.tree = x.terminal > 0.0 ? 1 : x.terminal < 0.0 ? 2 : 0;
    x.parent = x.tree != 0 ? kTerminal : kNone;
    x.stamp = 0, x.distance = 1, x.next_active = -1;
  }
  for (std::int32_t u = 0; u < n; ++u)
    if (node[u].tree != 0) activate(u);
  // Orphans: those of an augmenting path are adopted in reverse order of their discovery (the
  // ones nearest their terminal first: their subtrees hold the others), each together with the
  // orphans its adoption makes (its freed children, FIFO) before the next, as Kolmogorov's code.
  std::vector<std::int32_t> path_orphans, orphans;
  std::size_t orphan_next = 0;
  auto make_orphan = [&](std::int32_t u) { node[u].parent = kOrphan, orphans.push_back(u); };
  auto path_orphan = [&](std::int32_t u) { node[u].parent = kOrphan, path_orphans.push_back(u); };
  std::int32_t time = 0;
  Int augmentations = 0;
  // Open towards the tree's growth: source tree along a (a's residual), sink tree against it.
  auto open = [&](std::int32_t a, std::int8_t tree) {
    return (tree == 1 ? arc[a].residual : arc[a].reverse) > 0.0;
  };
  // Sends `amount` along arc a (its sister gains it); true if a is then saturated.
  auto send = [&](std::int32_t a, double amount) {
    Arc& x = arc[a];
    Arc& y = arc[x.sister];
    double left = x.residual - amount;
    const bool saturated = left <= 0.0;
    if (saturated) left = 0.0;
    x.residual = y.reverse = left;
    y.residual += amount, x.reverse = y.residual;
    return saturated;
  };
  std::int32_t current = -1;  // a node whose growth met the other tree: it is scanned again
  while (true) {
    const std::int32_t i = current >= 0 && node[current].tree != 0 ? current : next_active();
    current = -1;
    if (i < 0) break;
    const std::int8_t tree = node[i].tree;
    std::int32_t meeting = -1;  // an arc from a source-tree node to a sink-tree node
    for (std::int32_t a = node[i].first, end = node[i + 1].first; a < end; ++a) {
      if (!open(a, tree)) continue;
      const std::int32_t j = arc[a].head;
      Node& y = node[j];
      if (y.tree == 0) {
        y.tree = tree, y.parent = arc[a].sister, y.stamp = node[i].stamp, y.distance = node[i].distance + 1;
        activate(j);
      } else if (y.tree != tree) {
        meeting = tree == 1 ? a : arc[a].sister;
        break;
      } else if (y.stamp <= node[i].stamp && y.distance > node[i].distance) {
        y.parent = arc[a].sister, y.stamp = node[i].stamp, y.distance = node[i].distance + 1;
      }
    }
    if (++time == kFar) {  // the stamps would overflow: restart them (the heuristic only)
      for (std::int32_t u = 0; u < n; ++u) node[u].stamp = 0;
      time = 1;
    }
    if (meeting == -1) continue;
    current = i;
    // Augment along source → tail(meeting) → head(meeting) → sink.
    const std::int32_t tail = arc[arc[meeting].sister].head, head = arc[meeting].head;
    double bottleneck = arc[meeting].residual;
    for (std::int32_t u = tail;;) {
      const std::int32_t pa = node[u].parent;
      if (pa == kTerminal) { bottleneck = std::min(bottleneck, node[u].terminal); break; }
      bottleneck = std::min(bottleneck, arc[pa].reverse);
      u = arc[pa].head;
    }
    for (std::int32_t u = head;;) {
      const std::int32_t pa = node[u].parent;
      if (pa == kTerminal) { bottleneck = std::min(bottleneck, -node[u].terminal); break; }
      bottleneck = std::min(bottleneck, arc[pa].residual);
      u = arc[pa].head;
    }
    send(meeting, bottleneck);
    for (std::int32_t u = tail;;) {
      const std::int32_t pa = node[u].parent;
      if (pa == kTerminal) {
        if ((node[u].terminal -= bottleneck) <= 0.0) node[u].terminal = 0.0, path_orphan(u);
        break;
      }
      const std::int32_t up = arc[pa].head;
      if (send(arc[pa].sister, bottleneck)) path_orphan(u);  // along parent → u
      u = up;
    }
    for (std::int32_t u = head;;) {
      const std::int32_t pa = node[u].parent;
      if (pa == kTerminal) {
        if ((node[u].terminal += bottleneck) >= 0.0) node[u].terminal = 0.0, path_orphan(u);
        break;
      }
      const std::int32_t up = arc[pa].head;
      if (send(pa, bottleneck)) path_orphan(u);  // along u → parent
      u = up;
    }
    flow_ += bottleneck;
    // Adoption: each orphan looks for a parent in its tree with an open arc to it
    // and a path to the terminal (the shortest by the stamped distances); failing that it is
    // freed, its children become orphans and its tree neighbours that could reach it active.
    while (!path_orphans.empty()) {
      orphans.assign(1, path_orphans.back());
      path_orphans.pop_back();
      for (orphan_next = 0; orphan_next < orphans.size(); ++orphan_next) {
        const std::int32_t u = orphans[orphan_next];
        const std::int8_t t = node[u].tree;
        std::int32_t best = -1, best_distance = kFar;
        for (std::int32_t a = node[u].first, end = node[u + 1].first; a < end; ++a) {
          // The arc from the candidate parent towards u (source tree) or from u to it (sink tree).
          if ((t == 1 ? arc[a].reverse : arc[a].residual) <= 0.0) continue;
          const std::int32_t j = arc[a].head;
          if (node[j].tree != t || node[j].parent == kNone) continue;
          std::int32_t d = 0, k = j;
          while (true) {
            Node& z = node[k];
            if (z.stamp == time) { d += z.distance; break; }
            ++d;
            if (z.parent == kTerminal) { z.stamp = time, z.distance = 1; break; }
            if (z.parent == kOrphan) { d = kFar; break; }
            k = arc[z.parent].head;
          }
          if (d == kFar) continue;
          if (d < best_distance) best = a, best_distance = d;
          for (k = j; node[k].stamp != time; k = arc[node[k].parent].head) node[k].stamp = time, node[k].distance = d--;
        }
        if (best != -1) {
          node[u].parent = best, node[u].stamp = time, node[u].distance = best_distance + 1;
          continue;
        }
        for (std::int32_t a = node[u].first, end = node[u + 1].first; a < end; ++a) {
          const std::int32_t j = arc[a].head;
          const Node& y = node[j];
          if (y.tree != t || y.parent == kNone) continue;
          if ((t == 1 ? arc[a].reverse : arc[a].residual) > 0.0) activate(j);
          if (y.parent >= 0 && arc[y.parent].head == u) make_orphan(j);
        }
        node[u].tree = 0, node[u].parent = kNone;
      }
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
