# Installed with atmosh's CMake package: _atmosh_find_package(<key>) finds one external
# package that an atmosh component names in its exported link interface and sets
# _atmosh_have_<key> (TRUE/FALSE) and _atmosh_hint_<key> (the Debian package to install).
# Every search is QUIET and goes through find_package, so a consumer's
# CMAKE_DISABLE_FIND_PACKAGE_<Name> is honoured; atmosh's config file turns a missing
# package into a message for the component that needs it (find_dependency would end the
# whole config file instead, also for components the consumer did not ask for).
# The keys are those of cmake/AtmoshInstall.cmake (_atmosh_package_of).
include_guard(GLOBAL)

macro(_atmosh_find_package key)
  if(NOT DEFINED _atmosh_have_${key})
    set(_atmosh_have_${key} FALSE)
    if("${key}" STREQUAL "glm")
      set(_atmosh_hint_glm "libglm-dev")
      find_package(glm CONFIG QUIET)
      if(NOT TARGET glm::glm AND TARGET glm)
        add_library(glm::glm ALIAS glm)
      endif()
      if(TARGET glm::glm)
        set(_atmosh_have_glm TRUE)
      endif()
    elseif("${key}" STREQUAL "fftw3")
      # Named by its library file in the exported interface: nothing to find here.
      set(_atmosh_hint_fftw3 "libfftw3-dev")
      set(_atmosh_have_fftw3 TRUE)
    elseif("${key}" STREQUAL "GeographicLib")
      set(_atmosh_hint_GeographicLib "libgeographiclib-dev")
      include("${CMAKE_CURRENT_LIST_DIR}/atmoshGeographicLib.cmake")
      set(_atmosh_have_GeographicLib ${ATMOSH_GEOGRAPHICLIB_FOUND})
    elseif("${key}" STREQUAL "OpenGL")
      set(_atmosh_hint_OpenGL "libegl-dev libgl-dev")
      find_package(OpenGL QUIET COMPONENTS OpenGL EGL)
      if(TARGET OpenGL::EGL AND TARGET OpenGL::OpenGL)
        set(_atmosh_have_OpenGL TRUE)
      endif()
    elseif("${key}" STREQUAL "opencv")
      # Three OpenCV modules, located directly (Debian's OpenCVConfig.cmake needs every module).
      set(_atmosh_hint_opencv "libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev")
      find_path(ATMOSH_OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
      set(_atmosh_have_opencv TRUE)
      foreach(_atmosh_m core imgproc imgcodecs)
        find_library(ATMOSH_OPENCV_${_atmosh_m} opencv_${_atmosh_m})
        if(NOT ATMOSH_OPENCV_${_atmosh_m} OR NOT ATMOSH_OPENCV_INCLUDE_DIR)
          set(_atmosh_have_opencv FALSE)
        elseif(NOT TARGET atmosh_opencv::${_atmosh_m})
          add_library(atmosh_opencv::${_atmosh_m} UNKNOWN IMPORTED)
          set_target_properties(atmosh_opencv::${_atmosh_m} PROPERTIES
            IMPORTED_LOCATION "${ATMOSH_OPENCV_${_atmosh_m}}"
            INTERFACE_INCLUDE_DIRECTORIES "${ATMOSH_OPENCV_INCLUDE_DIR}")
        endif()
      endforeach()
    elseif("${key}" STREQUAL "embree")
      set(_atmosh_hint_embree "libembree-dev")
      find_package(embree 3 CONFIG QUIET)
      if(TARGET embree)
        set(_atmosh_have_embree TRUE)
      endif()
    elseif("${key}" STREQUAL "Threads")
      set(_atmosh_hint_Threads "libc6-dev")
      find_package(Threads QUIET)
      set(_atmosh_have_Threads ${Threads_FOUND})
    else()
      # Packages with a CMake config file under their own name (assimp, tinyobjloader,
      # tomlplusplus, nlohmann_json, fmt, CLI11, OpenEXR, TBB).
      set(_atmosh_hint_assimp "libassimp-dev")
      set(_atmosh_hint_tinyobjloader "libtinyobjloader-dev")
      set(_atmosh_hint_tomlplusplus "libtomlplusplus-dev")
      set(_atmosh_hint_nlohmann_json "nlohmann-json3-dev")
      set(_atmosh_hint_fmt "libfmt-dev")
      set(_atmosh_hint_CLI11 "libcli11-dev")
      set(_atmosh_hint_OpenEXR "libopenexr-dev")
      set(_atmosh_hint_TBB "libtbb-dev")
      find_package(${key} CONFIG QUIET)
      set(_atmosh_have_${key} ${${key}_FOUND})
    endif()
  endif()
endmacro()
