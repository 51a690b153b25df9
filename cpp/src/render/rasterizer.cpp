// The z-buffer rasterizer of the render chapter (see rasterizer.h for the two-pass design).
#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/render/rasterizer.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kStripRows = 16;                    // supersampled rows per visibility strip
constexpr std::int64_t kMaxSamples = 1LL << 25;  // 32M samples = 256 MB of depth and ids

// ---- colour space -------------------------------------------------------------------------

double srgb_to_linear(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

Eigen::Vector3d srgb_to_linear(const Eigen::Vector3d& c) {
  return {srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2])};
}

/// 8-bit sRGB encoding of linear values through a table (4096 steps are finer than 8 bits).
class SrgbEncoder {
 public:
  SrgbEncoder() {
    for (int i = 0; i < kSize; ++i) {
      const double c = static_cast<double>(i) / (kSize - 1);
      const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
      table_[i] = static_cast<std::uint8_t>(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
    }
  }
  std::uint8_t operator()(double linear) const {
    const double c = std::clamp(linear, 0.0, 1.0);
    return table_[static_cast<int>(c * (kSize - 1) + 0.5)];
  }

 private:
  static constexpr int kSize = 4096;
  std::array<std::uint8_t, kSize> table_{};
};

/// floor(value) clamped to [low, high] before the conversion (screen coordinates of triangles
/// near the camera can be far outside the int range).
int pixel_index(double value, int low, int high) {
  return static_cast<int>(std::clamp(std::floor(value), static_cast<double>(low), static_cast<double>(high)));
}

// ---- geometry -------------------------------------------------------------------------------

/// #F·3 by 3 (row 3f+k: corner k of face f) unit normals for smooth shading: at each corner the
/// angle-weighted average (Thürmer & Wüthrich 1998) of the normals of the faces around the
/// corner's vertex that make a dihedral angle of at most `crease_angle_deg` with the corner's
/// face, so sharp edges stay crisp; with 180 degrees these are the plain angle-weighted vertex
/// normals. Zero rows for degenerate faces (the shader then uses the face normal). Private to
/// the renderer until the geometry chapter provides vertex normals.
using CornerNormals = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
CornerNormals crease_aware_corner_normals(const VertexRef& V, const FaceRef& F,
                                          double crease_angle_deg) {
  const Eigen::Index faces = F.rows();
  // Unit face normals and corner angles, per face in parallel.
  VertexMatrix face_normal(faces, 3);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> corner_angle(faces, 3);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, faces, 8192),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index f = range.begin(); f != range.end(); ++f) {
      const std::array<Eigen::Vector3d, 3> p{V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(),
                                             V.row(F(f, 2)).transpose()};
      const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]);
      const double twice_area = normal.norm();
      if (!(twice_area > 0.0)) {
        face_normal.row(f).setZero();
        corner_angle.row(f).setZero();
        continue;
      }
      face_normal.row(f) = normal.transpose() / twice_area;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
        corner_angle(f, k) = std::atan2(twice_area, a.dot(b));  // |a x b| is 2A at every corner
      }
    }
  });
  // The corners around each vertex, in face order (so sums are deterministic).
  std::vector<std::int64_t> start(V.rows() + 1, 0);
  for (Eigen::Index f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) ++start[F(f, k) + 1];
  for (Eigen::Index v = 0; v < V.rows(); ++v) start[v + 1] += start[v];
  std::vector<std::int64_t> corners(start.back());
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (Eigen::Index f = 0; f < faces; ++f)
      for (int k = 0; k < 3; ++k) corners[fill[F(f, k)]++] = 3 * f + k;
  }
  const double cos_crease = crease_angle_deg >= 180.0 ? -2.0 : std::cos(crease_angle_deg * kPi / 180.0);
  // Per vertex, in parallel: each corner around it sums the faces around it within the crease
  // angle (each corner belongs to exactly one vertex, so the writes never collide).
  CornerNormals normals(3 * faces, 3);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, V.rows(), 4096),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    std::vector<Eigen::Vector3d> around;  // angle-weighted normals of the faces around v
    std::vector<Eigen::Vector3d> unit;    // their unit normals
    for (Eigen::Index v = range.begin(); v != range.end(); ++v) {
      const std::int64_t first = start[v], count = start[v + 1] - first;
      around.resize(count);
      unit.resize(count);
      Eigen::Vector3d total = Eigen::Vector3d::Zero();
      for (std::int64_t i = 0; i < count; ++i) {
        const std::int64_t corner = corners[first + i];
        unit[i] = face_normal.row(corner / 3).transpose();
        around[i] = corner_angle(corner / 3, corner % 3) * unit[i];
        total += around[i];
      }
      for (std::int64_t i = 0; i < count; ++i) {
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        if (cos_crease < -1.0) {
          sum = total;
        } else {
          for (std::int64_t j = 0; j < count; ++j)
            if (unit[j].dot(unit[i]) >= cos_crease) sum += around[j];
        }
        const double length = sum.norm();
        if (length > 0.0 && unit[i].squaredNorm() > 0.0)
          normals.row(corners[first + i]) = (sum / length).cast<float>().transpose();
        else
          normals.row(corners[first + i]).setZero();
      }
    }
  });
  return normals;
}

/// A projected vertex, kept to 16 bytes because triangles read them in random order (the
/// edge functions are evaluated in double from these values, identically for both triangles of
/// an edge, so single precision costs no watertightness).
struct ScreenVertex {
  float x = 0.0f, y = 0.0f;  // supersampled pixel coordinates, y down
  float depth = 0.0f;        // larger is closer: 1/z (perspective) or -z (orthographic)
  float inverse_z = 0.0f;    // 1/z for perspective-correct interpolation (1 when orthographic);
                             // 0 for a vertex behind the near plane, which is not drawable
  bool drawable() const { return inverse_z > 0.0f; }
};

/// The camera frame: right, up, forward (unit, orthogonal).
struct CameraFrame {
  Eigen::Vector3d right, up, forward;
};

CameraFrame camera_frame(const Camera& camera) {
  if (!camera.eye.allFinite() || !camera.target.allFinite() || !camera.up.allFinite())
    throw InputError("render: camera eye, target and up must be finite");
  const Eigen::Vector3d view = camera.target - camera.eye;
  if (!(view.norm() > 0.0)) throw InputError("render: camera eye and target coincide");
  CameraFrame frame;
  frame.forward = view.normalized();
  const Eigen::Vector3d right = frame.forward.cross(camera.up);
  if (!(right.norm() > 1e-9 * camera.up.norm()) || !(camera.up.norm() > 0.0))
    throw InputError("render: camera up vector is zero or parallel to the view direction");
  frame.right = right.normalized();
  frame.up = frame.right.cross(frame.forward);
  if (camera.orthographic) {
    if (!(camera.ortho_height > 0.0) || !std::isfinite(camera.ortho_height))
      throw InputError("render: orthographic camera needs ortho_height > 0, got " +
                       std::to_string(camera.ortho_height));
  } else if (!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0)) {
    throw InputError("render: camera fov_y_deg must be in (0, 180), got " +
                     std::to_string(camera.fov_y_deg));
  }
  return frame;
}

/// The signed edge function of the directed edge p → q at (x, y), evaluated with the edge's
/// endpoints in a canonical order (lower vertex index first) so that two triangles sharing an
/// edge get exactly opposite values and no sample on the edge falls through a crack.
struct Edge {
  double px, py, dx, dy, sign;
  double operator()(double x, double y) const { return sign * (dx * (y - py) - dy * (x - px)); }
  double length() const { return std::hypot(dx, dy); }
};

Edge make_edge(int i, int j, const ScreenVertex& a, const ScreenVertex& b) {
  if (i <= j) return {a.x, a.y, b.x - a.x, b.y - a.y, 1.0};
  return {b.x, b.y, a.x - b.x, a.y - b.y, -1.0};
}

/// Per-triangle set-up shared by the visibility and shading passes.
struct TriangleSetup {
  std::array<const ScreenVertex*, 3> vertex;
  std::array<Edge, 3> edge;  // edge[k] is opposite vertex k; edge[k](x, y) / area2 = barycentric k
  double area2 = 0.0;        // twice the signed screen area; negative for front faces (y down)

  TriangleSetup(const std::vector<ScreenVertex>& screen, const FaceRef& F, int face) {
    const int i0 = F(face, 0), i1 = F(face, 1), i2 = F(face, 2);
    vertex = {&screen[i0], &screen[i1], &screen[i2]};
    edge[0] = make_edge(i1, i2, *vertex[1], *vertex[2]);
    edge[1] = make_edge(i2, i0, *vertex[2], *vertex[0]);
    edge[2] = make_edge(i0, i1, *vertex[0], *vertex[1]);
    const ScreenVertex &a = *vertex[0], &b = *vertex[1], &c = *vertex[2];
    area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  }
  bool front() const { return area2 < 0.0; }
  /// Screen bounding box {x_low, x_high, y_low, y_high}.
  std::array<double, 4> bounds() const {
    const ScreenVertex &a = *vertex[0], &b = *vertex[1], &c = *vertex[2];
    return {std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}),
            std::max({a.y, b.y, c.y})};
  }
  bool drawable() const {
    return vertex[0]->drawable() && vertex[1]->drawable() && vertex[2]->drawable() && area2 != 0.0 &&
           std::isfinite(area2);
  }
};

// ---- shading --------------------------------------------------------------------------------

struct Light {
  Eigen::Vector3d direction;  // camera space (x right, y up, z towards the viewer), unit
  double intensity;
};

class Shader {
 public:
  Shader(const VertexRef& V, const FaceRef& F, const CameraFrame& frame,
         const RenderOptions& options)
      : V_(V), F_(F), frame_(frame), options_(options) {
    if (options.smooth_shading)
      corner_normals_ = crease_aware_corner_normals(V, F, options.crease_angle_deg);
    front_ = srgb_to_linear(options.front_color);
    back_ = srgb_to_linear(options.back_color);
    wire_ = srgb_to_linear(options.wireframe_color);
    checker_light_ = srgb_to_linear(options.checker_light);
    checker_dark_ = srgb_to_linear(options.checker_dark);
    if (options.scalar.size() > 0) {
      for (int i = 0; i < kColormapSteps; ++i)
        colormap_[i] = srgb_to_linear(
            colormap_color(options.colormap, static_cast<double>(i) / (kColormapSteps - 1)));
      const double span = options.scalar_max - options.scalar_min;
      scalar_scale_ = span > 0.0 ? 1.0 / span : 0.0;
    }
    lights_ = {Light{Eigen::Vector3d(-0.50, 0.65, 0.58).normalized(), 0.80},   // key: upper left
               Light{Eigen::Vector3d(0.80, -0.15, 0.45).normalized(), 0.20},   // fill: right
               Light{Eigen::Vector3d(0.20, 0.40, -0.90).normalized(), 0.25}};  // rim: behind
    halfway_ = (lights_[0].direction + Eigen::Vector3d::UnitZ()).normalized();
    has_attribute_ = options.scalar.size() > 0 || options.uv.rows() > 0;
    wire_half_width_ = 0.5 * options.wireframe_width * options.supersample;
  }

  /// Screen-space edge values and perspective-correct barycentric weights of sample (x, y).
  struct SampleWeights {
    std::array<double, 3> edge_value;
    std::array<double, 3> weight;
  };
  SampleWeights weights(const TriangleSetup& triangle, double x, double y) const {
    SampleWeights w;
    double total = 0.0;
    for (int k = 0; k < 3; ++k) {
      w.edge_value[k] = triangle.edge[k](x, y);
      const double screen_weight = std::max(0.0, w.edge_value[k] / triangle.area2);
      w.weight[k] = screen_weight * triangle.vertex[k]->inverse_z;  // perspective-correct
      total += w.weight[k];
    }
    if (total > 0.0) {
      for (double& v : w.weight) v /= total;
    } else {
      w.weight = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
    }
    return w;
  }

  /// The light a surface point receives: albedo * diffuse + specular (white).
  struct Lighting {
    double diffuse = 1.0;
    double specular = 0.0;
  };

  /// Lighting at the sample (the expensive part of shading: shared by the samples of a pixel
  /// that see the same triangle, as in multisample anti-aliasing).
  Lighting lighting(const TriangleSetup& triangle, int face, const SampleWeights& w) const {
    if (!options_.lighting) return {};
    const std::array<int, 3> index{F_(face, 0), F_(face, 1), F_(face, 2)};
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    if (options_.smooth_shading)
      for (int k = 0; k < 3; ++k)
        normal += w.weight[k] * corner_normals_.row(3 * static_cast<Eigen::Index>(face) + k).transpose().cast<double>();
    if (!(normal.squaredNorm() > 1e-12)) {
      const Eigen::Vector3d p0 = V_.row(index[0]), p1 = V_.row(index[1]), p2 = V_.row(index[2]);
      normal = (p1 - p0).cross(p2 - p0);
    }
    Eigen::Vector3d n(normal.dot(frame_.right), normal.dot(frame_.up), -normal.dot(frame_.forward));
    n.normalize();
    if (!triangle.front()) n = -n;
    Lighting light;
    light.diffuse = kAmbientGround + (kAmbientSky - kAmbientGround) * (0.5 + 0.5 * n.y());
    for (const Light& source : lights_)
      light.diffuse += source.intensity * std::max(0.0, n.dot(source.direction));
    const double highlight = std::max(0.0, n.dot(halfway_));
    const double h2 = highlight * highlight, h4 = h2 * h2, h8 = h4 * h4, h16 = h8 * h8;
    light.specular = specular_ * h16 * h16 * h8;  // Blinn-Phong, exponent 40
    return light;
  }

  /// Linear RGB of the sample: material (or scalar / checker colour) under `light`, then the
  /// wireframe line over it.
  Eigen::Vector3d color(const TriangleSetup& triangle, int face, const SampleWeights& w,
                        const Lighting& light) const {
    const bool front = triangle.front();
    Eigen::Vector3d albedo = front ? front_ : back_;
    if (has_attribute_) {
      Eigen::Vector3d attribute = Eigen::Vector3d::Ones();
      if (options_.scalar.size() > 0) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) s += w.weight[k] * options_.scalar[F_(face, k)];
        const double t = std::clamp((s - options_.scalar_min) * scalar_scale_, 0.0, 1.0);
        attribute = scalar_scale_ > 0.0 ? colormap_[static_cast<int>(t * (kColormapSteps - 1) + 0.5)]
                                        : colormap_[kColormapSteps / 2];
      }
      if (options_.uv.rows() > 0) {
        double u = 0.0, v = 0.0;
        for (int k = 0; k < 3; ++k) {
          const Eigen::Index row = options_.uv_per_corner ? 3 * static_cast<Eigen::Index>(face) + k
                                                          : F_(face, k);
          u += w.weight[k] * options_.uv(row, 0);
          v += w.weight[k] * options_.uv(row, 1);
        }
        const long parity = static_cast<long>(std::floor(u / options_.checker_size)) +
                            static_cast<long>(std::floor(v / options_.checker_size));
        const bool dark = (parity & 1L) != 0;
        if (options_.scalar.size() > 0)
          attribute *= dark ? 0.62 : 1.0;
        else
          attribute = dark ? checker_dark_ : checker_light_;
      }
      albedo = front ? attribute : (0.4 * attribute + 0.6 * back_).eval();
    }
    Eigen::Vector3d result = albedo * light.diffuse + Eigen::Vector3d::Constant(
        has_attribute_ ? 0.4 * light.specular : light.specular);

    if (options_.wireframe) {
      double distance = std::numeric_limits<double>::infinity(), longest = 0.0;
      const unsigned drawn = options_.wireframe_edges.empty() ? 7u : options_.wireframe_edges[face];
      for (int k = 0; k < 3; ++k) {
        const double length = triangle.edge[k].length();
        longest = std::max(longest, length);
        if (length > 0.0 && (drawn >> k & 1u)) distance = std::min(distance, std::abs(w.edge_value[k]) / length);
      }
      const double coverage = std::clamp(wire_half_width_ + 0.5 - distance, 0.0, 1.0);
      // Lines of triangles only a few pixels high fade, so dense meshes do not turn black.
      const double altitude = longest > 0.0 ? std::abs(triangle.area2) / longest / options_.supersample : 0.0;
      const double fade = std::clamp(altitude / kWireFadeAltitude, kWireMinimumFade, 1.0);
      const double alpha = coverage * options_.wireframe_opacity * fade;
      result = (1.0 - alpha) * result + alpha * wire_;
    }
    return result;
  }

 private:
  static constexpr int kColormapSteps = 1024;
  static constexpr double kAmbientGround = 0.05, kAmbientSky = 0.16, kSpecular = 0.18;
  static constexpr double kWireFadeAltitude = 7.0, kWireMinimumFade = 0.35;  // output pixels
  const VertexRef& V_;
  const FaceRef& F_;
  CameraFrame frame_;
  const RenderOptions& options_;
  CornerNormals corner_normals_;
  Eigen::Vector3d front_, back_, wire_, checker_light_, checker_dark_, halfway_;
  std::array<Eigen::Vector3d, kColormapSteps> colormap_;
  std::array<Light, 3> lights_;
  double scalar_scale_ = 0.0;
  double wire_half_width_ = 0.5;
  double specular_ = kSpecular;
  bool has_attribute_ = false;
};

// ---- validation -----------------------------------------------------------------------------

void validate_options(const VertexRef& V, const FaceRef& F, const RenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > kMaxImageSide || options.height > kMaxImageSide)
    throw InputError("render: image size must be in [1, " + std::to_string(kMaxImageSide) + "], got " +
                     std::to_string(options.width) + "x" + std::to_string(options.height));
  if (options.supersample < 1 || options.supersample > 4)
    throw InputError("render: supersample must be 1, 2, 3 or 4, got " +
                     std::to_string(options.supersample));
  const std::int64_t samples = static_cast<std::int64_t>(options.width) * options.height *
                               options.supersample * options.supersample;
  if (samples > kMaxSamples)
    throw InputError("render: " + std::to_string(samples) +
                     " samples (width*height*supersample^2) exceed the limit of " +
                     std::to_string(kMaxSamples) + "; lower the size or the supersampling");
  if (!(options.crease_angle_deg >= 0.0) || !std::isfinite(options.crease_angle_deg))
    throw InputError("render: crease_angle_deg must be >= 0 (180 or more: smooth everywhere)");
  if (!(options.wireframe_width > 0.0) || !std::isfinite(options.wireframe_width))
    throw InputError("render: wireframe_width must be > 0");
  if (!(options.wireframe_opacity >= 0.0 && options.wireframe_opacity <= 1.0))
    throw InputError("render: wireframe_opacity must be in [0, 1]");
  if (!options.wireframe_edges.empty() && static_cast<Eigen::Index>(options.wireframe_edges.size()) != F.rows())
    throw InputError("render: wireframe_edges has " + std::to_string(options.wireframe_edges.size()) +
                     " masks for " + std::to_string(F.rows()) + " faces");
  const std::array<const Eigen::Vector3d*, 7> colors{
      &options.front_color, &options.back_color, &options.wireframe_color,
      &options.background_top, &options.background_bottom, &options.checker_light,
      &options.checker_dark};
  for (const Eigen::Vector3d* color : colors)
    if (!color->allFinite()) throw InputError("render: colours must be finite");

  if (options.scalar.size() > 0) {
    validate_vertex_scalar(options.scalar, V.rows());
    if (!std::isfinite(options.scalar_min) || !std::isfinite(options.scalar_max) ||
        options.scalar_min > options.scalar_max)
      throw InputError("render: scalar range must be finite with min <= max, got [" +
                       std::to_string(options.scalar_min) + ", " +
                       std::to_string(options.scalar_max) + "]");
  }
  if (options.uv.rows() > 0) {
    const Eigen::Index expected = options.uv_per_corner ? 3 * F.rows() : V.rows();
    if (options.uv.rows() != expected)
      throw InputError("render: uv has " + std::to_string(options.uv.rows()) + " rows but " +
                       std::to_string(expected) +
                       (options.uv_per_corner ? " (3 per face) were expected for per-corner UVs"
                                              : " (one per vertex) were expected"));
    for (Eigen::Index i = 0; i < options.uv.rows(); ++i)
      if (!options.uv.row(i).allFinite())
        throw InputError("render: uv row " + std::to_string(i) + " holds a NaN or Inf");
    if (!(options.checker_size >= 0.0) || !std::isfinite(options.checker_size))
      throw InputError("render: checker_size must be > 0 (or 0 for automatic), got " +
                       std::to_string(options.checker_size));
  }
}

}  // namespace

void validate_vertex_scalar(const Eigen::VectorXd& values, Eigen::Index vertex_count) {
  if (values.size() != vertex_count)
    throw InputError("scalar has " + std::to_string(values.size()) + " values but the mesh has " +
                     std::to_string(vertex_count) + " vertices (one value per vertex expected)");
  for (Eigen::Index i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw InputError("scalar[" + std::to_string(i) + "] is " +
                       (std::isnan(values[i]) ? "NaN" : "infinite") + ": values must be finite");
}

std::pair<double, double> robust_scalar_range(const Eigen::VectorXd& values,
                                              bool symmetric_about_zero,
                                              double lower_percentile, double upper_percentile) {
  if (values.size() == 0) throw InputError("scalar range of an empty field");
  if (!(lower_percentile >= 0.0 && lower_percentile <= upper_percentile && upper_percentile <= 100.0))
    throw InputError("percentiles must satisfy 0 <= lower <= upper <= 100");
  std::vector<double> sorted(values.data(), values.data() + values.size());
  auto percentile = [&](double p) {
    const double position = p / 100.0 * static_cast<double>(sorted.size() - 1);
    const std::size_t below = static_cast<std::size_t>(std::floor(position));
    const std::size_t above = std::min(below + 1, sorted.size() - 1);
    std::nth_element(sorted.begin(), sorted.begin() + below, sorted.end());
    const double low = sorted[below];
    const double high = above == below ? low : *std::min_element(sorted.begin() + below + 1, sorted.end());
    return low + (position - below) * (high - low);
  };
  double low = percentile(lower_percentile), high = percentile(upper_percentile);
  if (!(high > low)) {  // the percentiles coincide (e.g. valences, mostly 6): use the extremes
    low = *std::min_element(sorted.begin(), sorted.end());
    high = *std::max_element(sorted.begin(), sorted.end());
  }
  if (!(high > low)) {  // a constant field: a small range around it, shown in the middle colour
    const double half = low == 0.0 ? 1.0 : 0.1 * std::abs(low);
    low -= half, high += half;
  }
  if (symmetric_about_zero && low < 0.0 && high > 0.0) {
    const double m = std::max(-low, high);
    low = -m, high = m;
  }
  return {low, high};
}

RgbaImage render_mesh(const VertexRef& V, const FaceRef& F, const Camera& camera,
                      const RenderOptions& options) {
  validate_mesh(V, F);
  validate_options(V, F, options);
  const CameraFrame frame = camera_frame(camera);
  RenderOptions resolved;  // only the automatic checker size needs resolving
  const RenderOptions* effective = &options;
  if (options.uv.rows() > 0 && options.checker_size == 0.0) {
    resolved = options;
    const double extent = (options.uv.colwise().maxCoeff() - options.uv.colwise().minCoeff()).maxCoeff();
    resolved.checker_size = extent > 0.0 ? extent / 8.0 : 1.0;
    effective = &resolved;
  }

  const int ss = options.supersample;
  const int width = options.width * ss, height = options.height * ss;

  // Project the vertices onto the supersampled screen.
  std::vector<ScreenVertex> screen(V.rows());
  const double distance = (camera.target - camera.eye).norm();
  const double near = 1e-6 * distance;
  const double focal = camera.orthographic
                           ? height / camera.ortho_height
                           : 0.5 * height / std::tan(camera.fov_y_deg * kPi / 360.0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, V.rows(), 4096),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index i = range.begin(); i != range.end(); ++i) {
      const Eigen::Vector3d p = V.row(i).transpose() - camera.eye;
      const double x = p.dot(frame.right), y = p.dot(frame.up), z = p.dot(frame.forward);
      ScreenVertex& s = screen[i];
      if (camera.orthographic) {
        s = {static_cast<float>(0.5 * width + focal * x), static_cast<float>(0.5 * height - focal * y),
             static_cast<float>(-z), 1.0f};
      } else if (z > near) {
        const double w = 1.0 / z;
        s = {static_cast<float>(0.5 * width + focal * x * w),
             static_cast<float>(0.5 * height - focal * y * w), static_cast<float>(w),
             static_cast<float>(w)};
        if (!std::isfinite(s.x) || !std::isfinite(s.y) || !(s.inverse_z > 0.0f)) s = ScreenVertex{};
      }
    }
  });

  // Bin the triangles into strips of rows (in face order, so strips draw deterministically).
  const int strips = (height + kStripRows - 1) / kStripRows;
  std::vector<std::int64_t> strip_start(strips + 1, 0);
  // The strips each face overlaps ({0, -1}: none), in parallel; faces that are not drawable,
  // off screen, or so small that their bounding box holds no sample centre get none.
  std::vector<std::array<int, 2>> face_strips(F.rows(), {0, -1});
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, F.rows(), 16384),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index f = range.begin(); f != range.end(); ++f) {
      const TriangleSetup triangle(screen, F, static_cast<int>(f));
      if (!triangle.drawable()) continue;
      const auto [x_low, x_high, y_low, y_high] = triangle.bounds();
      if (x_high < 0.0 || x_low > width || y_high < 0.0 || y_low > height) continue;
      if (std::ceil(x_low - 0.5) > std::floor(x_high - 0.5) ||
          std::ceil(y_low - 0.5) > std::floor(y_high - 0.5))
        continue;  // no sample centre inside the bounding box
      face_strips[f] = {pixel_index(y_low, 0, height - 1) / kStripRows,
                        pixel_index(y_high, 0, height - 1) / kStripRows};
    }
  });
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int s = face_strips[f][0]; s <= face_strips[f][1]; ++s) ++strip_start[s + 1];
  for (int s = 0; s < strips; ++s) strip_start[s + 1] += strip_start[s];
  std::vector<int> binned(strip_start[strips]);
  {
    std::vector<std::int64_t> fill(strip_start.begin(), strip_start.end() - 1);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int s = face_strips[f][0]; s <= face_strips[f][1]; ++s) binned[fill[s]++] = static_cast<int>(f);
  }

  // Visibility pass: nearest triangle per sample.
  const std::size_t samples = static_cast<std::size_t>(width) * height;
  std::vector<float> depth(samples, -std::numeric_limits<float>::infinity());
  std::vector<int> visible(samples, -1);
  tbb::parallel_for(tbb::blocked_range<int>(0, strips, 1), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s != range.end(); ++s) {
      const int row_begin = s * kStripRows, row_end = std::min(height, row_begin + kStripRows);
      for (std::int64_t b = strip_start[s]; b < strip_start[s + 1]; ++b) {
        const int f = binned[b];
        const TriangleSetup triangle(screen, F, f);
        const auto [x_low, x_high, y_low, y_high] = triangle.bounds();
        // Sample (x, y) sits at (x + 0.5, y + 0.5).
        const int x0 = pixel_index(std::ceil(x_low - 0.5), 0, width - 1);
        const int x1 = pixel_index(std::floor(x_high - 0.5), -1, width - 1);
        const int y0 = pixel_index(std::ceil(y_low - 0.5), row_begin, row_end - 1);
        const int y1 = pixel_index(std::floor(y_high - 0.5), row_begin - 1, row_end - 1);
        if (x0 > x1 || y0 > y1) continue;
        const double inverse_area = 1.0 / triangle.area2;
        const double d0 = triangle.vertex[0]->depth, d1 = triangle.vertex[1]->depth,
                     d2 = triangle.vertex[2]->depth;
        for (int y = y0; y <= y1; ++y) {
          const double py = y + 0.5;
          float* depth_row = depth.data() + static_cast<std::size_t>(y) * width;
          int* visible_row = visible.data() + static_cast<std::size_t>(y) * width;
          for (int x = x0; x <= x1; ++x) {
            const double px = x + 0.5;
            const double l0 = triangle.edge[0](px, py) * inverse_area;
            const double l1 = triangle.edge[1](px, py) * inverse_area;
            const double l2 = triangle.edge[2](px, py) * inverse_area;
            if (l0 < 0.0 || l1 < 0.0 || l2 < 0.0) continue;
            const float z = static_cast<float>(l0 * d0 + l1 * d1 + l2 * d2);
            if (z > depth_row[x]) {
              depth_row[x] = z;
              visible_row[x] = f;
            }
          }
        }
      }
    }
  });

  // Shading pass: each visible sample once, averaged per output pixel in linear light.
  const Shader shader(V, F, frame, *effective);
  const SrgbEncoder encode;
  RgbaImage image;
  image.width = options.width;
  image.height = options.height;
  image.pixels.assign(static_cast<std::size_t>(options.width) * options.height * 4, 0);
  const double samples_per_pixel = ss * ss;
  // Without a wireframe or per-vertex attributes a triangle's colour within one pixel is its
  // lighting alone, computed at the first sample that sees it.
  const bool uniform_per_triangle =
      !options.wireframe && options.scalar.size() == 0 && options.uv.rows() == 0;
  tbb::parallel_for(tbb::blocked_range<int>(0, options.height, 4), [&](const tbb::blocked_range<int>& range) {
    for (int row = range.begin(); row != range.end(); ++row) {
      const double t = options.height > 1 ? static_cast<double>(row) / (options.height - 1) : 0.0;
      const Eigen::Vector3d background =
          srgb_to_linear(((1.0 - t) * options.background_top + t * options.background_bottom).eval());
      for (int column = 0; column < options.width; ++column) {
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        int covered = 0;
        // Lighting once per triangle seen in this pixel; colour and wireframe once per sample.
        std::array<int, 16> group_face;
        std::array<Shader::Lighting, 16> group_light;
        std::array<Eigen::Vector3d, 16> group_color;  // when the colour does not vary per sample
        int groups = 0;
        for (int sy = 0; sy < ss; ++sy) {
          const int y = row * ss + sy;
          for (int sx = 0; sx < ss; ++sx) {
            const int x = column * ss + sx;
            const int f = visible[static_cast<std::size_t>(y) * width + x];
            if (f < 0) continue;
            ++covered;
            int g = 0;
            while (g < groups && group_face[g] != f) ++g;
            if (g < groups && uniform_per_triangle) {
              sum += group_color[g];
              continue;
            }
            const TriangleSetup triangle(screen, F, f);
            const Shader::SampleWeights w = shader.weights(triangle, x + 0.5, y + 0.5);
            if (g == groups) {
              group_face[g] = f;
              group_light[g] = shader.lighting(triangle, f, w);
              ++groups;
            }
            const Eigen::Vector3d color = shader.color(triangle, f, w, group_light[g]);
            if (uniform_per_triangle) group_color[g] = color;
            sum += color;
          }
        }
        std::uint8_t* pixel = image.pixels.data() + (static_cast<std::size_t>(row) * options.width + column) * 4;
        Eigen::Vector3d color;
        if (options.transparent_background) {
          color = covered > 0 ? Eigen::Vector3d(sum / covered) : Eigen::Vector3d::Zero();
          pixel[3] = static_cast<std::uint8_t>(std::lround(255.0 * covered / samples_per_pixel));
        } else {
          color = (sum + (samples_per_pixel - covered) * background) / samples_per_pixel;
          pixel[3] = 255;
        }
        for (int c = 0; c < 3; ++c) pixel[c] = encode(color[c]);
      }
    }
  });
  return image;
}

}  // namespace meshsmith::render
