// Vertex clustering on a uniform grid (§4.1).
#include <meshsmith/decimation/clustering.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/decimation/quadric.h>
#include <meshsmith/topology/manifold.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

namespace meshsmith::decimation {
namespace {

using Cell = std::array<std::int64_t, 3>;

/// The cells of the referenced vertices: cluster id per vertex (−1 if unreferenced), ids
/// numbered in lexicographic cell order, and the cell of each cluster.
struct Grid {
  Eigen::Vector3d origin;
  double cell_size = 0.0;
  std::vector<int> vertex_cluster;
  std::vector<Cell> cluster_cell;
};

std::vector<char> referenced_vertices(Eigen::Index n_vertices, const FaceRef& F) {
  std::vector<char> referenced(n_vertices, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) referenced[F(f, k)] = 1;
  return referenced;
}

/// Bits per axis of a packed cell key: cells per axis must stay below 2^21.
constexpr int kAxisBits = 21;

/// Origin of the grid (minimum corner of the referenced vertices) and the referenced vertices.
/// V and cell_size are in normalized coordinates (core/normalization.h), `exponent` the frame's
/// (for the message, in input units).
/// \throw InputError for a cell size that needs 2^21 or more cells along an axis.
std::vector<int> grid_vertices(const VertexRef& V, const std::vector<char>& referenced, double cell_size,
                               Eigen::Vector3d& origin, int exponent) {
  origin = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = -origin;
  std::vector<int> vertices;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (referenced[v]) {
      vertices.push_back(static_cast<int>(v));
      origin = origin.cwiseMin(V.row(v).transpose());
      upper = upper.cwiseMax(V.row(v).transpose());
    }
  const double extent = (upper - origin).maxCoeff();
  if (!(extent / cell_size < static_cast<double>((1 << kAxisBits) - 1)))
    throw InputError("cluster: cell_size " + number_text(std::ldexp(cell_size, exponent)) +
                     " is too small for the mesh extent (" + number_text(std::ldexp(extent, exponent)) +
                     "): 2^21 or more cells per axis");
  return vertices;
}

/// The packed cell (ix, iy, iz) of vertex v: ix in the high bits, so keys sort lexicographically.
std::uint64_t cell_key(const VertexRef& V, Eigen::Index v, const Eigen::Vector3d& origin, double cell_size) {
  std::uint64_t key = 0;
  for (int k = 0; k < 3; ++k)
    key = (key << kAxisBits) | static_cast<std::uint64_t>(std::floor((V(v, k) - origin(k)) / cell_size));
  return key;
}

Grid assign_cells(const VertexRef& V, const std::vector<char>& referenced, double cell_size, int exponent) {
  Grid grid;
  grid.cell_size = cell_size;
  const std::vector<int> vertices = grid_vertices(V, referenced, cell_size, grid.origin, exponent);
  std::vector<std::pair<std::uint64_t, int>> keyed(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i)
    keyed[i] = {cell_key(V, vertices[i], grid.origin, cell_size), vertices[i]};
  std::sort(keyed.begin(), keyed.end());
  grid.vertex_cluster.assign(V.rows(), -1);
  constexpr std::uint64_t mask = (std::uint64_t{1} << kAxisBits) - 1;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    const std::uint64_t key = keyed[i].first;
    if (i == 0 || key != keyed[i - 1].first)
      grid.cluster_cell.push_back({static_cast<std::int64_t>(key >> (2 * kAxisBits)),
                                   static_cast<std::int64_t>((key >> kAxisBits) & mask),
                                   static_cast<std::int64_t>(key & mask)});
    grid.vertex_cluster[keyed[i].second] = static_cast<int>(grid.cluster_cell.size()) - 1;
  }
  return grid;
}

/// Number of distinct cells of the referenced vertices (what assign_cells would number).
Eigen::Index count_cells(const VertexRef& V, const std::vector<char>& referenced, double cell_size, int exponent) {
  Eigen::Vector3d origin;
  const std::vector<int> vertices = grid_vertices(V, referenced, cell_size, origin, exponent);
  std::vector<std::uint64_t> keys(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) keys[i] = cell_key(V, vertices[i], origin, cell_size);
  std::sort(keys.begin(), keys.end());
  return static_cast<Eigen::Index>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

double median_of(std::vector<double>& values) {
  const std::size_t n = values.size(), middle = n / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  const double upper = values[middle];
  if (n % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + middle);
  return (lower + upper) / 2.0;
}

/// One representative position per cluster.
VertexMatrix representatives(const VertexRef& V, const FaceRef& F, const Grid& grid,
                             ClusterRepresentative representative) {
  const Eigen::Index n_clusters = static_cast<Eigen::Index>(grid.cluster_cell.size());
  VertexMatrix out(n_clusters, 3);
  if (representative == ClusterRepresentative::cell_center) {
    for (Eigen::Index c = 0; c < n_clusters; ++c)
      for (int k = 0; k < 3; ++k)
        out(c, k) = grid.origin(k) + (static_cast<double>(grid.cluster_cell[c][k]) + 0.5) * grid.cell_size;
    return out;
  }
  // Members of each cluster, contiguous (counting sort by cluster id).
  std::vector<int> offsets(n_clusters + 1, 0), members;
  for (int c : grid.vertex_cluster)
    if (c >= 0) ++offsets[c + 1];
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  members.resize(offsets.back());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (grid.vertex_cluster[v] >= 0) members[fill[grid.vertex_cluster[v]]++] = static_cast<int>(v);

  for (Eigen::Index c = 0; c < n_clusters; ++c) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = offsets[c]; i < offsets[c + 1]; ++i) sum += V.row(members[i]).transpose();
    out.row(c) = sum.transpose() / static_cast<double>(offsets[c + 1] - offsets[c]);
  }
  if (representative == ClusterRepresentative::median) {
    std::vector<double> values;
    for (Eigen::Index c = 0; c < n_clusters; ++c)
      for (int k = 0; k < 3; ++k) {
        values.clear();
        for (int i = offsets[c]; i < offsets[c + 1]; ++i) values.push_back(V(members[i], k));
        out(c, k) = median_of(values);
      }
  } else if (representative == ClusterRepresentative::quadric) {
    std::vector<Quadric> quadrics(n_clusters);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::Vector3d cross = (b - a).cross(c - a);
      const double norm = cross.norm();
      if (!(norm > 0.0)) continue;  // a zero-area face spans no plane
      const Quadric plane = Quadric::from_plane(cross / norm, a, 0.5 * norm);
      for (int k = 0; k < 3; ++k) quadrics[grid.vertex_cluster[F(f, k)]] += plane;
    }
    const double slack = 1e-6 * grid.cell_size;
    for (Eigen::Index c = 0; c < n_clusters; ++c) {
      const Eigen::Vector3d centroid = out.row(c).transpose();
      const Eigen::Vector3d x = quadrics[c].minimizer(centroid);
      bool inside = x.allFinite();
      for (int k = 0; k < 3 && inside; ++k) {
        const double low = grid.origin(k) + static_cast<double>(grid.cluster_cell[c][k]) * grid.cell_size;
        inside = x(k) >= low - slack && x(k) <= low + grid.cell_size + slack;
      }
      if (inside) out.row(c) = x.transpose();
    }
  }
  return out;
}


/// The cell size in normalized units. \throw InputError unless it is positive and finite.
double normalized_cell_size(double cell_size, const CoordinateFrame& frame) {
  if (!(cell_size > 0.0) || !std::isfinite(cell_size))
    throw InputError("cluster: cell_size must be a positive finite number, got " + number_text(cell_size));
  return std::max(frame.to_normalized(cell_size, 1), std::numeric_limits<double>::denorm_min());
}

}  // namespace

// Clustering runs on normalized coordinates (core/normalization.h): the quadric representative
// is of degree 4 in the coordinates and the grid extent a difference of two of them, which
// overflow near 1e77 and 1e308; the exact power-of-two scaling keeps the cells bit-identical.
ClusteringResult cluster_vertices(const VertexRef& input_V, const FaceRef& F, const ClusteringOptions& options,
                                  const Progress& progress) {
  validate_mesh(input_V, F);
  const CoordinateFrame frame = normalizing_frame(input_V);
  const double cell_size = normalized_cell_size(options.cell_size, frame);
  const VertexMatrix V = frame.normalize_vertices(input_V);
  progress.report(0.0, "cluster: grid");
  const Grid grid = assign_cells(V, referenced_vertices(V.rows(), F), cell_size, frame.exponent);
  progress.report(0.3, "cluster: representatives");
  const VertexMatrix cluster_position = representatives(V, F, grid, options.representative);
  progress.report(0.6, "cluster: triangles");

  // Triangles on three distinct clusters; of those on the same cluster triple, the first.
  std::vector<std::array<int, 3>> corners;
  std::vector<int> candidates;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const std::array<int, 3> c{grid.vertex_cluster[F(f, 0)], grid.vertex_cluster[F(f, 1)],
                               grid.vertex_cluster[F(f, 2)]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    candidates.push_back(static_cast<int>(corners.size()));
    corners.push_back(c);
  }
  std::vector<std::array<int, 3>> sorted_corners(corners);
  for (auto& c : sorted_corners) std::sort(c.begin(), c.end());
  std::sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return sorted_corners[a] != sorted_corners[b] ? sorted_corners[a] < sorted_corners[b] : a < b;
  });
  std::vector<char> keep(corners.size(), 0);
  for (std::size_t i = 0; i < candidates.size(); ++i)
    keep[candidates[i]] = i == 0 || sorted_corners[candidates[i]] != sorted_corners[candidates[i - 1]];

  // Output vertices: the clusters used by surviving triangles, in cell order.
  std::vector<int> cluster_output(cluster_position.rows(), -1);
  for (std::size_t t = 0; t < corners.size(); ++t)
    if (keep[t])
      for (int c : corners[t]) cluster_output[c] = 0;
  ClusteringResult result;
  int n_out = 0;
  for (int& index : cluster_output)
    if (index == 0) index = n_out++;
  result.V.resize(n_out, 3);
  for (Eigen::Index c = 0; c < cluster_position.rows(); ++c)
    if (cluster_output[c] >= 0) result.V.row(cluster_output[c]) = cluster_position.row(c);
  result.F.resize(std::count(keep.begin(), keep.end(), 1), 3);
  Eigen::Index row = 0;
  for (std::size_t t = 0; t < corners.size(); ++t)
    if (keep[t]) {
      for (int k = 0; k < 3; ++k) result.F(row, k) = cluster_output[corners[t][k]];
      ++row;
    }
  result.vertex_cluster.resize(V.rows());
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    result.vertex_cluster(v) = grid.vertex_cluster[v] >= 0 ? cluster_output[grid.vertex_cluster[v]] : -1;
  result.V = frame.vertices_to_input(result.V, "cluster: output vertex");
  result.is_manifold = result.F.rows() == 0 || topology::is_manifold(result.F);
  result.cell_size = options.cell_size;
  progress.report(1.0, "cluster: triangles");
  return result;
}

Eigen::Index occupied_cell_count(const VertexRef& V, const FaceRef& F, double cell_size) {
  validate_mesh(V, F);
  const CoordinateFrame frame = normalizing_frame(V);
  return count_cells(frame.normalize_vertices(V), referenced_vertices(V.rows(), F),
                     normalized_cell_size(cell_size, frame), frame.exponent);
}

double cell_size_for_vertex_count(const VertexRef& input_V, const FaceRef& F, Eigen::Index target_vertices) {
  validate_mesh(input_V, F);
  const CoordinateFrame frame = normalizing_frame(input_V);
  const VertexMatrix V = frame.normalize_vertices(input_V);
  if (target_vertices < 1)
    throw InputError("cluster: target_vertices must be at least 1, got " + std::to_string(target_vertices));
  const std::vector<char> referenced = referenced_vertices(V.rows(), F);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (referenced[v]) {
      low = low.cwiseMin(V.row(v).transpose());
      high = high.cwiseMax(V.row(v).transpose());
    }
  const double extent = (high - low).maxCoeff();
  // Every referenced vertex at one point: one cell whatever the size.
  if (!(extent > 0.0)) return frame.exponent == 0 ? 1.0 : std::ldexp(1.0, frame.exponent);
  // count(size) falls (in tendency) as size grows; at extent·(1 + ε) it is 1.
  double small = extent * 1e-6, large = extent * 1.000001;
  double best = large;
  Eigen::Index best_count = 1;
  // Close enough: within 0.5% below the target (the count moves in steps anyway).
  const Eigen::Index good_enough = target_vertices - target_vertices / 200;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double size = std::sqrt(small * large);
    const Eigen::Index count = count_cells(V, referenced, size, frame.exponent);
    if (count <= target_vertices && (best_count > target_vertices || count > best_count ||
                                     (count == best_count && size < best))) {
      best = size;
      best_count = count;
    }
    if (count <= target_vertices && count >= good_enough) break;
    (count > target_vertices ? small : large) = size;
    if (large / small < 1.0 + 1e-9) break;
  }
  return frame.to_input(best, 1, "cluster: the cell size");
}

}  // namespace meshsmith::decimation
