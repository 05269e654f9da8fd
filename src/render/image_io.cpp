// PNG encoding through stb_image_write, with zlib (already a dependency) as its compressor in
// parallel bands: smaller files than stb's built-in deflate, and no use of stb's global settings.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/render/image.hpp>

#include "io/atomic_file.hpp"
#include "render/banded_deflate.hpp"

#include <cstdlib>
#include <cstring>
#include <exception>
#include <vector>

namespace {

/// stb's compressor hook: zlib level 6 (level 9 is several times slower for ~2 % smaller files),
/// in parallel bands (banded_deflate()).
unsigned char* zlib_compress(unsigned char* data, int data_len, int* out_len, int /*quality*/) {
  std::vector<unsigned char> stream;
  try {
    stream = clustersurf::render::banded_deflate({data, static_cast<std::size_t>(data_len)}, 6);
  } catch (const std::exception&) {  // zlib's failure or out of memory: no exception crosses stb's C
    return nullptr;                  // stb reports the failure; encode_png() throws
  }
  auto* out = static_cast<unsigned char*>(std::malloc(stream.size()));
  if (out == nullptr) return nullptr;
  std::memcpy(out, stream.data(), stream.size());
  *out_len = static_cast<int>(stream.size());
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
