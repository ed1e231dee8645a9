# Installs headers, libraries and a relocatable CMake package: find_package(atmosh).
include(CMakePackageConfigHelpers)
install(EXPORT atmoshTargets NAMESPACE atmosh:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/atmosh)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/atmoshConfig.cmake.in
  ${CMAKE_BINARY_DIR}/atmoshConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/atmosh)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/atmoshConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/atmoshConfig.cmake ${CMAKE_BINARY_DIR}/atmoshConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/atmosh)
