// libFuzzer target: the PLY reader, as a point cloud and as a triangle mesh.

#include "fuzz_checks.hpp"

#include <clustersurf/errors.hpp>
#include <clustersurf/point_cloud_io.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clustersurf;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    fuzz::check_cloud(parse_point_cloud(bytes, FileFormat::Ply, "fuzz.ply"));
  } catch (const InputError&) {
  }
  try {
    ReadOptions drop;
    drop.drop_non_finite = true;
    fuzz::check_mesh(parse_triangle_mesh(bytes, FileFormat::Ply, "fuzz.ply", drop));
  } catch (const InputError&) {
  }
  return 0;
}
