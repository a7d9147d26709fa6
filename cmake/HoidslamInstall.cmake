# hoidslam as an installed package (docs/library.md):
#   <prefix>/bin/hoidslam                      the command
#   <prefix>/lib/libhoidslam.so                the public API with every module behind it
#   <prefix>/include/hoidslam/                 hoidslam.h, hoidslam_opencv.h, version.h, core/error.h
#   <prefix>/share/hoidslam/                   config/*.yaml, data/vocabulary/ (core::ShippedDir finds them)
#   <prefix>/share/hoidslam/web/               the viewer's page (installed by web/CMakeLists.txt)
#   <prefix>/lib/cmake/hoidslam/               find_package(hoidslam) → hoidslam::hoidslam
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# libhoidslam.so: the API module's objects, with the modules they use linked in from their static libraries.
add_library(hoidslam_library SHARED $<TARGET_OBJECTS:hoidslam_api>)
target_link_libraries(hoidslam_library PRIVATE hoidslam_api)
target_include_directories(hoidslam_library PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src>
                                                   $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
                                                   $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_compile_features(hoidslam_library PUBLIC cxx_std_20)
set_target_properties(hoidslam_library PROPERTIES OUTPUT_NAME hoidslam EXPORT_NAME hoidslam
                      VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
                      LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/lib)
add_library(hoidslam::hoidslam ALIAS hoidslam_library)

install(TARGETS hoidslam RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS hoidslam_library EXPORT hoidslamTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/src/hoidslam/hoidslam.h ${PROJECT_SOURCE_DIR}/src/hoidslam/hoidslam_opencv.h
              ${PROJECT_BINARY_DIR}/include/hoidslam/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hoidslam)
install(FILES ${PROJECT_SOURCE_DIR}/src/hoidslam/core/error.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hoidslam/core)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config DESTINATION ${CMAKE_INSTALL_DATADIR}/hoidslam)
install(FILES ${PROJECT_SOURCE_DIR}/data/vocabulary/orb-k10-l5.hbow ${PROJECT_SOURCE_DIR}/data/vocabulary/README.md
        DESTINATION ${CMAKE_INSTALL_DATADIR}/hoidslam/data/vocabulary)

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/hoidslam)
install(EXPORT hoidslamTargets NAMESPACE hoidslam:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hoidslamConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/hoidslamConfig.cmake INSTALL_DESTINATION ${config_dir}
                              PATH_VARS CMAKE_INSTALL_DATADIR)
# 0.x: a minor version may change the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hoidslamConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hoidslamConfig.cmake ${PROJECT_BINARY_DIR}/hoidslamConfigVersion.cmake
        DESTINATION ${config_dir})

if(HOIDSLAM_BUILD_TESTS AND HOIDSLAM_TEST_INSTALL)
  # Installs into a fresh prefix and builds and runs examples/cpp against it (about half a minute).
  add_test(NAME install.PackageBuildsAndRunsAConsumer
           COMMAND ${PROJECT_SOURCE_DIR}/scripts/check-install.sh ${PROJECT_BINARY_DIR})
  set_tests_properties(install.PackageBuildsAndRunsAConsumer PROPERTIES SKIP_RETURN_CODE 77 COST 100)
endif()
