// Bindings of the io chapter.
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_io(py::module_& m) {}

}  // namespace meshsmith::python
