# The baker's part of the install (DNG_BUILD_BAKER): dngbake, and dng::baker as its own export set
# with the headers its declarations need. Kept apart from dngridTargets so that find_package(dngrid)
# on a machine without the baker's libraries still gives the runtime.
install(TARGETS dngbake RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
set_target_properties(dng_baker PROPERTIES EXPORT_NAME baker)
install(TARGETS dng_baker EXPORT dngridBakerTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
target_include_directories(dng_baker INTERFACE $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# The public API only (dng/baker/bake.h, dng/baker/import.h); the stages stay internal.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/baker/include/dng/baker DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dng)
install(EXPORT dngridBakerTargets NAMESPACE dng:: DESTINATION ${DNG_CMAKE_DIR})
# Where this build found OpenVDB's Find module (Debian ships no config file), for the package to look too.
configure_file(${CMAKE_CURRENT_LIST_DIR}/dngridBakerDependencies.cmake.in
               ${CMAKE_CURRENT_BINARY_DIR}/dngridBakerDependencies.cmake @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dngridBakerDependencies.cmake DESTINATION ${DNG_CMAKE_DIR})
