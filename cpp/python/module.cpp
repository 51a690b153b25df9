// meshsmith._core: the compiled half of the Python package. One submodule per chapter.
#include "bindings.h"

#include <meshsmith/core/errors.h>

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "meshsmith C++ core (use the meshsmith package, not this module directly)";
  py::register_exception<meshsmith::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<meshsmith::SolverError>(m, "SolverError", PyExc_RuntimeError);
  py::register_exception<meshsmith::Cancelled>(m, "Cancelled", PyExc_Exception);

  auto core = m.def_submodule("core");
  meshsmith::python::bind_core(core);
  auto io = m.def_submodule("io");
  meshsmith::python::bind_io(io);
  auto topology = m.def_submodule("topology");
  meshsmith::python::bind_topology(topology);
  auto geometry = m.def_submodule("geometry");
  meshsmith::python::bind_geometry(geometry);
  auto render = m.def_submodule("render");
  meshsmith::python::bind_render(render);
  auto points = m.def_submodule("points");
  meshsmith::python::bind_points(points);
  auto tessellation = m.def_submodule("tessellation");
  meshsmith::python::bind_tessellation_delaunay(tessellation);
  meshsmith::python::bind_tessellation_contouring(tessellation);
  auto decimation = m.def_submodule("decimation");
  meshsmith::python::bind_decimation_qem(decimation);
  meshsmith::python::bind_decimation_clustering(decimation);
  meshsmith::python::bind_decimation_progressive(decimation);
  auto parametrization = m.def_submodule("parametrization");
  meshsmith::python::bind_parametrization_maps(parametrization);
  meshsmith::python::bind_parametrization_abf(parametrization);
  auto repair = m.def_submodule("repair");
  meshsmith::python::bind_repair(repair);
  meshsmith::python::bind_repair_holes(repair);
  meshsmith::python::bind_repair_intersections(repair);
  meshsmith::python::bind_repair_degenerate(repair);
  meshsmith::python::bind_repair_volumetric(repair);
  auto smoothing = m.def_submodule("smoothing");
  meshsmith::python::bind_smoothing(smoothing);
  auto registration = m.def_submodule("registration");
  meshsmith::python::bind_registration(registration);
  auto reconstruction = m.def_submodule("reconstruction");
  meshsmith::python::bind_reconstruction(reconstruction);
  meshsmith::python::bind_reconstruction_depth(reconstruction);
  meshsmith::python::bind_reconstruction_graph_cut(reconstruction);
  meshsmith::python::bind_smoothing_fairing(smoothing);
  auto deformation = m.def_submodule("deformation");
  meshsmith::python::bind_deformation(deformation);
  auto quadrangulation = m.def_submodule("quadrangulation");
  meshsmith::python::bind_quadrangulation(quadrangulation);
  meshsmith::python::bind_quadrangulation_extraction(quadrangulation);
  meshsmith::python::bind_quadrangulation_dual_loops(quadrangulation);
  meshsmith::python::bind_quadrangulation_spectral(quadrangulation);
}
