#include "mesh_cholesky.h"

#include <dlfcn.h>

namespace meshsmith::parametrization::detail {

namespace {

/// The OpenMP runtime's per-thread controls, if the process has loaded one.
struct OpenMpControls {
  int (*get_dynamic)() = nullptr;
  void (*set_dynamic)(int) = nullptr;
  int (*get_max_threads)() = nullptr;
  void (*set_num_threads)(int) = nullptr;
  bool available() const { return get_dynamic && set_dynamic && get_max_threads && set_num_threads; }
};

const OpenMpControls& openmp_controls() {
  static const OpenMpControls controls = [] {
    OpenMpControls found;
    // RTLD_NOLOAD: only a runtime already loaded (by CHOLMOD) is used; the handle is kept.
    for (const char* name : {"libgomp.so.1", "libomp.so.5", "libomp.so", "libiomp5.so"}) {
      void* library = dlopen(name, RTLD_LAZY | RTLD_NOLOAD);
      if (!library) continue;
      found.get_dynamic = reinterpret_cast<int (*)()>(dlsym(library, "omp_get_dynamic"));
      found.set_dynamic = reinterpret_cast<void (*)(int)>(dlsym(library, "omp_set_dynamic"));
      found.get_max_threads = reinterpret_cast<int (*)()>(dlsym(library, "omp_get_max_threads"));
      found.set_num_threads = reinterpret_cast<void (*)(int)>(dlsym(library, "omp_set_num_threads"));
      if (found.available()) break;
      found = OpenMpControls{};
    }
    return found;
  }();
  return controls;
}

}  // namespace

SingleThreadedOpenMp::SingleThreadedOpenMp() {
  const OpenMpControls& omp = openmp_controls();
  if (!omp.available()) return;
  active_ = true;
  saved_dynamic_ = omp.get_dynamic();
  saved_threads_ = omp.get_max_threads();
  omp.set_dynamic(1);
  omp.set_num_threads(1);
}

SingleThreadedOpenMp::~SingleThreadedOpenMp() {
  if (!active_) return;
  const OpenMpControls& omp = openmp_controls();
  omp.set_num_threads(saved_threads_);
  omp.set_dynamic(saved_dynamic_);
}

}  // namespace meshsmith::parametrization::detail
