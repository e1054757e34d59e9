#pragma once
/// What a sweep records per variant, and the tables it writes: summary.csv (one row per
/// variant) and pareto.csv (the non-dominated designs). Units: W in J/m², compliance in J,
/// displacement in m, time in s; the material fraction is Σ α A / Σ A of the final design.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cutwork {

/// One variant's outcome: the completion marker variants/<id>/result.json holds exactly this.
struct VariantResult {
  std::string id;
  std::vector<nlohmann::json> values;  ///< one per axis
  bool ok = false;
  std::string reason;                  ///< why it failed (one line), empty when ok
  int stencils = 0;
  double material_fraction = NAN;
  double W_max_uncut = NAN, W_max_pattern = NAN, W_max_final = NAN;
  double W_peak_final = NAN;           ///< the ligament peak estimate of the final design (J/m²)
  double W_lig_final = NAN;            ///< narrow ligaments' W_lig (J/m²; NaN: none searched)
  double compliance = NAN;             ///< of the final design
  double compliance_error = NAN;       ///< its discretisation estimate (NaN: not estimated)
  int converged = -1;                  ///< the estimate's verdict: 1, 0, or −1 (not estimated)
  double max_displacement = NAN;       ///< of the final design
  double seconds = 0;                  ///< wall time of the variant
  int rank = 0;                        ///< the MPI rank that ran it (0 without MPI)

  /// Fills the measured fields from a design's report.json (solvers/report/design_report.h).
  void take_report(const nlohmann::json& report);
  nlohmann::json to_json() const;
  /// Reads a marker; throws InputError naming `origin` when it is not one.
  static VariantResult from_json(const nlohmann::json& j, const std::string& origin);
};

/// The summary table: id, one column per axis (headed by its JSON pointer), status, reason,
/// stencils, material_fraction, W_max_uncut, W_max_pattern, W_max_final, W_peak_final, W_lig_final,
/// compliance, compliance_error (the final design's discretisation estimate), converged (yes / no),
/// max_displacement, seconds. Numbers in shortest round-trip form (compliance_error to four
/// significant digits: its refined solves' last digits depend on the threads a variant ran with);
/// missing ones empty.
std::string summary_csv(const std::vector<std::string>& axis_pointers, const std::vector<VariantResult>& results);

/// Indices of the points not dominated by any other (both coordinates minimised: a point is
/// dominated when another is no worse in both and better in one). Non-finite points are left out.
/// Sorted by x, then y.
std::vector<size_t> pareto_front(const std::vector<double>& x, const std::vector<double>& y);

/// The two fronts of a sweep's successful variants: material fraction against W_max_final and
/// against compliance (indices into `results`).
struct ParetoFronts {
  std::vector<size_t> w_max, compliance;
};
ParetoFronts sweep_pareto_fronts(const std::vector<VariantResult>& results);

/// pareto.csv: front (W_max or compliance), id, the axis values, material_fraction,
/// W_max_final, compliance; rows of each front by increasing material fraction.
std::string pareto_csv(const std::vector<std::string>& axis_pointers, const std::vector<VariantResult>& results,
                       const ParetoFronts& fronts);

/// A CSV table read back (RFC 4180 quoting), for tests and tools.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// Column index of `name`; throws InputError when there is none.
  size_t column(const std::string& name) const;
};
CsvTable parse_csv(const std::string& text);

}  // namespace cutwork
