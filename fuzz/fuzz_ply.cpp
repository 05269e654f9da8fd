// libFuzzer target: the PLY reader, as a point cloud and as a triangle mesh.

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return clustersurf::fuzz::parse_everything(data, size, clustersurf::FileFormat::Ply, "fuzz.ply", true);
}
