#pragma once
// 8-bit RGBA pictures: the ray tracer's output, text and color-bar overlays, grids, PNG files.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace clustersurf {

/// One pixel, straight (not premultiplied) alpha; a = 0 is fully transparent.
struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  bool operator==(const Rgba8&) const = default;
};

/// A width × height picture, rows top to bottom, 4 bytes (RGBA) per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<Rgba8> pixels;  ///< width × height, row-major

  Image() = default;
  /// A picture filled with `fill`.
  Image(int w, int h, Rgba8 fill = {})
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}
  Rgba8& at(int x, int y) {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
  }
  const Rgba8& at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)];
  }
};

/// Writes `image` as a PNG file, atomically (temporary file, then rename). Throws IoError.
void write_png(const std::filesystem::path& file, const Image& image);
/// The PNG encoding of `image` (the bytes write_png writes).
std::string encode_png(const Image& image);

/// Fills the rectangle [x, x + w) × [y, y + h), clipped to the image, blending `color` over
/// the pixels by its alpha.
void fill_rect(Image& image, int x, int y, int w, int h, Rgba8 color);
/// Draws one line of text (stb_easy_font's glyphs, about 7 × `scale` pixels tall) with its
/// top-left corner at (x, y), clipped to the image.
void draw_text(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale = 1);
/// Width in pixels of `text` as draw_text() draws it at `scale`.
int text_width(std::string_view text, int scale = 1);

/// Places `cells` (all of the same size) in a grid of `columns` columns (0: as square as
/// possible), each with its label centered under it, on `background`.
Image compose_grid(std::span<const Image> cells, std::span<const std::string> labels, Rgba8 background,
                   int columns = 0);

}  // namespace clustersurf
