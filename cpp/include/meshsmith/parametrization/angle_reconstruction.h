#pragma once
/// \file angle_reconstruction.h
/// Planar coordinates from triangle angles (§5.1.3, the last step of ABF; Sheffer, Lévy,
/// Mogilnitskaya, Bogart, "ABF++", 2005, §5): the least-squares layout in the manner of LSCM.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>
#include <meshsmith/parametrization/abf.h>

#include <array>

namespace meshsmith::parametrization {

/// Two vertices held fixed by the layout, and where.
struct AnglePins {
  std::array<int, 2> vertices{};                ///< distinct vertex indices
  std::array<Eigen::Vector2d, 2> positions{};   ///< their UV positions (distinct)
};

/// Lays out triangles with the given angles in the plane: for each face (a, b, c) with the
/// corner of largest sine at c, the sine law and the angle at a give
///   (u_c − u_a) = (sin α_b / sin α_c) · R(α_a) (u_b − u_a),
/// R(θ) the counter-clockwise rotation; these #F complex linear equations are solved in the
/// least-squares sense with the two pinned vertices fixed (Hermitian normal equations, CHOLMOD). Angles that
/// satisfy ABF's triangle, vertex and wheel conditions are reproduced exactly (up to round-off),
/// with every triangle counter-clockwise; other angles give the least-squares compromise.
///
/// F: #F×3 triangles over #V = n_vertices vertices, angles: #F×3 (column k at corner k).
/// Returns #V×2 coordinates.
/// \pre F is connected through its edges, every vertex is used, angles are in (0, π).
/// \throw InputError if shapes disagree, an angle is outside (0, π) or not finite, a pin is
///        out of range, the pins coincide, or a vertex is used by no face.
/// \throw SolverError if the normal equations are singular (F not edge-connected).
geometry::ParameterMatrix uv_from_angles(const FaceRef& F, Eigen::Index n_vertices, const AngleRef& angles,
                                         const AnglePins& pins, const Progress& progress = {});

}  // namespace meshsmith::parametrization
