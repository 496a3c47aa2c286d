# Install rules and the relocatable CMake package: find_package(dngrid) -> dng::runtime, dng::format,
# dng::writer, dng::c (the C ABI, libdngrid).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS dng_format dng_runtime dng_writer dng_c EXPORT dngridTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/format/include/ ${PROJECT_SOURCE_DIR}/runtime/include/
        ${PROJECT_BINARY_DIR}/runtime/generated/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(EXPORT dngridTargets NAMESPACE dng:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dngrid)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/dngridConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/dngridConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dngrid)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/dngridConfigVersion.cmake
                                 COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dngridConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/dngridConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dngrid)
