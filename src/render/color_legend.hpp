#pragma once
// The color bar of the error view: the distance ramp from 0 to its full-red value, labelled.

#include <clustersurf/render/image.hpp>

#include <string>

namespace clustersurf::render {

/// Draws the green → red distance bar with "0" and ">= max_value" labels and a title in the
/// bottom-left corner of `image`, on a translucent white panel.
void draw_color_legend(Image& image, double max_value, const std::string& title);

}  // namespace clustersurf::render
