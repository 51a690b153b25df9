// Bindings of boundary maps, harmonic/Tutte, stretch-minimizing, LSCM, cut to disk (§5.1.1–5.1.2).
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_parametrization_maps(py::module_& m) {
  (void)m;  // filled in with the chapter's functions
}

}  // namespace meshsmith::python
