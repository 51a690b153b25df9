// Details in local frames (multiresolution editing), shared by transfer_details and the
// detail-preserving HarmonicDeformer.
#include <meshsmith/deformation/multiresolution.h>

#include "vertex_sets.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/normals.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/parallel_for.h>

#include <string>

namespace meshsmith::deformation {

namespace {

/// The frame (rows: tangent, bitangent, normal) at vertex i of `base`; false without one.
bool local_frame(const VertexRef& base, const VertexMatrix& normals, Eigen::Index i, int neighbour,
                 Eigen::Matrix3d& frame) {
  if (neighbour < 0) return false;
  const Eigen::Vector3d n = normals.row(i).transpose();
  if (n.squaredNorm() < 0.25) return false;  // unit normals, or the zero vector
  Eigen::Vector3d t = (base.row(neighbour) - base.row(i)).transpose();
  t -= n.dot(t) * n;
  const double length = t.norm();
  if (!(length > 0.0)) return false;
  t /= length;
  frame.row(0) = t.transpose();
  frame.row(1) = n.cross(t).transpose();
  frame.row(2) = n.transpose();
  return true;
}

}  // namespace

DetailFrames encode_details(const VertexRef& V, const VertexRef& base, const FaceRef& F,
                            const std::vector<char>& with_detail) {
  static const char* function = "encode_details";
  validate_mesh(V, F);
  const Eigen::Index n = V.rows();
  detail::check_positions(base, n, "base", function);
  if (!with_detail.empty() && static_cast<Eigen::Index>(with_detail.size()) != n) {
    throw InputError(std::string(function) + ": with_detail has " + std::to_string(with_detail.size()) +
                     " flags for " + std::to_string(n) + " vertices");
  }
  DetailFrames details;
  details.neighbour = Eigen::VectorXi::Constant(n, -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = F(f, c), next = F(f, (c + 1) % 3);
      if (details.neighbour[v] < 0 && next != v) details.neighbour[v] = next;
    }
  }
  details.coefficients.setZero(n, 3);
  details.world.setZero(n, 3);
  const VertexMatrix normals = geometry::vertex_normals(base, F);
  tbb::parallel_for(Eigen::Index(0), n, [&](Eigen::Index v) {
    if (!with_detail.empty() && !with_detail[v]) {
      details.neighbour[v] = -1;
      return;
    }
    const Eigen::Vector3d detail = (V.row(v) - base.row(v)).transpose();
    details.world.row(v) = detail.transpose();
    Eigen::Matrix3d frame;
    if (local_frame(base, normals, v, details.neighbour[v], frame)) {
      details.coefficients.row(v) = (frame * detail).transpose();
    } else {
      details.neighbour[v] = -1;
    }
  });
  return details;
}

VertexMatrix decode_details(const VertexRef& base, const FaceRef& F, const DetailFrames& details) {
  const Eigen::Index n = details.neighbour.size();
  detail::check_positions(base, n, "base", "decode_details");
  validate_mesh(base, F);
  const VertexMatrix normals = geometry::vertex_normals(base, F);
  VertexMatrix out = base;
  tbb::parallel_for(Eigen::Index(0), n, [&](Eigen::Index v) {
    Eigen::Matrix3d frame;
    if (local_frame(base, normals, v, details.neighbour[v], frame)) {
      out.row(v) += (frame.transpose() * details.coefficients.row(v).transpose()).transpose();
    } else {
      out.row(v) += details.world.row(v);
    }
  });
  return out;
}

VertexMatrix transfer_details(const VertexRef& V, const VertexRef& base, const FaceRef& F,
                              const VertexRef& edited_base) {
  detail::check_positions(edited_base, V.rows(), "edited_base", "transfer_details");
  return decode_details(edited_base, F, encode_details(V, base, F));
}

}  // namespace meshsmith::deformation
