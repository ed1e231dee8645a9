# Locates every dependency from Debian 12 packages and exposes imported targets.
# Included by the top-level build (consumers: the installed atmoshConfig.cmake).
include_guard(GLOBAL)
include(CMakeFindDependencyMacro)

find_package(glm CONFIG REQUIRED)
if(NOT TARGET glm::glm AND TARGET glm)
  add_library(glm::glm ALIAS glm)
endif()

# GeographicLib: its CMake package, else the find-module Debian ships (the same lookup
# as the installed atmosh package, see atmoshGeographicLib.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/atmoshGeographicLib.cmake)
if(NOT ATMOSH_GEOGRAPHICLIB_FOUND)
  message(FATAL_ERROR "GeographicLib not found: install libgeographiclib-dev (scripts/setup-debian.sh)")
endif()

if(NOT ATMOSH_DEPENDENCIES_LIBS_ONLY)
  find_package(OpenEXR CONFIG REQUIRED)
  find_package(CLI11 CONFIG REQUIRED)
  find_package(tomlplusplus CONFIG REQUIRED)
  find_package(nlohmann_json CONFIG REQUIRED)
  find_package(fmt CONFIG REQUIRED)
  find_package(Threads REQUIRED)
  # Precomputed radiance transfer (apps/prt): ray casting and mesh input.
  find_package(embree 3 CONFIG REQUIRED)
  find_package(tinyobjloader CONFIG REQUIRED)
  find_package(assimp CONFIG REQUIRED)
  # Debian's OpenCVConfig.cmake lives in the all-modules libopencv-dev; we need
  # three modules only, so locate them directly.
  find_path(ATMOSH_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
  foreach(_m core imgproc imgcodecs)
    find_library(ATMOSH_OPENCV_${_m} opencv_${_m} REQUIRED)
    if(NOT TARGET atmosh_opencv::${_m})
      add_library(atmosh_opencv::${_m} UNKNOWN IMPORTED)
      set_target_properties(atmosh_opencv::${_m} PROPERTIES
        IMPORTED_LOCATION "${ATMOSH_OPENCV_${_m}}"
        INTERFACE_INCLUDE_DIRECTORIES "${ATMOSH_OPENCV_INCLUDE_DIR}")
    endif()
  endforeach()
  # netCDF-4 output (apps/io): the C library, located directly (Debian's netCDFConfig.cmake
  # names the static libraries and development files of every library netCDF uses).
  find_path(ATMOSH_NETCDF_INCLUDE_DIR netcdf.h REQUIRED)
  find_library(ATMOSH_NETCDF_LIBRARY netcdf REQUIRED)
  if(NOT TARGET atmosh_netcdf::netcdf)
    add_library(atmosh_netcdf::netcdf UNKNOWN IMPORTED)
    set_target_properties(atmosh_netcdf::netcdf PROPERTIES
      IMPORTED_LOCATION "${ATMOSH_NETCDF_LIBRARY}" INTERFACE_INCLUDE_DIRECTORIES "${ATMOSH_NETCDF_INCLUDE_DIR}")
  endif()
  if(ATMOSH_WITH_GPU)
    find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
  endif()
endif()
