#pragma once
// The options of the renderers (RenderOptions) described once (core/option_spec.hpp): the CLI's
// `render` flags and the Python module's Tree.render() keywords, their help texts and defaults
// are made from this list, and the values either front end is given are checked here.

#include <clustersurf/core/option_spec.hpp>
#include <clustersurf/render/render.hpp>

#include <vector>

namespace clustersurf {

/// An option of render_tree(), render_mesh() and render_points().
using RenderOptionSpec = OptionSpecOf<RenderOptions>;

/// The picture's options (stage Render), in the order the front ends list them: its size and
/// sampling, what it shows, the camera, the background and shading. The framing, the level of
/// detail and the reference points are the callers' to set.
std::vector<RenderOptionSpec> render_option_schema();

/// set_options() over render_option_schema().
void set_options(RenderOptions& o, const OptionValues& values);

/// A background as parse_background() reads it back: "transparent", "white", "black" or "#rrggbb".
std::string background_text(const Rgba8& color);

}  // namespace clustersurf
