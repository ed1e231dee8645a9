# Locates GeographicLib and provides the imported target GeographicLib::GeographicLib.
# Used by the build (AtmoshDependencies.cmake) and installed with atmosh's CMake package.
#
# GeographicLib's own CMake package (installed by an upstream source build) is taken if
# found. Debian's libgeographiclib-dev ships no package file, only a find-module in
# <prefix>/share/cmake/geographiclib/FindGeographicLib.cmake: it is looked for under
# every prefix CMake searches (CMAKE_PREFIX_PATH, then the system prefixes such as /usr),
# never at one fixed path. Sets ATMOSH_GEOGRAPHICLIB_FOUND. Honours
# CMAKE_DISABLE_FIND_PACKAGE_GeographicLib (both searches go through find_package).
include_guard(GLOBAL)

set(ATMOSH_GEOGRAPHICLIB_FOUND FALSE)
if(NOT TARGET GeographicLib::GeographicLib)
  find_package(GeographicLib CONFIG QUIET)
endif()
if(NOT TARGET GeographicLib::GeographicLib)
  set(_atmosh_geo_dirs)
  foreach(_atmosh_p IN LISTS CMAKE_PREFIX_PATH CMAKE_SYSTEM_PREFIX_PATH)
    list(APPEND _atmosh_geo_dirs "${_atmosh_p}/share/cmake/geographiclib")
  endforeach()
  find_path(ATMOSH_GEOGRAPHICLIB_MODULE_DIR FindGeographicLib.cmake PATHS ${_atmosh_geo_dirs} NO_DEFAULT_PATH)
  if(ATMOSH_GEOGRAPHICLIB_MODULE_DIR)
    set(_atmosh_saved_module_path "${CMAKE_MODULE_PATH}")
    list(PREPEND CMAKE_MODULE_PATH "${ATMOSH_GEOGRAPHICLIB_MODULE_DIR}")
    find_package(GeographicLib MODULE QUIET)
    set(CMAKE_MODULE_PATH "${_atmosh_saved_module_path}")
    if(GeographicLib_FOUND AND NOT TARGET GeographicLib::GeographicLib)
      add_library(GeographicLib::GeographicLib UNKNOWN IMPORTED)
      set_target_properties(GeographicLib::GeographicLib PROPERTIES
        IMPORTED_LOCATION "${GeographicLib_LIBRARIES}"
        INTERFACE_INCLUDE_DIRECTORIES "${GeographicLib_INCLUDE_DIRS}")
    endif()
  endif()
endif()
if(TARGET GeographicLib::GeographicLib)
  set(ATMOSH_GEOGRAPHICLIB_FOUND TRUE)
endif()
