// The libFuzzer entry point of one target: compiled once per target with
// CUTWORK_FUZZ_TARGET set to its function (see tests/fuzz/CMakeLists.txt).
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return CUTWORK_FUZZ_TARGET(data, size);
}
