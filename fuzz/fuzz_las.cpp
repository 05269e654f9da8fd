// libFuzzer target: the LAS reader.

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return clustersurf::fuzz::parse_everything(data, size, clustersurf::FileFormat::Las, "fuzz.las", false);
}
