#pragma once
/// \file collapse_record.h
/// The record of one collapse performed by incremental decimation (§4.2), in the order performed.
/// Read backwards, the records are the vertex splits of a progressive mesh (§4.3; Hoppe 1996):
/// vsplit(kept, left, right) re-creates `removed` and the faces (removed, kept, left) and
/// (kept, removed, right).
#include <Eigen/Core>

namespace meshsmith::decimation {

struct CollapseRecord {
  int removed = -1;  ///< vertex that disappears (index into the input V)
  int kept = -1;     ///< vertex it merges into (index into the input V)
  /// Third vertex of the face (removed, kept, left), counter-clockwise: the face of the half-edge
  /// removed→kept. −1 when that half-edge is on the boundary.
  int left = -1;
  /// Third vertex of the face (kept, removed, right), counter-clockwise: the face of the half-edge
  /// kept→removed. −1 when that half-edge is on the boundary.
  int right = -1;
  Eigen::Vector3d removed_position = Eigen::Vector3d::Zero();      ///< `removed` just before
  Eigen::Vector3d kept_position_before = Eigen::Vector3d::Zero();  ///< `kept` just before
  /// `kept` after the collapse: equal to kept_position_before for a half-edge collapse, the
  /// optimal (QEM) placement for a full-edge collapse. The difference is the offset a vertex split
  /// undoes.
  Eigen::Vector3d kept_position_after = Eigen::Vector3d::Zero();
};

}  // namespace meshsmith::decimation
