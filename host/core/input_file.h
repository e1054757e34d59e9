#pragma once
/// Reading a user's input file whole, with the checks every reader needs first: it exists, it is
/// a regular file (a FIFO or a device would block or never end), and it is not larger than a cap.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace cutwork {

/// Caps on input files (bytes). Meshes: 1 GiB (about 20 million faces in binary STL, beyond what
/// the solvers can factorise); JSON documents (scenes, stencils.json, exemplars): 256 MiB.
inline constexpr std::uintmax_t max_mesh_file_bytes = std::uintmax_t(1) << 30;
inline constexpr std::uintmax_t max_json_file_bytes = std::uintmax_t(256) << 20;

/// Throws InputError("<path>: <problem>") unless `path` is an existing regular file (symbolic
/// links followed) of at most `max_bytes` bytes; `kind` names what was expected ("a mesh file").
/// Returns its size.
std::uintmax_t check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes,
                                const std::string& kind);

/// check_input_file, then the whole content.
std::string read_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes, const std::string& kind);

/// `text` for a one-line message: control characters as spaces, at most `max_chars` characters
/// (then "..." and the full length), so that a key or value a user wrote cannot make an error
/// line megabytes long.
std::string excerpt(std::string_view text, std::size_t max_chars = 80);

}  // namespace cutwork
