#pragma once
/// \file camera.h
/// Cameras for the rasterizer (render chapter): a look-at camera with a perspective or
/// orthographic projection, and automatic framing of a mesh from a named direction.
#include <meshsmith/core/types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>

namespace meshsmith::render {

/// Which world axis points up in pictures ("y": OBJ/glTF convention, "z": CAD/scan convention;
/// x and the negative axes for the rest).
enum class UpAxis { x, y, z, minus_x, minus_y, minus_z };

/// The up axis called `name`: "x", "y", "z" (or "+x", ...), "-x", "-y", "-z".
/// \throw InputError for any other name.
UpAxis up_axis_from_name(const std::string& name);

/// A look-at camera. The image plane is perpendicular to (target - eye); `up` fixes the roll
/// and need not be orthogonal to the view direction, only not parallel to it.
struct Camera {
  Eigen::Vector3d eye{0.0, 0.0, 1.0};     ///< camera position
  Eigen::Vector3d target{0.0, 0.0, 0.0};  ///< point seen at the image centre
  Eigen::Vector3d up{0.0, 1.0, 0.0};      ///< approximate up direction on the screen
  double fov_y_deg = 30.0;                ///< vertical field of view (perspective), in (0, 180)
  bool orthographic = false;              ///< parallel projection instead of perspective
  double ortho_height = 2.0;              ///< world-space height of the view (orthographic only)
};

/// How frame_camera places the camera.
struct FramingOptions {
  double azimuth_deg = 35.0;    ///< rotation about the up axis; 0 looks at the front, 90 from the right
  double elevation_deg = 25.0;  ///< angle above the horizontal plane; 90 looks straight down
  UpAxis up = UpAxis::y;        ///< world up axis
  double aspect = 4.0 / 3.0;    ///< image width / height
  double fov_y_deg = 30.0;      ///< vertical field of view of the perspective camera
  bool orthographic = false;    ///< frame for a parallel projection
  double margin = 0.06;         ///< free border on the tight side, as a fraction of the image size
};

/// Unit vector from the target towards the eye for a view direction (azimuth, elevation).
/// With UpAxis::y the front view (0, 0) looks from +z, the right view (90, 0) from +x and the top
/// view (0, 90) from +y; with UpAxis::z the front view looks from -y and the top view from +z;
/// with UpAxis::x the front view looks from +z with +x up (screen right is -y). A negative axis
/// keeps its positive axis's front direction, upside down: the top view looks from the negative axis.
Eigen::Vector3d view_direction(double azimuth_deg, double elevation_deg, UpAxis up);

/// The camera that looks at the mesh vertices V (#V×3) from the direction of `options`
/// and frames them as tightly as `options.margin` allows: the perspective distance and the
/// lateral shift are solved exactly so that every vertex lies inside the view frustum and the
/// silhouette is centred (the orthographic height likewise). The returned camera's `up` is the
/// exact screen-up vector, so straight top and bottom views are well defined.
/// \pre V is non-empty and finite.
/// \throw InputError for empty or non-finite V, aspect <= 0, fov outside (0, 180) or margin
///        outside [0, 0.45).
Camera frame_camera(const VertexRef& V, const FramingOptions& options = {});

}  // namespace meshsmith::render
