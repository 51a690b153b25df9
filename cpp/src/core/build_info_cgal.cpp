// CGAL translation unit (compiled with CGAL's flags, see CMakeLists.txt).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/version.h>

#include <string>

namespace meshsmith {

std::string cgal_version() {
  // Evaluate one exact predicate so the kernel (and GMP/MPFR behind it) is really linked.
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  const bool kernel_works = CGAL::orientation(Kernel::Point_2(0, 0), Kernel::Point_2(1, 0),
                                              Kernel::Point_2(0, 1)) == CGAL::LEFT_TURN;
  return kernel_works ? std::string(CGAL_VERSION_STR) : std::string("unusable");
}

}  // namespace meshsmith
