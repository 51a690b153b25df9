// Bindings of the render chapter.
#include "bindings.h"
#include "convert.h"

namespace meshsmith::python {

void bind_render(py::module_& m) {}

}  // namespace meshsmith::python
