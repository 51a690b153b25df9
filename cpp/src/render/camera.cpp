// Camera framing of the render chapter.
#include <meshsmith/core/errors.h>
#include <meshsmith/render/camera.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double degrees) { return degrees * kPi / 180.0; }

/// The world frame of an up axis: up, the direction the front view looks from, and screen right
/// in the front view (right = up × front, so the frame is right-handed). The front view looks from
/// +z for the x and y axes and from -y for the z axes (the CAD/scan convention), and a negative
/// axis turns the picture upside down about the front direction.
struct AxisFrame {
  Eigen::Vector3d up, front, right;
};

AxisFrame axis_frame(UpAxis axis) {
  AxisFrame frame;
  switch (axis) {
    case UpAxis::x: frame.up = {1, 0, 0}, frame.front = {0, 0, 1}; break;
    case UpAxis::y: frame.up = {0, 1, 0}, frame.front = {0, 0, 1}; break;
    case UpAxis::z: frame.up = {0, 0, 1}, frame.front = {0, -1, 0}; break;
    case UpAxis::minus_x: frame.up = {-1, 0, 0}, frame.front = {0, 0, 1}; break;
    case UpAxis::minus_y: frame.up = {0, -1, 0}, frame.front = {0, 0, 1}; break;
    case UpAxis::minus_z: frame.up = {0, 0, -1}, frame.front = {0, -1, 0}; break;
  }
  frame.right = frame.up.cross(frame.front);
  return frame;
}

/// Screen-right vector for an azimuth: horizontal, so it stays defined for top and bottom views.
Eigen::Vector3d right_direction(double azimuth_deg, UpAxis up) {
  const double a = radians(azimuth_deg);
  const AxisFrame frame = axis_frame(up);
  return std::cos(a) * frame.right - std::sin(a) * frame.front;
}

}  // namespace

UpAxis up_axis_from_name(const std::string& name) {
  if (name == "x" || name == "+x") return UpAxis::x;
  if (name == "y" || name == "+y") return UpAxis::y;
  if (name == "z" || name == "+z") return UpAxis::z;
  if (name == "-x") return UpAxis::minus_x;
  if (name == "-y") return UpAxis::minus_y;
  if (name == "-z") return UpAxis::minus_z;
  throw InputError("unknown up axis '" + name + "': use x, y, z, -x, -y or -z");
}

Eigen::Vector3d view_direction(double azimuth_deg, double elevation_deg, UpAxis up) {
  const double a = radians(azimuth_deg), e = radians(elevation_deg);
  const AxisFrame frame = axis_frame(up);
  return std::cos(e) * (std::sin(a) * frame.right + std::cos(a) * frame.front) + std::sin(e) * frame.up;
}

Camera frame_camera(const VertexRef& V, const FramingOptions& options) {
  if (V.rows() == 0) throw InputError("frame_camera: V is empty");
  if (!V.allFinite()) throw InputError("frame_camera: V holds a NaN or Inf");
  if (!(options.aspect > 0.0) || !std::isfinite(options.aspect))
    throw InputError("frame_camera: aspect must be > 0, got " + std::to_string(options.aspect));
  if (!(options.fov_y_deg > 0.0 && options.fov_y_deg < 180.0))
    throw InputError("frame_camera: fov_y_deg must be in (0, 180), got " +
                     std::to_string(options.fov_y_deg));
  if (!(options.margin >= 0.0 && options.margin < 0.45))
    throw InputError("frame_camera: margin must be in [0, 0.45), got " +
                     std::to_string(options.margin));
  if (!std::isfinite(options.azimuth_deg) || !std::isfinite(options.elevation_deg))
    throw InputError("frame_camera: azimuth and elevation must be finite");

  const Eigen::Vector3d towards_eye = view_direction(options.azimuth_deg, options.elevation_deg, options.up);
  const Eigen::Vector3d forward = -towards_eye;
  const Eigen::Vector3d right = right_direction(options.azimuth_deg, options.up);
  const Eigen::Vector3d screen_up = right.cross(forward).normalized();

  const Eigen::Vector3d low = V.colwise().minCoeff().transpose();
  const Eigen::Vector3d high = V.colwise().maxCoeff().transpose();
  const Eigen::Vector3d center = 0.5 * (low + high);
  double radius = 0.5 * (high - low).norm();
  if (!(radius > 0.0)) radius = 1.0;  // a single point: frame a unit neighbourhood

  Camera camera;
  camera.up = screen_up;
  camera.fov_y_deg = options.fov_y_deg;
  camera.orthographic = options.orthographic;
  const double usable = 1.0 - 2.0 * options.margin;
  const double inf = std::numeric_limits<double>::infinity();

  if (options.orthographic) {
    double x_low = inf, x_high = -inf, y_low = inf, y_high = -inf;
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      const Eigen::Vector3d p = V.row(i).transpose() - center;
      const double x = p.dot(right), y = p.dot(screen_up);
      x_low = std::min(x_low, x), x_high = std::max(x_high, x);
      y_low = std::min(y_low, y), y_high = std::max(y_high, y);
    }
    double height = std::max(y_high - y_low, (x_high - x_low) / options.aspect) / usable;
    if (!(height > 0.0)) height = 2.0 * radius;
    camera.target = center + 0.5 * (x_low + x_high) * right + 0.5 * (y_low + y_high) * screen_up;
    camera.ortho_height = height;
    camera.eye = camera.target - 3.0 * radius * forward;
    return camera;
  }

  // Perspective: a vertex (x, y, z) in the frame (right, up, forward) about the centre is inside
  // the frustum of an eye at centre + a*right + b*up - D*forward iff |x - a| <= tx (D + z) and
  // |y - b| <= ty (D + z). Over all vertices this gives D >= (max(x - tx z) - min(x + tx z)) / 2tx
  // and the centred a = (max(x - tx z) + min(x + tx z)) / 2, and the same for y.
  const double ty = std::tan(radians(options.fov_y_deg) / 2.0) * usable;
  const double tx = ty * options.aspect;
  double x_minus = -inf, x_plus = inf, y_minus = -inf, y_plus = inf, z_low = inf;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i).transpose() - center;
    const double x = p.dot(right), y = p.dot(screen_up), z = p.dot(forward);
    x_minus = std::max(x_minus, x - tx * z), x_plus = std::min(x_plus, x + tx * z);
    y_minus = std::max(y_minus, y - ty * z), y_plus = std::min(y_plus, y + ty * z);
    z_low = std::min(z_low, z);
  }
  double distance = std::max((x_minus - x_plus) / (2.0 * tx), (y_minus - y_plus) / (2.0 * ty));
  // Keep every vertex in front of the eye, and a sensible distance for a point-like mesh.
  distance = std::max({distance, -z_low + 1e-3 * radius, 1e-3 * radius});
  const double a = 0.5 * (x_minus + x_plus), b = 0.5 * (y_minus + y_plus);
  camera.target = center + a * right + b * screen_up;
  camera.eye = camera.target - distance * forward;
  camera.ortho_height = 2.0 * distance * std::tan(radians(options.fov_y_deg) / 2.0);
  return camera;
}

}  // namespace meshsmith::render
