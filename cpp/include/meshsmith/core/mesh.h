#pragma once
/// \file mesh.h
/// The halfedge mesh used where an algorithm edits connectivity (collapse, split, flip):
/// OpenMesh's TriMesh with double-precision points and normals, plus conversion to and from
/// (V, F) arrays.
#include <meshsmith/core/types.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace meshsmith {

/// OpenMesh traits with double precision (OpenMesh's default stores floats).
struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

/// Builds a TriMesh from V (#V by 3) and F (#F by 3). Vertex i of the result is row i of V and
/// face j is row j of F, so indices carry over both ways.
/// \pre validate_mesh(V, F) passes (it is called here).
/// \throw InputError if a face has a repeated vertex or cannot be added without breaking
///        manifoldness (a "complex edge" or "complex vertex"): the message names the face and
///        suggests topology::split_non_manifold_vertices / repair.
TriMesh to_trimesh(const VertexRef& V, const FaceRef& F);

/// Writes the mesh back as arrays, skipping deleted elements (call after garbage collection or
/// not: indices are compacted in order of the handles).
Mesh from_trimesh(const TriMesh& mesh);

}  // namespace meshsmith
