#pragma once
/// Shared by the fuzz targets (tests/fuzz/*_fuzzer.cpp): each defines LLVMFuzzerTestOneInput,
/// which must return normally for every input; an InputError is a correct answer to bad input,
/// anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
///
/// Built two ways: with clang and -DCUTWORK_BUILD_FUZZERS=ON as libFuzzer executables
/// (cutwork_fuzz_<target>, see tests/fuzz/README.md), and always as cutwork_fuzz_replay, which
/// runs every target over its seed corpus and the regression inputs of crashes found (a ctest).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace cutwork::fuzz {

/// Writes `data` to a file named `name` in a per-process scratch folder and returns its path
/// (the readers take paths: the checks on the file itself are part of what is fuzzed).
std::filesystem::path scratch_file(const std::string& name, std::string_view data);

/// Small work limits, so that an input asking for a fine mesh or many stencils is refused
/// quickly instead of timing the fuzzer out (the limits themselves are tested elsewhere).
void use_small_limits();

}  // namespace cutwork::fuzz

/// The targets, one per reader (names as in CMake: cutwork_fuzz_<name>).
int fuzz_scene(const std::uint8_t* data, std::size_t size);
int fuzz_stencils_json(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_obj(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_ply(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_off(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_stl(const std::uint8_t* data, std::size_t size);
