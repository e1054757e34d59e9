#include "host/cli/checkpoint.h"

#include <cmath>

#include "host/core/error.h"
#include "host/core/json_io.h"

namespace cutwork::cli {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
constexpr const char* format_name = "cutwork design checkpoint 1";

// Non-finite numbers (an objective that was never evaluated) travel as strings.
json number(double v) { return std::isfinite(v) ? json(v) : json(std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf"); }
double number(const json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  return s == "inf" ? INFINITY : s == "-inf" ? -INFINITY : NAN;
}

json matrix(const RowMatX3d& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) rows.push_back({number(m(i, 0)), number(m(i, 1)), number(m(i, 2))});
  return rows;
}
RowMatX3d matrix(const json& rows) {
  RowMatX3d m(Eigen::Index(rows.size()), 3);
  for (size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) m(Eigen::Index(i), k) = number(rows[i][size_t(k)]);
  return m;
}

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
      s.position[k] = number(j.at("position")[size_t(k)]);
      s.where.bary[k] = number(j.at("bary")[size_t(k)]);
    }
    s.where.face = j.at("face").get<int>();
    s.scale = number(j.at("scale"));
    s.angle = number(j.at("angle"));
    s.type = j.at("type").get<int>();
    layout.push_back(s);
  }
  return layout;
}

json pattern_json(const PatternPhaseResult& r) {
  json histories = json::array();
  for (const auto& h : r.round_histories) {
    json round = json::array();
    for (double v : h) round.push_back(number(v));
    histories.push_back(round);
  }
  json radii = json::array();
  for (Eigen::Index i = 0; i < r.bounding_radii.size(); ++i) radii.push_back(number(r.bounding_radii[i]));
  const PatternTerms& t = r.terms_end;
  return {{"layout", layout_json(r.layout)}, {"normals", matrix(r.normals)}, {"tangents", matrix(r.tangents)},
          {"bounding_radii", radii}, {"objective", r.objective}, {"exemplar", r.exemplar},
          {"field_symmetry", r.field_symmetry}, {"unit", number(r.unit)}, {"epsilon", number(r.epsilon)},
          {"initial_count", r.initial_count}, {"removed", r.removed},
          {"inserted_by_hole_filling", r.inserted_by_hole_filling}, {"rounds", r.rounds},
          {"iterations", r.iterations}, {"evaluations", r.evaluations}, {"type_changes", r.type_changes},
          {"stop_reason", r.stop_reason}, {"round_histories", histories},
          {"objective_start", number(r.objective_start)}, {"objective_end", number(r.objective_end)},
          {"terms_end", {number(t.det), number(t.collision), number(t.boundary), number(t.repulsion),
                         number(t.growth), number(t.tether)}},
          {"seconds", number(r.seconds)}, {"seconds_initialize", number(r.seconds_initialize)},
          {"seconds_optimize", number(r.seconds_optimize)}, {"notes", r.notes}};
}

PatternPhaseResult pattern_from(const json& j) {
  PatternPhaseResult r;
  r.layout = layout_from(j.at("layout"));
  r.normals = matrix(j.at("normals"));
  r.tangents = matrix(j.at("tangents"));
  const json& radii = j.at("bounding_radii");
  r.bounding_radii.resize(Eigen::Index(radii.size()));
  for (size_t i = 0; i < radii.size(); ++i) r.bounding_radii[Eigen::Index(i)] = number(radii[i]);
  r.objective = j.at("objective").get<std::string>();
  r.exemplar = j.at("exemplar").get<std::string>();
  r.field_symmetry = j.at("field_symmetry").get<int>();
  r.unit = number(j.at("unit"));
  r.epsilon = number(j.at("epsilon"));
  r.initial_count = j.at("initial_count").get<int>();
  r.removed = j.at("removed").get<int>();
  r.inserted_by_hole_filling = j.at("inserted_by_hole_filling").get<int>();
  r.rounds = j.at("rounds").get<int>();
  r.iterations = j.at("iterations").get<int>();
  r.evaluations = j.at("evaluations").get<int>();
  r.type_changes = j.at("type_changes").get<int>();
  r.stop_reason = j.at("stop_reason").get<std::string>();
  for (const json& round : j.at("round_histories")) {
    r.round_histories.emplace_back();
    for (const json& v : round) r.round_histories.back().push_back(number(v));
  }
  r.objective_start = number(j.at("objective_start"));
  r.objective_end = number(j.at("objective_end"));
  const json& t = j.at("terms_end");
  r.terms_end = {number(t[0]), number(t[1]), number(t[2]), number(t[3]), number(t[4]), number(t[5])};
  r.seconds = number(j.at("seconds"));
  r.seconds_initialize = number(j.at("seconds_initialize"));
  r.seconds_optimize = number(j.at("seconds_optimize"));
  r.notes = j.at("notes").get<std::vector<std::string>>();
  return r;
}
}  // namespace

fs::path checkpoint_path(const fs::path& dir) { return dir / ".cutwork-checkpoint.json"; }

json checkpoint_fingerprint(const Scene& scene, int iterations) {
  return {{"scene", scene_to_json(scene)}, {"iterations", iterations}};
}

void write_pattern_checkpoint(const fs::path& dir, const json& fingerprint, const PatternPhaseResult& pattern) {
  write_json_atomic(checkpoint_path(dir),
                    {{"format", format_name}, {"fingerprint", fingerprint}, {"phase", "pattern"},
                     {"pattern", pattern_json(pattern)}});
}

std::optional<PatternPhaseResult> read_pattern_checkpoint(const fs::path& dir, const json& fingerprint) {
  const fs::path file = checkpoint_path(dir);
  if (!fs::exists(file)) return std::nullopt;
  const json doc = read_json_file(file);
  if (!doc.is_object() || doc.value("format", "") != format_name)
    throw InputError(file.string() + ": not a checkpoint of this version of cutwork design (remove it to start "
                                     "again)");
  if (doc.at("fingerprint") != fingerprint)
    throw InputError(file.string() + ": the checkpoint was made for another scene or other options (run "
                                     "without --resume to start again, which replaces it)");
  try {
    return pattern_from(doc.at("pattern"));
  } catch (const json::exception& e) {
    throw InputError(file.string() + ": damaged checkpoint (" + std::string(e.what()) + "); remove it to start again");
  }
}

}  // namespace cutwork::cli
