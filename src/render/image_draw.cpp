// Rectangles and text on images. Text uses stb_easy_font (Debian's libstb-dev), which turns a
// string into axis-aligned quads; they are filled as rectangles, scaled by an integer factor.

#include <clustersurf/render/image.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include <stb/stb_easy_font.h>

namespace clustersurf {

namespace {

Rgba8 blend_over(Rgba8 src, Rgba8 dst) {
  const int a = src.a;
  if (a == 255) return src;
  const int out_a = a + dst.a * (255 - a) / 255;
  if (out_a == 0) return {0, 0, 0, 0};
  const auto mix = [&](int s, int d) {
    return static_cast<std::uint8_t>(std::clamp((s * a + d * dst.a * (255 - a) / 255) / out_a, 0, 255));
  };
  return {mix(src.r, dst.r), mix(src.g, dst.g), mix(src.b, dst.b), static_cast<std::uint8_t>(out_a)};
}

/// The text with characters stb_easy_font lacks (outside printable ASCII) replaced by '?'.
std::string printable(std::string_view text) {
  std::string s(text);
  for (char& c : s)
    if (c < 32 || c > 126) c = '?';
  return s;
}

}  // namespace

void fill_rect(Image& image, int x, int y, int w, int h, Rgba8 color) {
  const int x0 = std::max(x, 0), y0 = std::max(y, 0);
  const int x1 = std::min(x + w, image.width), y1 = std::min(y + h, image.height);
  for (int j = y0; j < y1; ++j)
    for (int i = x0; i < x1; ++i) image.at(i, j) = blend_over(color, image.at(i, j));
}

void draw_text(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale) {
  std::string s = printable(text);
  // stb_easy_font: 4 vertices of 16 bytes per quad; ~270 bytes per character is plenty.
  std::vector<float> buffer(std::max<std::size_t>(s.size(), 1) * 70 * 4);
  const int quads =
      stb_easy_font_print(0, 0, s.data(), nullptr, buffer.data(), static_cast<int>(buffer.size() * sizeof(float)));
  for (int q = 0; q < quads; ++q) {
    const float* v = &buffer[static_cast<std::size_t>(q) * 16];  // 4 vertices × (x, y, z, color)
    float qx0 = v[0], qy0 = v[1], qx1 = v[0], qy1 = v[1];
    for (int k = 1; k < 4; ++k) {
      qx0 = std::min(qx0, v[4 * k]), qx1 = std::max(qx1, v[4 * k]);
      qy0 = std::min(qy0, v[4 * k + 1]), qy1 = std::max(qy1, v[4 * k + 1]);
    }
    fill_rect(image, x + static_cast<int>(qx0) * scale, y + static_cast<int>(qy0) * scale,
              static_cast<int>(qx1 - qx0) * scale, static_cast<int>(qy1 - qy0) * scale, color);
  }
}

int text_width(std::string_view text, int scale) {
  std::string s = printable(text);
  return stb_easy_font_width(s.data()) * scale;
}

}  // namespace clustersurf
