// PNG encoding through stb_image_write, with zlib (already a dependency) as its compressor:
// smaller files than stb's built-in deflate, and no use of stb's global settings.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/image.hpp>

#include "io/atomic_file.hpp"

#include <zlib.h>

#include <cstdlib>
#include <cstring>

namespace {

/// stb's compressor hook: zlib level 6 (level 9 is several times slower for ~2 % smaller files).
unsigned char* zlib_compress(unsigned char* data, int data_len, int* out_len, int /*quality*/) {
  uLongf size = compressBound(static_cast<uLong>(data_len));
  auto* out = static_cast<unsigned char*>(std::malloc(size));
  if (out == nullptr) return nullptr;
  if (compress2(out, &size, data, static_cast<uLong>(data_len), 6) != Z_OK) {
    std::free(out);
    return nullptr;
  }
  *out_len = static_cast<int>(size);
  return out;
}

}  // namespace

#define STBIW_ZLIB_COMPRESS zlib_compress
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace clustersurf {

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw OptionError("cannot encode an empty or inconsistent image as PNG");
  std::string bytes;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  static_assert(sizeof(Rgba8) == 4);
  if (stbi_write_png_to_func(append, &bytes, image.width, image.height, 4, image.pixels.data(), image.width * 4) == 0)
    throw IoError("PNG encoding failed (out of memory?)");
  return bytes;
}

void write_png(const std::filesystem::path& file, const Image& image) {
  const std::string bytes = encode_png(image);
  io::AtomicFile out(file);
  out.write(bytes);
  out.commit();
}

}  // namespace clustersurf
