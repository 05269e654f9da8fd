# `cmake --install`: the headers, the static libraries and the CMake package clustersurf
# (cmake/clustersurfConfig.cmake.in), so that another project can
#   find_package(clustersurf CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE clustersurf::clustersurf)
# (examples/CMakeLists.txt does). The CLI installs too; the Python module has its own rules.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CLUSTERSURF_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/clustersurf" CACHE STRING
    "Where the CMake package files go, relative to the prefix")

install(FILES "${PROJECT_BINARY_DIR}/generated/clustersurf/version.hpp" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/clustersurf")

# The parts this build has (CLUSTERSURF_MESHING), named in the package config too.
if(CLUSTERSURF_MESHING)
  set(CLUSTERSURF_PARTS io tree mesh render evaluation viewer)
else()
  set(CLUSTERSURF_PARTS io tree viewer)
endif()
set(_clustersurf_targets clustersurf)
foreach(part IN LISTS CLUSTERSURF_PARTS)
  set_target_properties(clustersurf_${part} PROPERTIES EXPORT_NAME ${part})
  list(APPEND _clustersurf_targets clustersurf_${part})
endforeach()
# Each part's header folders (docs/architecture.md, "Parts and layers"); the umbrella header
# with every part.
set(_clustersurf_folders_io core io)
set(_clustersurf_folders_tree spatial proxy cluster surface regions)
set(_clustersurf_folders_mesh mesh pipeline tiling)
set(_clustersurf_folders_render render)
set(_clustersurf_folders_evaluation evaluation)
set(_clustersurf_folders_viewer view)
foreach(part IN LISTS CLUSTERSURF_PARTS)
  foreach(folder IN LISTS _clustersurf_folders_${part})
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/include/clustersurf/${folder}" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/clustersurf")
  endforeach()
endforeach()
if(CLUSTERSURF_MESHING)
  install(FILES "${PROJECT_SOURCE_DIR}/include/clustersurf/clustersurf.hpp" DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/clustersurf")
endif()
install(TARGETS ${_clustersurf_targets}
        EXPORT clustersurfTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
        INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
if(TARGET clustersurf_cli)
  install(TARGETS clustersurf_cli RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")
endif()
install(EXPORT clustersurfTargets NAMESPACE clustersurf:: DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")

configure_package_config_file("${PROJECT_SOURCE_DIR}/cmake/clustersurfConfig.cmake.in"
                              "${PROJECT_BINARY_DIR}/clustersurfConfig.cmake"
                              INSTALL_DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")
write_basic_package_version_file("${PROJECT_BINARY_DIR}/clustersurfConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/clustersurfConfig.cmake" "${PROJECT_BINARY_DIR}/clustersurfConfigVersion.cmake"
        DESTINATION "${CLUSTERSURF_INSTALL_CMAKEDIR}")
