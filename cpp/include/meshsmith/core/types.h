#pragma once
/// \file types.h
/// Array types of the public API. Row-major so that numpy (C-order) arrays map onto them
/// without a copy; any Eigen (n, 3) matrix converts to them implicitly.
#include <Eigen/Core>

namespace meshsmith {

/// #V by 3 vertex positions.
using VertexMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #F by 3 triangles: zero-based indices into the rows of a VertexMatrix, counter-clockwise.
using FaceMatrix = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #E by 2 undirected edges.
using EdgeMatrix = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Read-only views used as function arguments: bind to matrices and to mapped numpy buffers.
using VertexRef = Eigen::Ref<const VertexMatrix>;
using FaceRef = Eigen::Ref<const FaceMatrix>;

/// A triangle mesh as plain arrays.
struct Mesh {
  VertexMatrix V;
  FaceMatrix F;
};

}  // namespace meshsmith
