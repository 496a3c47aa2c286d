# Install rules, the relocatable CMake package and the pkg-config file:
#   find_package(dngrid) -> dng::runtime, dng::format, dng::writer, dng::c (the C ABI, libdngrid), and
#   dng::baker when the baker was built and its libraries are found (required with COMPONENTS baker);
#   pkg-config dngrid -> libdngrid and its header dng/dng.h.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DNG_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/dngrid)

# Installed names match the in-tree aliases: dng::runtime, not dng::dng_runtime.
set_target_properties(dng_format PROPERTIES EXPORT_NAME format)
set_target_properties(dng_runtime PROPERTIES EXPORT_NAME runtime)
set_target_properties(dng_writer PROPERTIES EXPORT_NAME writer)
set_target_properties(dng_c PROPERTIES EXPORT_NAME c)

install(TARGETS dng_format dng_runtime dng_writer dng_c EXPORT dngridTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/format/include/ ${PROJECT_SOURCE_DIR}/runtime/include/
        ${PROJECT_BINARY_DIR}/runtime/generated/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(EXPORT dngridTargets NAMESPACE dng:: DESTINATION ${DNG_CMAKE_DIR})

# dngdump reads files through the runtime alone: installed whenever it was built, baker or not.
if(TARGET dngdump)
  install(TARGETS dngdump RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
if(DNG_BUILD_BAKER)
  include(DngInstallBaker)
endif()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/dngridConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/dngridConfig.cmake INSTALL_DESTINATION ${DNG_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/dngridConfigVersion.cmake
                                 COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dngridConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/dngridConfigVersion.cmake
        DESTINATION ${DNG_CMAKE_DIR})

# pkg-config: paths relative to the .pc file, so an installed tree can be moved (cmake --install --prefix).
file(RELATIVE_PATH DNG_PC_TO_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
configure_file(${CMAKE_CURRENT_LIST_DIR}/dngrid.pc.in ${CMAKE_CURRENT_BINARY_DIR}/dngrid.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dngrid.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
