# The HTML viewer's page template (web/viewer/), compiled into the library so that
# `clustersurf view` needs no file at run time. The page is checked in, bundled
# (web/viewer/dist/viewer.html), so building needs no Node.js. Where Node.js and the npm packages
# three and esbuild are installed (scripts/setup), the build bundles the page from its sources
# instead (node web/viewer/build.mjs), and the test viewer_bundle_current fails while the
# checked-in copy differs from it (scripts/bundle-viewer regenerates it).
# Defines CLUSTERSURF_VIEWER_SOURCE (the generated .cpp) for src/CMakeLists.txt. Included once
# per directory: a second include would define the same custom command outputs again.
include_guard(DIRECTORY)
set(CLUSTERSURF_BUNDLE_VIEWER AUTO CACHE STRING
    "Bundle the viewer page from web/viewer/src with Node.js: ON, OFF (embed the checked-in web/viewer/dist/viewer.html), or AUTO (when node and the npm packages are installed)")
set_property(CACHE CLUSTERSURF_BUNDLE_VIEWER PROPERTY STRINGS AUTO ON OFF)

set(CLUSTERSURF_VIEWER_PAGE "${PROJECT_SOURCE_DIR}/web/viewer/dist/viewer.html")
set(CLUSTERSURF_VIEWER_BUNDLED OFF CACHE INTERNAL "" FORCE)
find_program(CLUSTERSURF_NODE node)  # the viewer's browser test runs on it too
if(CLUSTERSURF_BUNDLE_VIEWER)  # AUTO or ON
  set(_clustersurf_missing_module "")
  foreach(module three esbuild)
    if(NOT EXISTS "${PROJECT_SOURCE_DIR}/node_modules/${module}/package.json")
      set(_clustersurf_missing_module "${module}")
    endif()
  endforeach()
  if(CLUSTERSURF_NODE AND NOT _clustersurf_missing_module)
    set(CLUSTERSURF_VIEWER_BUNDLED ON CACHE INTERNAL "" FORCE)
  elseif(NOT CLUSTERSURF_BUNDLE_VIEWER STREQUAL "AUTO")
    message(FATAL_ERROR "CLUSTERSURF_BUNDLE_VIEWER=ON needs Node.js and the npm packages three and esbuild "
                        "(node: '${CLUSTERSURF_NODE}', missing module: '${_clustersurf_missing_module}'). "
                        "Run scripts/setup (it installs nodejs and runs npm ci), or configure with OFF.")
  endif()
endif()

set(CLUSTERSURF_VIEWER_SOURCE "${PROJECT_BINARY_DIR}/generated/viewer/viewer_template.cpp")
if(CLUSTERSURF_VIEWER_BUNDLED)
  message(STATUS "Viewer page: bundled from web/viewer/src (${CLUSTERSURF_NODE})")
  file(GLOB CLUSTERSURF_VIEWER_JS CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/web/viewer/src/*.js")
  set(_viewer_html "${PROJECT_BINARY_DIR}/generated/viewer/viewer_template.html")
  add_custom_command(
    OUTPUT "${_viewer_html}"
    COMMAND "${CLUSTERSURF_NODE}" "${PROJECT_SOURCE_DIR}/web/viewer/build.mjs" "${_viewer_html}"
    DEPENDS "${PROJECT_SOURCE_DIR}/web/viewer/build.mjs" "${PROJECT_SOURCE_DIR}/web/viewer/index.html"
            ${CLUSTERSURF_VIEWER_JS} "${PROJECT_SOURCE_DIR}/package-lock.json"
    WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
    COMMENT "Bundling the HTML viewer (three.js, esbuild)"
    VERBATIM)
else()
  message(STATUS "Viewer page: the checked-in web/viewer/dist/viewer.html")
  set(_viewer_html "${CLUSTERSURF_VIEWER_PAGE}")
endif()
add_custom_command(
  OUTPUT "${CLUSTERSURF_VIEWER_SOURCE}"
  COMMAND "${CMAKE_COMMAND}" "-DINPUT=${_viewer_html}" "-DOUTPUT=${CLUSTERSURF_VIEWER_SOURCE}"
          -P "${PROJECT_SOURCE_DIR}/cmake/embed_file.cmake"
  DEPENDS "${_viewer_html}" "${PROJECT_SOURCE_DIR}/cmake/embed_file.cmake"
  COMMENT "Embedding the viewer template"
  VERBATIM)
