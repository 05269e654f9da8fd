// libFuzzer target: PointStream, which reads a binary PLY of points, a LAS, E57 or PCD file
// (binary_compressed too) or XYZ and PTX text in place, a block at a time (other files it reads whole through the
// readers fuzz_ply covers). Every block must hold finite points, and the blocks together the file's points (an E57
// file's valid ones: at most its records), the same again after a rewind.

#include "fuzz_checks.hpp"

#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/io/point_stream.hpp>

#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clustersurf;
  // The same bytes as a .ply (binary PLY, LAS, E57 and PCD by their signature, others read
  // whole), as a .xyz and a .ptx (text read in place) and as a .pcd.
  static const std::string stem = (fuzz::scratch_directory() / "stream").string();
  for (const std::string& file : {stem + ".ply", stem + ".xyz", stem + ".ptx", stem + ".pcd"}) {
    std::ofstream(file, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    for (const bool drop : {false, true}) {
      try {
        ReadOptions options;
        options.drop_non_finite = drop;
        PointStream stream(file, options);
        PointCloud block;
        // E57 records marked invalid and PCD records without a position hold no point.
        const auto starts = [&](const char* magic) {
          return size >= std::strlen(magic) && std::memcmp(data, magic, std::strlen(magic)) == 0;
        };
        const bool holes = starts("ASTM-E57") || starts("# .PCD") || starts("VERSION ") || file.ends_with(".pcd");
        std::uint64_t total = 0, first = 0;
        for (int pass = 0; pass < 2; ++pass, stream.rewind()) {
          first = total;
          total = 0;
          while (stream.read(7, block)) {
            fuzz::require(block.positions.allFinite() && block.size() <= 7);
            fuzz::require(!stream.has_normals() || (block.normals.rows() == block.size() && block.normals.allFinite()));
            total += static_cast<std::uint64_t>(block.size());
          }
          fuzz::require(total <= stream.size());
          fuzz::require(drop || holes || total == stream.size());
          fuzz::require(pass == 0 || total == first);
        }
        // The reader, given the whole file, finds the same points (when it reads the file at
        // all: it also checks fields the stream does not decode, and refuses an empty cloud).
        std::optional<PointCloud> whole;
        try {
          whole = read_point_cloud(file, options);
        } catch (const InputError&) {}
        if (whole) fuzz::require(static_cast<std::uint64_t>(whole->size()) == total);
      } catch (const InputError&) {}
    }
  }
  return 0;
}
