#include "host/cli/checkpoint.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/json_io.h"

namespace cutwork::cli {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace cutwork::solvers;

namespace {
constexpr const char* format_name = "cutwork design checkpoint 2";
static_assert(std::endian::native == std::endian::little, "checkpoints store little-endian doubles");

// ------------------------------------------------------------------ numbers and vectors

// Non-finite numbers (an objective that was never evaluated) travel as strings.
json number(double v) { return std::isfinite(v) ? json(v) : json(std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf"); }
double number(const json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s != "inf" && s != "-inf" && s != "nan") throw std::invalid_argument("'" + s + "' is not a number");
  return s == "inf" ? INFINITY : s == "-inf" ? -INFINITY : NAN;
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// n doubles as base64 of their bytes (exact, about 11 characters a number).
std::string encode(const double* v, size_t n) {
  const auto* b = reinterpret_cast<const unsigned char*>(v);
  const size_t bytes = n * sizeof(double);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  for (size_t i = 0; i < bytes; i += 3) {
    const uint32_t chunk = uint32_t(b[i]) << 16 | (i + 1 < bytes ? uint32_t(b[i + 1]) << 8 : 0) |
                           (i + 2 < bytes ? uint32_t(b[i + 2]) : 0);
    out += kBase64[chunk >> 18 & 63];
    out += kBase64[chunk >> 12 & 63];
    out += i + 1 < bytes ? kBase64[chunk >> 6 & 63] : '=';
    out += i + 2 < bytes ? kBase64[chunk & 63] : '=';
  }
  return out;
}
std::vector<double> decode(const json& j) {
  const std::string s = j.get<std::string>();
  if (s.size() % 4 != 0) throw std::invalid_argument("a vector's base64 text has a bad length");
  std::vector<unsigned char> bytes;
  bytes.reserve(s.size() / 4 * 3);
  for (size_t i = 0; i < s.size(); i += 4) {
    uint32_t chunk = 0;
    int pad = 0;
    for (size_t k = 0; k < 4; ++k) {
      const char c = s[i + k];
      const char* p = c == '=' ? nullptr : std::strchr(kBase64, c);
      if (c != '=' && (!p || c == '\0')) throw std::invalid_argument("a vector's base64 text has a bad character");
      pad += c == '=';
      chunk = chunk << 6 | (p ? uint32_t(p - kBase64) : 0);
    }
    bytes.push_back(chunk >> 16 & 255);
    if (pad < 2) bytes.push_back(chunk >> 8 & 255);
    if (pad < 1) bytes.push_back(chunk & 255);
  }
  if (bytes.size() % sizeof(double) != 0) throw std::invalid_argument("a vector's length is not whole doubles");
  std::vector<double> v(bytes.size() / sizeof(double));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), bytes.size());
  return v;
}

json vec(const Eigen::VectorXd& v) { return encode(v.data(), size_t(v.size())); }
Eigen::VectorXd vec(const json& j, Eigen::Index expected = -1) {
  const std::vector<double> d = decode(j);
  if (expected >= 0 && Eigen::Index(d.size()) != expected)
    throw std::invalid_argument(fmt::format("a vector has {} entries where {} belong", d.size(), expected));
  return Eigen::Map<const Eigen::VectorXd>(d.data(), Eigen::Index(d.size()));
}
json vec(const std::vector<double>& v) { return encode(v.data(), v.size()); }
json mat(const RowMatX3d& m) { return encode(m.data(), size_t(m.size())); }
RowMatX3d mat(const json& j) {
  const std::vector<double> d = decode(j);
  if (d.size() % 3 != 0) throw std::invalid_argument("a #×3 matrix's length is not a multiple of 3");
  return Eigen::Map<const RowMatX3d>(d.data(), Eigen::Index(d.size() / 3), 3);
}

/// FNV-1a (64 bit) of the text: a damaged checkpoint must not give a silently different design.
std::string digest(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return fmt::format("{:016x}", h);
}

// ------------------------------------------------------------------ layouts and results

json layout_json(const StencilLayout& layout) {
  json list = json::array();
  for (const PlacedStencil& s : layout)
    list.push_back({{"position", {number(s.position.x()), number(s.position.y()), number(s.position.z())}},
                    {"face", s.where.face},
                    {"bary", {number(s.where.bary.x()), number(s.where.bary.y()), number(s.where.bary.z())}},
                    {"scale", number(s.scale)},
                    {"angle", number(s.angle)},
                    {"type", s.type}});
  return list;
}
StencilLayout layout_from(const json& list) {
  StencilLayout layout;
  for (const json& j : list) {
    PlacedStencil s;
    for (int k = 0; k < 3; ++k) {
      s.position[k] = number(j.at("position").at(size_t(k)));
      s.where.bary[k] = number(j.at("bary").at(size_t(k)));
    }
    s.where.face = j.at("face").get<int>();
    s.scale = number(j.at("scale"));
    s.angle = number(j.at("angle"));
    s.type = j.at("type").get<int>();
    layout.push_back(s);
  }
  return layout;
}

json histories_json(const std::vector<std::vector<double>>& histories) {
  json list = json::array();
  for (const auto& h : histories) list.push_back(vec(h));
  return list;
}
std::vector<std::vector<double>> histories_from(const json& list) {
  std::vector<std::vector<double>> out;
  for (const json& h : list) out.push_back(decode(h));
  return out;
}

json stats_json(const JointOptimizerStats& s) {
  return {{"rounds", s.rounds}, {"iterations", s.iterations}, {"evaluations", s.evaluations},
          {"type_changes", s.type_changes}, {"removed", s.removed}, {"stop_reason", s.stop_reason},
          {"round_histories", histories_json(s.round_histories)}, {"seconds_optimize", number(s.seconds_optimize)}};
}
void stats_from(const json& j, JointOptimizerStats& s) {
  s.rounds = j.at("rounds").get<int>();
  s.iterations = j.at("iterations").get<int>();
  s.evaluations = j.at("evaluations").get<int>();
  s.type_changes = j.at("type_changes").get<int>();
  s.removed = j.at("removed").get<int>();
  s.stop_reason = j.at("stop_reason").get<std::string>();
  s.round_histories = histories_from(j.at("round_histories"));
  s.seconds_optimize = number(j.at("seconds_optimize"));
}

json pattern_json(const PatternPhaseResult& r) {
  const PatternTerms& t = r.terms_end;
  return {{"optimiser", stats_json(r)}, {"layout", layout_json(r.layout)}, {"normals", mat(r.normals)},
          {"tangents", mat(r.tangents)}, {"bounding_radii", vec(r.bounding_radii)}, {"objective", r.objective},
          {"exemplar", r.exemplar}, {"field_symmetry", r.field_symmetry}, {"unit", number(r.unit)},
          {"epsilon", number(r.epsilon)}, {"initial_count", r.initial_count},
          {"inserted_by_hole_filling", r.inserted_by_hole_filling},
          {"objective_start", number(r.objective_start)}, {"objective_end", number(r.objective_end)},
          {"terms_end", {number(t.det), number(t.collision), number(t.boundary), number(t.repulsion),
                         number(t.growth), number(t.tether)}},
          {"seconds", number(r.seconds)}, {"seconds_initialize", number(r.seconds_initialize)}, {"notes", r.notes}};
}
PatternPhaseResult pattern_from(const json& j) {
  PatternPhaseResult r;
  stats_from(j.at("optimiser"), r);
  r.layout = layout_from(j.at("layout"));
  r.normals = mat(j.at("normals"));
  r.tangents = mat(j.at("tangents"));
  r.bounding_radii = vec(j.at("bounding_radii"));
  r.objective = j.at("objective").get<std::string>();
  r.exemplar = j.at("exemplar").get<std::string>();
  r.field_symmetry = j.at("field_symmetry").get<int>();
  r.unit = number(j.at("unit"));
  r.epsilon = number(j.at("epsilon"));
  r.initial_count = j.at("initial_count").get<int>();
  r.inserted_by_hole_filling = j.at("inserted_by_hole_filling").get<int>();
  r.objective_start = number(j.at("objective_start"));
  r.objective_end = number(j.at("objective_end"));
  const json& t = j.at("terms_end");
  r.terms_end = {number(t.at(0)), number(t.at(1)), number(t.at(2)), number(t.at(3)), number(t.at(4)), number(t.at(5))};
  r.seconds = number(j.at("seconds"));
  r.seconds_initialize = number(j.at("seconds_initialize"));
  r.notes = j.at("notes").get<std::vector<std::string>>();
  return r;
}

json structure_json(const StructurePhaseResult& r) {
  return {{"optimiser", stats_json(r)}, {"layout", layout_json(r.layout)}, {"objective", r.objective},
          {"beta", number(r.beta)}, {"beta_history", vec(r.beta_history)}, {"w_ref", number(r.w_ref)},
          {"c_ref", number(r.c_ref)}, {"J", {number(r.J_start), number(r.J_end)}},
          {"S", {number(r.S_start), number(r.S_end)}}, {"P", {number(r.P_start), number(r.P_end)}},
          {"optimisations", r.optimisations}, {"inserted_by_hole_filling", r.inserted_by_hole_filling},
          {"removed_for_min_feature", r.removed_for_min_feature},
          {"covered_area", {number(r.covered_area_target), number(r.covered_area_final)}},
          {"restorations", r.restorations}, {"max_restoring_change", number(r.max_restoring_change)},
          {"seconds", number(r.seconds)}, {"notes", r.notes}};
}
StructurePhaseResult structure_from(const json& j) {
  StructurePhaseResult r;
  stats_from(j.at("optimiser"), r);
  r.layout = layout_from(j.at("layout"));
  r.objective = j.at("objective").get<std::string>();
  r.beta = number(j.at("beta"));
  r.beta_history = decode(j.at("beta_history"));
  r.w_ref = number(j.at("w_ref"));
  r.c_ref = number(j.at("c_ref"));
  r.J_start = number(j.at("J").at(0));
  r.J_end = number(j.at("J").at(1));
  r.S_start = number(j.at("S").at(0));
  r.S_end = number(j.at("S").at(1));
  r.P_start = number(j.at("P").at(0));
  r.P_end = number(j.at("P").at(1));
  r.optimisations = j.at("optimisations").get<int>();
  r.inserted_by_hole_filling = j.at("inserted_by_hole_filling").get<int>();
  r.removed_for_min_feature = j.value("removed_for_min_feature", 0);  // (absent before the minimum feature)
  r.covered_area_target = number(j.at("covered_area").at(0));
  r.covered_area_final = number(j.at("covered_area").at(1));
  r.restorations = j.at("restorations").get<int>();
  r.max_restoring_change = number(j.at("max_restoring_change"));
  r.seconds = number(j.at("seconds"));
  r.notes = j.at("notes").get<std::vector<std::string>>();
  return r;
}

// ------------------------------------------------------------------ optimiser state

json lbfgsb_json(const LbfgsbState& st) {
  const LbfgsbResult& r = st.result;
  json s = json::array(), y = json::array();
  for (size_t i = 0; i < st.s.size(); ++i) {
    s.push_back(vec(st.s[i]));
    y.push_back(vec(st.y[i]));
  }
  return {{"result", {{"x", vec(r.x)}, {"f", number(r.f)}, {"f_start", number(r.f_start)},
                      {"iterations", r.iterations}, {"evaluations", r.evaluations}, {"restarts", r.restarts},
                      {"scale", number(r.scale)}, {"history", vec(r.history)}}},
          {"best_at_restart", number(st.best_at_restart)}, {"x", vec(st.x)}, {"gradient", vec(st.gradient)},
          {"direction", vec(st.direction)}, {"f", number(st.f)}, {"k", st.k}, {"f_past", vec(st.f_past)},
          {"s", s}, {"y", y}, {"cache_x", vec(st.cache_x)}, {"cache_gradient", vec(st.cache_gradient)},
          {"cache_f", number(st.cache_f)}, {"first_of_run", st.first_of_run}};
}
/// An L-BFGS-B state of n variables.
LbfgsbState lbfgsb_from(const json& j, Eigen::Index n) {
  LbfgsbState st;
  const json& r = j.at("result");
  st.result.x = vec(r.at("x"), n);
  st.result.f = number(r.at("f"));
  st.result.f_start = number(r.at("f_start"));
  st.result.iterations = r.at("iterations").get<int>();
  st.result.evaluations = r.at("evaluations").get<int>();
  st.result.restarts = r.at("restarts").get<int>();
  st.result.scale = number(r.at("scale"));
  st.result.history = decode(r.at("history"));
  st.best_at_restart = number(j.at("best_at_restart"));
  st.x = vec(j.at("x"), n);
  st.gradient = vec(j.at("gradient"), n);
  st.direction = vec(j.at("direction"), n);
  st.f = number(j.at("f"));
  st.k = j.at("k").get<int>();
  st.f_past = vec(j.at("f_past"));
  if (j.at("s").size() != j.at("y").size()) throw std::invalid_argument("unpaired L-BFGS corrections");
  for (size_t i = 0; i < j.at("s").size(); ++i) {
    st.s.push_back(vec(j.at("s").at(i), n));
    st.y.push_back(vec(j.at("y").at(i), n));
  }
  st.cache_x = vec(j.at("cache_x"), n);
  st.cache_gradient = vec(j.at("cache_gradient"), n);
  st.cache_f = number(j.at("cache_f"));
  st.first_of_run = j.at("first_of_run").get<bool>();
  if (st.k < 1 || st.f_past.size() > 1000) throw std::invalid_argument("an L-BFGS-B state out of range");
  return st;
}

json phase_json(const PhaseSnapshot& p) {
  const JointOptimizerState& o = p.optimizer;
  json optimizer = {{"layout", layout_json(o.layout)}, {"matched_types", o.matched_types}, {"lower", vec(o.lower)}, {"upper", vec(o.upper)},
                    {"angle0", vec(o.angle0)}, {"used", o.used}, {"scale", number(o.scale)}, {"round", o.round},
                    {"best_round_end", number(o.best_round_end)}, {"stalled_rounds", o.stalled_rounds},
                    {"lbfgsb", p.lbfgsb ? lbfgsb_json(*p.lbfgsb) : json(nullptr)}};
  return {{"outer", p.cursor.outer}, {"fill", p.cursor.fill}, {"rng", p.rng.state()}, {"optimizer", optimizer}};
}
PhaseResume phase_from(const json& j) {
  PhaseResume p;
  p.cursor.outer = j.at("outer").get<int>();
  p.cursor.fill = j.at("fill").get<int>();
  p.rng = j.at("rng").get<std::string>();
  PatternRng(1).set_state(p.rng);  // refused here rather than half-way
  const json& o = j.at("optimizer");
  JointOptimizerState& st = p.optimizer;
  st.layout = layout_from(o.at("layout"));
  const Eigen::Index S = Eigen::Index(st.layout.size());
  st.matched_types = o.at("matched_types").get<std::vector<int>>();
  if (Eigen::Index(st.matched_types.size()) != S) throw std::invalid_argument("matched types do not fit the layout");
  st.lower = vec(o.at("lower"), S);
  st.upper = vec(o.at("upper"), S);
  st.angle0 = vec(o.at("angle0"), S);
  st.used = o.at("used").get<int>();
  st.scale = number(o.at("scale"));
  st.round = o.at("round").get<int>();
  st.best_round_end = number(o.at("best_round_end"));
  st.stalled_rounds = o.at("stalled_rounds").get<int>();
  if (!o.at("lbfgsb").is_null()) {
    // 4 variables per stencil (pattern), 5 with the angles (structure).
    const Eigen::Index n = Eigen::Index(decode(o.at("lbfgsb").at("x")).size());
    if (n != 4 * S && n != 5 * S) throw std::invalid_argument("the L-BFGS-B state does not fit the layout");
    st.lbfgsb = lbfgsb_from(o.at("lbfgsb"), n);
  }
  if (p.cursor.outer < 0 || p.cursor.fill < 0 || st.used < 0 || st.round < 0)
    throw std::invalid_argument("a phase position out of range");
  return p;
}

json params_json(const std::vector<StencilParams>& params) {
  std::vector<double> flat;
  json types = json::array();
  for (const StencilParams& p : params) {
    flat.insert(flat.end(), {p.position.x(), p.position.y(), p.position.z(), p.scale, p.angle});
    types.push_back(p.type);
  }
  return {{"values", vec(flat)}, {"types", types}};
}
std::vector<StencilParams> params_from(const json& j) {
  const std::vector<double> flat = decode(j.at("values"));
  const json& types = j.at("types");
  if (flat.size() != 5 * types.size()) throw std::invalid_argument("stencil parameters do not fit their types");
  std::vector<StencilParams> out;
  for (size_t i = 0; i < types.size(); ++i)
    out.push_back({Vec3(flat[5 * i], flat[5 * i + 1], flat[5 * i + 2]), flat[5 * i + 3], flat[5 * i + 4],
                   types.at(i).get<int>()});
  return out;
}

const char* stage_name(DesignStage s) {
  switch (s) {
    case DesignStage::Pattern: return "pattern";
    case DesignStage::PatternEnd: return "pattern_end";
    case DesignStage::Structure: return "structure";
    case DesignStage::StructureEnd: return "structure_end";
  }
  return "";
}
DesignStage stage_from(const json& j) {
  for (DesignStage s : {DesignStage::Pattern, DesignStage::PatternEnd, DesignStage::Structure, DesignStage::StructureEnd})
    if (j.get<std::string>() == stage_name(s)) return s;
  throw std::invalid_argument("unknown stage " + j.dump());
}

DesignResume resume_from(const json& doc) {
  DesignResume r;
  r.stage = stage_from(doc.at("stage"));
  r.pattern = pattern_from(doc.at("pattern"));
  const bool structure = r.stage == DesignStage::Structure || r.stage == DesignStage::StructureEnd;
  if (structure) {
    r.structure = structure_from(doc.at("structure"));
    r.shell_stencils = params_from(doc.at("shell").at("stencils"));
    r.equilibrium = mat(doc.at("shell").at("equilibrium"));
  }
  if (r.stage == DesignStage::Pattern || r.stage == DesignStage::Structure) r.phase = phase_from(doc.at("phase"));
  return r;
}
}  // namespace

fs::path checkpoint_path(const fs::path& dir) { return dir / ".cutwork-checkpoint.json"; }

json checkpoint_fingerprint(const Scene& scene, int iterations) {
  return {{"scene", scene_to_json(scene)}, {"iterations", iterations}};
}

const char* stage_description(DesignStage stage) {
  switch (stage) {
    case DesignStage::Pattern: return "inside the pattern phase";
    case DesignStage::PatternEnd: return "at the end of the pattern phase";
    case DesignStage::Structure: return "inside the structural phase";
    case DesignStage::StructureEnd: return "at the end of the structural phase";
  }
  return "";
}

std::uintmax_t write_checkpoint(const fs::path& dir, const json& fingerprint, const DesignSnapshot& state) {
  json doc = {{"format", format_name}, {"fingerprint", fingerprint}, {"stage", stage_name(state.stage)},
              {"pattern", pattern_json(state.pattern)}};
  if (state.structure) doc["structure"] = structure_json(*state.structure);
  if (state.phase) doc["phase"] = phase_json(*state.phase);
  if (state.shell_stencils && state.equilibrium)
    doc["shell"] = {{"stencils", params_json(*state.shell_stencils)}, {"equilibrium", mat(*state.equilibrium)}};
  doc["digest"] = digest(doc.dump());
  const std::string text = doc.dump() + "\n";
  write_file_atomic(checkpoint_path(dir), text);
  return text.size();
}

std::optional<DesignResume> read_checkpoint(const fs::path& dir, const json& fingerprint) {
  const fs::path file = checkpoint_path(dir);
  if (!fs::exists(file)) return std::nullopt;
  json doc;
  try {
    doc = read_json_file(file);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (a damaged checkpoint: remove it to start again)");
  }
  if (!doc.is_object() || !doc.contains("format") || doc["format"] != format_name)
    throw InputError(file.string() + ": not a checkpoint of this version of cutwork design (remove it to start "
                                     "again)");
  const json stored = doc.contains("digest") ? doc["digest"] : json();
  doc.erase("digest");
  if (!stored.is_string() || stored.get<std::string>() != digest(doc.dump()))
    throw InputError(file.string() + ": damaged checkpoint (its content does not match its digest); remove it to "
                                     "start again");
  if (doc.value("fingerprint", json()) != fingerprint)
    throw InputError(file.string() + ": the checkpoint was made for another scene or other options (run "
                                     "without --resume to start again, which replaces it)");
  try {
    return resume_from(doc);
  } catch (const std::exception& e) {
    throw InputError(file.string() + ": damaged checkpoint (" + std::string(e.what()) + "); remove it to start again");
  }
}

}  // namespace cutwork::cli
