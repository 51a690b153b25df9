// Bindings of hole filling (§2.4.1): a thin wrapper over meshsmith::repair::fill_holes
// (python/meshsmith/repair/holes.py documents it for users).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/repair/fill_holes.h>

#include <pybind11/stl.h>

#include <cstdint>
#include <string>

namespace meshsmith::python {

void bind_repair_holes(py::module_& m) {
  m.def("fill_holes", [](const py::object& V, const py::object& F, const py::object& holes, const py::object& max_hole_edges,
                         double max_hole_diameter, bool keep_border, const std::string& search, bool refine, bool fair,
                         double density, bool islands, const py::object& callback) {
    const MeshArguments mesh(V, F);
    repair::FillHolesOptions options;
    if (!holes.is_none()) {
      const IndexArray chosen = as_index_vector(holes, "holes");
      options.holes.assign(chosen.data(), chosen.data() + chosen.size());
    }
    options.max_hole_edges = integer_argument<int>(max_hole_edges, "max_hole_edges", 0);
    options.max_hole_diameter = max_hole_diameter;
    options.keep_border = keep_border;
    options.search = parse_choice<repair::HoleSearch>(search, "search", {{"delaunay", repair::HoleSearch::delaunay},
                                                                         {"exact", repair::HoleSearch::exact}});
    options.refine = refine;
    options.fair = fair;
    options.density = density;
    options.islands = islands;
    const Progress progress = make_progress(callback);
    auto result = without_gil([&] { return repair::fill_holes(mesh.V(), mesh.F(), options, progress); });
    const auto patches = static_cast<Eigen::Index>(result.patches.size());
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, 7, Eigen::RowMajor> table(patches, 7);
    for (Eigen::Index p = 0; p < patches; ++p) {
      const auto& r = result.patches[p];
      table.row(p) << r.loop, r.loop_edges, r.faces, r.vertices, r.delaunay ? 1 : 0, r.face_begin, r.vertex_begin;
    }
    Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> measures(patches, 2);
    for (Eigen::Index p = 0; p < patches; ++p)
      measures.row(p) << result.patches[p].max_dihedral_angle, result.patches[p].edge_length_ratio;
    py::list loops;
    for (const auto& loop : result.loops) {
      Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> row(static_cast<Eigen::Index>(loop.size()));
      for (std::size_t j = 0; j < loop.size(); ++j) row[static_cast<Eigen::Index>(j)] = loop[j];
      loops.append(to_numpy(std::move(row)));
    }
    py::list island_lists;
    for (const auto& r : result.patches) island_lists.append(py::cast(r.islands));
    py::list unfilled;
    for (const auto& u : result.unfilled) unfilled.append(py::make_tuple(u.loop, u.reason));
    py::dict report;
    report["patches"] = to_numpy(std::move(table));
    report["measures"] = to_numpy(std::move(measures));
    report["loops"] = loops;
    report["unfilled"] = unfilled;
    report["islands"] = island_lists;
    report["kept_borders"] = result.kept_borders;
    return py::make_tuple(to_numpy(std::move(result.V)), indices_to_numpy(result.F), report);
  }, py::arg("V"), py::arg("F"), py::arg("holes") = py::none(), py::arg("max_hole_edges") = 0,
     py::arg("max_hole_diameter") = 0.0, py::arg("keep_border") = false, py::arg("search") = "delaunay",
     py::arg("refine") = true, py::arg("fair") = true, py::arg("density") = 1.4142135623730951,
     py::arg("islands") = true, py::arg("progress") = py::none(),
     "Liepa hole filling (§2.4.1). Returns (V, F, report); see meshsmith.repair.fill_holes.");
}

}  // namespace meshsmith::python
