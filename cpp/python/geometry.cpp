// Bindings of the geometry chapter.
#include "bindings.h"
#include "convert.h"
#include "geometry_differential.h"

namespace meshsmith::python {

void bind_geometry(py::module_& m) { bind_geometry_differential(m); }

}  // namespace meshsmith::python
