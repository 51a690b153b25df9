#pragma once
/// \file build_info.h
/// What the core was built with: its version and those of the libraries it links.
#include <string>
#include <utility>
#include <vector>

namespace meshsmith {

/// meshsmith's version, e.g. "0.1.0".
std::string version();

/// (library, version) for each linked dependency: Eigen, OpenMesh, CGAL, CHOLMOD, Spectra,
/// TBB, nanoflann. Each entry is read from the library itself (headers or runtime), so it also
/// proves the library is linked.
std::vector<std::pair<std::string, std::string>> dependency_versions();

}  // namespace meshsmith
