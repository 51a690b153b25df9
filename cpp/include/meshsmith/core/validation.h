#pragma once
/// \file validation.h
/// Checks at the library boundary (DESIGN.md, "Errors"): every public function validates its
/// input with these before it touches it.
#include <meshsmith/core/types.h>

#include <string>
#include <vector>

namespace meshsmith {

/// \throw InputError if V is empty or holds a NaN/Inf (the message names the row and column).
void validate_vertices(const VertexRef& V, const char* name = "V");

/// \throw InputError if V or F is empty (when `allow_empty_faces` is false), V holds a
/// NaN/Inf, or a face index is outside [0, #V). The message names the offending face.
void validate_mesh(const VertexRef& V, const FaceRef& F, bool allow_empty_faces = false);

/// Defects of a mesh that many algorithms need to know about but that are not errors in
/// themselves. Index lists are sorted ascending.
struct MeshDefects {
  std::vector<int> degenerate_faces;      ///< faces with a repeated vertex index
  std::vector<int> zero_area_faces;       ///< faces with distinct indices but area <= area_tolerance
  std::vector<int> duplicate_faces;       ///< faces on the same vertex set as an earlier face (later copies)
  std::vector<int> unreferenced_vertices; ///< vertices used by no face
  bool empty() const {
    return degenerate_faces.empty() && zero_area_faces.empty() && duplicate_faces.empty() &&
           unreferenced_vertices.empty();
  }
  /// One line per kind of defect, e.g. "3 degenerate faces (first: 17)"; "" if none.
  std::string summary() const;
};

/// Finds the defects above. `area_tolerance` is absolute (default 0: exactly flat triangles).
/// \pre validate_mesh(V, F) passes.  Runs in O(#F log #F).
MeshDefects find_mesh_defects(const VertexRef& V, const FaceRef& F, double area_tolerance = 0.0);

}  // namespace meshsmith
