#pragma once
/// \file rasterizer.h
/// A software z-buffer rasterizer that draws shaded pictures of triangle meshes: smooth
/// (interpolated angle-weighted normals, split at creases) or flat shading with a key, a fill and a rim light over a hemisphere
/// ambient term, back faces in their own tint so holes show, an optional per-vertex scalar
/// field through a colormap, an optional checkerboard through texture coordinates and an
/// optional wireframe drawn in the fragment stage from the distance to the triangle's edges.
/// Anti-aliased by supersampling (an ss×ss grid of samples per pixel, averaged in linear light).
///
/// It works in two passes over a supersampled image: a visibility pass that bins triangles into
/// horizontal strips and rasterizes each strip (in parallel, each strip in triangle order, so
/// the result does not depend on the number of threads), then a shading pass that lights each
/// triangle once per pixel (as multisampling does) and evaluates colour and wireframe per sample,
/// with perspective-correct interpolation of normals, scalars and UVs.
#include <meshsmith/core/types.h>
#include <meshsmith/render/camera.h>
#include <meshsmith/render/colormap.h>

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace meshsmith::render {

/// #V×2 (per vertex) or 3#F×2 (per corner, row 3f+k is corner k of face f) texture coordinates.
using UvMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// What to draw and how. Colours are sRGB in [0, 1].
struct RenderOptions {
  int width = 800;                 ///< output image width in pixels, >= 1
  int height = 600;                ///< output image height in pixels, >= 1
  int supersample = 3;             ///< samples per pixel along each axis, 1..4
  bool smooth_shading = true;      ///< interpolate vertex normals (false: one normal per face)
  /// Smooth shading keeps edges whose dihedral angle exceeds this crisp (per-corner normals
  /// average only the faces around the vertex within this angle); >= 180: smooth everywhere.
  double crease_angle_deg = 60.0;
  bool lighting = true;            ///< false: unlit colours (albedo only), e.g. for UV layouts
  Eigen::Vector3d front_color{0.60, 0.68, 0.80};  ///< material of front faces (soft gray-blue)
  Eigen::Vector3d back_color{0.88, 0.56, 0.42};   ///< material of back faces (warm, shows holes)

  bool wireframe = false;          ///< draw triangle edges
  double wireframe_width = 1.0;    ///< line width in output pixels, > 0
  Eigen::Vector3d wireframe_color{0.10, 0.11, 0.14};
  double wireframe_opacity = 0.75; ///< in [0, 1]; lines of triangles under ~7 pixels high fade
  /// Which edges the wireframe draws: #F masks, bit k set to draw the edge opposite vertex k of
  /// face f (a quad mesh split into triangles hides its diagonals); empty: every edge.
  std::vector<std::uint8_t> wireframe_edges;

  Eigen::Vector3d background_top{1.0, 1.0, 1.0};      ///< vertical gradient, top row
  Eigen::Vector3d background_bottom{0.88, 0.90, 0.94}; ///< bottom row
  bool transparent_background = false;  ///< alpha = coverage, colours not blended with the background

  /// Per-vertex scalar field (#V, or empty for none), coloured through `colormap` with
  /// [scalar_min, scalar_max] mapped onto the colormap's ends (values outside are clamped).
  Eigen::VectorXd scalar;
  double scalar_min = 0.0;
  double scalar_max = 1.0;
  Colormap colormap = Colormap::viridis;

  /// Texture coordinates (empty for none) shown as a checkerboard of squares of side
  /// `checker_size` in UV units; with a scalar field the checker darkens the colormap.
  UvMatrix uv;
  bool uv_per_corner = false;      ///< uv rows are corners (3#F) instead of vertices (#V)
  double checker_size = 0.0;       ///< > 0, or 0 for an eighth of the larger UV extent
  Eigen::Vector3d checker_light{0.95, 0.95, 0.93};
  Eigen::Vector3d checker_dark{0.36, 0.42, 0.54};
};

/// An 8-bit RGBA image, row-major: pixel (row, column) channel c at pixels[(row*width+column)*4+c].
/// With an opaque background alpha is 255 everywhere.
struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};

/// \throw InputError unless `values` holds one finite value per vertex (vertex_count of them);
/// the message names the first NaN/Inf.
void validate_vertex_scalar(const Eigen::VectorXd& values, Eigen::Index vertex_count);

/// The range that colours a scalar field well: the lower and upper percentiles (numpy's default
/// linear interpolation between order statistics), so a few outliers do not wash out the
/// colours. With `symmetric_about_zero` and a range that contains 0, the range becomes [-m, m],
/// m = max(|low|, |high|), so zero sits at the centre of a diverging colormap. When the
/// percentiles coincide the range is [min, max]; a constant field c gets [c - d, c + d] with
/// d = 0.1|c| (1 if c = 0), so the range is never empty.
/// \pre values is non-empty and finite (validate_vertex_scalar).
/// \throw InputError for empty values or percentiles outside 0 <= lower <= upper <= 100.
std::pair<double, double> robust_scalar_range(const Eigen::VectorXd& values,
                                              bool symmetric_about_zero,
                                              double lower_percentile = 2.0,
                                              double upper_percentile = 98.0);

/// The largest width or height of a rendered picture, in pixels (before supersampling).
constexpr int kMaxImageSide = 16384;

/// Renders the triangle mesh (V #V×3, F #F×3) seen through `camera`.
/// Triangles with a vertex behind the camera's near plane (closer than 1e-6 of the eye-target
/// distance) are not drawn; auto-framed cameras (frame_camera) never produce such triangles.
/// Smooth-shading normals are angle-weighted averages of face normals, split at creases.
/// \pre validate_mesh(V, F) passes.
/// \throw InputError for an invalid mesh, a size outside [1, 16384] or more than 2^25 samples,
///        supersample outside 1..4, a degenerate camera (eye == target, up parallel to the view,
///        fov outside (0, 180), ortho_height <= 0), a scalar of the wrong length or with a
///        NaN/Inf, scalar_min > scalar_max, UVs of the wrong size or non-finite, checker_size < 0,
///        wireframe_width <= 0, crease_angle_deg < 0. Messages name the offending element.
RgbaImage render_mesh(const VertexRef& V, const FaceRef& F, const Camera& camera,
                      const RenderOptions& options = {});

}  // namespace meshsmith::render
