// Bindings of the topology chapter.
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_topology(py::module_& m) {}

}  // namespace meshsmith::python
