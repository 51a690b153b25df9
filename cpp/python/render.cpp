// Bindings of the render chapter: camera framing, the rasterizer, colormap tables.
#include "bindings.h"
#include "convert.h"

#include <meshsmith/render/camera.h>
#include <meshsmith/render/colormap.h>
#include <meshsmith/render/rasterizer.h>

#include <pybind11/stl.h>

#include <array>
#include <cstring>

namespace meshsmith::python {
namespace {

using render::Camera;
using render::RenderOptions;

Eigen::Vector3d as_color(const std::array<double, 3>& c) { return {c[0], c[1], c[2]}; }

py::dict camera_to_dict(const Camera& camera) {
  py::dict out;
  out["eye"] = std::array<double, 3>{camera.eye[0], camera.eye[1], camera.eye[2]};
  out["target"] = std::array<double, 3>{camera.target[0], camera.target[1], camera.target[2]};
  out["up"] = std::array<double, 3>{camera.up[0], camera.up[1], camera.up[2]};
  out["fov_y_deg"] = camera.fov_y_deg;
  out["orthographic"] = camera.orthographic;
  out["ortho_height"] = camera.ortho_height;
  return out;
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("frame_camera", [](const py::object& V, double azimuth_deg, double elevation_deg,
                           const std::string& up, double aspect, double fov_y_deg,
                           bool orthographic, double margin) {
    auto vertices = as_real_matrix(V, "V", 3);
    render::FramingOptions options;
    options.azimuth_deg = azimuth_deg;
    options.elevation_deg = elevation_deg;
    options.up = render::up_axis_from_name(up);
    options.aspect = aspect;
    options.fov_y_deg = fov_y_deg;
    options.orthographic = orthographic;
    options.margin = margin;
    Camera camera;
    {
      py::gil_scoped_release release;
      camera = render::frame_camera(map_vertices(vertices), options);
    }
    return camera_to_dict(camera);
  }, py::arg("V"), py::arg("azimuth_deg"), py::arg("elevation_deg"), py::arg("up") = "y",
     py::arg("aspect") = 4.0 / 3.0, py::arg("fov_y_deg") = 30.0, py::arg("orthographic") = false,
     py::arg("margin") = 0.06,
     "Camera dict (eye, target, up, fov_y_deg, orthographic, ortho_height) framing V.");

  m.def("render_mesh", [](const py::object& V, const py::object& F,
                          std::array<double, 3> eye, std::array<double, 3> target,
                          std::array<double, 3> up, double fov_y_deg, bool orthographic,
                          double ortho_height, const py::object& width_in, const py::object& height_in,
                          const py::object& supersample_in,
                          bool smooth_shading, double crease_angle_deg, bool lighting, bool wireframe,
                          double wireframe_width, std::array<double, 3> front_color,
                          std::array<double, 3> back_color, std::array<double, 3> wireframe_color,
                          std::array<double, 3> background_top,
                          std::array<double, 3> background_bottom, bool transparent_background,
                          const py::object& scalar, double scalar_min, double scalar_max,
                          const std::string& colormap, const py::object& uv,
                          double checker_size, const py::object& wireframe_edges) {
    auto vertices = as_real_matrix(V, "V", 3);
    auto faces = as_index_matrix(F, "F", 3);
    const int width = integer_argument<int>(width_in, "width", 1, render::kMaxImageSide);
    const int height = integer_argument<int>(height_in, "height", 1, render::kMaxImageSide);
    const int supersample = integer_argument<int>(supersample_in, "supersample", 1, 4);
    Camera camera;
    camera.eye = as_color(eye);
    camera.target = as_color(target);
    camera.up = as_color(up);
    camera.fov_y_deg = fov_y_deg;
    camera.orthographic = orthographic;
    camera.ortho_height = ortho_height;
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.supersample = supersample;
    options.smooth_shading = smooth_shading;
    options.crease_angle_deg = crease_angle_deg;
    options.lighting = lighting;
    options.wireframe = wireframe;
    options.wireframe_width = wireframe_width;
    options.front_color = as_color(front_color);
    options.back_color = as_color(back_color);
    options.wireframe_color = as_color(wireframe_color);
    options.background_top = as_color(background_top);
    options.background_bottom = as_color(background_bottom);
    options.transparent_background = transparent_background;
    options.colormap = render::colormap_from_name(colormap);
    if (!scalar.is_none()) {
      auto values = as_real_vector(scalar, "scalar");
      options.scalar = Eigen::Map<const Eigen::VectorXd>(values.data(), values.shape(0));
      options.scalar_min = scalar_min;
      options.scalar_max = scalar_max;
    }
    if (!uv.is_none()) {
      py::array array = as_numeric_array(uv, "uv", Elements::real);
      RealArray coordinates;
      if (array.ndim() == 3) {
        if (array.shape(1) != 3 || array.shape(2) != 2)
          throw InputError("uv has shape " + shape_of(array) +
                           ": expected (#V, 2) per vertex or (#F, 3, 2) per corner");
        coordinates = as_real_matrix(array.reshape({array.shape(0) * 3, py::ssize_t(2)}), "uv", 2);
        options.uv_per_corner = true;
      } else {
        coordinates = as_real_matrix(array, "uv", 2);
      }
      options.uv = Eigen::Map<const render::UvMatrix>(coordinates.data(), coordinates.shape(0), 2);
      options.checker_size = checker_size;
    }
    if (!wireframe_edges.is_none()) {
      const IndexArray masks = as_index_vector(wireframe_edges, "wireframe_edges");
      options.wireframe_edges.resize(static_cast<std::size_t>(masks.shape(0)));
      for (py::ssize_t f = 0; f < masks.shape(0); ++f) {
        const int mask = masks.data()[f];
        if (mask < 0 || mask > 7) throw InputError("wireframe_edges[" + std::to_string(f) + "] = " + std::to_string(mask) + ": expected a 3-bit mask in [0, 7]");
        options.wireframe_edges[static_cast<std::size_t>(f)] = static_cast<std::uint8_t>(mask);
      }
    }
    render::RgbaImage image;
    {
      py::gil_scoped_release release;
      image = render::render_mesh(map_vertices(vertices), map_faces(faces), camera, options);
    }
    py::array_t<std::uint8_t> out({image.height, image.width, 4});
    std::memcpy(out.mutable_data(), image.pixels.data(), image.pixels.size());
    return out;
  }, py::arg("V"), py::arg("F"), py::arg("eye"), py::arg("target"), py::arg("up"),
     py::arg("fov_y_deg"), py::arg("orthographic"), py::arg("ortho_height"), py::arg("width"),
     py::arg("height"), py::arg("supersample"), py::arg("smooth_shading"), py::arg("crease_angle_deg"), py::arg("lighting"),
     py::arg("wireframe"), py::arg("wireframe_width"), py::arg("front_color"),
     py::arg("back_color"), py::arg("wireframe_color"), py::arg("background_top"),
     py::arg("background_bottom"), py::arg("transparent_background"), py::arg("scalar"),
     py::arg("scalar_min"), py::arg("scalar_max"), py::arg("colormap"), py::arg("uv"),
     py::arg("checker_size"), py::arg("wireframe_edges") = py::none(),
     "(H, W, 4) uint8 RGBA picture of (V, F); see meshsmith.render.render for the meaning.");

  m.def("colormap_table", [](const std::string& name, const py::object& steps_in) {
    const render::Colormap colormap = render::colormap_from_name(name);
    const int steps = integer_argument<int>(steps_in, "steps", 2, 1 << 20);
    VertexMatrix table(steps, 3);
    for (int i = 0; i < steps; ++i)
      table.row(i) = render::colormap_color(colormap, static_cast<double>(i) / (steps - 1)).transpose();
    return to_numpy(std::move(table));
  }, py::arg("name"), py::arg("steps") = 256, "(steps, 3) sRGB colours in [0, 1] of a colormap.");

  m.def("scalar_range", [](const py::object& scalar, const py::object& vertex_count_in,
                           bool symmetric_about_zero, double lower_percentile,
                           double upper_percentile) {
    auto values = as_real_vector(scalar, "scalar");
    const auto vertex_count = integer_argument<Eigen::Index>(vertex_count_in, "vertex_count", 0);
    const Eigen::Map<const Eigen::VectorXd> mapped(values.data(), values.shape(0));
    const Eigen::VectorXd field = mapped;
    render::validate_vertex_scalar(field, vertex_count);
    return render::robust_scalar_range(field, symmetric_about_zero, lower_percentile, upper_percentile);
  }, py::arg("scalar"), py::arg("vertex_count"), py::arg("symmetric_about_zero"),
     py::arg("lower_percentile") = 2.0, py::arg("upper_percentile") = 98.0,
     "Validated robust (low, high) colouring range of a per-vertex scalar field.");

  m.def("uv_layout_vertices", [](const py::object& UV) {
    auto coordinates = as_real_matrix(UV, "UV", 2);
    VertexMatrix V = VertexMatrix::Zero(coordinates.shape(0), 3);
    for (py::ssize_t i = 0; i < coordinates.shape(0); ++i) {
      V(i, 0) = coordinates.at(i, 0);
      V(i, 1) = coordinates.at(i, 1);
    }
    return to_numpy(std::move(V));
  }, py::arg("UV"), "(n, 3) vertices (u, v, 0) of (n, 2) texture coordinates.");

  m.attr("max_image_side") = render::kMaxImageSide;
  m.def("colormap_names", &render::colormap_names);
  m.def("colormap_is_diverging", [](const std::string& name) {
    return render::colormap_is_diverging(render::colormap_from_name(name));
  }, py::arg("name"));
}

}  // namespace meshsmith::python
