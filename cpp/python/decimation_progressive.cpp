// Bindings of progressive meshes (§4.3).
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_decimation_progressive(py::module_& m) {
  (void)m;  // filled in with the chapter's functions
}

}  // namespace meshsmith::python
