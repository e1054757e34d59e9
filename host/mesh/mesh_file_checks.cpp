#include "host/mesh/mesh_file_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <sstream>
#include <vector>

#include "host/core/error.h"
#include "host/core/input_file.h"

namespace cutwork {

namespace {

// ---- PLY ------------------------------------------------------------------------------------

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> ply_type(const std::string& name) {
  if (name == "char" || name == "int8") return PlyType::kInt8;
  if (name == "uchar" || name == "uint8") return PlyType::kUint8;
  if (name == "short" || name == "int16") return PlyType::kInt16;
  if (name == "ushort" || name == "uint16") return PlyType::kUint16;
  if (name == "int" || name == "int32") return PlyType::kInt32;
  if (name == "uint" || name == "uint32") return PlyType::kUint32;
  if (name == "float" || name == "float32") return PlyType::kFloat32;
  if (name == "double" || name == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8: return 1;
    case PlyType::kInt16:
    case PlyType::kUint16: return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 0;
}

struct PlyProperty {
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
  PlyType type = PlyType::kFloat32;
  std::string name;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

/// Reads the values of a PLY body one at a time, as doubles (exact for every PLY integer type).
class PlyBody {
 public:
  PlyBody(std::string_view body, PlyFormat format) : m_body(body), m_format(format) {}

  /// False when the data ends (or an ASCII token is not a number).
  bool next(PlyType type, double& value) {
    if (m_format == PlyFormat::kAscii) {
      skip_space();
      if (m_pos >= m_body.size()) return false;
      std::size_t end = m_pos;
      while (end < m_body.size() && !is_space(m_body[end])) ++end;
      const char* first = m_body.data() + m_pos;
      const char* last = m_body.data() + end;
      m_pos = end;
      if (*first == '+') ++first;  // from_chars does not take a leading '+'
      const auto [ptr, ec] = std::from_chars(first, last, value);
      if (ec == std::errc::result_out_of_range) return true;  // huge or tiny: assimp's problem
      return ec == std::errc() && ptr == last;
    }
    const std::size_t n = ply_size(type);
    if (m_pos + n > m_body.size()) return false;
    char bytes[8];
    std::memcpy(bytes, m_body.data() + m_pos, n);
    m_pos += n;
    const bool file_little = m_format == PlyFormat::kBinaryLittle;
    if (file_little != (std::endian::native == std::endian::little)) std::reverse(bytes, bytes + n);
    switch (type) {
      case PlyType::kInt8: value = double(std::int8_t(bytes[0])); break;
      case PlyType::kUint8: value = double(std::uint8_t(bytes[0])); break;
      case PlyType::kInt16: value = load<std::int16_t>(bytes); break;
      case PlyType::kUint16: value = load<std::uint16_t>(bytes); break;
      case PlyType::kInt32: value = load<std::int32_t>(bytes); break;
      case PlyType::kUint32: value = load<std::uint32_t>(bytes); break;
      case PlyType::kFloat32: value = load<float>(bytes); break;
      case PlyType::kFloat64: value = load<double>(bytes); break;
    }
    return true;
  }

  /// The bytes not read yet.
  std::size_t remaining() const { return m_body.size() - m_pos; }

  /// True when nothing but (ASCII) whitespace is left.
  bool at_end() {
    if (m_format == PlyFormat::kAscii) skip_space();
    return m_pos >= m_body.size();
  }

 private:
  template <typename T>
  static double load(const char* bytes) {
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return double(v);
  }
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
  void skip_space() {
    while (m_pos < m_body.size() && is_space(m_body[m_pos])) ++m_pos;
  }

  std::string_view m_body;
  PlyFormat m_format;
  std::size_t m_pos = 0;
};

std::string declared_counts(const std::vector<PlyElement>& elements) {
  std::string s;
  for (const PlyElement& e : elements) s += (s.empty() ? "" : ", ") + fmt::format("{} {}", e.count, e.name);
  return s;
}

bool is_integer_in(double value, double lo, double hi_exclusive) {
  return value == std::floor(value) && value >= lo && value < hi_exclusive;
}

// ---- OFF ------------------------------------------------------------------------------------

std::vector<std::string> tokens_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

std::optional<long long> as_integer(const std::string& token) {
  long long v = 0;
  const char* first = token.data();
  if (*first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
  return v;
}

bool is_number(const std::string& token) {
  double v = 0;
  const char* first = token.data();
  if (*first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
  return (ec == std::errc() || ec == std::errc::result_out_of_range) &&
         ptr == token.data() + token.size();
}

}  // namespace

void check_ply_structure(std::string_view content, const std::string& what) {
  auto fail = [&](const std::string& problem) { throw InputError(what + ": " + problem); };
  // assimp takes the magic number in any case ("plY"), and then loops forever on a header it
  // cannot parse: every such file is checked here.
  std::string magic(content.substr(0, 3));
  for (char& c : magic) c = char(std::tolower(static_cast<unsigned char>(c)));
  // (assimp also hunts for a header further on, and can loop for ever there: refuse here)
  if (magic != "ply") fail("cannot be parsed: Invalid .ply file: Incorrect magic number (expected 'ply' or 'PLY').");

  // Header: lines up to "end_header". Parsed strictly — assimp 5.2 loops forever on some
  // malformed headers (e.g. a bare "property" line), so nothing questionable may reach it.
  std::vector<PlyElement> elements;
  std::optional<PlyFormat> format;
  int format_line = 0;
  std::size_t pos = 0;
  bool header_done = false;
  int line_number = 0;
  while (pos < content.size()) {
    std::size_t eol = content.find('\n', pos);
    if (eol == std::string_view::npos) eol = content.size();
    std::string line(content.substr(pos, eol - pos));
    pos = std::min(eol + 1, content.size());
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // A header is text: a control byte (a NUL inside a property name crashed assimp's PLY reader,
    // fuzz-regressions/mesh_ply/segv-nul-in-property-name.ply) is refused, and named by its
    // position, not echoed.
    for (std::size_t k = 0; k < line.size(); ++k) {
      const auto c = static_cast<unsigned char>(line[k]);
      if ((c < 0x20 && c != '\t') || c == 0x7f)
        fail(fmt::format("PLY header line {} has a control byte 0x{:02x} at column {} (binary data in the "
                         "header, or not a PLY file)",
                         line_number, c, k + 1));
    }
    const std::vector<std::string> t = tokens_of(line);
    auto bad_line = [&](const std::string& why) {
      fail(fmt::format("PLY header line {} '{}': {}", line_number, line, why));
    };
    if (line_number == 1) {
      if (t.size() != 1 || (t[0] != "ply" && t[0] != "PLY")) bad_line("expected just 'ply'");
      continue;
    }
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      header_done = true;
      break;
    }
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (t.size() != 3) bad_line("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      // One format: with two, this check and assimp could read the data by different ones (binary
      // then ascii crashed assimp, SEGV; ascii then binary leaked: fuzz-regressions/mesh_ply).
      if (format) bad_line(fmt::format("a second format line (the first is line {})", format_line));
      format_line = line_number;
      if (t[1] == "ascii") format = PlyFormat::kAscii;
      else if (t[1] == "binary_little_endian") format = PlyFormat::kBinaryLittle;
      else if (t[1] == "binary_big_endian") format = PlyFormat::kBinaryBig;
      else bad_line("unknown format '" + t[1] + "'");
    } else if (t[0] == "element") {
      if (t.size() != 3) bad_line("expected 'element <name> <count>'");
      const auto count = as_integer(t[2]);
      if (!count || *count < 0) bad_line("the element count is not a non-negative integer");
      // assimp reads the leading digits of a name such as "8888888888888vertex" as a count and
      // allocated 62 GB for it (fuzz-regressions/mesh_ply/oom-element-name-with-leading-digits.ply).
      const unsigned char first = static_cast<unsigned char>(t[1].front());
      if (!(std::isalpha(first) || first == '_')) bad_line("an element name must start with a letter");
      elements.push_back({t[1], *count, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) bad_line("a property before any element");
      PlyProperty p;
      if (t.size() >= 2 && t[1] == "list") {
        if (t.size() != 5) bad_line("expected 'property list <count type> <item type> <name>'");
        const auto count_type = ply_type(t[2]), type = ply_type(t[3]);
        if (!count_type || !type) bad_line("unknown property type");
        if (*count_type == PlyType::kFloat32 || *count_type == PlyType::kFloat64)
          bad_line("a list length must have an integer type");
        p.is_list = true, p.count_type = *count_type, p.type = *type, p.name = t[4];
      } else {
        if (t.size() != 3) bad_line("expected 'property <type> <name>'");
        const auto type = ply_type(t[1]);
        if (!type) bad_line("unknown property type '" + t[1] + "'");
        p.type = *type, p.name = t[2];
      }
      elements.back().properties.push_back(p);
    } else {
      bad_line("not a PLY header keyword");
    }
  }
  if (!header_done) fail("PLY header has no end_header line (truncated or not a PLY file)");
  if (!format) fail("PLY header has no format line");

  long long num_vertices = -1;
  for (const PlyElement& e : elements) {
    if (e.name != "vertex") continue;
    num_vertices = e.count;
    // Positions are properties x, y and z of the vertex element; assimp reads a missing one as 0
    // and the mesh then fails later for a reason that does not name the cause.
    for (const char* axis : {"x", "y", "z"}) {
      const bool present = std::any_of(e.properties.begin(), e.properties.end(),
                                       [&](const PlyProperty& p) { return !p.is_list && p.name == axis; });
      if (!present) fail(fmt::format("the PLY vertex element has no '{}' property (positions are x, y and z)", axis));
    }
  }

  // The declared counts against the size of the data, before anything is read: an item of an
  // element takes at least its fixed-size properties' bytes and its lists' length fields
  // (binary), or one character and a separator per property (ASCII; the file's last value needs
  // no separator). Divided, not multiplied: the counts may be anything up to 2^63 - 1.
  const std::string_view data = content.substr(pos);
  const std::uint64_t data_bytes = data.size();
  for (const PlyElement& e : elements) {
    const auto count = std::uint64_t(e.count);
    if (e.properties.empty()) {
      // Nothing to read per item, but assimp builds (binary) or skips a line for (ASCII) each
      // one: no more of them than bytes in the file.
      if (count > data_bytes)
        fail(fmt::format("the PLY header declares {} {} elements without properties, more than the {} bytes "
                         "of data after the header (wrong element count?)",
                         e.count, e.name, data_bytes));
      continue;
    }
    std::uint64_t min_bytes = 0;
    for (const PlyProperty& p : e.properties)
      min_bytes += *format == PlyFormat::kAscii ? 2 : ply_size(p.is_list ? p.count_type : p.type);
    const std::uint64_t room = data_bytes + (*format == PlyFormat::kAscii ? 1 : 0);
    if (count > room / min_bytes)
      fail(fmt::format("the PLY header declares {} {} elements, but the {} bytes of data after the header "
                       "hold at most {} (at least {} byte{} each; truncated file or wrong element count)",
                       e.count, e.name, data_bytes, room / min_bytes, min_bytes, min_bytes == 1 ? "" : "s"));
  }

  PlyBody body(data, *format);
  for (const PlyElement& e : elements) {
    if (e.properties.empty()) continue;  // no data to check (the count is bounded above)
    for (long long i = 0; i < e.count; ++i) {
      auto truncated = [&] {
        fail(fmt::format("the file ends inside {} {} of the {} declared in the PLY header "
                         "(truncated file or wrong element count)",
                         e.name, i, e.count));
      };
      for (const PlyProperty& p : e.properties) {
        double value = 0;
        if (!p.is_list) {
          if (!body.next(p.type, value)) truncated();
          continue;
        }
        double count = 0;
        if (!body.next(p.count_type, count)) truncated();
        if (!is_integer_in(count, 0, 1e9))
          fail(fmt::format("{} {}: list '{}' has an invalid length {}", e.name, i, p.name, count));
        const bool corners =
            e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
        if (corners && count < 3)
          fail(fmt::format("face {} has {} vertices (a face needs at least 3)", i, count));
        // Each value takes at least one byte (ASCII: a character): a longer list is cut short.
        const std::size_t value_bytes = *format == PlyFormat::kAscii ? 1 : ply_size(p.type);
        if (count > double(body.remaining() / value_bytes)) truncated();
        for (long long k = 0; k < (long long)(count); ++k) {
          if (!body.next(p.type, value)) truncated();
          if (corners && num_vertices >= 0 && !is_integer_in(value, 0, double(num_vertices)))
            fail(fmt::format("face {} index {} out of range [0,{})", i, value, num_vertices));
        }
      }
    }
  }
  if (!body.at_end())
    fail(fmt::format("data continues after the elements declared in the PLY header ({}): wrong "
                     "element count?",
                     declared_counts(elements)));
}

void check_off_structure(std::string_view content, const std::string& what) {
  auto fail = [&](const std::string& problem) { throw InputError(what + ": " + problem); };
  // Non-empty lines with comments removed.
  std::vector<std::string> lines;
  {
    std::istringstream in{std::string(content)};
    for (std::string line; std::getline(in, line);) {
      if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      // (blank by the tokenizer's own notion of space: a line of form feeds or vertical tabs is blank)
      if (!tokens_of(line).empty()) lines.push_back(line);
    }
  }
  if (lines.empty()) fail("no OFF header (the file holds only blank or comment lines)");

  // Header: "[ST][C][N][4][n]OFF [dim] [nv nf ne]" or, headerless, the counts directly.
  // Strict like the PLY check: what is not understood here is not handed to assimp.
  std::vector<std::string> tokens = tokens_of(lines[0]);
  std::size_t next = 1;
  const std::string magic = tokens[0];
  const bool has_magic = magic.size() >= 3 && magic.compare(magic.size() - 3, 3, "OFF") == 0;
  if (has_magic) {
    if (lines[0].find("BINARY") != std::string::npos) fail("binary OFF files are not supported");
    const std::string flags = magic.substr(0, magic.size() - 3);
    tokens.erase(tokens.begin());
    if (flags.find('n') != std::string::npos) {  // dimension precedes the counts
      if (tokens.empty()) {
        if (next >= lines.size()) fail("the OFF header ends before the dimension");
        tokens = tokens_of(lines[next++]);
      }
      const auto dim = as_integer(tokens[0]);
      if (!dim || *dim != 3) fail("only 3D OFF files are supported (dimension '" + tokens[0] + "')");
      tokens.erase(tokens.begin());
    }
    if (tokens.empty()) {
      if (next >= lines.size()) fail("the OFF header has no vertex and face counts");
      tokens = tokens_of(lines[next++]);
    }
  }
  const auto nv = tokens.size() >= 2 ? as_integer(tokens[0]) : std::nullopt;
  const auto nf = tokens.size() >= 2 ? as_integer(tokens[1]) : std::nullopt;
  if (!nv || !nf)
    fail(has_magic ? "the OFF header's vertex and face counts are missing or not integers"
                   : "not an OFF file: it starts neither with 'OFF' nor with the vertex and face counts");
  if (*nv < 0 || *nf < 0) fail(fmt::format("negative counts in the OFF header ({} {})", *nv, *nf));

  // Each count on its own first (their sum may overflow), then both together: every vertex and
  // every face is one non-blank line.
  const long long available = (long long)(lines.size() - next);
  if (*nv > available)
    fail(fmt::format("the OFF header declares {} vertices, but the file has only {} data lines (truncated "
                     "file or wrong counts)",
                     *nv, available));
  if (*nf > available)
    fail(fmt::format("the OFF header declares {} faces, but the file has only {} data lines (truncated file "
                     "or wrong counts)",
                     *nf, available));
  if (*nf > available - *nv)
    fail(fmt::format("the file ends before the {} vertices and {} faces declared in the OFF header "
                     "({} data lines found; truncated file or wrong counts)",
                     *nv, *nf, available));
  for (long long v = 0; v < *nv; ++v) {
    const auto t = tokens_of(lines[next + v]);
    if (t.size() < 3 || !is_number(t[0]) || !is_number(t[1]) || !is_number(t[2]))
      fail(fmt::format("vertex {} does not start with 3 coordinates: '{}'", v, lines[next + v]));
  }
  next += std::size_t(*nv);
  for (long long f = 0; f < *nf; ++f) {
    const auto t = tokens_of(lines[next + f]);
    const auto n = as_integer(t[0]);
    if (!n) fail(fmt::format("face {} does not start with its number of corners: '{}'", f, lines[next + f]));
    if (*n < 3) fail(fmt::format("face {} has {} vertices (a face needs at least 3)", f, *n));
    // assimp's OFF reader silently drops such faces
    if (*n > 9) fail(fmt::format("face {} has {} vertices; OFF faces with more than 9 are not supported", f, *n));
    if ((long long)(t.size()) < 1 + *n)
      fail(fmt::format("face {} lists fewer than its {} vertex indices", f, *n));
    for (std::size_t k = std::size_t(1 + *n); k < t.size(); ++k) {  // a colour: numbers only (assimp crashes on bytes)
      char* end = nullptr;
      std::strtod(t[k].c_str(), &end);
      if (end != t[k].c_str() + t[k].size())
        fail(fmt::format("face {}: '{}' after the vertex indices is not a number (a colour component)", f,
                         excerpt(t[k], 40)));
    }
    for (long long k = 0; k < *n; ++k) {
      const auto index = as_integer(t[1 + k]);
      if (!index) fail(fmt::format("face {} index '{}' is not an integer", f, t[1 + k]));
      if (*index < 0 || *index >= *nv)
        fail(fmt::format("face {} index {} out of range [0,{})", f, *index, *nv));
    }
  }
  next += std::size_t(*nf);
  if (next < lines.size())
    fail(fmt::format("data continues after the {} vertices and {} faces declared in the OFF "
                     "header: wrong counts?",
                     *nv, *nf));
}

/// An ASCII STL, strictly: "solid NAME" on the first line, then facets
///   facet normal N N N / outer loop / vertex X Y Z (three) / endloop / endfacet
/// and "endsolid [NAME]" (further solids may follow). assimp reports a bad number by quoting the
/// rest of the file, and leaks the mesh it was building when it meets anything unexpected, so
/// nothing malformed may reach it.
/// A number as assimp's fast_atoreal_move reads it to its end: a sign, then nan, inf or infinity
/// (any case), or digits with at most one point (a leading point followed by a digit) and an
/// exponent. strtod takes more (leading space, hexadecimal), on which assimp throws.
static bool is_plain_real(const std::string& token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
  std::string rest = token.substr(i);
  for (char& ch : rest) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (rest == "nan" || rest == "inf" || rest == "infinity") return true;
  auto digit = [&](std::size_t k) { return k < token.size() && token[k] >= '0' && token[k] <= '9'; };
  if (!digit(i) && !(i < token.size() && token[i] == '.' && digit(i + 1))) return false;
  while (digit(i)) ++i;
  if (i < token.size() && token[i] == '.') {
    ++i;
    while (digit(i)) ++i;
  }
  if (i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
    ++i;
    if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
    if (!digit(i)) return false;
    while (digit(i)) ++i;
  }
  return i == token.size();
}

static void check_ascii_stl_grammar(std::string_view text, const std::string& what) {
  std::istringstream in{std::string(text)};
  long long facet = -1;
  auto fail = [&](const std::string& problem) {
    throw InputError(fmt::format("{}: cannot be parsed: ASCII STL{}: {}", what,
                                 facet >= 0 ? fmt::format(" facet {}", facet) : std::string(), problem));
  };
  std::vector<std::string> pending;  // tokens of a "solid" line after its name, in reverse order
  bool from_pending = false;  // the last token came from `pending` (its line is already read)
  auto next = [&](std::string& token) {
    from_pending = !pending.empty();
    if (!from_pending) return bool(in >> token);
    token = std::move(pending.back());
    pending.pop_back();
    return true;
  };
  auto expect = [&](const char* word) {
    std::string token;
    if (!next(token)) fail(fmt::format("the file ends where '{}' was expected", word));
    if (token != word) fail(fmt::format("'{}' where '{}' was expected", excerpt(token, 40), word));
  };
  // The three numbers on the keyword's own line, as assimp reads them: separated by spaces and
  // tabs only, the line ending at a carriage return, form feed or NUL (the last two refused before
  // this is reached: check_stl_structure) as well as at '\n', each a
  // plain number (is_plain_real). Past the line's end, or on anything else, assimp throws and
  // leaks what it built. What follows the numbers stays in the stream.
  auto numbers = [&](const std::string& of) {
    if (pending.empty()) {
      std::string line;
      std::getline(in, line);
      const std::size_t end = line.find_first_of(std::string("\r\f\0", 3));
      std::vector<std::string> words;
      std::string word;
      for (char ch : line.substr(0, end)) {
        if (ch != ' ' && ch != '\t') {
          word += ch;
        } else if (!word.empty()) {
          words.push_back(word);
          word.clear();
        }
      }
      if (!word.empty()) words.push_back(word);
      if (words.size() < 3)
        fail(fmt::format("the {} has {} numbers on its line (separated by spaces or tabs), expected 3", of,
                         words.size()));
      if (end != std::string::npos)
        for (std::string& rest : tokens_of(line.substr(end + 1))) words.push_back(std::move(rest));
      pending.assign(words.rbegin(), words.rend());
    }
    for (int k = 0; k < 3; ++k) {
      std::string token;
      if (!next(token)) fail(fmt::format("the file ends inside the {}", of));
      if (!is_plain_real(token)) fail(fmt::format("{} coordinate {} '{}' is not a number", of, k, excerpt(token, 40)));
    }
  };
  auto skip_line = [&] {
    if (from_pending) {
      pending.clear();
      return;
    }
    std::string rest;
    std::getline(in, rest);
  };
  // "solid [NAME]": as in assimp, the name is one token and the rest of its line is body.
  auto solid_line = [&] {
    std::string line;
    std::getline(in, line);
    std::vector<std::string> words = tokens_of(line);
    if (!words.empty()) words.erase(words.begin());  // the name
    pending.assign(words.rbegin(), words.rend());
  };
  std::string token;
  next(token);  // "solid" (checked by the caller)
  solid_line();
  while (next(token)) {
    if (token == "endsolid") {
      skip_line();
      if (!next(token)) break;
      if (token != "solid") fail(fmt::format("'{}' after 'endsolid' (expected another 'solid' or the end)",
                                             excerpt(token, 40)));
      solid_line();
      continue;
    }
    if (token != "facet") fail(fmt::format("'{}' where 'facet' or 'endsolid' was expected", excerpt(token, 40)));
    ++facet;
    expect("normal");
    numbers("normal");
    expect("outer");
    expect("loop");
    int corners = 0;
    bool more = next(token);
    for (; more && token == "vertex"; ++corners, more = next(token)) numbers(fmt::format("vertex {}", corners));
    if (!more) fail("the file ends inside the facet's loop");
    if (token != "endloop") fail(fmt::format("'{}' where 'vertex' or 'endloop' was expected", excerpt(token, 40)));
    if (corners != 3)
      throw InputError(fmt::format("{}: facet {} has {} vertices (STL facets are triangles)", what, facet, corners));
    expect("endfacet");
  }
}

void check_stl_structure(std::string_view content, const std::string& what) {
  // A binary STL is 80 header bytes, a uint32 facet count and 50 bytes per facet; its header
  // may start with "solid" too, so the size decides (as in assimp).
  if (content.size() >= 84) {
    std::uint64_t facets = 0;  // little endian
    for (int b = 3; b >= 0; --b) facets = (facets << 8) | std::uint8_t(content[80 + b]);
    if (content.size() == 84 + 50 * facets) return;
  }
  std::size_t start = content.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos || content.substr(start, 5) != "solid") {
    // Neither: say why for each (assimp says only "Failed to determine STL storage representation").
    if (content.size() < 84)
      throw InputError(fmt::format("{}: cannot be parsed: not an STL file: an ASCII STL starts with 'solid', and {} bytes are too "
                                   "few for a binary STL (80-byte header, facet count, 50 bytes per facet)",
                                   what, content.size()));
    std::uint64_t facets = 0;
    for (int b = 3; b >= 0; --b) facets = (facets << 8) | std::uint8_t(content[80 + b]);
    throw InputError(fmt::format("{}: cannot be parsed: not an STL file: an ASCII STL starts with 'solid', and a binary STL "
                                 "declaring {} facets would be {} bytes long, not {}",
                                 what, facets, 84 + 50 * facets, content.size()));
  }
  // An ASCII STL is text: spaces, tabs and line ends (LF, CR) between its words. assimp ends a line
  // at a NUL or a form feed and reads on, but such a byte between a facet's vertices (fuzzer:
  // "vertex 0 1 .0<NUL>      vertex 1 0 0", and "outer loop\n     <FF>vertex 0 0 0") makes it
  // throw and leak what it built; no exporter writes one, so every C0 control byte other than tab,
  // LF and CR is refused wherever it is, with the facet it is in.
  const auto control = std::find_if(content.begin(), content.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 && c != '\t' && c != '\n' && c != '\r';
  });
  if (control != content.end()) {
    const auto at = std::size_t(control - content.begin());
    const std::string_view before = content.substr(0, at);
    std::string where = "ASCII STL";
    if (before.find("facet") != std::string_view::npos) {
      std::size_t facet = 0;
      for (std::size_t p = before.find("endfacet"); p != std::string_view::npos; p = before.find("endfacet", p + 8))
        ++facet;
      where = fmt::format("ASCII STL facet {}", facet);
    }
    const std::string byte = *control == '\0' ? std::string("a NUL byte")
                                              : fmt::format("a control byte 0x{:02x}", static_cast<unsigned char>(*control));
    throw InputError(fmt::format("{}: cannot be parsed: {}: {} at offset {} (line {}); an ASCII STL is text (spaces, tabs "
                                 "and line ends between its words)",
                                 what, where, byte, at, 1 + std::count(before.begin(), before.end(), '\n')));
  }
  check_ascii_stl_grammar(content.substr(start), what);
}

}  // namespace cutwork
