// Several pictures side by side, each labelled underneath.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/image.hpp>

#include <algorithm>
#include <cmath>

namespace clustersurf {

Image compose_grid(std::span<const Image> cells, std::span<const std::string> labels, Rgba8 background, int columns) {
  if (cells.empty()) throw OptionError("a grid needs at least one picture");
  const int w = cells[0].width, h = cells[0].height;
  for (const Image& c : cells)
    if (c.width != w || c.height != h) throw OptionError("the pictures of a grid must have the same size");
  const int n = static_cast<int>(cells.size());
  const int cols = columns > 0 ? std::min(columns, n) : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const int rows = (n + cols - 1) / cols;
  const int scale = std::max(1, h / 300);
  const int label_h = labels.empty() ? 0 : 14 * scale;
  Image out(cols * w, rows * (h + label_h), background);
  const Rgba8 ink = (background.r + background.g + background.b) / 3 < 128 && background.a > 0
                        ? Rgba8{235, 235, 235, 255}
                        : Rgba8{30, 30, 30, 255};
  for (int k = 0; k < n; ++k) {
    const int ox = (k % cols) * w, oy = (k / cols) * (h + label_h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.at(ox + x, oy + y) = cells[static_cast<std::size_t>(k)].at(x, y);
    if (static_cast<std::size_t>(k) < labels.size()) {
      const std::string& label = labels[static_cast<std::size_t>(k)];
      draw_text(out, ox + (w - text_width(label, scale)) / 2, oy + h + 3 * scale, label, ink, scale);
    }
  }
  return out;
}

}  // namespace clustersurf
