# The CMake package (docs/python.md "From your C++ project"): `cmake --install build --prefix P`
# installs the library (static, position-independent), the public headers include/dampsym/
# (dampsym.hpp: the C++ API; plugin.h: the plugin ABI), the dampsym command line and
# P/lib/cmake/dampsym/dampsymConfig.cmake with its version file and exported target
# dampsym::dampsym; a consumer's find_package(dampsym) finds the library's dependencies with
# find_dependency (cmake/dampsymConfig.cmake.in). examples/consumer/ is such a consumer.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(DAMPSYM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/dampsym)
install(TARGETS dampsym_lib EXPORT dampsymTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS dampsym RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES include/dampsym/dampsym.hpp include/dampsym/plugin.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/dampsym)
install(EXPORT dampsymTargets NAMESPACE dampsym:: DESTINATION ${DAMPSYM_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/dampsymConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/dampsymConfig.cmake
                              INSTALL_DESTINATION ${DAMPSYM_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/dampsymConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dampsymConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/dampsymConfigVersion.cmake
        DESTINATION ${DAMPSYM_INSTALL_CMAKEDIR})

# ctest package.consumer: install into a temporary prefix, then configure, build and test
# examples/consumer against it (cmake/consumer_test.cmake).
if(DAMPSYM_TESTS AND NOT DAMPSYM_SANITIZE)
  add_test(NAME package.consumer
           COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR}
                   -DSOURCE_DIR=${CMAKE_CURRENT_SOURCE_DIR}/examples/consumer
                   -DWORK_DIR=${CMAKE_BINARY_DIR}/consumer-test
                   -DCXX=${CMAKE_CXX_COMPILER} -DLAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/cmake/consumer_test.cmake)
  set_tests_properties(package.consumer PROPERTIES LABELS "package" TIMEOUT 600)
endif()
