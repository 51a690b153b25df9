// Depth images (§2.3). Pixels are visited in row-major order, so point indices are the ranks of
// the valid pixels; the mesh pass looks up each pixel's point through one h×w index image.
#include <meshsmith/reconstruction/depth_images.h>

#include <meshsmith/core/errors.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace meshsmith::reconstruction {

namespace {

void check_camera(const DepthRef& depth, const PinholeCamera& camera, const std::vector<char>& mask) {
  if (depth.rows() == 0 || depth.cols() == 0)
    throw InputError("depth has shape (" + std::to_string(depth.rows()) + ", " + std::to_string(depth.cols()) +
                     "): expected a non-empty h×w image");
  const auto nonzero_finite = [](double x) { return std::isfinite(x) && x != 0.0; };
  if (!nonzero_finite(camera.fx)) throw InputError("fx = " + number_text(camera.fx) + ": expected a nonzero focal length");
  if (!nonzero_finite(camera.fy)) throw InputError("fy = " + number_text(camera.fy) + ": expected a nonzero focal length");
  if (!std::isfinite(camera.cx)) throw InputError("cx = " + number_text(camera.cx) + ": expected a finite number");
  if (!std::isfinite(camera.cy)) throw InputError("cy = " + number_text(camera.cy) + ": expected a finite number");
  if (!(camera.depth_scale > 0.0) || !std::isfinite(camera.depth_scale))
    throw InputError("depth_scale = " + number_text(camera.depth_scale) + ": expected a positive finite number");
  if (!mask.empty() && static_cast<Eigen::Index>(mask.size()) != depth.size())
    throw InputError("mask has " + std::to_string(mask.size()) + " pixels for a depth image of " +
                     std::to_string(depth.rows()) + "×" + std::to_string(depth.cols()));
}

void check_jump(double max_jump) {
  if (!(max_jump >= 0.0))
    throw InputError("max_jump = " + number_text(max_jump) + ": expected a relative depth jump >= 0");
}

bool valid_depth(double d) { return std::isfinite(d) && d > 0.0; }

/// |a − b| <= max_jump · min(a, b) for positive depths a, b (+inf max_jump: always).
bool joined(double a, double b, double max_jump) { return std::abs(a - b) <= max_jump * std::min(a, b); }

}  // namespace

DepthPoints depth_to_points(const DepthRef& depth, const PinholeCamera& camera, const std::vector<char>& mask) {
  check_camera(depth, camera, mask);
  const Eigen::Index h = depth.rows(), w = depth.cols();
  Eigen::Index count = 0;
  for (Eigen::Index k = 0; k < h * w; ++k)
    if (valid_depth(depth.data()[k]) && (mask.empty() || mask[std::size_t(k)])) ++count;
  DepthPoints out;
  out.points.resize(count, 3);
  out.pixels.resize(count, 2);
  Eigen::Index n = 0;
  for (Eigen::Index v = 0; v < h; ++v)
    for (Eigen::Index u = 0; u < w; ++u) {
      const Eigen::Index k = v * w + u;
      const double d = depth(v, u);
      if (!valid_depth(d) || (!mask.empty() && !mask[std::size_t(k)])) continue;
      const double z = d / camera.depth_scale;
      out.points.row(n) << (double(u) - camera.cx) * z / camera.fx, (double(v) - camera.cy) * z / camera.fy, z;
      out.pixels.row(n) << v, u;
      ++n;
    }
  if (!out.points.allFinite())
    throw InputError("depth_to_points: a back-projected point leaves the double range (depth / depth_scale too large)");
  return out;
}

DepthMesh depth_to_mesh(const DepthRef& depth, const PinholeCamera& camera, double max_jump,
                        const std::vector<char>& mask) {
  check_jump(max_jump);
  DepthPoints points = depth_to_points(depth, camera, mask);
  const Eigen::Index h = depth.rows(), w = depth.cols();
  std::vector<int> vertex(std::size_t(h * w), -1);
  for (Eigen::Index i = 0; i < points.pixels.rows(); ++i)
    vertex[std::size_t(points.pixels(i, 0) * w + points.pixels(i, 1))] = int(i);
  std::vector<Eigen::Vector3i> faces;
  const auto z = [&](int i) { return points.points(i, 2); };
  const auto add = [&](int a, int b, int c) {
    if (a < 0 || b < 0 || c < 0) return;
    if (joined(z(a), z(b), max_jump) && joined(z(b), z(c), max_jump) && joined(z(c), z(a), max_jump))
      faces.emplace_back(a, b, c);
  };
  for (Eigen::Index v = 0; v + 1 < h; ++v)
    for (Eigen::Index u = 0; u + 1 < w; ++u) {
      // a b   (row v)      orientation: a → c → d is clockwise in the image (y down), so the
      // c d   (row v + 1)  normal of the back-projected triangle faces the camera (−z).
      const int a = vertex[std::size_t(v * w + u)], b = vertex[std::size_t(v * w + u + 1)];
      const int c = vertex[std::size_t((v + 1) * w + u)], d = vertex[std::size_t((v + 1) * w + u + 1)];
      const int valid = (a >= 0) + (b >= 0) + (c >= 0) + (d >= 0);
      if (valid < 3) continue;
      if (valid == 4) {
        if (std::abs(z(a) - z(d)) <= std::abs(z(b) - z(c))) {
          add(a, c, d);
          add(a, d, b);
        } else {
          add(a, c, b);
          add(b, c, d);
        }
      } else if (a < 0) {
        add(b, c, d);
      } else if (b < 0) {
        add(a, c, d);
      } else if (c < 0) {
        add(a, d, b);
      } else {
        add(a, c, b);
      }
    }
  DepthMesh mesh;
  mesh.V = std::move(points.points);
  mesh.pixels = std::move(points.pixels);
  mesh.F.resize(Eigen::Index(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) mesh.F.row(Eigen::Index(f)) = faces[f].transpose();
  return mesh;
}

ScanlinePoints scanline_to_points(const Eigen::Ref<const Eigen::VectorXd>& depths, const Eigen::Vector2d& center,
                                  const Eigen::Vector2d& direction, double opening_angle, double max_jump) {
  const Eigen::Index n = depths.size();
  if (n == 0) throw InputError("depths is empty: expected at least one sample");
  if (!center.allFinite()) throw InputError("center: expected finite coordinates");
  const double length = direction.norm();
  if (!direction.allFinite() || !(length > 0.0) || !std::isfinite(length))
    throw InputError("direction: expected a finite nonzero vector");
  if (!(opening_angle > 0.0 && opening_angle < M_PI))
    throw InputError("opening_angle = " + number_text(opening_angle) + ": expected radians in (0, pi)");
  check_jump(max_jump);
  const Eigen::Vector2d v = direction / length, v_perp(v.y(), -v.x());
  const double h = 0.5 / std::tan(0.5 * opening_angle);
  ScanlinePoints out;
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2i> segments;
  Eigen::Index previous = -1;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = depths(i);
    if (!valid_depth(d)) {
      previous = -1;
      continue;
    }
    const double x = (double(i) + 0.5) / double(n);
    const Eigen::Vector2d ray = h * v + (x - 0.5) * v_perp;  // s_i − c
    points.push_back(center + d * ray / ray.norm());
    out.samples.push_back(i);
    if (previous >= 0 && joined(depths(previous), d, max_jump))
      segments.emplace_back(int(points.size()) - 2, int(points.size()) - 1);
    previous = i;
  }
  out.points.resize(Eigen::Index(points.size()), 2);
  for (std::size_t k = 0; k < points.size(); ++k) out.points.row(Eigen::Index(k)) = points[k].transpose();
  out.segments.resize(Eigen::Index(segments.size()), 2);
  for (std::size_t k = 0; k < segments.size(); ++k) out.segments.row(Eigen::Index(k)) = segments[k].transpose();
  if (!out.points.allFinite()) throw InputError("scanline_to_points: a point leaves the double range");
  return out;
}

}  // namespace meshsmith::reconstruction
