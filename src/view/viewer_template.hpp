#pragma once
// The viewer page template: web/viewer/index.html with the bundled script inlined, produced by
// web/viewer/build.mjs and compiled into the library by cmake/embed_file.cmake (no runtime
// file lookup).

#include <string_view>

namespace clustersurf::view {

/// The marker in the template that write_viewer_html() replaces with the data blocks.
inline constexpr std::string_view kDataMarker = "<!--CLUSTERSURF_DATA-->";

/// The template's bytes (UTF-8 HTML holding kDataMarker exactly once).
std::string_view viewer_template();

}  // namespace clustersurf::view
