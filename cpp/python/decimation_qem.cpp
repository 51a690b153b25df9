// Bindings of incremental QEM decimation (§4.2).
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_decimation_qem(py::module_& m) {
  (void)m;  // filled in with the chapter's functions
}

}  // namespace meshsmith::python
