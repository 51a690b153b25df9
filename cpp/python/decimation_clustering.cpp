// Bindings of vertex clustering (§4.1).
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_decimation_clustering(py::module_& m) {
  (void)m;  // filled in with the chapter's functions
}

}  // namespace meshsmith::python
