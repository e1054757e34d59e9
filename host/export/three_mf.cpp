// 3MF through lib3mf 1.8.1 (Debian 12's lib3mf-dev), whose public interface is the C ABI of
// Model/COM/NMR_DLLInterfaces.h: opaque handles, LIB3MFRESULT codes, lib3mf_getlasterror.
#include <Model/COM/NMR_DLLInterfaces.h>

#include <memory>
#include <vector>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/export/solid.h"

namespace cutwork {
namespace {

using namespace NMR;

/// Releases a lib3mf handle.
struct Handle {
  PLib3MFBase* p = nullptr;
  Handle() = default;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (p != nullptr) lib3mf_release(p);
  }
};

/// Throws InputError("<file>: lib3mf: <what>: <message>") unless `result` is success.
void check(LIB3MFRESULT result, PLib3MFBase* instance, const std::filesystem::path& path, const char* what) {
  if (result == LIB3MF_OK) return;
  DWORD code = 0;
  LPCSTR message = nullptr;
  if (instance != nullptr) lib3mf_getlasterror(instance, &code, &message);
  throw InputError(fmt::format("{}: lib3mf: {} failed ({:#x}{}{})", path.string(), what, unsigned(result),
                               message ? ": " : "", message ? message : ""));
}

}  // namespace

void write_3mf(const std::filesystem::path& path, const Solid& solid, const std::string& name) {
  Handle model, mesh, item, writer;
  check(lib3mf_createmodel(&model.p), nullptr, path, "createmodel");
  check(lib3mf_model_setunit(model.p, MODELUNIT_MILLIMETER), model.p, path, "setunit");
  check(lib3mf_model_addmeshobject(model.p, &mesh.p), model.p, path, "addmeshobject");
  check(lib3mf_object_setnameutf8(mesh.p, name.c_str()), mesh.p, path, "setname");
  std::vector<MODELMESHVERTEX> vertices(size_t(solid.vertices.rows()));
  for (size_t v = 0; v < vertices.size(); ++v)
    for (int k = 0; k < 3; ++k) vertices[v].m_fPosition[k] = FLOAT(1e3 * solid.vertices(Eigen::Index(v), k));
  std::vector<MODELMESHTRIANGLE> triangles(size_t(solid.faces.rows()));
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) triangles[f].m_nIndices[k] = DWORD(solid.faces(Eigen::Index(f), k));
  check(lib3mf_meshobject_setgeometry(mesh.p, vertices.data(), DWORD(vertices.size()), triangles.data(),
                                      DWORD(triangles.size())),
        mesh.p, path, "setgeometry");
  check(lib3mf_model_addbuilditem(model.p, mesh.p, nullptr, &item.p), model.p, path, "addbuilditem");
  check(lib3mf_model_querywriter(model.p, "3mf", &writer.p), model.p, path, "querywriter");
  ULONG64 size = 0;
  check(lib3mf_writer_getstreamsize(writer.p, &size), writer.p, path, "getstreamsize");
  std::string buffer(size_t(size), '\0');
  check(lib3mf_writer_writetobuffer(writer.p, reinterpret_cast<BYTE*>(buffer.data()), size), writer.p, path,
        "writetobuffer");
  write_file_atomic(path, buffer);
}

ThreeMfMesh read_3mf(const std::filesystem::path& path) {
  Handle model, reader, iterator;
  check(lib3mf_createmodel(&model.p), nullptr, path, "createmodel");
  check(lib3mf_model_queryreader(model.p, "3mf", &reader.p), model.p, path, "queryreader");
  check(lib3mf_reader_readfromfileutf8(reader.p, path.c_str()), reader.p, path, "read");
  check(lib3mf_model_getmeshobjects(model.p, &iterator.p), model.p, path, "getmeshobjects");
  BOOL has = false;
  check(lib3mf_resourceiterator_movenext(iterator.p, &has), iterator.p, path, "movenext");
  if (!has) throw InputError(path.string() + ": no mesh object");
  Handle mesh;
  check(lib3mf_resourceiterator_getcurrent(iterator.p, &mesh.p), iterator.p, path, "getcurrent");
  DWORD nv = 0, nt = 0;
  check(lib3mf_meshobject_getvertexcount(mesh.p, &nv), mesh.p, path, "getvertexcount");
  check(lib3mf_meshobject_gettrianglecount(mesh.p, &nt), mesh.p, path, "gettrianglecount");
  std::vector<MODELMESHVERTEX> vertices(nv);
  std::vector<MODELMESHTRIANGLE> triangles(nt);
  check(lib3mf_meshobject_getvertices(mesh.p, vertices.data(), nv, nullptr), mesh.p, path, "getvertices");
  check(lib3mf_meshobject_gettriangleindices(mesh.p, triangles.data(), nt, nullptr), mesh.p, path, "gettriangles");
  DWORD unit = 0;
  check(lib3mf_model_getunit(model.p, &unit), model.p, path, "getunit");
  ThreeMfMesh out;
  out.unit = unit == MODELUNIT_MILLIMETER ? "millimeter" : unit == MODELUNIT_METER ? "meter" : fmt::format("{}", unit);
  out.vertices.resize(nv, 3);
  for (DWORD v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) out.vertices(v, k) = vertices[v].m_fPosition[k];
  out.faces.resize(nt, 3);
  for (DWORD f = 0; f < nt; ++f)
    for (int k = 0; k < 3; ++k) out.faces(f, k) = int(triangles[f].m_nIndices[k]);
  return out;
}

}  // namespace cutwork
