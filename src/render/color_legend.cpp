// Color bar legend for the error view.

#include "render/color_legend.hpp"

#include <clustersurf/surface/palette.hpp>

#include <algorithm>
#include <cstdio>

namespace clustersurf::render {

void draw_color_legend(Image& image, double max_value, const std::string& title) {
  const int scale = std::max(1, image.height / 400);
  const int bar_w = std::max(60, image.width / 3), bar_h = std::max(6, image.height / 50);
  const int margin = std::max(4, image.width / 40), text_h = 9 * scale;
  char label[64];
  std::snprintf(label, sizeof label, ">= %.3g", max_value);
  const int panel_w = std::max({bar_w, text_width(title, scale), 0}) + 2 * margin / 2;
  const int panel_h = bar_h + 2 * text_h + margin;
  const int px = margin / 2, py = image.height - panel_h - margin / 2;
  fill_rect(image, px, py, panel_w, panel_h, {255, 255, 255, 200});
  const int bx = px + margin / 2, by = py + margin / 4 + text_h;
  const Rgba8 ink{30, 30, 30, 255};
  draw_text(image, bx, py + margin / 4, title, ink, scale);
  for (int i = 0; i < bar_w; ++i) {
    const auto c = distance_color(static_cast<double>(i) / (bar_w - 1));
    fill_rect(image, bx + i, by, 1, bar_h, {c.x(), c.y(), c.z(), 255});
  }
  draw_text(image, bx, by + bar_h + scale, "0", ink, scale);
  draw_text(image, bx + bar_w - text_width(label, scale), by + bar_h + scale, label, ink, scale);
}

}  // namespace clustersurf::render
