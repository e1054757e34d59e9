#pragma once
/// Structural pre-checks of PLY and OFF files, run by read_mesh before assimp sees the file.
///
/// Why: assimp 5.2 repairs some broken files silently instead of failing — its OFF reader clamps
/// a face index ≥ #V to #V−1 (a negative one reads as 0) and drops faces with 0 or > 9 corners;
/// its PLY reader keeps reading past a short element list, turning face data into vertices,
/// and loops forever on some malformed headers; its STL reader ignores extra facet vertices.
/// Each check here walks the file's declared structure (header counts, per-element properties)
/// and throws InputError("<what>: <problem>") for what assimp would hide: data that ends before
/// the declared counts, extra data after them, faces with fewer than 3 corners and face indices
/// outside [0,#V). Files these checks cannot interpret are left to assimp's own errors.
///
/// Header counts are believed only as far as the file's size allows, and are checked against it
/// before anything is read or allocated for them (a count may be anything up to 2^63 - 1): an
/// OFF count beyond the data lines, a PLY element count beyond what the bytes after the header
/// can hold (at its smallest encoding), a PLY list length beyond the bytes left, a binary STL
/// facet count that does not give the file's size. The work done here is O(file size) whatever
/// the header says, and assimp never sees a header that claims more than the file holds.
#include <string>
#include <string_view>

namespace cutwork {

/// `content`: the whole file (ASCII or binary PLY); `what` prefixes the message.
void check_ply_structure(std::string_view content, const std::string& what);

/// `content`: the whole STL file. Binary files pass; in ASCII ones every facet must have
/// exactly 3 vertices (assimp drops the 4th and later vertices of a facet without a word).
void check_stl_structure(std::string_view content, const std::string& what);

/// `content`: the whole ASCII OFF file (variants COFF, NOFF, STOFF, 4OFF, nOFF and headerless).
void check_off_structure(std::string_view content, const std::string& what);

}  // namespace cutwork
