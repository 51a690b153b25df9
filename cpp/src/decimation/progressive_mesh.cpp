// Progressive meshes (§4.3): vertex splits, levels of detail, selective refinement, file format.
#include <meshsmith/decimation/progressive_mesh.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numeric>
#include <string>

namespace meshsmith::decimation {
namespace {

std::string split_name(Eigen::Index k) { return "vertex split " + std::to_string(k); }

/// Vertex → incident faces, kept while a mesh is edited by collapses or splits.
using Incidence = std::vector<std::vector<int>>;

void erase_face(std::vector<int>& faces, int f) {
  faces.erase(std::remove(faces.begin(), faces.end(), f), faces.end());
}

int corner_of(const FaceMatrix& faces, int f, int v) {
  for (int c = 0; c < 3; ++c)
    if (faces(f, c) == v) return c;
  return -1;
}

/// The faces around v as (next, prev) pairs: the face (v, next, prev) counter-clockwise.
/// Returns the face f in `around` with faces(f) = (v, next, ·) (want_next) or (v, ·, prev), or −1.
int find_face(const FaceMatrix& faces, const std::vector<int>& around, int v, int neighbour, bool want_next) {
  for (int f : around) {
    const int c = corner_of(faces, f, v);
    if (faces(f, want_next ? (c + 1) % 3 : (c + 2) % 3) == neighbour) return f;
  }
  return -1;
}

/// True when the faces around v form one fan: a single path or cycle of faces joined through
/// their edges at v, no directed edge from v used twice (edge-manifold and oriented at v).
bool is_single_fan(const FaceMatrix& faces, const std::vector<int>& around, int v) {
  const std::size_t n = around.size();
  if (n == 0) return true;
  std::vector<std::pair<int, int>> edges(n);  // (next, prev)
  for (std::size_t i = 0; i < n; ++i) {
    const int f = around[i], c = corner_of(faces, f, v);
    edges[i] = {faces(f, (c + 1) % 3), faces(f, (c + 2) % 3)};
  }
  std::vector<int> nexts(n), prevs(n);
  for (std::size_t i = 0; i < n; ++i) nexts[i] = edges[i].first, prevs[i] = edges[i].second;
  std::sort(nexts.begin(), nexts.end());
  std::sort(prevs.begin(), prevs.end());
  if (std::adjacent_find(nexts.begin(), nexts.end()) != nexts.end() ||
      std::adjacent_find(prevs.begin(), prevs.end()) != prevs.end())
    return false;
  // A face whose `next` is no other face's `prev` starts the path; at most one may.
  std::size_t start = 0, starts = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!std::binary_search(prevs.begin(), prevs.end(), edges[i].first)) start = i, ++starts;
  if (starts > 1) return false;
  // Walk counter-clockwise from the start (to the face whose next is our prev), counting faces.
  std::size_t seen = 1, current = start;
  for (; seen < n; ++seen) {
    std::size_t following = n;
    for (std::size_t j = 0; j < n; ++j)
      if (edges[j].first == edges[current].second) following = j;
    if (following == n || following == start) break;
    current = following;
  }
  return seen == n;
}

/// The wedge of faces around `kept` from face `first` counter-clockwise to face `last`, completed
/// from the start of the fan when the walk from `first` reaches the boundary first; an absent end
/// is −1 (the wedge then runs to the boundary). These are the faces a vertex split hands to the
/// new vertex (§4.3 and the CollapseRecord convention). False if they do not form such a wedge.
bool walk_wedge(const FaceMatrix& faces, const std::vector<int>& around, int kept, int first, int last,
                std::vector<int>& fan) {
  fan.clear();
  const std::size_t limit = around.size();
  bool reached_last = false;
  for (int f = first; f >= 0 && !reached_last;) {
    if (fan.size() >= limit) return false;
    fan.push_back(f);
    reached_last = f == last;
    if (!reached_last) f = find_face(faces, around, kept, faces(f, (corner_of(faces, f, kept) + 2) % 3), true);
  }
  if (last >= 0 && !reached_last)
    for (int f = last; f >= 0;) {
      if (fan.size() >= limit || std::find(fan.begin(), fan.end(), f) != fan.end()) return false;
      fan.push_back(f);
      f = find_face(faces, around, kept, faces(f, (corner_of(faces, f, kept) + 1) % 3), false);
    }
  return true;
}

/// The faces around v at a vertex split: the first and last faces of the wedge, (kept, left, ·)
/// and (kept, ·, right), and kept's own faces across the edges to left and right, (kept, ·, left)
/// and (kept, right, ·). −1 where absent. Hoppe's fn0..fn3 plus the wedge ends.
std::array<int, 4> wedge_faces(const FaceMatrix& faces, const std::vector<int>& around, int kept, int left, int right) {
  const auto at = [&](int neighbour, bool want_next) {
    return neighbour >= 0 ? find_face(faces, around, kept, neighbour, want_next) : -1;
  };
  return {at(left, true), at(right, false), at(left, false), at(right, true)};
}

void check_finite(const Eigen::Vector3d& p, Eigen::Index k) {
  if (!p.allFinite()) throw InputError(split_name(k) + ": a position is NaN or Inf");
}

}  // namespace

ProgressiveMesh::ProgressiveMesh(VertexMatrix base_V, FaceMatrix base_F, std::vector<VertexSplit> splits,
                                 std::vector<int> input_vertex_ids, const Progress& progress)
    : base_V_(std::move(base_V)), base_F_(std::move(base_F)), splits_(std::move(splits)),
      input_vertex_id_(std::move(input_vertex_ids)) {
  validate_mesh(base_V_, base_F_);
  const Eigen::Index n_base = base_V_.rows(), n_splits = split_count(), n_vertices = n_base + n_splits;
  if (static_cast<Eigen::Index>(input_vertex_id_.size()) != n_vertices)
    throw InputError("progressive mesh: " + std::to_string(input_vertex_id_.size()) + " input vertex ids for " +
                     std::to_string(n_vertices) + " vertices");
  pm_vertex_id_.assign(n_vertices, -1);
  for (Eigen::Index v = 0; v < n_vertices; ++v) {
    const int input = input_vertex_id_[v];
    if (input < 0 || input >= n_vertices || pm_vertex_id_[input] >= 0)
      throw InputError("progressive mesh: input vertex ids are not a permutation (vertex " + std::to_string(v) + ")");
    pm_vertex_id_[input] = static_cast<int>(v);
  }
  face_begin_.assign(n_splits + 1, base_F_.rows());
  for (Eigen::Index k = 0; k < n_splits; ++k) {
    const VertexSplit& s = splits_[k];
    face_begin_[k + 1] = face_begin_[k] + (s.left >= 0) + (s.right >= 0);
  }
  if (face_begin_.back() > std::numeric_limits<int>::max() / 3)
    throw InputError("progressive mesh: too many faces");

  // Replay every split on the full-size state: checks each one, records its corner changes and
  // the splits it depends on, and ends at the full level.
  current_ = base_state();
  State& state = current_;
  Incidence around(n_vertices);
  for (Eigen::Index f = 0; f < base_F_.rows(); ++f) {
    if (base_F_(f, 0) == base_F_(f, 1) || base_F_(f, 1) == base_F_(f, 2) || base_F_(f, 0) == base_F_(f, 2))
      throw InputError("progressive mesh: base face " + std::to_string(f) + " repeats a vertex");
    for (int c = 0; c < 3; ++c) around[base_F_(f, c)].push_back(static_cast<int>(f));
  }
  for (Eigen::Index v = 0; v < n_base; ++v)
    if (!is_single_fan(state.faces, around[v], static_cast<int>(v)))
      throw InputError("progressive mesh: the base mesh is not manifold at vertex " + std::to_string(v));

  std::vector<int> vertex_creator(n_vertices, -1), face_creator(face_begin_.back(), -1), last_split(n_vertices, -1);
  kept_before_.resize(n_splits);
  change_offsets_.assign(1, 0);
  dependency_offsets_.assign(1, 0);
  legality_offsets_.assign(1, 0);
  std::vector<int> star_dependencies;
  for (Eigen::Index k = 0; k < n_splits; ++k) {
    progress.report(static_cast<double>(k) / static_cast<double>(n_splits), "progressive mesh: checking the splits");
    const VertexSplit& s = splits_[k];
    const int removed = static_cast<int>(n_base + k);
    const auto active = [&](int v) { return v >= 0 && v < removed; };
    if (!active(s.kept) || (s.left >= 0 && !active(s.left)) || (s.right >= 0 && !active(s.right)) ||
        (s.left < 0 && s.right < 0) || s.left < -1 || s.right < -1 || s.left == s.kept || s.right == s.kept ||
        (s.left >= 0 && s.left == s.right))
      throw InputError(split_name(k) + ": (v_s, v_l, v_r) = (" + std::to_string(s.kept) + ", " +
                       std::to_string(s.left) + ", " + std::to_string(s.right) +
                       ") must name distinct active vertices (v_l, v_r may be -1, not both)");
    check_finite(s.removed_position, k);
    check_finite(s.kept_position, k);

    const std::array<int, 4> wedge = wedge_faces(state.faces, around[s.kept], s.kept, s.left, s.right);
    if ((s.left >= 0 && wedge[0] < 0 && wedge[2] < 0) || (s.right >= 0 && wedge[1] < 0 && wedge[3] < 0))
      throw InputError(split_name(k) + ": v_l " + std::to_string(s.left) + " or v_r " + std::to_string(s.right) +
                       " is not a neighbour of v_s " + std::to_string(s.kept));
    std::vector<int> fan;
    if (!walk_wedge(state.faces, around[s.kept], s.kept, wedge[0], wedge[1], fan))
      throw InputError(split_name(k) + ": the faces around v_s do not form a fan");
    wedge_faces_.push_back(wedge);
    for (int f : fan) {
      const int c = corner_of(state.faces, f, s.kept);
      state.faces(f, c) = removed;
      change_corners_.push_back(3 * f + c);
      erase_face(around[s.kept], f);
      around[removed].push_back(f);
    }
    change_offsets_.push_back(static_cast<int>(change_corners_.size()));
    int next_face = static_cast<int>(face_begin_[k]);
    const auto add_face = [&](int a, int b, int c) {
      state.faces.row(next_face) << a, b, c;
      for (int v : {a, b, c}) around[v].push_back(next_face);
      face_creator[next_face++] = static_cast<int>(k);
    };
    if (s.left >= 0) add_face(removed, s.kept, s.left);
    if (s.right >= 0) add_face(s.kept, removed, s.right);
    kept_before_[k] = state.positions.row(s.kept).transpose();
    state.positions.row(s.kept) = s.kept_position.transpose();
    state.positions.row(removed) = s.removed_position.transpose();
    vertex_creator[removed] = static_cast<int>(k);

    for (int v : {s.kept, removed, s.left, s.right})
      if (v >= 0 && !is_single_fan(state.faces, around[v], v))
        throw InputError(split_name(k) + " makes the mesh non-manifold at vertex " + std::to_string(v));

    // Dependencies: the earlier split of v_s, and the creators of every face and vertex of the
    // star of the new edge (kept, removed) at level k + 1.
    star_dependencies.clear();
    star_dependencies.push_back(last_split[s.kept]);
    for (int v : {s.kept, removed})
      for (int f : around[v]) {
        star_dependencies.push_back(face_creator[f]);
        for (int c = 0; c < 3; ++c) star_dependencies.push_back(vertex_creator[state.faces(f, c)]);
      }
    std::sort(star_dependencies.begin(), star_dependencies.end());
    star_dependencies.erase(std::unique(star_dependencies.begin(), star_dependencies.end()), star_dependencies.end());
    for (int d : star_dependencies)
      if (d >= 0 && d < k) dependencies_.push_back(d);
    dependency_offsets_.push_back(static_cast<int>(dependencies_.size()));
    // Hoppe's legality: v_s active (its creation and earlier splits) and the wedge faces present.
    star_dependencies.assign({last_split[s.kept], vertex_creator[s.kept]});
    for (int f : wedge)
      if (f >= 0) star_dependencies.push_back(face_creator[f]);
    for (int d : star_dependencies)
      if (d >= 0 && d < k) legality_dependencies_.push_back(d);
    legality_offsets_.push_back(static_cast<int>(legality_dependencies_.size()));
    last_split[s.kept] = static_cast<int>(k);
  }
  level_ = n_splits;
  full_positions_.resize(n_vertices, 3);
  for (Eigen::Index v = 0; v < n_vertices; ++v) full_positions_.row(input_vertex_id_[v]) = state.positions.row(v);
}

ProgressiveMesh::State ProgressiveMesh::base_state() const {
  State state;
  state.positions = VertexMatrix::Zero(base_V_.rows() + split_count(), 3);
  state.positions.topRows(base_V_.rows()) = base_V_;
  state.faces = FaceMatrix::Constant(face_begin_.back(), 3, -1);
  state.faces.topRows(base_F_.rows()) = base_F_;
  return state;
}

void ProgressiveMesh::apply_split(State& state, Eigen::Index k) const {
  const VertexSplit& s = splits_[k];
  const int removed = static_cast<int>(base_V_.rows() + k);
  for (int i = change_offsets_[k]; i < change_offsets_[k + 1]; ++i)
    state.faces(change_corners_[i] / 3, change_corners_[i] % 3) = removed;
  Eigen::Index f = face_begin_[k];
  if (s.left >= 0) state.faces.row(f++) << removed, s.kept, s.left;
  if (s.right >= 0) state.faces.row(f) << s.kept, removed, s.right;
  state.positions.row(s.kept) = s.kept_position.transpose();
  state.positions.row(removed) = s.removed_position.transpose();
}

void ProgressiveMesh::undo_split(State& state, Eigen::Index k) const {
  const VertexSplit& s = splits_[k];
  for (int i = change_offsets_[k]; i < change_offsets_[k + 1]; ++i)
    state.faces(change_corners_[i] / 3, change_corners_[i] % 3) = s.kept;
  state.positions.row(s.kept) = kept_before_[k].transpose();
}

Eigen::Index ProgressiveMesh::level_for_face_count(Eigen::Index n_faces) const {
  if (n_faces < face_begin_.front() || n_faces > face_begin_.back())
    throw InputError("progressive mesh: " + std::to_string(n_faces) + " faces is outside the range of levels [" +
                     std::to_string(face_begin_.front()) + ", " + std::to_string(face_begin_.back()) + "]");
  // face_begin_ is non-decreasing: the last level whose count is <= n_faces.
  return static_cast<Eigen::Index>(std::upper_bound(face_begin_.begin(), face_begin_.end(), n_faces) -
                                   face_begin_.begin()) - 1;
}

void ProgressiveMesh::set_level(Eigen::Index level) {
  if (level < 0 || level > split_count())
    throw InputError("progressive mesh: level " + std::to_string(level) + " is outside [0, " +
                     std::to_string(split_count()) + "]");
  for (; level_ < level; ++level_) apply_split(current_, level_);
  for (; level_ > level; --level_) undo_split(current_, level_ - 1);
}

Mesh ProgressiveMesh::extract(const State& state, const std::vector<char>& vertex_active,
                              const std::vector<char>& face_active) const {
  std::vector<int> output_index(vertex_active.size(), -1);
  int n_out = 0;
  for (int pm : pm_vertex_id_)
    if (vertex_active[pm]) output_index[pm] = n_out++;
  Mesh mesh;
  mesh.V.resize(n_out, 3);
  for (std::size_t pm = 0; pm < vertex_active.size(); ++pm)
    if (output_index[pm] >= 0) mesh.V.row(output_index[pm]) = state.positions.row(pm);
  mesh.F.resize(std::count(face_active.begin(), face_active.end(), 1), 3);
  Eigen::Index row = 0;
  for (std::size_t f = 0; f < face_active.size(); ++f)
    if (face_active[f]) {
      for (int c = 0; c < 3; ++c) mesh.F(row, c) = output_index[state.faces(f, c)];
      ++row;
    }
  return mesh;
}

Mesh ProgressiveMesh::current_mesh() const {
  std::vector<char> vertex_active(base_V_.rows() + split_count(), 0), face_active(face_begin_.back(), 0);
  std::fill_n(vertex_active.begin(), vertex_count(level_), 1);
  std::fill_n(face_active.begin(), face_count(level_), 1);
  return extract(current_, vertex_active, face_active);
}

std::vector<char> ProgressiveMesh::dependency_closure(std::vector<char> applied, const std::vector<int>& offsets,
                                                     const std::vector<int>& dependencies) const {
  // Dependencies point to earlier splits: one backward pass closes the set.
  for (Eigen::Index k = split_count() - 1; k >= 0; --k)
    if (applied[k])
      for (int i = offsets[k]; i < offsets[k + 1]; ++i) applied[dependencies[i]] = 1;
  return applied;
}

bool ProgressiveMesh::apply_split_at_cut(State& state, std::vector<std::vector<int>>& around, Eigen::Index k) const {
  const VertexSplit& s = splits_[k];
  const int removed = static_cast<int>(base_V_.rows() + k);
  const std::array<int, 4>& wedge = wedge_faces_[k];
  for (int f : wedge)
    if (f >= 0 && std::find(around[s.kept].begin(), around[s.kept].end(), f) == around[s.kept].end()) return false;
  const auto neighbour = [&](int f, int step) { return state.faces(f, (corner_of(state.faces, f, s.kept) + step) % 3); };
  // The fundamental cut vertices: whatever vertices now sit where v_l and v_r were recorded.
  const int left = s.left < 0 ? -1 : wedge[0] >= 0 ? neighbour(wedge[0], 1) : neighbour(wedge[2], 2);
  const int right = s.right < 0 ? -1 : wedge[1] >= 0 ? neighbour(wedge[1], 2) : neighbour(wedge[3], 1);
  if (left >= 0 && left == right) return false;
  std::vector<int> fan;
  if (!walk_wedge(state.faces, around[s.kept], s.kept, wedge[0], wedge[1], fan)) return false;
  for (int f : fan) {
    state.faces(f, corner_of(state.faces, f, s.kept)) = removed;
    erase_face(around[s.kept], f);
    around[removed].push_back(f);
  }
  Eigen::Index f = face_begin_[k];
  const auto add_face = [&](int a, int b, int c) {
    state.faces.row(f) << a, b, c;
    for (int v : {a, b, c}) around[v].push_back(static_cast<int>(f));
    ++f;
  };
  if (left >= 0) add_face(removed, s.kept, left);
  if (right >= 0) add_face(s.kept, removed, right);
  state.positions.row(s.kept) = s.kept_position.transpose();
  state.positions.row(removed) = s.removed_position.transpose();
  for (int v : {s.kept, removed, left, right})
    if (v >= 0 && !is_single_fan(state.faces, around[v], v)) return false;
  return true;
}

Mesh ProgressiveMesh::selective_refinement(const std::vector<char>& selected_input_vertices, bool whole_stars) const {
  const Eigen::Index n_base = base_V_.rows(), n_splits = split_count();
  if (static_cast<Eigen::Index>(selected_input_vertices.size()) != n_base + n_splits)
    throw InputError("selective refinement: " + std::to_string(selected_input_vertices.size()) +
                     " selection flags for " + std::to_string(n_base + n_splits) + " vertices");
  std::vector<char> wanted(n_splits, 0);
  for (Eigen::Index k = 0; k < n_splits; ++k)
    wanted[k] = selected_input_vertices[input_vertex_id_[splits_[k].kept]] ||
                selected_input_vertices[input_vertex_id_[n_base + k]];
  std::vector<char> vertex_active(n_base + n_splits, 0), face_active(face_begin_.back(), 0);
  const auto activate = [&](const std::vector<char>& applied) {
    std::fill(vertex_active.begin(), vertex_active.end(), 0);
    std::fill(face_active.begin(), face_active.end(), 0);
    std::fill_n(vertex_active.begin(), n_base, 1);
    std::fill_n(face_active.begin(), face_count(0), 1);
    for (Eigen::Index k = 0; k < n_splits; ++k)
      if (applied[k]) {
        vertex_active[n_base + k] = 1;
        std::fill(face_active.begin() + face_begin_[k], face_active.begin() + face_begin_[k + 1], 1);
      }
  };

  // First Hoppe's legality test (v_s and the wedge faces present; v_l, v_r found as the vertices
  // now at their place): few forced splits, each one checked to keep the mesh manifold.
  if (!whole_stars) {
    const std::vector<char> applied = dependency_closure(wanted, legality_offsets_, legality_dependencies_);
    State state = base_state();
    std::vector<std::vector<int>> around(n_base + n_splits);
    for (Eigen::Index f = 0; f < base_F_.rows(); ++f)
      for (int c = 0; c < 3; ++c) around[base_F_(f, c)].push_back(static_cast<int>(f));
    bool valid = true;
    for (Eigen::Index k = 0; k < n_splits && valid; ++k)
      if (applied[k]) valid = apply_split_at_cut(state, around, k);
    if (valid) {
      activate(applied);
      return extract(state, vertex_active, face_active);
    }
  }
  // Otherwise the closure over whole stars, under which every split meets exactly the
  // neighbourhood it was recorded in (always valid).
  const std::vector<char> applied = dependency_closure(wanted, dependency_offsets_, dependencies_);
  State state = base_state();
  for (Eigen::Index k = 0; k < n_splits; ++k)
    if (applied[k]) apply_split(state, k);
  activate(applied);
  return extract(state, vertex_active, face_active);
}

ProgressiveMesh progressive_mesh_from_collapses(const VertexRef& V, const FaceRef& F,
                                                const std::vector<CollapseRecord>& collapses,
                                                const Progress& progress) {
  validate_mesh(V, F);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2))
      throw InputError("progressive mesh: face " + std::to_string(f) +
                       " repeats a vertex; the full level must reproduce the input, remove such faces first");
  const Eigen::Index n_vertices = V.rows();
  FaceMatrix faces = F;
  VertexMatrix positions = V;
  Incidence around(n_vertices);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) around[F(f, c)].push_back(static_cast<int>(f));
  std::vector<char> vertex_alive(n_vertices, 1), face_alive(F.rows(), 1);
  std::vector<VertexSplit> reversed;  // in collapse order, input numbering
  reversed.reserve(collapses.size());
  for (std::size_t r = 0; r < collapses.size(); ++r) {
    progress.report(0.5 * static_cast<double>(r) / static_cast<double>(collapses.size()),
                    "progressive mesh: vertex splits");
    const CollapseRecord& c = collapses[r];
    const auto alive = [&](int v) { return v >= 0 && v < n_vertices && vertex_alive[v]; };
    const std::string name = "collapse " + std::to_string(r);
    if (!alive(c.removed) || !alive(c.kept) || c.removed == c.kept || (c.left >= 0 && !alive(c.left)) ||
        (c.right >= 0 && !alive(c.right)))
      throw InputError(name + " names a vertex that is not in the mesh it is applied to");
    // The faces on the edge must be exactly (removed, kept, left) and (kept, removed, right).
    int vanishing = 0;
    for (int f : around[c.removed]) {
      const int k = corner_of(faces, f, c.kept);
      if (k < 0) continue;
      const int third = faces(f, 3 - k - corner_of(faces, f, c.removed));
      const bool removed_to_kept = faces(f, (k + 2) % 3) == c.removed;
      if (third != (removed_to_kept ? c.left : c.right))
        throw InputError(name + ": the faces on edge (" + std::to_string(c.removed) + ", " + std::to_string(c.kept) +
                         ") do not match its left/right vertices");
      ++vanishing;
    }
    if (vanishing != (c.left >= 0) + (c.right >= 0))
      throw InputError(name + ": edge (" + std::to_string(c.removed) + ", " + std::to_string(c.kept) +
                       ") has " + std::to_string(vanishing) + " faces, its record names " +
                       std::to_string((c.left >= 0) + (c.right >= 0)));
    reversed.push_back({c.kept, c.left, c.right, positions.row(c.removed).transpose(),
                        positions.row(c.kept).transpose()});
    for (int f : std::vector<int>(around[c.removed])) {
      if (corner_of(faces, f, c.kept) >= 0) {
        face_alive[f] = 0;
        for (int k = 0; k < 3; ++k)
          if (faces(f, k) != c.removed) erase_face(around[faces(f, k)], f);
      } else {
        faces(f, corner_of(faces, f, c.removed)) = c.kept;
        around[c.kept].push_back(f);
      }
    }
    around[c.removed].clear();
    vertex_alive[c.removed] = 0;
    positions.row(c.kept) = c.kept_position_after.transpose();
  }

  // PM numbering: surviving vertices in input order, then the removed ones, last collapse first.
  std::vector<int> pm_of_input(n_vertices, -1), input_of_pm;
  for (Eigen::Index v = 0; v < n_vertices; ++v)
    if (vertex_alive[v]) {
      pm_of_input[v] = static_cast<int>(input_of_pm.size());
      input_of_pm.push_back(static_cast<int>(v));
    }
  const Eigen::Index n_base = static_cast<Eigen::Index>(input_of_pm.size());
  for (auto c = collapses.rbegin(); c != collapses.rend(); ++c) {
    pm_of_input[c->removed] = static_cast<int>(input_of_pm.size());
    input_of_pm.push_back(c->removed);
  }
  VertexMatrix base_V(n_base, 3);
  for (Eigen::Index v = 0; v < n_base; ++v) base_V.row(v) = positions.row(input_of_pm[v]);
  FaceMatrix base_F(std::count(face_alive.begin(), face_alive.end(), 1), 3);
  Eigen::Index row = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (face_alive[f]) {
      for (int k = 0; k < 3; ++k) base_F(row, k) = pm_of_input[faces(f, k)];
      ++row;
    }
  std::vector<VertexSplit> splits(reversed.rbegin(), reversed.rend());
  const auto pm = [&](int v) { return v >= 0 ? pm_of_input[v] : -1; };
  for (VertexSplit& s : splits) s.kept = pm(s.kept), s.left = pm(s.left), s.right = pm(s.right);
  return ProgressiveMesh(std::move(base_V), std::move(base_F), std::move(splits), std::move(input_of_pm),
                         progress.subrange(0.5, 1.0));
}

ProgressiveMesh progressive_mesh(const VertexRef& V, const FaceRef& F, QemOptions options, const Progress& progress) {
  options.record_collapses = true;
  if (options.target_faces == 0 && options.max_error == 0.0) options.target_faces = 1;  // as far as it goes
  const QemResult result = decimate_qem(V, F, options, progress.subrange(0.0, 0.9));
  if (result.split_vertex_origin.size() > 0)
    throw InputError("progressive mesh: the input is not manifold or not consistently oriented (the decimator "
                     "had to split vertices); run topology.split_non_manifold_vertices / repair first");
  progress.report(0.9, "progressive mesh: vertex splits");
  ProgressiveMesh mesh = progressive_mesh_from_collapses(V, F, result.collapses, progress.subrange(0.9, 1.0));
  progress.report(1.0, "progressive mesh: vertex splits");
  return mesh;
}

// ------------------------------------------------------------------------------------------------
// File format (little-endian): "MSPM", u32 version, u64 #base vertices, u64 #base faces,
// u64 #splits; base positions (f64×3 each), base faces (i32×3 each), input ids of the base
// vertices (i32 each); then per split: i32 kept, left, right, input id of the new vertex,
// f64×3 new vertex position, f64×3 kept position.

namespace {

constexpr char kMagic[4] = {'M', 'S', 'P', 'M'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint64_t kHeaderBytes = 4 + 4 + 3 * 8;
constexpr std::uint64_t kBaseVertexBytes = 3 * 8 + 4, kBaseFaceBytes = 3 * 4, kSplitBytes = 4 * 4 + 6 * 8;

template <typename T>
void put(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}
template <typename T>
T take(std::ifstream& in) {
  T value;
  in.read(reinterpret_cast<char*>(&value), sizeof(T));
  return value;
}

}  // namespace

void save_progressive_mesh(const std::string& path, const ProgressiveMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError("cannot write progressive mesh file " + path);
  out.write(kMagic, 4);
  put(out, kVersion);
  const VertexMatrix& V = mesh.base_vertices();
  const FaceMatrix& F = mesh.base_faces();
  put(out, static_cast<std::uint64_t>(V.rows()));
  put(out, static_cast<std::uint64_t>(F.rows()));
  put(out, static_cast<std::uint64_t>(mesh.split_count()));
  out.write(reinterpret_cast<const char*>(V.data()), static_cast<std::streamsize>(V.size() * sizeof(double)));
  out.write(reinterpret_cast<const char*>(F.data()), static_cast<std::streamsize>(F.size() * sizeof(int)));
  const std::vector<int>& ids = mesh.input_vertex_ids();
  for (Eigen::Index v = 0; v < V.rows(); ++v) put(out, static_cast<std::int32_t>(ids[v]));
  for (Eigen::Index k = 0; k < mesh.split_count(); ++k) {
    const VertexSplit& s = mesh.splits()[k];
    for (int value : {s.kept, s.left, s.right, ids[V.rows() + k]}) put(out, static_cast<std::int32_t>(value));
    for (int c = 0; c < 3; ++c) put(out, s.removed_position(c));
    for (int c = 0; c < 3; ++c) put(out, s.kept_position(c));
  }
  if (!out.flush()) throw InputError("error while writing progressive mesh file " + path);
}

ProgressiveMesh load_progressive_mesh(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError("cannot open progressive mesh file " + path);
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  if (size < kHeaderBytes) throw InputError(path + ": truncated progressive mesh file (no complete header)");
  char magic[4];
  in.read(magic, 4);
  if (std::memcmp(magic, kMagic, 4) != 0) throw InputError(path + ": not a meshsmith progressive mesh (bad magic)");
  const auto version = take<std::uint32_t>(in);
  if (version != kVersion)
    throw InputError(path + ": progressive mesh format version " + std::to_string(version) + ", this reader knows " +
                     std::to_string(kVersion));
  const auto n_vertices = take<std::uint64_t>(in), n_faces = take<std::uint64_t>(in), n_splits = take<std::uint64_t>(in);
  constexpr std::uint64_t limit = std::numeric_limits<int>::max() / 4;
  if (n_vertices > limit || n_faces > limit || n_splits > limit || n_vertices == 0 || n_faces == 0)
    throw InputError(path + ": corrupt progressive mesh header (counts " + std::to_string(n_vertices) + ", " +
                     std::to_string(n_faces) + ", " + std::to_string(n_splits) + ")");
  const std::uint64_t expected =
      kHeaderBytes + n_vertices * kBaseVertexBytes + n_faces * kBaseFaceBytes + n_splits * kSplitBytes;
  if (size != expected)
    throw InputError(path + ": progressive mesh file has " + std::to_string(size) + " bytes, its header announces " +
                     std::to_string(expected) + (size < expected ? " (truncated)" : " (trailing data)"));
  VertexMatrix V(n_vertices, 3);
  FaceMatrix F(n_faces, 3);
  in.read(reinterpret_cast<char*>(V.data()), static_cast<std::streamsize>(V.size() * sizeof(double)));
  in.read(reinterpret_cast<char*>(F.data()), static_cast<std::streamsize>(F.size() * sizeof(int)));
  std::vector<int> ids(n_vertices + n_splits);
  for (std::uint64_t v = 0; v < n_vertices; ++v) ids[v] = take<std::int32_t>(in);
  std::vector<VertexSplit> splits(n_splits);
  for (std::uint64_t k = 0; k < n_splits; ++k) {
    VertexSplit& s = splits[k];
    s.kept = take<std::int32_t>(in);
    s.left = take<std::int32_t>(in);
    s.right = take<std::int32_t>(in);
    ids[n_vertices + k] = take<std::int32_t>(in);
    for (int c = 0; c < 3; ++c) s.removed_position(c) = take<double>(in);
    for (int c = 0; c < 3; ++c) s.kept_position(c) = take<double>(in);
  }
  if (!in) throw InputError(path + ": error while reading the progressive mesh file");
  try {
    return ProgressiveMesh(std::move(V), std::move(F), std::move(splits), std::move(ids));
  } catch (const InputError& error) {
    throw InputError(path + ": corrupt progressive mesh: " + error.what());
  }
}

}  // namespace meshsmith::decimation
