#pragma once
/// \file progressive_mesh.h
/// Progressive meshes (§4.3; Hoppe 1996, selective refinement after Hoppe 1997): a coarse base
/// mesh and the vertex splits that undo, one by one in reverse, the collapses of incremental
/// decimation (§4.2), so that any level of detail between the base and the full mesh is reached
/// incrementally, the whole is stored in transmission order (base first), and parts of the mesh
/// can be refined selectively.
///
/// Numbering ("PM order"): the base vertices are 0 .. #B−1 and vertex split k creates vertex
/// #B + k; the base faces come first, then each split appends the faces it creates. Level k is
/// the mesh after splits 0 .. k−1 (level 0: the base mesh, level #splits: the full mesh). Meshes
/// handed out list their vertices in the order of the input mesh (input_vertex_ids), so the full
/// level is the input: same positions bit for bit, same faces up to order and rotation.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/decimation/collapse_record.h>
#include <meshsmith/decimation/decimate.h>

#include <array>
#include <string>
#include <vector>

namespace meshsmith::decimation {

/// One vertex split v_s → (v_s, v_new) (§4.3), the inverse of one collapse. It creates vertex
/// #B + k at `removed_position`, moves `kept` to `kept_position` (for a full-edge collapse this
/// undoes the placement: the offset of §4.3), gives v_new the faces around `kept` from `left` to
/// `right` (counter-clockwise), and creates the faces (v_new, kept, left) and (kept, v_new, right).
struct VertexSplit {
  int kept = -1;   ///< v_s, an active vertex (PM numbering)
  int left = -1;   ///< v_l (PM numbering), −1 if the edge v_new→kept will be on the boundary
  int right = -1;  ///< v_r (PM numbering), −1 if the edge kept→v_new will be on the boundary
  Eigen::Vector3d removed_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d kept_position = Eigen::Vector3d::Zero();
};

class ProgressiveMesh {
 public:
  /// The transmission form: base mesh (#B×3 positions, #BF×3 faces in PM numbering), the vertex
  /// splits in refinement order, and the input index of every PM vertex (#B + #splits, a
  /// permutation). Replays every split once to check it and to derive the corner changes.
  /// \throw InputError if the base mesh is not a valid manifold mesh, `input_vertex_ids` is not a
  ///        permutation, or a split names an inactive vertex, names v_l/v_r that are not
  ///        neighbours of v_s on the right sides, or would make the mesh non-manifold (the message
  ///        names the split).
  ProgressiveMesh(VertexMatrix base_V, FaceMatrix base_F, std::vector<VertexSplit> splits,
                  std::vector<int> input_vertex_ids, const Progress& progress = {});

  Eigen::Index split_count() const { return static_cast<Eigen::Index>(splits_.size()); }
  Eigen::Index level() const { return level_; }
  Eigen::Index vertex_count(Eigen::Index level) const { return base_V_.rows() + level; }
  Eigen::Index face_count(Eigen::Index level) const { return face_begin_.at(static_cast<std::size_t>(level)); }
  /// The highest level with at most `n_faces` faces.
  /// \throw InputError if n_faces is outside [face_count(0), face_count(split_count())].
  Eigen::Index level_for_face_count(Eigen::Index n_faces) const;

  /// Moves the current level to `level` by applying or undoing the splits in between:
  /// O(changed corners), independent of the mesh size. \throw InputError if out of range.
  void set_level(Eigen::Index level);
  /// The mesh at the current level, vertices in input order (O(#V + #F)).
  Mesh current_mesh() const;

  /// Selective refinement (§4.3): the mesh in which every vertex split touching a selected input
  /// vertex (as v_s or as the new vertex) is applied, with the splits it depends on forced first.
  /// Default: Hoppe's legality test — a split needs v_s active (the split that created it and its
  /// earlier splits applied) and its wedge faces present (the faces on both sides of the edges to
  /// v_l and v_r); v_l and v_r themselves are the fundamental cut vertices, i.e. whatever vertices
  /// now sit at their place, so they need not be forced. Every such split is checked to keep the
  /// mesh manifold; should one fail, or with `whole_stars`, the dependencies are taken over whole
  /// stars instead (the splits that created every vertex and face around the split edge), so each
  /// split meets exactly the neighbourhood it was recorded in: always valid, more refinement.
  /// The result is a valid manifold mesh, vertices in input order. Independent of the current level.
  /// \throw InputError if `selected_input_vertices` does not have one entry per input vertex.
  Mesh selective_refinement(const std::vector<char>& selected_input_vertices, bool whole_stars = false) const;

  /// Positions at the full level in input order (the input V): what selection predicates see.
  const VertexMatrix& full_positions() const { return full_positions_; }

  const VertexMatrix& base_vertices() const { return base_V_; }
  const FaceMatrix& base_faces() const { return base_F_; }
  const std::vector<VertexSplit>& splits() const { return splits_; }
  const std::vector<int>& input_vertex_ids() const { return input_vertex_id_; }

 private:
  struct State {
    VertexMatrix positions;  // every PM vertex; meaningful where active
    FaceMatrix faces;        // every PM face; meaningful where active
  };
  State base_state() const;
  void apply_split(State& state, Eigen::Index k) const;
  void undo_split(State& state, Eigen::Index k) const;
  Mesh extract(const State& state, const std::vector<char>& vertex_active, const std::vector<char>& face_active) const;
  std::vector<char> dependency_closure(std::vector<char> applied, const std::vector<int>& offsets,
                                       const std::vector<int>& dependencies) const;
  /// Split k where its wedge faces are, with the vertices found there (selective refinement);
  /// false if that would not be a valid manifold split (the state is then unusable).
  bool apply_split_at_cut(State& state, std::vector<std::vector<int>>& around, Eigen::Index k) const;

  VertexMatrix base_V_;
  FaceMatrix base_F_;
  std::vector<VertexSplit> splits_;
  std::vector<int> input_vertex_id_;  // PM vertex → input vertex
  std::vector<int> pm_vertex_id_;     // input vertex → PM vertex
  // Derived by the replay in the constructor.
  std::vector<Eigen::Index> face_begin_;        // #splits+1: faces at each level
  std::vector<Eigen::Vector3d> kept_before_;    // position of v_s before split k (undo target)
  std::vector<int> change_offsets_, change_corners_;  // CSR: corners 3f+c that split k turns v_s → v_new
  std::vector<int> dependency_offsets_, dependencies_;  // CSR: splits whose stars split k needs (strong)
  std::vector<int> legality_offsets_, legality_dependencies_;  // CSR: Hoppe's legality (v_s, wedge faces)
  std::vector<std::array<int, 4>> wedge_faces_;  // first/last wedge face, v_s's faces across v_l, v_r
  VertexMatrix full_positions_;
  State current_;
  Eigen::Index level_ = 0;
};

/// Builds the progressive mesh of (V, F) from the collapses that decimated it, in the order
/// performed (CollapseRecord, indices into V). The base mesh is (V, F) after all collapses.
/// \pre validate_mesh(V, F) passes; F is manifold, oriented, without faces that repeat a vertex;
///      `collapses` were performed on (V, F).
/// \throw InputError if a precondition fails, if a collapse is inconsistent with the mesh it is replayed on (the message
///        names it), or as the ProgressiveMesh constructor. \throw Cancelled (progress, once per collapse).
ProgressiveMesh progressive_mesh_from_collapses(const VertexRef& V, const FaceRef& F,
                                                const std::vector<CollapseRecord>& collapses,
                                                const Progress& progress = {});

/// Decimates (V, F) with decimate_qem (§4.2) under `options` (its stop rules; with none given,
/// down to the smallest mesh the decimator reaches) and records the collapses as vertex splits.
/// \throw InputError as decimate_qem and progressive_mesh_from_collapses. \throw Cancelled.
ProgressiveMesh progressive_mesh(const VertexRef& V, const FaceRef& F, QemOptions options,
                                 const Progress& progress = {});

/// Writes `mesh` in transmission order: a header (magic "MSPM", version, counts), the base mesh,
/// then the vertex splits in refinement order. Little-endian binary.
/// \throw InputError if the file cannot be written.
void save_progressive_mesh(const std::string& path, const ProgressiveMesh& mesh);

/// Reads a file written by save_progressive_mesh. Every count is checked against the file size
/// before anything is allocated, and every split is replayed and checked.
/// \throw InputError for a missing, foreign (bad magic), newer (version), truncated or corrupt file.
ProgressiveMesh load_progressive_mesh(const std::string& path);

}  // namespace meshsmith::decimation
