#include "host/sweep/sweep_results.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {

using nlohmann::json;

namespace {

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
double number_or_nan(const json& j) { return j.is_number() ? j.get<double>() : NAN; }

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string csv_number(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); }

/// An axis value as a CSV cell: strings without their JSON quotes, anything else as JSON.
std::string csv_value(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

std::string csv_line(const std::vector<std::string>& cells) {
  std::string line;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += csv_field(cells[i]);
  }
  return line + "\n";
}

}  // namespace

void VariantResult::take_report(const json& report) {
  const json& st = report.at("structure");
  stencils = report.at("stencils").at("count").get<int>();
  material_fraction = number_or_nan(st.at("material_fraction_final"));
  W_max_uncut = number_or_nan(st.at("W_max_uncut"));
  W_max_pattern = number_or_nan(st.at("W_max_pattern"));
  W_max_final = number_or_nan(st.at("W_max_final"));
  compliance = number_or_nan(st.at("compliance_final"));
  max_displacement = number_or_nan(st.at("max_displacement_final"));
  W_peak_final = number_or_nan(st.value("W_peak_max_final", json()));
  W_lig_final = st.contains("ligaments") ? number_or_nan(st["ligaments"].value("W_ligament_max", json())) : NAN;
  // How far from converged the compliance is (absent with --no-discretisation-estimate).
  const json& d = report.value("discretisation", json());
  if (d.is_object() && d.contains("final")) {
    compliance_error = number_or_nan(d["final"].value("estimated_error", json()));
    converged = d["final"].value("converged", false) ? 1 : 0;
  }
}

json VariantResult::to_json() const {
  return {{"id", id},
          {"values", values},
          {"status", ok ? "ok" : "failed"},
          {"reason", reason},
          {"stencils", stencils},
          {"material_fraction", number_or_null(material_fraction)},
          {"W_max_uncut", number_or_null(W_max_uncut)},
          {"W_max_pattern", number_or_null(W_max_pattern)},
          {"W_max_final", number_or_null(W_max_final)},
          {"W_peak_final", number_or_null(W_peak_final)},
          {"W_lig_final", number_or_null(W_lig_final)},
          {"compliance", number_or_null(compliance)},
          {"compliance_error", number_or_null(compliance_error)},
          {"converged", converged < 0 ? json(nullptr) : json(converged == 1)},
          {"max_displacement", number_or_null(max_displacement)},
          {"seconds", seconds},
          {"rank", rank}};
}

VariantResult VariantResult::from_json(const json& j, const std::string& origin) {
  try {
    VariantResult r;
    r.id = j.at("id").get<std::string>();
    r.values = j.at("values").get<std::vector<json>>();
    r.ok = j.at("status").get<std::string>() == "ok";
    r.reason = j.at("reason").get<std::string>();
    r.stencils = j.at("stencils").get<int>();
    r.material_fraction = number_or_nan(j.at("material_fraction"));
    r.W_max_uncut = number_or_nan(j.at("W_max_uncut"));
    r.W_max_pattern = number_or_nan(j.at("W_max_pattern"));
    r.W_max_final = number_or_nan(j.at("W_max_final"));
    r.compliance = number_or_nan(j.at("compliance"));
    // (Markers of sweeps run before these were recorded have none of them.)
    r.W_peak_final = number_or_nan(j.value("W_peak_final", json()));
    r.W_lig_final = number_or_nan(j.value("W_lig_final", json()));
    r.compliance_error = number_or_nan(j.value("compliance_error", json()));
    if (j.contains("converged") && j["converged"].is_boolean()) r.converged = j["converged"].get<bool>() ? 1 : 0;
    r.max_displacement = number_or_nan(j.at("max_displacement"));
    r.seconds = j.at("seconds").get<double>();
    r.rank = j.value("rank", 0);
    return r;
  } catch (const json::exception& e) {
    throw InputError(origin + ": not a sweep variant's result (" + e.what() + ")");
  }
}

std::string summary_csv(const std::vector<std::string>& axis_pointers, const std::vector<VariantResult>& results) {
  std::vector<std::string> header{"id"};
  header.insert(header.end(), axis_pointers.begin(), axis_pointers.end());
  for (const char* c : {"status", "reason", "stencils", "material_fraction", "W_max_uncut", "W_max_pattern",
                        "W_max_final", "W_peak_final", "W_lig_final", "compliance", "compliance_error", "converged",
                        "max_displacement", "seconds"})
    header.emplace_back(c);
  std::string text = csv_line(header);
  for (const VariantResult& r : results) {
    std::vector<std::string> row{r.id};
    for (const json& v : r.values) row.push_back(csv_value(v));
    row.insert(row.end(), {r.ok ? "ok" : "failed", r.reason, r.ok ? std::to_string(r.stencils) : std::string(),
                           csv_number(r.material_fraction), csv_number(r.W_max_uncut), csv_number(r.W_max_pattern),
                           csv_number(r.W_max_final), csv_number(r.W_peak_final), csv_number(r.W_lig_final),
                           csv_number(r.compliance),
                           // Four digits: the estimate's refined solves run with the variant's
                           // share of the threads, and its last digits follow the BLAS's blocking.
                           std::isfinite(r.compliance_error) ? fmt::format("{:.4g}", r.compliance_error) : std::string(),
                           r.converged < 0 ? std::string() : std::string(r.converged ? "yes" : "no"),
                           csv_number(r.max_displacement), fmt::format("{:.3f}", r.seconds)});
    text += csv_line(row);
  }
  return text;
}

std::vector<size_t> pareto_front(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<size_t> order;
  for (size_t i = 0; i < x.size(); ++i)
    if (std::isfinite(x[i]) && std::isfinite(y[i])) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return x[a] != x[b] ? x[a] < x[b] : y[a] < y[b];
  });
  // Sweep by increasing x: a point is on the front when its y is below every y before it, or it
  // ties the best point exactly (equal points do not dominate each other).
  std::vector<size_t> front;
  double best_y = INFINITY, best_x = NAN;
  for (size_t i : order) {
    if (y[i] < best_y) {
      front.push_back(i);
      best_y = y[i];
      best_x = x[i];
    } else if (y[i] == best_y && x[i] == best_x) {
      front.push_back(i);
    }
  }
  return front;
}

ParetoFronts sweep_pareto_fronts(const std::vector<VariantResult>& results) {
  std::vector<double> m, w, c;
  for (const VariantResult& r : results) {
    m.push_back(r.ok ? r.material_fraction : NAN);
    w.push_back(r.W_max_final);
    c.push_back(r.compliance);
  }
  return {pareto_front(m, w), pareto_front(m, c)};
}

std::string pareto_csv(const std::vector<std::string>& axis_pointers, const std::vector<VariantResult>& results,
                       const ParetoFronts& fronts) {
  std::vector<std::string> header{"front", "id"};
  header.insert(header.end(), axis_pointers.begin(), axis_pointers.end());
  header.insert(header.end(), {"material_fraction", "W_max_final", "compliance"});
  std::string text = csv_line(header);
  const auto rows = [&](const char* front, const std::vector<size_t>& idx) {
    for (size_t i : idx) {
      const VariantResult& r = results[i];
      std::vector<std::string> row{front, r.id};
      for (const json& v : r.values) row.push_back(csv_value(v));
      row.insert(row.end(), {csv_number(r.material_fraction), csv_number(r.W_max_final), csv_number(r.compliance)});
      text += csv_line(row);
    }
  };
  rows("W_max", fronts.w_max);
  rows("compliance", fronts.compliance);
  return text;
}

size_t CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw InputError("CSV table: no column '" + name + "'");
  return size_t(it - header.begin());
}

CsvTable parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> lines;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false, any = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') cell += '"', ++i;
      else if (c == '"') quoted = false;
      else cell += c;
    } else if (c == '"') {
      quoted = any = true;
    } else if (c == ',') {
      row.push_back(std::move(cell)), cell.clear(), any = true;
    } else if (c == '\n') {
      row.push_back(std::move(cell)), cell.clear();
      lines.push_back(std::move(row)), row.clear();
      any = false;
    } else if (c != '\r') {
      cell += c, any = true;
    }
  }
  if (any || !cell.empty()) row.push_back(cell), lines.push_back(row);
  CsvTable t;
  if (lines.empty()) return t;
  t.header = lines.front();
  t.rows.assign(lines.begin() + 1, lines.end());
  return t;
}

}  // namespace cutwork
