#include <meshsmith/core/build_info.h>

#include <Eigen/Core>
#include <OpenMesh/Core/System/config.h>
#include <Spectra/Util/Version.h>
#include <nanoflann.hpp>
#include <oneapi/tbb/version.h>
#include <suitesparse/cholmod.h>

#include <sstream>

namespace meshsmith {

std::string cgal_version();  // build_info_cgal.cpp: compiled apart with CGAL's flags

namespace {
std::string join(int major, int minor, int patch) {
  std::ostringstream out;
  out << major << "." << minor << "." << patch;
  return out.str();
}
}  // namespace

std::string version() { return MESHSMITH_VERSION_STRING; }

std::vector<std::pair<std::string, std::string>> dependency_versions() {
  int cholmod[3] = {0, 0, 0};
  cholmod_version(cholmod);  // a runtime call: proves libcholmod is linked
  return {
      {"Eigen", join(EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)},
      {"OpenMesh", join((OM_VERSION >> 16) & 0xff, (OM_VERSION >> 8) & 0xff, OM_VERSION & 0xff)},
      {"CGAL", cgal_version()},
      {"CHOLMOD", join(cholmod[0], cholmod[1], cholmod[2])},
      {"Spectra", join(SPECTRA_MAJOR_VERSION, SPECTRA_MINOR_VERSION, SPECTRA_PATCH_VERSION)},
      {"TBB", TBB_runtime_version()},
      {"nanoflann", join((NANOFLANN_VERSION >> 8) & 0xf, (NANOFLANN_VERSION >> 4) & 0xf, NANOFLANN_VERSION & 0xf)},
  };
}

}  // namespace meshsmith
