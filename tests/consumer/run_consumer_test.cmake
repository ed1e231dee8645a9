# Installs the build tree into a scratch prefix, then configures, builds and runs the
# consumer projects under tests/consumer against it:
#   sh_only   find_package(atmosh COMPONENTS sh), with every lookup of GeographicLib,
#             EGL and OpenGL poisoned (see below);
#   prt       find_package(atmosh COMPONENTS prt): a bake through the installed library;
#   pkgconfig sh_only/main.cpp compiled with `pkg-config --cflags --libs atmosh`;
#   python    python/consumer.py: the installed Python package (component `python`,
#             PREFIX/<PYTHON_DIR>/atmosh) imported with PYTHONPATH set to that folder
#             computes a sun position (skipped when the module is not built).
# Arguments: BUILD_DIR, SOURCE_DIR (tests/consumer), WORK_DIR, GENERATOR, CXX, SHARED,
# LAUNCHER (the build's compiler launcher, e.g. ccache: repeated runs compile nothing),
# PYTHON (the interpreter; empty: no Python module), PYTHON_DIR (where the package goes,
# relative to the prefix).
#
# The poison: a folder put first on CMAKE_PREFIX_PATH and CMAKE_MODULE_PATH whose
# GeographicLib, OpenGL and EGL package files and find-modules stop the configuration
# with FATAL_ERROR. Any find_package() of those packages, in config or module mode, would
# load one of them before the real one (Debian's files are found through the same
# paths, after these). The sh-only consumer must configure through it; controls show
# that each poison stops a lookup of its package.
file(REMOVE_RECURSE "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
set(poison "${WORK_DIR}/poison")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run("cmake --install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")

foreach(pkg GeographicLib OpenGL EGL)
  set(stop "message(FATAL_ERROR \"atmosh consumer poison: ${pkg} was looked for\")\n")
  file(WRITE "${poison}/share/cmake/${pkg}/${pkg}Config.cmake" "${stop}")
  file(WRITE "${poison}/modules/Find${pkg}.cmake" "${stop}")
endforeach()
file(WRITE "${poison}/init.cmake" "set(CMAKE_PREFIX_PATH \"${poison};${prefix}\" CACHE PATH \"\")
set(CMAKE_MODULE_PATH \"${poison}/modules\" CACHE PATH \"\")\n")
set(poisoned -C "${poison}/init.cmake")

set(configure ${CMAKE_COMMAND} -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX})
if(LAUNCHER)
  list(APPEND configure -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()

# sh only, poisoned
run("configuring tests/consumer/sh_only (GeographicLib, OpenGL, EGL poisoned)"
    ${configure} -S "${SOURCE_DIR}/sh_only" -B "${WORK_DIR}/sh_only" ${poisoned})
run("building tests/consumer/sh_only" ${CMAKE_COMMAND} --build "${WORK_DIR}/sh_only")
run("running consumer_sh" "${WORK_DIR}/sh_only/consumer_sh")
message(STATUS "sh_only: ${last_output}")

# Controls: the poison bites. atmosh's own GeographicLib lookup and find_package of
# OpenGL and EGL, each in an empty project, must stop on their poison.
set(atmosh_cmake_dir "${prefix}/lib/cmake/atmosh")
if(NOT EXISTS "${atmosh_cmake_dir}")
  file(GLOB atmosh_cmake_dir "${prefix}/lib/*/cmake/atmosh")
endif()
file(WRITE "${WORK_DIR}/control/CMakeLists.txt" "cmake_minimum_required(VERSION 3.25)
project(poison_control NONE)
if(WHAT STREQUAL \"GeographicLib\")
  include(\"${atmosh_cmake_dir}/atmoshGeographicLib.cmake\")
else()
  find_package(\${WHAT})
endif()
")
foreach(pkg GeographicLib OpenGL EGL)
  execute_process(COMMAND ${CMAKE_COMMAND} -S "${WORK_DIR}/control" -B "${WORK_DIR}/control/${pkg}" ${poisoned} -DWHAT=${pkg}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc EQUAL 0 OR NOT out MATCHES "atmosh consumer poison: ${pkg} was looked for")
    message(FATAL_ERROR "control: looking for ${pkg} under the poison should stop on it (${rc}):\n${out}")
  endif()
endforeach()
# atmosh::atmo links GeographicLib privately: a static archive's consumer needs it (the
# configuration must stop on the poison), a shared library's does not (it must pass).
execute_process(COMMAND ${configure} -S "${SOURCE_DIR}/sh_only" -B "${WORK_DIR}/atmo" ${poisoned}
                -DATMOSH_CONSUMER_COMPONENTS=atmo
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(SHARED AND NOT rc EQUAL 0)
  message(FATAL_ERROR "shared build: atmosh::atmo should configure without GeographicLib (${rc}):\n${out}")
elseif(NOT SHARED AND (rc EQUAL 0 OR NOT out MATCHES "atmosh consumer poison: GeographicLib was looked for"))
  message(FATAL_ERROR "static build: atmosh::atmo under the poison should stop on GeographicLib (${rc}):\n${out}")
endif()

# find_package(atmosh) without COMPONENTS where GeographicLib, OpenGL and EGL are absent
# (CMAKE_DISABLE_FIND_PACKAGE_*): it loads what it can, atmosh::sh among them, and says
# what it left out (a static build: atmo and everything above it).
execute_process(COMMAND ${configure} -S "${SOURCE_DIR}/sh_only" -B "${WORK_DIR}/all" -DCMAKE_PREFIX_PATH=${prefix}
                -DATMOSH_CONSUMER_COMPONENTS= -DCMAKE_DISABLE_FIND_PACKAGE_GeographicLib=ON
                -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON -DCMAKE_DISABLE_FIND_PACKAGE_EGL=ON
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0 OR (NOT SHARED AND NOT out MATCHES "atmosh::atmo needs GeographicLib"))
  message(FATAL_ERROR "find_package(atmosh) without COMPONENTS, GeographicLib/OpenGL/EGL disabled (${rc}):\n${out}")
endif()

# prt
run("configuring tests/consumer/prt" ${configure} -S "${SOURCE_DIR}/prt" -B "${WORK_DIR}/prt" -DCMAKE_PREFIX_PATH=${prefix})
run("building tests/consumer/prt" ${CMAKE_COMMAND} --build "${WORK_DIR}/prt")
run("running consumer_prt" "${WORK_DIR}/prt/consumer_prt")
message(STATUS "prt: ${last_output}")

# pkg-config
find_program(PKG_CONFIG NAMES pkg-config pkgconf REQUIRED)
file(GLOB_RECURSE pcs "${prefix}/*/atmosh.pc")
list(GET pcs 0 pc)
get_filename_component(pcdir "${pc}" DIRECTORY)
get_filename_component(libdir "${pcdir}" DIRECTORY)
set(static)
if(NOT SHARED)
  set(static --static)  # static archives: their own dependencies go on the link line too
endif()
run("pkg-config ${static} --cflags --libs atmosh"
    ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pcdir} ${PKG_CONFIG} ${static} --cflags --libs atmosh)
string(STRIP "${last_output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
run("compiling sh_only/main.cpp with pkg-config's flags"
    ${LAUNCHER} ${CXX} -std=c++20 "${SOURCE_DIR}/sh_only/main.cpp" ${flags} -o "${WORK_DIR}/consumer_pkgconfig")
run("running consumer_pkgconfig" ${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${libdir} "${WORK_DIR}/consumer_pkgconfig")
message(STATUS "pkgconfig: ${last_output}")

# Python
if(PYTHON)
  set(pydir "${prefix}/${PYTHON_DIR}")
  if(NOT EXISTS "${pydir}/atmosh/__init__.py")
    message(FATAL_ERROR "the Python module is built but not installed into ${pydir}/atmosh")
  endif()
  run("running python/consumer.py with PYTHONPATH=${pydir}"
      ${CMAKE_COMMAND} -E env PYTHONPATH=${pydir} LD_LIBRARY_PATH=${libdir} PYTHONDONTWRITEBYTECODE=1
      ${PYTHON} "${SOURCE_DIR}/python/consumer.py" "${prefix}")
  message(STATUS "python: ${last_output}")
else()
  message(STATUS "python: skipped (the Python module is not built)")
endif()
