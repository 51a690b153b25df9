#pragma once
// One binding function per chapter (DESIGN.md: cpp/python/<chapter>.cpp); module.cpp calls each
// with the chapter's submodule of meshsmith._core.
#include <pybind11/pybind11.h>

namespace meshsmith::python {
void bind_core(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_topology(pybind11::module_& m);
void bind_render(pybind11::module_& m);
void bind_geometry(pybind11::module_& m);
void bind_geometry_differential(pybind11::module_& m);  // called by bind_geometry
void bind_geometry_metrics(pybind11::module_& m);       // called by bind_geometry
void bind_points(pybind11::module_& m);
void bind_tessellation_delaunay(pybind11::module_& m);    // module.cpp calls both on "tessellation"
void bind_tessellation_contouring(pybind11::module_& m);
void bind_decimation_qem(pybind11::module_& m);           // module.cpp calls these three on "decimation"
void bind_decimation_clustering(pybind11::module_& m);
void bind_decimation_progressive(pybind11::module_& m);
void bind_parametrization_maps(pybind11::module_& m);     // module.cpp calls both on "parametrization"
void bind_parametrization_abf(pybind11::module_& m);
void bind_repair(pybind11::module_& m);
void bind_repair_holes(pybind11::module_& m);           // module.cpp calls these three on "repair" too
void bind_repair_intersections(pybind11::module_& m);
void bind_repair_degenerate(pybind11::module_& m);
void bind_repair_volumetric(pybind11::module_& m);
void bind_smoothing(pybind11::module_& m);
void bind_registration(pybind11::module_& m);
void bind_reconstruction_depth(pybind11::module_& m);     // on "reconstruction"
void bind_smoothing_fairing(pybind11::module_& m);       // module.cpp calls both on "smoothing"
void bind_deformation(pybind11::module_& m);
void bind_quadrangulation(pybind11::module_& m);
void bind_quadrangulation_extraction(pybind11::module_& m);  // module.cpp calls it on "quadrangulation"
void bind_quadrangulation_dual_loops(pybind11::module_& m);  // on "quadrangulation"
void bind_reconstruction(pybind11::module_& m);
void bind_reconstruction_graph_cut(pybind11::module_& m);  // on "reconstruction"
void bind_quadrangulation_spectral(pybind11::module_& m);  // on "quadrangulation"
}  // namespace meshsmith::python
