#pragma once
/// \file components.h
/// Connected components of a triangle mesh (§2, mesh definitions).
#include <meshsmith/core/types.h>

namespace meshsmith::topology {

/// Component labels of the faces and vertices of a mesh.
struct Components {
  int count = 0;                ///< number of components
  Eigen::VectorXi face_labels;   ///< #F: component of each face, in [0, count)
  Eigen::VectorXi vertex_labels; ///< #V: component of each vertex; -1 for a vertex no face uses
};

/// Connected components of F where two faces are connected when they share a VERTEX (as
/// `igl::vertex_components` and most tools do): two cubes touching at one corner are one
/// component. Components are numbered in the order of their first face, so face 0 is in
/// component 0. Runs in O(#F α(#V)) (union-find).
/// F: #F×3 triangles; n_vertices: #V (< 0: max index + 1).
/// \throw InputError as checked_vertex_count.
Components connected_components(const FaceRef& F, Eigen::Index n_vertices = -1);

}  // namespace meshsmith::topology
