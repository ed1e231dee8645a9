# Installs atmosh: libraries and their headers, the command line, a relocatable CMake
# package with one component per library (find_package(atmosh COMPONENTS sh prt ...)),
# pkg-config files, and the Debian packages of `cpack -G DEB` (runtime and -dev).
# Included at the end of the top-level CMakeLists.txt, once every target exists.
#
# Install components (cmake --install build --component ...): "runtime" holds the
# command line and shared libraries, "dev" the headers, static libraries, the .so
# links, the CMake package and the pkg-config files.
include(CMakePackageConfigHelpers)
set(ATMOSH_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/atmosh)
set(ATMOSH_PKGCONFIG_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# External package of one link item (an imported target or a library file): a key of
# cmake/atmoshFindDependency.cmake, "" for what needs nothing, "?" for an unknown item.
function(_atmosh_package_of item out)
  set(key "?")
  if(item MATCHES "^glm(::glm)?$")
    set(key glm)
  elseif(item MATCHES "^GeographicLib::")
    set(key GeographicLib)
  elseif(item MATCHES "^OpenGL::")
    set(key OpenGL)
  elseif(item MATCHES "^(OpenEXR|Imath)::")
    set(key OpenEXR)
  elseif(item MATCHES "^atmosh_opencv::")
    set(key opencv)
  elseif(item MATCHES "^atmosh_netcdf::")
    set(key netcdf)
  elseif(item STREQUAL "embree")
    set(key embree)
  elseif(item MATCHES "^(tinyobjloader|assimp|tomlplusplus|nlohmann_json|fmt|CLI11|TBB)::")
    set(key ${CMAKE_MATCH_1})
  elseif(item STREQUAL "Threads::Threads")
    set(key Threads)
  elseif(item MATCHES "/libfftw3\\.(so|a)$")
    set(key fftw3)
  elseif(item MATCHES "^-?l?(pthread|m|dl|rt)$")
    set(key "")
  endif()
  set(${out} "${key}" PARENT_SCOPE)
endfunction()

# Per key: pkg-config modules (or linker flags where the package has no .pc file) and
# the Debian development packages a static consumer needs.
set(_atmosh_pc_glm glm)
set(_atmosh_deb_glm libglm-dev)
set(_atmosh_pc_fftw3 fftw3)
set(_atmosh_deb_fftw3 libfftw3-dev)
set(_atmosh_pc_GeographicLib geographiclib)
set(_atmosh_deb_GeographicLib libgeographiclib-dev)
set(_atmosh_pc_OpenGL egl opengl)
set(_atmosh_deb_OpenGL libegl-dev libgl-dev)
set(_atmosh_pc_OpenEXR OpenEXR)
set(_atmosh_deb_OpenEXR libopenexr-dev)
set(_atmosh_libs_opencv -lopencv_imgcodecs -lopencv_imgproc -lopencv_core)
set(_atmosh_deb_opencv libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev)
set(_atmosh_pc_netcdf netcdf)
set(_atmosh_deb_netcdf libnetcdf-dev)
set(_atmosh_libs_embree -lembree3)
set(_atmosh_deb_embree libembree-dev)
set(_atmosh_pc_tinyobjloader tinyobjloader)
set(_atmosh_deb_tinyobjloader libtinyobjloader-dev)
set(_atmosh_pc_assimp assimp)
set(_atmosh_deb_assimp libassimp-dev)
set(_atmosh_libs_Threads -pthread)
set(_atmosh_pc_tomlplusplus tomlplusplus)
set(_atmosh_deb_tomlplusplus libtomlplusplus-dev)
set(_atmosh_pc_nlohmann_json nlohmann_json)
set(_atmosh_deb_nlohmann_json nlohmann-json3-dev)
set(_atmosh_pc_fmt fmt)
set(_atmosh_deb_fmt libfmt-dev)
set(_atmosh_deb_CLI11 libcli11-dev)
set(_atmosh_pc_TBB tbb)
set(_atmosh_deb_TBB libtbb-dev)

# atmosh_install_component(<component> <target>): installs library <target> as the
# CMake target atmosh::<component> (its own export file), its public headers (the
# source-tree folders of its public include directories) and atmosh-<component>.pc.
# Does nothing when <target> is not built (e.g. gpu with ATMOSH_WITH_GPU=OFF).
# Components are listed in dependency order; dependencies are read from the target.
function(atmosh_install_component component target)
  if(NOT TARGET ${target})
    return()
  endif()
  set_property(GLOBAL APPEND PROPERTY ATMOSH_COMPONENTS ${component})
  set_property(GLOBAL PROPERTY ATMOSH_TARGET_${component} ${target})
  set_property(GLOBAL PROPERTY ATMOSH_COMPONENT_OF_${target} ${component})
  # Shared libraries: versioned (dpkg-shlibdeps and the shlibs file need a SONAME), and
  # no <target>_EXPORTS define (the same compile line as a static build: ccache hits).
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${component}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR} DEFINE_SYMBOL "")
  if(BUILD_SHARED_LIBS AND CMAKE_INSTALL_RPATH STREQUAL "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
    # Installed libraries find each other beside themselves (RUNPATH is not inherited
    # from the executable).
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN")
  endif()

  # Public include folders inside the tree: build-tree only in the export, installed
  # under include/ (where every atmosh header lives, <atmosh/...>).
  get_target_property(_inc ${target} INTERFACE_INCLUDE_DIRECTORIES)
  set(_new_inc)
  set(_headers)
  foreach(_d IN LISTS _inc)
    string(FIND "${_d}/" "${PROJECT_SOURCE_DIR}/" _in_source)
    string(FIND "${_d}/" "${PROJECT_BINARY_DIR}/" _in_build)
    if(_d MATCHES "^\\$<BUILD_INTERFACE:(.*)>$")
      list(APPEND _headers "${CMAKE_MATCH_1}")
      list(APPEND _new_inc "${_d}")
    elseif(_d MATCHES "^\\$<INSTALL_INTERFACE:")
    elseif(_in_source EQUAL 0 OR _in_build EQUAL 0)
      list(APPEND _headers "${_d}")
      list(APPEND _new_inc "$<BUILD_INTERFACE:${_d}>")
    elseif(_d)
      list(APPEND _new_inc "${_d}")
    endif()
  endforeach()
  list(APPEND _new_inc "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")
  set_property(TARGET ${target} PROPERTY INTERFACE_INCLUDE_DIRECTORIES "${_new_inc}")
  foreach(_h IN LISTS _headers)
    install(DIRECTORY "${_h}/" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
  endforeach()

  install(TARGETS ${target} EXPORT atmosh-${component}-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(EXPORT atmosh-${component}-targets NAMESPACE atmosh:: FILE atmosh-${component}-targets.cmake
    DESTINATION ${ATMOSH_CMAKE_INSTALL_DIR} COMPONENT dev)
endfunction()

# Link items of a target, aliases resolved: public (targets its exported link interface
# names without $<LINK_ONLY:>) and private (the rest of what it links; library files
# and flags carry no usage requirements and count as private).
function(_atmosh_link_items target out_public out_private)
  get_target_property(_iface ${target} INTERFACE_LINK_LIBRARIES)
  get_target_property(_all ${target} LINK_LIBRARIES)
  set(_pub)
  set(_priv)
  foreach(_l IN LISTS _iface _all)
    set(_private TRUE)
    if(_l MATCHES "^\\$<LINK_ONLY:(.*)>$")
      set(_l "${CMAKE_MATCH_1}")
    elseif(_l MATCHES "^\\$<")   # $<BUILD_INTERFACE:...> and the like: not exported
      continue()
    elseif(_l IN_LIST _iface AND TARGET "${_l}")
      set(_private FALSE)
    endif()
    if(NOT _l)
      continue()
    endif()
    if(TARGET "${_l}")
      get_target_property(_aliased "${_l}" ALIASED_TARGET)
      if(_aliased)
        set(_l "${_aliased}")
      endif()
    endif()
    if(_private)
      list(APPEND _priv "${_l}")
    else()
      list(APPEND _pub "${_l}")
    endif()
  endforeach()
  if(_pub)
    list(REMOVE_DUPLICATES _pub)
  endif()
  foreach(_l IN LISTS _pub)
    list(REMOVE_ITEM _priv "${_l}")
  endforeach()
  if(_priv)
    list(REMOVE_DUPLICATES _priv)
  endif()
  set(${out_public} "${_pub}" PARENT_SCOPE)
  set(${out_private} "${_priv}" PARENT_SCOPE)
endfunction()

# The installed libraries, in dependency order. A new library is one line here.
atmosh_install_component(core atmosh_core)
atmosh_install_component(sh atmosh_sh)
atmosh_install_component(atmo atmosh_atmo)
atmosh_install_component(gpu atmosh_gpu)
atmosh_install_component(io atmosh_io)
atmosh_install_component(scene atmosh_scene)
atmosh_install_component(prt atmosh_prt)
atmosh_install_component(studies atmosh_studies)
atmosh_install_component(gi atmosh_gi)

if(TARGET atmosh)
  install(TARGETS atmosh RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
endif()

# ---- CMake package and pkg-config files, from what each component links --------------
get_property(ATMOSH_COMPONENTS GLOBAL PROPERTY ATMOSH_COMPONENTS)
get_target_property(_atmosh_type atmosh_sh TYPE)
if(_atmosh_type STREQUAL "SHARED_LIBRARY")
  set(ATMOSH_LIBRARY_KIND shared)
else()
  set(ATMOSH_LIBRARY_KIND static)
endif()
set(ATMOSH_COMPONENT_TABLE "# Written by cmake/AtmoshInstall.cmake: components in dependency order, the\n# components each one loads first, and the external packages it needs.\nset(_atmosh_components ${ATMOSH_COMPONENTS})\n")
set(_atmosh_all_pc_modules)
set(_atmosh_all_dev_debs)
foreach(_c IN LISTS ATMOSH_COMPONENTS)
  get_property(_t GLOBAL PROPERTY ATMOSH_TARGET_${_c})
  _atmosh_link_items(${_t} _pub _priv)
  set(_needs)            # atmosh components, transitively
  set(_packages)         # external package keys the exported targets name
  set(_pc_requires)      # pkg-config
  set(_pc_requires_private)
  set(_pc_libs)
  set(_pc_libs_private)
  foreach(_scope pub priv)
    foreach(_l IN LISTS _${_scope})
      if(TARGET "${_l}" AND _l MATCHES "^atmosh_[a-z0-9_]+$" AND NOT _l MATCHES "^atmosh_opencv")
        get_property(_dc GLOBAL PROPERTY ATMOSH_COMPONENT_OF_${_l})
        if(NOT _dc)
          message(FATAL_ERROR "atmosh::${_c} links ${_l}, which is not installed: add "
            "atmosh_install_component(<name> ${_l}) before it in cmake/AtmoshInstall.cmake")
        endif()
        get_property(_dneeds GLOBAL PROPERTY ATMOSH_NEEDS_${_dc})
        list(APPEND _needs ${_dneeds} ${_dc})
        if(_scope STREQUAL "pub")
          list(APPEND _pc_requires atmosh-${_dc})
        else()
          list(APPEND _pc_requires_private atmosh-${_dc})
        endif()
        continue()
      endif()
      _atmosh_package_of("${_l}" _key)
      if(_key STREQUAL "?")
        message(FATAL_ERROR "atmosh::${_c} links '${_l}': name its package in _atmosh_package_of "
          "(cmake/AtmoshInstall.cmake) and how to find it in cmake/atmoshFindDependency.cmake")
      elseif(NOT _key)
        continue()
      endif()
      if(_scope STREQUAL "pub" OR ATMOSH_LIBRARY_KIND STREQUAL "static")
        list(APPEND _packages ${_key})
        list(APPEND _atmosh_all_dev_debs ${_atmosh_deb_${_key}})
      endif()
      if(_scope STREQUAL "pub")
        list(APPEND _pc_requires ${_atmosh_pc_${_key}})
        list(APPEND _pc_libs ${_atmosh_libs_${_key}})
      else()
        list(APPEND _pc_requires_private ${_atmosh_pc_${_key}})
        list(APPEND _pc_libs_private ${_atmosh_libs_${_key}})
      endif()
    endforeach()
  endforeach()
  foreach(_v _needs _packages _pc_requires _pc_requires_private _pc_libs _pc_libs_private)
    if(${_v})
      list(REMOVE_DUPLICATES ${_v})
    endif()
  endforeach()
  set_property(GLOBAL PROPERTY ATMOSH_NEEDS_${_c} ${_needs})
  string(APPEND ATMOSH_COMPONENT_TABLE "set(_atmosh_needs_${_c} ${_needs})\nset(_atmosh_packages_${_c} ${_packages})\n")

  # atmosh-<component>.pc; the prefix is the one installed into (cmake --install --prefix,
  # or /usr inside the .deb), filled in at install time.
  get_target_property(_out ${_t} OUTPUT_NAME)
  if(NOT _out)
    set(_out ${_t})
  endif()
  get_target_property(_type ${_t} TYPE)
  set(_own_lib "-L\${libdir} -l${_out}")
  if(_type STREQUAL "INTERFACE_LIBRARY")  # headers only
    set(_own_lib "")
  endif()
  list(JOIN _pc_requires " " _r)
  list(JOIN _pc_requires_private " " _rp)
  list(JOIN _pc_libs " " _lpub)
  list(JOIN _pc_libs_private " " _lp)
  file(WRITE ${PROJECT_BINARY_DIR}/pkgconfig/atmosh-${_c}.pc.in
"prefix=@ATMOSH_PC_PREFIX@
libdir=\${prefix}/${CMAKE_INSTALL_LIBDIR}
includedir=\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}

Name: atmosh-${_c}
Description: atmosh::${_c} (${PROJECT_DESCRIPTION}), ${ATMOSH_LIBRARY_KIND} library
Version: ${PROJECT_VERSION}
Requires: ${_r}
Requires.private: ${_rp}
Cflags: -I\${includedir}
Libs: ${_own_lib} ${_lpub}
Libs.private: ${_lp}
")
  list(APPEND _atmosh_all_pc_modules atmosh-${_c})
endforeach()

list(REVERSE _atmosh_all_pc_modules)
list(JOIN _atmosh_all_pc_modules " " _r)
file(WRITE ${PROJECT_BINARY_DIR}/pkgconfig/atmosh.pc.in
"prefix=@ATMOSH_PC_PREFIX@

Name: atmosh
Description: ${PROJECT_DESCRIPTION}: every installed library (atmosh-<component> for one)
Version: ${PROJECT_VERSION}
Requires: ${_r}
")
foreach(_pc IN LISTS _atmosh_all_pc_modules ITEMS atmosh)
  install(CODE "
    file(READ \"${PROJECT_BINARY_DIR}/pkgconfig/${_pc}.pc.in\" _atmosh_pc)
    string(REPLACE \"@ATMOSH_PC_PREFIX@\" \"\${CMAKE_INSTALL_PREFIX}\" _atmosh_pc \"\${_atmosh_pc}\")
    set(_atmosh_pc_file \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${ATMOSH_PKGCONFIG_INSTALL_DIR}/${_pc}.pc\")
    message(STATUS \"Installing: \${_atmosh_pc_file}\")
    file(WRITE \"\${_atmosh_pc_file}\" \"\${_atmosh_pc}\")" COMPONENT dev)
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/atmoshConfig.cmake.in
  ${PROJECT_BINARY_DIR}/atmoshConfig.cmake
  INSTALL_DESTINATION ${ATMOSH_CMAKE_INSTALL_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/atmoshConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/atmoshConfig.cmake ${PROJECT_BINARY_DIR}/atmoshConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/atmoshFindDependency.cmake ${CMAKE_CURRENT_LIST_DIR}/atmoshGeographicLib.cmake
  DESTINATION ${ATMOSH_CMAKE_INSTALL_DIR} COMPONENT dev)

# ---- Debian packages: cpack -G DEB (from a build configured with CMAKE_INSTALL_PREFIX=/usr)
# atmosh (runtime: the command line, and the shared libraries of a shared build) and
# atmosh-dev (headers, CMake package, pkg-config files, static libraries or .so links).
# The runtime package's dependencies come from dpkg-shlibdeps; atmosh-dev depends on
# the -dev packages of what its libraries expose (a static build: everything they link).
list(REMOVE_DUPLICATES _atmosh_all_dev_debs)
set(CPACK_PACKAGE_NAME atmosh)
set(CPACK_PACKAGE_VENDOR "atmosh")
set(CPACK_PACKAGE_CONTACT "atmosh maintainers <atmosh@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME atmosh)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION science)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME atmosh-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "${PROJECT_DESCRIPTION}: the atmosh command line and libraries")
set(CPACK_COMPONENT_DEV_DESCRIPTION "${PROJECT_DESCRIPTION}: headers, CMake package and pkg-config files")
list(JOIN _atmosh_all_dev_debs ", " CPACK_DEBIAN_DEV_PACKAGE_DEPENDS)
if(ATMOSH_LIBRARY_KIND STREQUAL "shared")
  # The libraries are in the runtime package (with a shlibs file): atmosh-dev needs
  # exactly that version. dpkg-shlibdeps resolves the links between the packaged files
  # through their RUNPATH ($ORIGIN..., set above).
  set(CPACK_COMPONENT_DEV_DEPENDS runtime)
  set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
  set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
endif()
include(CPack)
