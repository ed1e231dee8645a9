# Builds the Debian packages of a build tree (cpack -G DEB) into a scratch folder and
# checks them without installing them on the machine:
#   - atmosh (runtime) declares, through dpkg-shlibdeps, the Debian package of every
#     shared library its ELF files load (NEEDED entries resolved by ldconfig, owners by
#     dpkg -S), except the package's own libatmosh_* libraries;
#   - atmosh-dev depends on libglm-dev (atmosh::sh's public headers include GLM);
#   - the two packages, unpacked into a folder, are a usable prefix: the sh-only consumer
#     project (tests/consumer/sh_only) configures, builds and runs against it.
# Arguments: BUILD_DIR, SOURCE_DIR (tests), WORK_DIR, GENERATOR, CXX.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

get_filename_component(cmake_bin "${CMAKE_COMMAND}" DIRECTORY)
find_program(CPACK cpack HINTS "${cmake_bin}" REQUIRED)
run("cpack -G DEB" ${CPACK} -G DEB --config "${BUILD_DIR}/CPackConfig.cmake" -B "${WORK_DIR}")
file(GLOB runtime_deb "${WORK_DIR}/atmosh_*.deb")
file(GLOB dev_deb "${WORK_DIR}/atmosh-dev_*.deb")
if(NOT runtime_deb OR NOT dev_deb)
  message(FATAL_ERROR "cpack made no atmosh_*.deb or atmosh-dev_*.deb in ${WORK_DIR}")
endif()

run("dpkg-deb -f Depends" dpkg-deb -f "${runtime_deb}" Depends)
string(STRIP "${last_output}" runtime_depends)
run("dpkg-deb -f Depends" dpkg-deb -f "${dev_deb}" Depends)
string(STRIP "${last_output}" dev_depends)
message(STATUS "atmosh Depends: ${runtime_depends}")
string(REGEX REPLACE " *\\([^)]*\\)" "" runtime_packages "${runtime_depends}")  # names only
string(REGEX REPLACE " *[,|] *" ";" runtime_packages "${runtime_packages}")
message(STATUS "atmosh-dev Depends: ${dev_depends}")
if(NOT dev_depends MATCHES "(^|, )libglm-dev($|,| )")
  message(FATAL_ERROR "atmosh-dev does not depend on libglm-dev: ${dev_depends}")
endif()

set(root "${WORK_DIR}/root")
run("dpkg-deb -x" dpkg-deb -x "${runtime_deb}" "${root}")
run("dpkg-deb -x" dpkg-deb -x "${dev_deb}" "${root}")

# NEEDED entries of every ELF file in the runtime package -> owning Debian packages.
run("dpkg-deb -c" dpkg-deb -c "${runtime_deb}")
string(REGEX MATCHALL "\\./[^\n ]+" files "${last_output}")
run("ldconfig -p" ldconfig -p)
set(ldcache "${last_output}")
set(checked 0)
foreach(f IN LISTS files)
  set(path "${root}/${f}")
  if(IS_DIRECTORY "${path}" OR IS_SYMLINK "${path}")
    continue()
  endif()
  execute_process(COMMAND readelf -d "${path}" RESULT_VARIABLE rc OUTPUT_VARIABLE dyn ERROR_QUIET)
  if(NOT rc EQUAL 0)
    continue()  # not an ELF file
  endif()
  string(REGEX MATCHALL "Shared library: \\[[^]]+\\]" needed "${dyn}")
  foreach(n IN LISTS needed)
    string(REGEX REPLACE "Shared library: \\[(.*)\\]" "\\1" lib "${n}")
    if(lib MATCHES "^libatmosh_")
      continue()
    endif()
    string(REPLACE "+" "\\+" lib_re "${lib}")
    string(REPLACE "." "\\." lib_re "${lib_re}")
    if(NOT ldcache MATCHES "${lib_re} \\(libc6,x86-64[^)]*\\) => ([^\n]+)")
      message(FATAL_ERROR "${f} needs ${lib}, which ldconfig does not know")
    endif()
    set(file "${CMAKE_MATCH_1}")
    execute_process(COMMAND dpkg -S "${file}" RESULT_VARIABLE rc OUTPUT_VARIABLE owner ERROR_QUIET)
    if(NOT rc EQUAL 0)  # merged /usr: ldconfig may say /lib/..., dpkg knows /usr/lib/...
      string(REGEX REPLACE "^/(lib|lib64)/" "/usr/\\1/" file "${file}")
      run("dpkg -S ${file}" dpkg -S "${file}")
      set(owner "${last_output}")
    endif()
    string(REGEX REPLACE "^([^:,]+).*" "\\1" owner "${owner}")
    if(NOT owner IN_LIST runtime_packages)
      message(FATAL_ERROR "${f} needs ${lib} (package ${owner}), which atmosh does not depend on: ${runtime_depends}")
    endif()
    math(EXPR checked "${checked} + 1")
  endforeach()
endforeach()
if(checked EQUAL 0)
  message(FATAL_ERROR "no ELF file with dependencies found in ${runtime_deb}")
endif()
message(STATUS "${checked} NEEDED entries, each covered by atmosh's Depends")

# The unpacked packages as a prefix.
file(GLOB_RECURSE config "${root}/*/atmoshConfig.cmake")
get_filename_component(atmosh_dir "${config}" DIRECTORY)
run("configuring tests/consumer/sh_only against the unpacked packages"
    ${CMAKE_COMMAND} -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX}
    -S "${SOURCE_DIR}/consumer/sh_only" -B "${WORK_DIR}/sh_only" -Datmosh_DIR=${atmosh_dir})
run("building it" ${CMAKE_COMMAND} --build "${WORK_DIR}/sh_only")
file(GLOB_RECURSE libdirs LIST_DIRECTORIES true "${root}/*/libatmosh_sh.so*")
set(ld_path)
foreach(l IN LISTS libdirs)
  get_filename_component(d "${l}" DIRECTORY)
  set(ld_path "${d}")
endforeach()
run("running it" ${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${ld_path} "${WORK_DIR}/sh_only/consumer_sh")
message(STATUS "sh_only against the .deb contents: ${last_output}")
