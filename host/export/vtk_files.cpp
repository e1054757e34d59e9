// VTK XML writer and (libxml2) reader; see vtk_files.h for the format.
#include "host/export/vtk_files.h"

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <cerrno>
#include <cstdlib>
#include <memory>
#include <ostream>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork {
namespace {

constexpr int kVtkTriangle = 5;
constexpr int kVtkPolyLine = 4;

/// Writes one ASCII DataArray; `values` are written 6 (or `components`) to a line.
template <typename Values>
void data_array(std::ostream& os, const char* type, const std::string& name, int components, const Values& values,
                Eigen::Index count) {
  os << "        <DataArray type=\"" << type << "\"";
  if (!name.empty()) os << " Name=\"" << name << "\"";
  if (components > 1) os << " NumberOfComponents=\"" << components << "\"";
  os << " format=\"ascii\">\n";
  const int per_line = components > 1 ? components : 6;
  for (Eigen::Index i = 0; i < count; ++i) {
    os << (i % per_line == 0 ? "          " : " ") << values(i);
    if (i % per_line == per_line - 1 || i + 1 == count) os << "\n";
  }
  os << "        </DataArray>\n";
}

void float_array(std::ostream& os, const std::string& name, int components, const double* data, Eigen::Index count) {
  data_array(os, "Float64", name, components, [&](Eigen::Index i) { return fmt::format("{:.17g}", data[i]); },
             count);
}

void check_xml_name(const std::string& name) {
  for (char ch : name)
    if (ch == '"' || ch == '<' || ch == '>' || ch == '&')
      throw InputError(fmt::format("field name '{}': must not contain XML markup characters", name));
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const SurfaceMesh& mesh, const MeshFields& fields) {
  const Eigen::Index nv = mesh.num_vertices(), nf = mesh.num_faces();
  for (const auto& [name, f] : fields.face) {
    check_xml_name(name);
    if (f.size() != nf)
      throw InternalError(fmt::format("{}: face field '{}' has {} values for {} faces", path.string(), name, f.size(), nf));
  }
  for (const auto& [name, f] : fields.vertex) {
    check_xml_name(name);
    if (f.rows() != nv)
      throw InternalError(
          fmt::format("{}: vertex field '{}' has {} rows for {} vertices", path.string(), name, f.rows(), nv));
  }
  const RowMatX3i& F = mesh.faces();
  write_file_atomic(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
          "  <UnstructuredGrid>\n"
       << fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", nv, nf);
    os << "      <PointData>\n";
    for (const auto& [name, f] : fields.vertex) float_array(os, name, 3, f.data(), 3 * nv);
    os << "      </PointData>\n      <CellData>\n";
    for (const auto& [name, f] : fields.face) float_array(os, name, 1, f.data(), nf);
    os << "      </CellData>\n      <Points>\n";
    float_array(os, "Points", 3, mesh.vertices().data(), 3 * nv);
    os << "      </Points>\n      <Cells>\n";
    data_array(os, "Int64", "connectivity", 1, [&](Eigen::Index i) { return F(i / 3, i % 3); }, 3 * nf);
    data_array(os, "Int64", "offsets", 1, [&](Eigen::Index i) { return 3 * (i + 1); }, nf);
    data_array(os, "UInt8", "types", 1, [&](Eigen::Index) { return kVtkTriangle; }, nf);
    os << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
}

void write_vtp_polylines(const std::filesystem::path& path, const std::vector<RowMatX3d>& lines, bool closed,
                         const std::map<std::string, Eigen::VectorXd>& cell_fields) {
  const Eigen::Index nl = Eigen::Index(lines.size());
  for (const auto& [name, f] : cell_fields) {
    check_xml_name(name);
    if (f.size() != nl)
      throw InternalError(fmt::format("{}: line field '{}' has {} values for {} lines", path.string(), name, f.size(), nl));
  }
  std::vector<double> points;
  std::vector<long long> connectivity, offsets;
  for (const RowMatX3d& line : lines) {
    const Eigen::Index first = Eigen::Index(points.size() / 3);
    for (Eigen::Index k = 0; k < line.rows(); ++k) {
      points.insert(points.end(), {line(k, 0), line(k, 1), line(k, 2)});
      connectivity.push_back(first + k);
    }
    if (closed && line.rows() > 0) connectivity.push_back(first);
    offsets.push_back((long long)connectivity.size());
  }
  const Eigen::Index np = Eigen::Index(points.size() / 3);
  write_file_atomic(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
          "  <PolyData>\n"
       << fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" "
                      "NumberOfPolys=\"0\">\n",
                      np, nl);
    os << "      <CellData>\n";
    for (const auto& [name, f] : cell_fields) float_array(os, name, 1, f.data(), nl);
    os << "      </CellData>\n      <Points>\n";
    float_array(os, "Points", 3, points.data(), 3 * np);
    os << "      </Points>\n      <Lines>\n";
    data_array(os, "Int64", "connectivity", 1, [&](Eigen::Index i) { return connectivity[size_t(i)]; },
               Eigen::Index(connectivity.size()));
    data_array(os, "Int64", "offsets", 1, [&](Eigen::Index i) { return offsets[size_t(i)]; }, nl);
    os << "      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  });
}

namespace {

using XmlDoc = std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)>;

std::string attribute(xmlNode* node, const char* name) {
  xmlChar* v = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  if (v == nullptr) return {};
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

bool is_element(xmlNode* node, const char* name) {
  return node != nullptr && node->type == XML_ELEMENT_NODE &&
         xmlStrcmp(node->name, reinterpret_cast<const xmlChar*>(name)) == 0;
}

xmlNode* child(xmlNode* parent, const char* name) {
  for (xmlNode* c = parent ? parent->children : nullptr; c != nullptr; c = c->next)
    if (is_element(c, name)) return c;
  return nullptr;
}

struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& what) const { throw InputError(file + ": " + what); }

  xmlNode* need(xmlNode* parent, const char* name) const {
    xmlNode* c = child(parent, name);
    if (c == nullptr) fail(fmt::format("no <{}> element", name));
    return c;
  }

  /// The numbers of an ASCII DataArray; exactly `count` of them.
  std::vector<double> numbers(xmlNode* array, size_t count) const {
    const std::string name = attribute(array, "Name");
    if (attribute(array, "format") != "ascii")
      fail(fmt::format("DataArray '{}': only format=\"ascii\" is read", name));
    xmlChar* text = xmlNodeGetContent(array);
    std::vector<double> out;
    const char* p = reinterpret_cast<const char*>(text);
    while (p != nullptr && *p != '\0') {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(p, &end);
      if (end == p) {
        while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') ++p;
        if (*p == '\0') break;
        xmlFree(text);
        fail(fmt::format("DataArray '{}': not a number near '{:.20}'", name, p));
      }
      out.push_back(v);
      p = end;
    }
    xmlFree(text);
    if (out.size() != count) fail(fmt::format("DataArray '{}': {} values, expected {}", name, out.size(), count));
    return out;
  }

  std::map<std::string, xmlNode*> arrays(xmlNode* parent) const {
    std::map<std::string, xmlNode*> out;
    for (xmlNode* c = parent ? parent->children : nullptr; c != nullptr; c = c->next)
      if (is_element(c, "DataArray")) out[attribute(c, "Name")] = c;
    return out;
  }
};

long long parse_count(const Reader& r, const std::string& text, const char* what) {
  char* end = nullptr;
  const long long n = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || n < 0) r.fail(fmt::format("{}=\"{}\" is not a count", what, text));
  return n;
}

/// A VTK XML file's document (kept alive), its <Piece> and the piece's counts.
struct VtkPiece {
  XmlDoc doc{nullptr, &xmlFreeDoc};
  xmlNode* piece = nullptr;
  long long points = 0;  ///< NumberOfPoints
  long long items = 0;   ///< NumberOfCells or NumberOfLines
};

/// Reads `path` as a VTK XML file of `type` ("UnstructuredGrid", "PolyData") whose items are
/// counted by the attribute `item_count` ("NumberOfCells", "NumberOfLines").
VtkPiece open_piece(const Reader& r, const std::filesystem::path& path, const std::string& type,
                    const char* item_count) {
  VtkPiece p;
  p.doc.reset(xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING | XML_PARSE_HUGE));
  if (!p.doc) r.fail("cannot be read as XML");
  xmlNode* root = xmlDocGetRootElement(p.doc.get());
  if (!is_element(root, "VTKFile") || attribute(root, "type") != type) r.fail("not a VTK XML " + type + " file");
  p.piece = r.need(r.need(root, type.c_str()), "Piece");
  p.points = parse_count(r, attribute(p.piece, "NumberOfPoints"), "NumberOfPoints");
  p.items = parse_count(r, attribute(p.piece, item_count), item_count);
  return p;
}

/// The coordinates (3·count) of the <Points> of `piece`.
std::vector<double> point_coordinates(const Reader& r, xmlNode* piece, long long count) {
  xmlNode* points = child(r.need(piece, "Points"), "DataArray");
  if (points == nullptr) r.fail("<Points> has no DataArray");
  return r.numbers(points, size_t(3 * count));
}

}  // namespace

VtuContents read_vtu(const std::filesystem::path& path) {
  Reader r{path.string()};
  const VtkPiece file = open_piece(r, path, "UnstructuredGrid", "NumberOfCells");
  xmlNode* piece = file.piece;
  const long long nv = file.points, nf = file.items;

  VtuContents out;
  const std::vector<double> xyz = point_coordinates(r, piece, nv);
  out.vertices = Eigen::Map<const RowMatX3d>(xyz.data(), Eigen::Index(nv), 3);

  const auto cells = r.arrays(r.need(piece, "Cells"));
  for (const char* name : {"connectivity", "offsets", "types"})
    if (!cells.count(name)) r.fail(fmt::format("<Cells> has no '{}' array", name));
  const std::vector<double> types = r.numbers(cells.at("types"), size_t(nf));
  const std::vector<double> offsets = r.numbers(cells.at("offsets"), size_t(nf));
  for (long long f = 0; f < nf; ++f)
    if (types[size_t(f)] != kVtkTriangle || offsets[size_t(f)] != double(3 * (f + 1)))
      r.fail(fmt::format("cell {} is not a triangle", f));
  const std::vector<double> conn = r.numbers(cells.at("connectivity"), size_t(3 * nf));
  out.faces.resize(Eigen::Index(nf), 3);
  for (size_t i = 0; i < conn.size(); ++i) {
    if (conn[i] < 0 || conn[i] >= double(nv)) r.fail(fmt::format("connectivity[{}] = {} is out of range", i, conn[i]));
    out.faces(Eigen::Index(i / 3), Eigen::Index(i % 3)) = int(conn[i]);
  }
  for (const auto& [name, node] : r.arrays(child(piece, "CellData"))) {
    const std::vector<double> v = r.numbers(node, size_t(nf));
    out.fields.face[name] = Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(nf));
  }
  for (const auto& [name, node] : r.arrays(child(piece, "PointData"))) {
    if (attribute(node, "NumberOfComponents") != "3") r.fail(fmt::format("point array '{}' is not a 3-vector", name));
    const std::vector<double> v = r.numbers(node, size_t(3 * nv));
    out.fields.vertex[name] = Eigen::Map<const RowMatX3d>(v.data(), Eigen::Index(nv), 3);
  }
  return out;
}

VtpContents read_vtp_polylines(const std::filesystem::path& path) {
  Reader r{path.string()};
  const VtkPiece file = open_piece(r, path, "PolyData", "NumberOfLines");
  xmlNode* piece = file.piece;
  const long long np = file.points, nl = file.items;
  const std::vector<double> xyz = point_coordinates(r, piece, np);
  const auto lines = r.arrays(r.need(piece, "Lines"));
  for (const char* name : {"connectivity", "offsets"})
    if (!lines.count(name)) r.fail(fmt::format("<Lines> has no '{}' array", name));
  const std::vector<double> offsets = r.numbers(lines.at("offsets"), size_t(nl));
  const std::vector<double> conn = r.numbers(lines.at("connectivity"), nl > 0 ? size_t(offsets.back()) : 0);
  VtpContents out;
  size_t begin = 0;
  for (long long l = 0; l < nl; ++l) {
    const size_t end = size_t(offsets[size_t(l)]);
    if (end < begin || end > conn.size()) r.fail(fmt::format("offsets[{}] = {} is out of order", l, end));
    RowMatX3d pts(Eigen::Index(end - begin), 3);
    for (size_t k = begin; k < end; ++k) {
      const double i = conn[k];
      if (i < 0 || i >= double(np)) r.fail(fmt::format("connectivity[{}] = {} is out of range", k, i));
      pts.row(Eigen::Index(k - begin)) << xyz[size_t(3 * i)], xyz[size_t(3 * i + 1)], xyz[size_t(3 * i + 2)];
    }
    out.lines.push_back(std::move(pts));
    begin = end;
  }
  for (const auto& [name, node] : r.arrays(child(piece, "CellData"))) {
    const std::vector<double> v = r.numbers(node, size_t(nl));
    out.cell_fields[name] = Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(nl));
  }
  return out;
}

}  // namespace cutwork
