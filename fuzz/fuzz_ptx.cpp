// libFuzzer target: the PTX reader.

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return clustersurf::fuzz::parse_everything(data, size, clustersurf::FileFormat::Ptx, "fuzz.ptx", false);
}
