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

/// Header-count mutations for the OFF, PLY and STL targets (lying headers: counts far beyond
/// the file, off by one, wrapping 32- and 64-bit readers). An input that starts with
/// kHeaderMutationTag and a selector byte stands for the file after those 3 bytes with one
/// header count rewritten: the selector's high nibble picks the count (OFF: vertices, faces,
/// edges; PLY: the element lines in order; STL: the binary facet count, bytes 80-83), modulo
/// how many there are, and its low nibble the value (header_count_values). Any other input is
/// the file itself. Deterministic, so that libFuzzer's mutations of the selector byte explore
/// the extremes, and a crash found that way replays from its input file.
inline constexpr std::string_view kHeaderMutationTag = "\xFFH";

/// The 16 values a count `c` (as declared; 0 when it is not a non-negative integer) is rewritten
/// to: 0, 1, c-1, c+1, 2c, c+2^32, INT32_MAX, 2^31, UINT32_MAX, 2^32, INT64_MAX, 2^63,
/// UINT64_MAX, 2^64, -1, 10^30 (decimal text; a binary STL count takes the low 32 bits).
std::string header_count_value(std::uint64_t c, unsigned index, std::uint32_t* low32 = nullptr);

/// `file` (extension ".off", ".ply" or ".stl") with the count that `selector` picks rewritten;
/// unchanged when it has no such count.
std::string mutate_header_counts(const std::string& extension, std::string_view file, std::uint8_t selector);

/// `input` as the mesh targets read it: mutate_header_counts applied when it starts with the tag.
std::string mesh_fuzz_input(const std::string& extension, std::string_view input);

}  // namespace cutwork::fuzz

/// The targets, one per reader (names as in CMake: cutwork_fuzz_<name>).
int fuzz_scene(const std::uint8_t* data, std::size_t size);
int fuzz_stencils_json(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_obj(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_ply(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_off(const std::uint8_t* data, std::size_t size);
int fuzz_mesh_stl(const std::uint8_t* data, std::size_t size);
