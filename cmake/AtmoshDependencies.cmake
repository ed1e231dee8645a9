# Locates every dependency from Debian 12 packages and exposes imported targets.
# Included by the top-level build and (through atmoshConfig.cmake) by consumers.
include_guard(GLOBAL)
include(CMakeFindDependencyMacro)

find_package(glm CONFIG REQUIRED)
if(NOT TARGET glm::glm AND TARGET glm)
  add_library(glm::glm ALIAS glm)
endif()

# Debian ships GeographicLib's find-module only (no config package): use it and
# wrap its variables in an imported target.
list(APPEND CMAKE_MODULE_PATH /usr/share/cmake/geographiclib)
find_package(GeographicLib REQUIRED)
if(NOT TARGET GeographicLib::GeographicLib)
  add_library(GeographicLib::GeographicLib UNKNOWN IMPORTED)
  set_target_properties(GeographicLib::GeographicLib PROPERTIES
    IMPORTED_LOCATION "${GeographicLib_LIBRARIES}"
    INTERFACE_INCLUDE_DIRECTORIES "${GeographicLib_INCLUDE_DIRS}")
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
  if(ATMOSH_WITH_GPU)
    find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
  endif()
endif()
