#pragma once
/// \file depth_images.h
/// Depth images to points and meshes (§2.3, "Compute world coordinates from Depth Camera"):
/// pinhole back-projection of every valid pixel, and a triangle mesh over the pixel grid that is
/// cut wherever neighbouring depths jump (a silhouette against the background), so separate
/// objects stay separate. The 2D scanline case of §2.3 (one row of distances along rays) is
/// scanline_to_points.
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace meshsmith::reconstruction {

/// h×w depths, row-major (row = image v, column = image u).
using DepthImage = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using DepthRef = Eigen::Ref<const DepthImage>;
/// #points×2 (row, column) pixel of each output point.
using PixelMatrix = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// The pinhole camera of a depth image: focal lengths and principal point in pixels, and the
/// depth unit (OpenCV / Open3D conventions: z = depth / depth_scale along the optical axis,
/// x = (u − cx) z / fx, y = (v − cy) z / fy; camera at the origin looking along +z, y down).
struct PinholeCamera {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;
  double depth_scale = 1.0;  ///< stored depth units per output length unit (1000: millimetres → metres)
};

struct DepthPoints {
  VertexMatrix points;  ///< n×3 camera-frame positions of the valid pixels, in row-major pixel order
  PixelMatrix pixels;   ///< n×2 (row, column) of each point
};

struct DepthMesh {
  VertexMatrix V;  ///< n×3, the points of depth_to_points (every valid pixel, also those in no triangle)
  FaceMatrix F;    ///< #F×3 triangles, normals facing the camera
  PixelMatrix pixels;  ///< n×2 (row, column) of each vertex
};

/// Back-projects every valid pixel. A pixel is valid if its depth is finite and > 0 (0 and NaN
/// are the usual "no measurement" values) and mask (h×w, empty for none) is nonzero there.
/// \throw InputError if the image is empty, fx or fy is zero or not finite, cx or cy is not
///        finite, depth_scale is not positive and finite, or the mask's shape differs.
DepthPoints depth_to_points(const DepthRef& depth, const PinholeCamera& camera,
                            const std::vector<char>& mask = {});

/// The mesh of the pixel grid: each 2×2 block of valid pixels gives two triangles (split along
/// the diagonal of the smaller depth difference), three valid pixels give one; a triangle is
/// dropped if one of its edges joins depths z_i, z_j with |z_i − z_j| > max_jump · min(z_i, z_j)
/// (a depth discontinuity; max_jump >= 0 relative, +inf keeps every triangle).
/// \throw InputError as depth_to_points, or if max_jump is negative or NaN.
DepthMesh depth_to_mesh(const DepthRef& depth, const PinholeCamera& camera, double max_jump,
                        const std::vector<char>& mask = {});

struct ScanlinePoints {
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> points;  ///< k×2 positions of the valid samples
  std::vector<std::int64_t> samples;  ///< k indices of those samples
  EdgeMatrix segments;                ///< #S×2 consecutive valid samples without a jump (rows of points)
};

/// The 2D case of §2.3: n distances d_i measured along the rays of a 1D camera at `center`
/// looking along `direction` with opening angle `opening_angle` (radians, in (0, π)). The image
/// line lies at h = 1 / (2 tan(α/2)) in front of the centre, sample i at relative position
/// x_i = (i + ½)/n on it: s_i = c + h v + (x_i − ½) v⊥ with v⊥ = (v_y, −v_x), and
/// p_i = c + d_i (s_i − c)/‖s_i − c‖. Samples with d_i not finite or <= 0 are skipped; neighbours
/// are joined by a segment unless |d_i − d_j| > max_jump · min(d_i, d_j).
/// \throw InputError if depths is empty, center or direction is not finite, direction is zero,
///        opening_angle is outside (0, π), or max_jump is negative or NaN.
ScanlinePoints scanline_to_points(const Eigen::Ref<const Eigen::VectorXd>& depths, const Eigen::Vector2d& center,
                                  const Eigen::Vector2d& direction, double opening_angle, double max_jump);

}  // namespace meshsmith::reconstruction
