// W_peak's cost per evaluation (solvers/objective/peak_energy_density.h) on the built-in `sheet` at
// about 2e4 and 2e5 faces (bench/scene_models.h), sagged, every face cut (α 0.4–1):
//
//   BM_PeakEnergyDensity/<faces>/<rule>/<vjp>
//       rule 0: the worst shape's factors (no cover); rule 1: by shape and by corner, a library of
//       stars and circles, each face covered by one or both (the cover of a design of two shapes,
//       corner moments at ε 0.05–0.6); vjp 0: W_peak alone (a report, the line search), 1: its
//       vector–Jacobian product in x, α and the cover (the peak objective's gradient).
//
// Counter faces/s: faces per wall second, all of the machine's threads (TBB's default arena). The
// by-shape rule reads each covering shape's factors at four (ρ) × two (ε) nodes per part.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>

#include "bench/scene_models.h"
#include "solvers/objective/peak_energy_density.h"

namespace cutwork {
namespace {

struct PeakCase {
  std::unique_ptr<solvers::ShellModel> model;
  RowMatX3d x;
  Eigen::VectorXd alpha;
  solvers::ShapeCover cover;
};

const PeakCase& peak_case(int faces) {
  static std::map<int, PeakCase> cache;
  PeakCase& c = cache[faces];
  if (c.model) return c;
  const solvers::ShellModel& sheet = bench::sheet_model(faces, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  StencilLibrary shapes;
  shapes.add(make_builtin_stencil("star", {}, "star"));
  shapes.add(make_builtin_stencil("circle", {}, "circle"));
  MechanicsSettings mechanics = sheet.mechanics();
  mechanics.stiffness_curve = solvers::calibrate_fill_stiffness(shapes, sheet.material());
  mechanics.corner_radius = 0.001;
  c.model = std::make_unique<solvers::ShellModel>(sheet.mesh(), sheet.material(), sheet.load_case(), mechanics);
  const int nf = c.model->num_faces();
  c.x = c.model->rest_positions();
  for (int v = 0; v < c.x.rows(); ++v)
    if (!c.model->fixed()[v])
      c.x(v, 2) -= 0.01 * std::sin(std::numbers::pi * c.x(v, 0)) * std::sin(std::numbers::pi * c.x(v, 1));
  c.alpha.resize(nf);
  c.cover.covered.resize(nf, 2);
  c.cover.corner.resize(nf, 2);
  for (int t = 0; t < nf; ++t) {
    c.alpha[t] = 0.4 + 0.6 * double(t % 7) / 6;
    const double hole = 1 - c.alpha[t], share = double(t % 5) / 4;  // stars' share of the hole
    c.cover.covered(t, 0) = share * hole;
    c.cover.covered(t, 1) = (1 - share) * hole;
    c.cover.corner(t, 0) = (0.05 + 0.55 * double(t % 11) / 10) * c.cover.covered(t, 0);
    c.cover.corner(t, 1) = 0.1 * c.cover.covered(t, 1);
  }
  return c;
}

void BM_PeakEnergyDensity(benchmark::State& state) {
  const PeakCase& c = peak_case(int(state.range(0)));
  const bool by_shape = state.range(1) != 0, vjp = state.range(2) != 0;
  const solvers::ConcentrationMap K(c.model->mechanics().stiffness_curve);
  const solvers::ShapeCover* cover = by_shape ? &c.cover : nullptr;
  const Eigen::VectorXd weights = Eigen::VectorXd::Ones(c.model->num_faces());
  RowMatX3d dx;
  Eigen::VectorXd da;
  solvers::ShapeCover dc;
  for (auto _ : state) {
    if (vjp) {
      solvers::peak_energy_density_vjp(*c.model, c.x, c.alpha, K, nullptr, weights, &dx, &da, cover,
                                       by_shape ? &dc : nullptr);
      benchmark::DoNotOptimize(dx.data());
    } else {
      const Eigen::VectorXd P = solvers::peak_energy_density(*c.model, c.x, c.alpha, K, nullptr, cover);
      benchmark::DoNotOptimize(P.data());
    }
  }
  state.counters["faces"] = c.model->num_faces();
  state.counters["faces/s"] =
      benchmark::Counter(double(c.model->num_faces()) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(by_shape ? "by shape and corner" : "worst shape") + (vjp ? ", vjp" : ""));
}

BENCHMARK(BM_PeakEnergyDensity)
    ->ArgsProduct({{20000, 200000}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace cutwork
