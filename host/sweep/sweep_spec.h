#pragma once
/// A sweep file (docs/SWEEP.md): a base scene and axes, each a JSON pointer into the scene with a
/// list of values, a range with a count, or a distribution, combined as a full grid, a Latin
/// hypercube or random samples. Parsing and expansion only; `cutwork sweep` runs the variants.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/scene/scene.h"

namespace cutwork {

enum class Sampling { Grid, LatinHypercube, Random };

/// One axis: where it writes into the scene and what it takes.
struct SweepAxis {
  enum class Kind { Values, Range, Distribution };
  std::string pointer;                 ///< JSON pointer into the scene document (/material/thickness)
  std::string where;                   ///< the axis' own path in the sweep file (/axes/1), for messages
  Kind kind = Kind::Values;
  std::vector<nlohmann::json> values;  ///< Values: the list, any JSON values
  double lo = 0, hi = 0;               ///< Range: [lo, hi]; Distribution: uniform/log_uniform bounds
  int count = 0;                       ///< Range: points on a grid (lo and hi included)
  bool log = false;                    ///< Range: geometric spacing (lo, hi > 0)
  std::string distribution;            ///< Distribution: uniform, log_uniform or normal
  double mean = 0, sd = 0;             ///< Distribution normal: mean and standard deviation
  bool integer = false;                ///< round numbers to integers (counts, seeds)

  /// The grid points of a Values or Range axis (not a Distribution).
  std::vector<nlohmann::json> grid() const;
  /// The axis' value at quantile u ∈ [0, 1): Values pick entry ⌊u·n⌋, a Range is mapped
  /// linearly (or geometrically) onto [lo, hi], a Distribution by its inverse CDF.
  nlohmann::json at_quantile(double u) const;
};

struct SweepSpec {
  std::string origin;                  ///< the sweep file, for messages
  std::string name;                    ///< the sweep's name (default: the file's stem)
  nlohmann::ordered_json base;         ///< the base scene's complete document (scene_to_json)
  std::string base_origin;             ///< how messages name the base (builtin:bowl, a file)
  std::filesystem::path base_dir;      ///< where relative paths of the base resolve
  std::vector<SweepAxis> axes;
  Sampling sampling = Sampling::Grid;
  int samples = 0;                     ///< Latin hypercube / random: the number of variants
  unsigned seed = 1;
  int iterations = 0;                  ///< L-BFGS-B iterations per phase (0: the scene's)
  std::string phases = "pattern,structure";
};

/// One point of the sweep: its id, the value of every axis and its scene document.
struct SweepVariant {
  std::string id;                      ///< v001, v002, ... in expansion order
  std::vector<nlohmann::json> values;  ///< one per axis
  nlohmann::ordered_json scene;        ///< the base document with the values written in
};

/// Parses a sweep document. `origin` names it in messages; relative scene files resolve against
/// `dir`. The base scene is loaded (and validated) here. Throws InputError
/// "<origin>: <json path>: <problem>".
SweepSpec parse_sweep(const nlohmann::json& doc, const std::string& origin, const std::filesystem::path& dir);
/// Reads and parses a sweep file.
SweepSpec load_sweep(const std::filesystem::path& file);

/// The axis values of every variant, in order: a grid varies the last axis fastest; a Latin
/// hypercube puts one sample in each of `samples` equal strata of every axis (strata permuted
/// independently per axis, a uniform point within each stratum); random draws every axis
/// independently. Deterministic for the seed (host/pattern/random.h).
std::vector<std::vector<nlohmann::json>> expand_axes(const SweepSpec& spec);

/// Every variant with its scene document, each validated as a scene before it is returned
/// (`scenes`, when given, receives the parsed scenes). Throws InputError naming the variant,
/// its values and the scene's JSON path: "<origin>: variant v003 (/material/thickness = -1):
/// /material/thickness: must be > 0 ...".
std::vector<SweepVariant> expand_sweep(const SweepSpec& spec, std::vector<Scene>* scenes = nullptr);

/// "pointer = value, ..." of a variant, for messages.
std::string describe_values(const SweepSpec& spec, const std::vector<nlohmann::json>& values);

}  // namespace cutwork
