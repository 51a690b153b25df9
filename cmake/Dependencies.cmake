# The Debian packages the core stands on. Shared by the project and by the installed
# meshsmithConfig.cmake, so a C++ consumer finds exactly what the library was built with.
# CGAL comes last: it prepends its own Find modules to CMAKE_MODULE_PATH.
if(NOT DEFINED CMAKE_POLICY_DEFAULT_CMP0167)
  set(CMAKE_POLICY_DEFAULT_CMP0167 NEW)  # CMake 4: Boost through its own config
endif()
find_package(Eigen3 3.3 REQUIRED CONFIG)
find_package(OpenMesh REQUIRED CONFIG)   # targets OpenMeshCore / OpenMeshTools; no version file
find_package(TBB REQUIRED CONFIG)
find_package(nanoflann REQUIRED CONFIG)
find_package(Spectra REQUIRED CONFIG)
find_package(CHOLMOD REQUIRED)           # cmake/FindCHOLMOD.cmake
set(CGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE TRUE)
find_package(CGAL REQUIRED)
include(CGAL_Eigen3_support)
