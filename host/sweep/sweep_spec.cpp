#include "host/sweep/sweep_spec.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/pattern/random.h"
#include "host/scene/json_reader.h"

namespace cutwork {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// x with Φ(x) = u (standard normal), by bisection on erfc: exact to round-off, no tables.
double normal_quantile(double u) {
  u = std::clamp(u, 1e-15, 1 - 1e-15);
  double lo = -40, hi = 40;
  for (int i = 0; i < 200 && hi - lo > 1e-15; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < u ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

json number_value(double v, bool integer) { return integer ? json(std::llround(v)) : json(v); }

SweepAxis parse_axis(JsonObjectReader& a, Sampling sampling) {
  SweepAxis axis;
  axis.where = a.path();
  axis.pointer = a.required_string("path");
  try {
    (void)json::json_pointer(axis.pointer);
  } catch (const json::exception&) {
    a.fail("path", "'" + axis.pointer + "' is not a JSON pointer (like /material/thickness)");
  }
  if (axis.pointer.empty()) a.fail("path", "must point into the scene, not at the whole scene");
  axis.integer = a.boolean("integer", false);
  const int kinds = int(a.has("values")) + int(a.has("range")) + int(a.has("distribution"));
  if (kinds != 1) a.fail("path", "an axis needs exactly one of values, range or distribution");
  if (a.has("values")) {
    axis.kind = SweepAxis::Kind::Values;
    const json& v = a.array("values");
    if (v.empty()) a.fail("values", "must list at least one value");
    axis.values.assign(v.begin(), v.end());
  } else if (a.has("range")) {
    axis.kind = SweepAxis::Kind::Range;
    const json* r = a.child("range");
    if (!r->is_array() || r->size() != 2 || !(*r)[0].is_number() || !(*r)[1].is_number())
      a.fail("range", "must be [low, high] (two numbers)");
    axis.lo = (*r)[0].get<double>();
    axis.hi = (*r)[1].get<double>();
    if (!std::isfinite(axis.lo) || !std::isfinite(axis.hi) || axis.lo > axis.hi)
      a.fail("range", "must be [low, high] with low <= high");
    axis.count = a.integer("count", 0, 1, 1000000);
    if (axis.count == 0) a.fail("count", "is required with a range (the number of points, ends included)");
    axis.log = a.string("spacing", "linear", {"linear", "log"}) == "log";
    if (axis.log && axis.lo <= 0) a.fail("range", "log spacing needs low > 0");
  } else {
    axis.kind = SweepAxis::Kind::Distribution;
    axis.distribution = a.required_string("distribution", {"uniform", "log_uniform", "normal"});
    if (sampling == Sampling::Grid)
      a.fail("distribution", "a grid needs values or a range; a distribution needs sampling latin_hypercube or random");
    if (axis.distribution == "normal") {
      axis.mean = a.required_number("mean", -1e300, 1e300);
      axis.sd = a.required_number("sd", 0, 1e300, true);
    } else {
      const bool log = axis.distribution == "log_uniform";
      axis.lo = a.required_number("min", log ? 0 : -1e300, 1e300, log);
      axis.hi = a.required_number("max", axis.lo, 1e300);
    }
  }
  a.finish();
  return axis;
}

/// The base scene: a built-in name, a scene or mesh file (relative to the sweep file), or inline.
void parse_base(SweepSpec& spec, const json& base, const std::string& where, const fs::path& dir) {
  // Paths inside the base resolve to absolute ones (scene_to_json writes them resolved), so the
  // variants' documents are valid wherever they are read; paths an axis writes resolve against
  // the sweep file's folder.
  spec.base_dir = fs::absolute(dir);
  if (base.is_string()) {
    const std::string what = base.get<std::string>();
    const fs::path p = fs::path(what).is_absolute() ? fs::path(what) : spec.base_dir / what;
    std::error_code ec;
    const bool file = fs::exists(p, ec);
    const Scene s = load_scene(file ? p.string() : what);
    spec.base = scene_to_json(s);
    spec.base_origin = file ? p.string() : "builtin:" + what;
  } else if (base.is_object()) {
    spec.base_origin = spec.origin + ": " + where;
    spec.base = scene_to_json(parse_scene(base, spec.base_origin, spec.base_dir));
  } else {
    throw InputError(spec.origin + ": " + where + ": must be a built-in scene name, a scene file or a scene object");
  }
}

/// Every axis must write into an object or array the base scene has.
void check_pointer(const SweepSpec& spec, const SweepAxis& axis) {
  const json::json_pointer ptr(axis.pointer);
  const json::json_pointer parent = ptr.parent_pointer();
  const std::string at = spec.origin + ": " + axis.where + "/path: " + axis.pointer + ": ";
  if (!spec.base.contains(parent) || !(spec.base.at(parent).is_object() || spec.base.at(parent).is_array()))
    throw InputError(at + "the scene has no object or array at " + (parent.empty() ? "/" : parent.to_string()) +
                     " (see `cutwork show` for a scene's complete document)");
  const nlohmann::ordered_json& p = spec.base.at(parent);
  if (p.is_array()) {
    const std::string& last = ptr.back();
    const bool digits = !last.empty() && std::all_of(last.begin(), last.end(), ::isdigit);
    if (!digits || std::stoul(last) >= p.size())
      throw InputError(at + fmt::format("index '{}' is not in the scene's array of {} entries", last, p.size()));
  }
}

}  // namespace

std::vector<json> SweepAxis::grid() const {
  if (kind == Kind::Values) return values;
  std::vector<json> g;
  for (int i = 0; i < count; ++i) {
    const double t = count == 1 ? 0.0 : double(i) / (count - 1);
    const double v = log ? lo * std::pow(hi / lo, t) : lo + t * (hi - lo);
    g.push_back(number_value(i == count - 1 ? hi : v, integer));
  }
  return g;
}

json SweepAxis::at_quantile(double u) const {
  if (kind != Kind::Distribution) {
    const std::vector<json> g = grid();
    const size_t k = std::min(g.size() - 1, size_t(u * double(g.size())));
    return g[k];
  }
  if (distribution == "normal") return number_value(mean + sd * normal_quantile(u), integer);
  if (distribution == "log_uniform") return number_value(lo * std::pow(hi / lo, u), integer);
  return number_value(lo + u * (hi - lo), integer);
}

SweepSpec parse_sweep(const json& doc, const std::string& origin, const fs::path& dir) {
  SweepSpec spec;
  spec.origin = origin;
  JsonObjectReader r(doc, origin, "");
  spec.name = r.string("name", fs::path(origin).stem().string());
  const json* base = r.child("base");
  if (!base) throw InputError(origin + ": /base: is required (a built-in scene name, a scene file or a scene object)");
  const std::string s = r.string("sampling", "grid", {"grid", "latin_hypercube", "random"});
  spec.sampling = s == "grid" ? Sampling::Grid : s == "random" ? Sampling::Random : Sampling::LatinHypercube;
  if (spec.sampling == Sampling::Grid) {
    if (r.has("samples")) r.fail("samples", "is for latin_hypercube or random sampling; a grid has every combination");
  } else {
    spec.samples = r.integer("samples", 0, 1, 1000000);
    if (spec.samples == 0) r.fail("samples", "is required with latin_hypercube or random sampling");
  }
  spec.seed = unsigned(r.integer("seed", 1, 0, 2147483647));
  if (r.has("design")) {
    JsonObjectReader d = r.object("design");
    spec.iterations = d.integer("iterations", 0, 0, 1000000);
    spec.phases = d.string("phases", spec.phases, {"pattern", "pattern,structure"});
    d.finish();
  }
  const json& axes = r.array("axes");
  r.finish();
  if (axes.empty()) r.fail("axes", "must list at least one axis");
  for (size_t i = 0; i < axes.size(); ++i) {
    JsonObjectReader a(axes[i], origin, fmt::format("/axes/{}", i));
    spec.axes.push_back(parse_axis(a, spec.sampling));
  }
  try {
    parse_base(spec, *base, "/base", dir);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(origin + ": ", 0) == 0) throw;
    throw InputError(origin + ": /base: " + msg);
  }
  for (const SweepAxis& axis : spec.axes) check_pointer(spec, axis);
  size_t total = 1;
  if (spec.sampling == Sampling::Grid)
    for (const SweepAxis& a : spec.axes) {
      total *= a.grid().size();
      if (total > 1000000) throw InputError(origin + ": /axes: the grid has more than 1000000 variants");
    }
  return spec;
}

SweepSpec load_sweep(const fs::path& file) {
  const json doc = read_json_file(file);
  return parse_sweep(doc, file.string(), fs::absolute(file).parent_path());
}

std::vector<std::vector<json>> expand_axes(const SweepSpec& spec) {
  const size_t d = spec.axes.size();
  std::vector<std::vector<json>> out;
  if (spec.sampling == Sampling::Grid) {
    std::vector<std::vector<json>> grids;
    size_t total = 1;
    for (const SweepAxis& a : spec.axes) {
      grids.push_back(a.grid());
      total *= grids.back().size();
    }
    for (size_t k = 0; k < total; ++k) {
      std::vector<json> v(d);
      size_t rest = k;
      for (size_t j = d; j-- > 0;) {
        v[j] = grids[j][rest % grids[j].size()];
        rest /= grids[j].size();
      }
      out.push_back(std::move(v));
    }
    return out;
  }
  const int n = spec.samples;
  PatternRng rng(spec.seed);
  std::vector<std::vector<double>> u(d, std::vector<double>(size_t(n)));
  for (size_t j = 0; j < d; ++j) {
    if (spec.sampling == Sampling::Random) {
      for (int i = 0; i < n; ++i) u[j][size_t(i)] = rng.uniform();
      continue;
    }
    std::vector<int> strata(static_cast<size_t>(n));
    std::iota(strata.begin(), strata.end(), 0);
    for (int i = n - 1; i > 0; --i) std::swap(strata[size_t(i)], strata[size_t(rng.below(i + 1))]);
    for (int i = 0; i < n; ++i) u[j][size_t(i)] = (strata[size_t(i)] + rng.uniform()) / n;
  }
  for (int i = 0; i < n; ++i) {
    std::vector<json> v(d);
    for (size_t j = 0; j < d; ++j) v[j] = spec.axes[j].at_quantile(u[j][size_t(i)]);
    out.push_back(std::move(v));
  }
  return out;
}

std::string describe_values(const SweepSpec& spec, const std::vector<json>& values) {
  std::string s;
  for (size_t j = 0; j < values.size(); ++j)
    s += (j ? ", " : "") + spec.axes[j].pointer + " = " + values[j].dump();
  return s;
}

std::vector<SweepVariant> expand_sweep(const SweepSpec& spec, std::vector<Scene>* scenes) {
  const std::vector<std::vector<json>> points = expand_axes(spec);
  const int width = std::max(3, int(std::to_string(points.size()).size()));
  std::vector<SweepVariant> variants;
  for (size_t i = 0; i < points.size(); ++i) {
    SweepVariant v;
    v.id = fmt::format("v{:0{}}", i + 1, width);
    v.values = points[i];
    v.scene = spec.base;
    for (size_t j = 0; j < spec.axes.size(); ++j) v.scene[json::json_pointer(spec.axes[j].pointer)] = v.values[j];
    const std::string origin = spec.origin + ": variant " + v.id + " (" + describe_values(spec, v.values) + ")";
    Scene scene = parse_scene(nlohmann::json(v.scene), origin, spec.base_dir);
    if (scenes) scenes->push_back(std::move(scene));
    variants.push_back(std::move(v));
  }
  return variants;
}

}  // namespace cutwork
