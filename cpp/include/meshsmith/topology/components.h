#pragma once
/// \file components.h
/// Connected components of a triangle mesh (§2, mesh definitions).
#include <meshsmith/core/types.h>

namespace meshsmith::topology {

/// Component labels of the faces and vertices of a mesh.
struct Components {
  int count = 0;                 ///< number of components
  Eigen::VectorXi face_labels;   ///< #F: component of each face, in [0, count)
  Eigen::VectorXi vertex_labels; ///< #V: component of each vertex; -1 for a vertex no face uses
};

/// What joins two faces into one component.
enum class Connectivity {
  Vertex,  ///< a shared vertex (`igl::vertex_components`, trimesh, most tools): the default
  Edge,    ///< a shared edge (`igl::facet_components`): two cubes touching at a corner are two
};

/// Connected components of F. With the default Connectivity::Vertex, faces sharing only a vertex
/// are one component: two cubes touching at one corner are one component. With
/// Connectivity::Edge they are two, and a vertex in several components (a pinch) is labelled
/// with the component of its lowest-numbered face. Components are numbered in the order of their
/// first face, so face 0 is in component 0. Runs in O(#F α(#F)) (union-find).
/// F: #F×3 triangles; n_vertices: #V (< 0: max index + 1).
/// \throw InputError as checked_vertex_count.
Components connected_components(const FaceRef& F, Eigen::Index n_vertices = -1,
                                Connectivity connectivity = Connectivity::Vertex);

}  // namespace meshsmith::topology
