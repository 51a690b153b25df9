#include "mesh_cholesky.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <initializer_list>
#include <mutex>

namespace meshsmith::detail {

namespace {

/// The addresses of `symbols` in the first of `libraries` that the process has already loaded
/// (RTLD_NOLOAD: nothing is loaded here; the handle is kept) and that defines them all; all
/// null if there is none.
template <std::size_t N>
std::array<void*, N> loaded_symbols(std::initializer_list<const char*> libraries,
                                    const std::array<const char*, N>& symbols) {
  for (const char* name : libraries) {
    void* library = dlopen(name, RTLD_LAZY | RTLD_NOLOAD);
    if (!library) continue;
    std::array<void*, N> found{};
    for (std::size_t k = 0; k < N; ++k) found[k] = dlsym(library, symbols[k]);
    if (std::all_of(found.begin(), found.end(), [](void* symbol) { return symbol != nullptr; })) return found;
  }
  return {};
}

/// The OpenMP runtime's per-thread controls, if the process has loaded one (CHOLMOD did).
struct OpenMpControls {
  int (*get_dynamic)() = nullptr;
  void (*set_dynamic)(int) = nullptr;
  int (*get_max_threads)() = nullptr;
  void (*set_num_threads)(int) = nullptr;
  bool available() const { return get_dynamic != nullptr; }
};

const OpenMpControls& openmp_controls() {
  static const OpenMpControls controls = [] {
    const auto symbols = loaded_symbols<4>({"libgomp.so.1", "libomp.so.5", "libomp.so", "libiomp5.so"},
                                           {"omp_get_dynamic", "omp_set_dynamic", "omp_get_max_threads",
                                            "omp_set_num_threads"});
    OpenMpControls found;
    found.get_dynamic = reinterpret_cast<int (*)()>(symbols[0]);
    found.set_dynamic = reinterpret_cast<void (*)(int)>(symbols[1]);
    found.get_max_threads = reinterpret_cast<int (*)()>(symbols[2]);
    found.set_num_threads = reinterpret_cast<void (*)(int)>(symbols[3]);
    return found;
  }();
  return controls;
}

/// OpenBLAS's global thread count, if the process has loaded OpenBLAS.
struct BlasControls {
  int (*get_threads)() = nullptr;
  void (*set_threads)(int) = nullptr;
  bool available() const { return get_threads != nullptr; }
};

const BlasControls& blas_controls() {
  static const BlasControls controls = [] {
    const auto symbols = loaded_symbols<2>({"libopenblas.so.0", "libblas.so.3"},
                                           {"openblas_get_num_threads", "openblas_set_num_threads"});
    BlasControls found;
    found.get_threads = reinterpret_cast<int (*)()>(symbols[0]);
    found.set_threads = reinterpret_cast<void (*)(int)>(symbols[1]);
    return found;
  }();
  return controls;
}

std::mutex blas_mutex;
int blas_users = 0;
int blas_saved_threads = 1;

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const BlasControls& blas = blas_controls();
  if (!blas.available()) return;
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (blas_users++ == 0) {
    blas_saved_threads = blas.get_threads();
    blas.set_threads(1);
  }
}

SingleThreadedBlas::~SingleThreadedBlas() {
  const BlasControls& blas = blas_controls();
  if (!blas.available()) return;
  const std::lock_guard<std::mutex> lock(blas_mutex);
  if (--blas_users == 0) blas.set_threads(blas_saved_threads);
}

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

}  // namespace meshsmith::detail
