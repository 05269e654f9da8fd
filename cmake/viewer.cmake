# The HTML viewer's page template (web/viewer/): bundled by esbuild (node web/viewer/build.mjs)
# and compiled into the library, so `clustersurf view` needs no file at run time.
# Defines CLUSTERSURF_VIEWER_SOURCE (the generated .cpp) for src/CMakeLists.txt. Included once
# per directory: a second include would define the same custom command outputs again.
include_guard(DIRECTORY)
find_program(CLUSTERSURF_NODE node)
foreach(module three esbuild)
  if(NOT EXISTS "${PROJECT_SOURCE_DIR}/node_modules/${module}/package.json")
    set(_clustersurf_missing_module "${module}")
  endif()
endforeach()
if(NOT CLUSTERSURF_NODE OR _clustersurf_missing_module)
  message(FATAL_ERROR "The HTML viewer is bundled at build time with Node.js and the npm packages three and esbuild "
                      "(node: '${CLUSTERSURF_NODE}', missing module: '${_clustersurf_missing_module}'). "
                      "Run scripts/setup (it installs nodejs and runs npm ci), then configure again.")
endif()

file(GLOB CLUSTERSURF_VIEWER_JS CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/web/viewer/src/*.js")
set(_viewer_html "${PROJECT_BINARY_DIR}/generated/viewer/viewer_template.html")
set(CLUSTERSURF_VIEWER_SOURCE "${PROJECT_BINARY_DIR}/generated/viewer/viewer_template.cpp")
add_custom_command(
  OUTPUT "${_viewer_html}"
  COMMAND "${CLUSTERSURF_NODE}" "${PROJECT_SOURCE_DIR}/web/viewer/build.mjs" "${_viewer_html}"
  DEPENDS "${PROJECT_SOURCE_DIR}/web/viewer/build.mjs" "${PROJECT_SOURCE_DIR}/web/viewer/index.html"
          ${CLUSTERSURF_VIEWER_JS} "${PROJECT_SOURCE_DIR}/package-lock.json"
  WORKING_DIRECTORY "${PROJECT_SOURCE_DIR}"
  COMMENT "Bundling the HTML viewer (three.js, esbuild)"
  VERBATIM)
add_custom_command(
  OUTPUT "${CLUSTERSURF_VIEWER_SOURCE}"
  COMMAND "${CMAKE_COMMAND}" "-DINPUT=${_viewer_html}" "-DOUTPUT=${CLUSTERSURF_VIEWER_SOURCE}"
          -P "${PROJECT_SOURCE_DIR}/cmake/embed_file.cmake"
  DEPENDS "${_viewer_html}" "${PROJECT_SOURCE_DIR}/cmake/embed_file.cmake"
  COMMENT "Embedding the viewer template"
  VERBATIM)
