# `cmake --install`: the headers, the static libraries and the CMake package clustersurf
# (cmake/clustersurfConfig.cmake.in), so that another project can
#   find_package(clustersurf CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE clustersurf::clustersurf)
# (examples/CMakeLists.txt does). The CLI installs too; the Python module has its own rules.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CLUSTERSURF_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/clustersurf" CACHE STRING
    "Where the CMake package files go, relative to the prefix")

install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/clustersurf" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(FILES "${PROJECT_BINARY_DIR}/generated/clustersurf/version.hpp" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/clustersurf")

set(_clustersurf_parts io tree mesh render evaluation viewer)
foreach(part IN LISTS _clustersurf_parts)
  set_target_properties(clustersurf_${part} PROPERTIES EXPORT_NAME ${part})
endforeach()
install(TARGETS clustersurf clustersurf_io clustersurf_tree clustersurf_mesh clustersurf_render clustersurf_evaluation
                clustersurf_viewer
        EXPORT clustersurfTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(TARGETS clustersurf_cli RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
install(EXPORT clustersurfTargets NAMESPACE clustersurf:: DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/clustersurfConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/clustersurfConfig.cmake"
                              INSTALL_DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/clustersurfConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/clustersurfConfig.cmake" "${PROJECT_BINARY_DIR}/clustersurfConfigVersion.cmake"
        DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")
