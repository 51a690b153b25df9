// Bindings of the geometry chapter.
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_geometry(py::module_& m) {}

}  // namespace meshsmith::python
