// Bindings of ABF and ABF++ (§5.1.3).
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_parametrization_abf(py::module_& m) {
  (void)m;  // filled in with the chapter's functions
}

}  // namespace meshsmith::python
