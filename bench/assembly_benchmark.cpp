// Element throughput of the shell assembly (issue 12 item 3), on the built-in `sheet` at about
// 2e4 and 2e5 faces (bench/scene_models.h) in a smoothly sagged state (every element does real work).
//
//   BM_Assembly_<Kind>/<faces>/<need>   one element kind alone, serially on the benchmark thread:
//                                       gather positions, evaluate, scatter into the fixed pattern
//                                       (what assemble_shell does per element, without colours and
//                                       threads). Kind: Membrane (CST), ShapeOperator (the default
//                                       bending element), Hinge (the paper's, on a hinge model).
//   BM_Assembly_Shell/<Rule>/<faces>/<need>/<threads>
//                                       the whole shell (membranes + shape-operator bends) as the
//                                       solvers call it: shell_energy (need 0) or assemble_shell without
//                                       (1) and with (2) the Hessian, in a task_arena of <threads>;
//                                       counters nonzeros, element_colours and chunk_colours.
//                                       Rule: Linear, or HomogenisedSplit (the calibrated rule with
//                                       its bulk and shear parts, fill_stiffness_map.h).
// need: 0 energy only (the line search), 1 energy + gradient, 2 energy + gradient + Hessian.
// Counter elements/s: elements evaluated per CPU second — of the benchmark thread for the serial
// kinds, of the whole process (every TBB worker) for BM_Assembly_Shell. On a shared machine these
// are the rates to compare; the Time column is wall time.
#include <benchmark/benchmark.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>
#include <tuple>
#include <type_traits>

#include "bench/scene_models.h"
#include "solvers/shell/shell_energy.h"

namespace cutwork {
namespace {

using solvers::ElementKind;
using solvers::ElementNeed;
using solvers::ShellModel;

const char* const kNeedNames[] = {"energy", "gradient", "hessian"};

/// A smooth sag of 1% of the sheet's size (not the rest state, whose bending strain is zero).
RowMatX3d sagged(const ShellModel& model) {
  RowMatX3d x = model.rest_positions();
  for (int v = 0; v < x.rows(); ++v)
    if (!model.fixed()[v]) x(v, 2) -= 0.01 * std::sin(std::numbers::pi * x(v, 0)) * std::sin(std::numbers::pi * x(v, 1));
  return x;
}

/// [first, last) of the elements of one kind (the model stores them contiguously by kind).
std::pair<int, int> element_range(const ShellModel& model, ElementKind kind) {
  int first = -1, last = -1;
  for (int e = 0; e < model.num_elements(); ++e)
    if (model.element(e).kind == kind) {
      if (first < 0) first = e;
      last = e + 1;
    }
  return {std::max(first, 0), std::max(last, 0)};
}

void set_counters(benchmark::State& state, const ShellModel& model, double elements) {
  state.counters["faces"] = model.num_faces();
  state.counters["elements"] = elements;
  state.counters["elements/s"] = benchmark::Counter(elements * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel(kNeedNames[state.range(1)]);
}

void BM_Assembly_Kind(benchmark::State& state, ElementKind kind) {
  const BendingModel bending = kind == ElementKind::Hinge ? BendingModel::Hinge : BendingModel::ShapeOperator;
  const ShellModel& model = bench::sheet_model(int(state.range(0)), bending);
  const ElementNeed need = ElementNeed(state.range(1));
  const RowMatX3d x = sagged(model);
  const auto [first, last] = element_range(model, kind);
  const solvers::BlockAssembly& asmb = model.assembly();
  Eigen::VectorXd gradient(asmb.num_dofs());
  std::vector<double> hessian(std::size_t(asmb.num_nonzeros()));
  for (auto _ : state) {
    gradient.setZero();
    if (need == ElementNeed::Hessian) std::fill(hessian.begin(), hessian.end(), 0.0);
    double energy = 0;
    for (int e = first; e < last; ++e)
      solvers::visit_element(model, x, e, 1.0, need, [&](const auto& l) {
        constexpr int K = int(std::tuple_size_v<std::decay_t<decltype(l.vertex)>>);
        energy += l.energy;
        if (need != ElementNeed::Energy) asmb.scatter_vector<K>(e, l.gradient, gradient.data());
        if (need == ElementNeed::Hessian) asmb.scatter_matrix<K>(e, l.hessian, hessian.data());
      });
    benchmark::DoNotOptimize(energy);
    benchmark::DoNotOptimize(gradient.data());
    benchmark::DoNotOptimize(hessian.data());
  }
  set_counters(state, model, double(last - first));
}

void BM_Assembly_Shell(benchmark::State& state, FillStiffness stiffness,
                       PerforationLattice lattice = PerforationLattice::Hexagonal) {
  const ShellModel& model = bench::sheet_model(int(state.range(0)), BendingModel::ShapeOperator, stiffness, lattice);
  const ElementNeed need = ElementNeed(state.range(1));
  tbb::task_arena arena(int(state.range(2)));
  const RowMatX3d x = sagged(model);
  // Cut faces (α < 1), so that the homogenised rule's factors are not all 1.
  Eigen::VectorXd alpha(model.num_faces());
  for (int t = 0; t < alpha.size(); ++t) alpha[t] = 0.4 + 0.6 * double(t % 7) / 6;
  solvers::ShellAssembly out;
  for (auto _ : state) {
    arena.execute([&] {
      if (need == ElementNeed::Energy)
        out.energy = solvers::shell_energy(model, x, alpha);
      else
        solvers::assemble_shell(model, x, alpha, need == ElementNeed::Hessian, out);
    });
    benchmark::DoNotOptimize(out.energy);
  }
  // Evaluations: a split element's shear and anisotropic parts are evaluated with its bulk part.
  int evaluated = 0;
  for (int e = 0; e < model.num_elements(); ++e) {
    const solvers::FillPart part = model.element(e).part;
    evaluated += part != solvers::FillPart::Shear && part != solvers::FillPart::Anisotropy;
  }
  set_counters(state, model, double(evaluated));
  state.counters["threads"] = double(state.range(2));
  state.counters["nonzeros"] = double(model.assembly().num_nonzeros());
  state.counters["element_colours"] = double(model.assembly().colours().size());
  state.counters["chunk_colours"] = double(model.assembly().chunk_colours().size());
}

void kind_args(benchmark::internal::Benchmark* b) {
  for (int faces : {20000, 200000})
    for (int need = 0; need < 3; ++need) b->Args({faces, need});
}

void shell_args(benchmark::internal::Benchmark* b) {
  const int all = tbb::info::default_concurrency();
  for (int faces : {20000, 200000})
    for (int need = 0; need < 3; ++need) {
      b->Args({faces, need, 1});
      if (all > 1) b->Args({faces, need, all});
    }
}

BENCHMARK_CAPTURE(BM_Assembly_Kind, Membrane, ElementKind::Membrane)->Apply(kind_args)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Assembly_Kind, ShapeOperator, ElementKind::Bend)->Apply(kind_args)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Assembly_Kind, Hinge, ElementKind::Hinge)->Apply(kind_args)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Assembly_Shell, Linear, FillStiffness::Linear)
    ->Apply(shell_args)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();
// The homogenised rule with the isotropic split: twice the membranes and bends in the model, each
// pair evaluated once by the assembly (visit_split_element), one by one by nothing on this path.
BENCHMARK_CAPTURE(BM_Assembly_Shell, HomogenisedSplit, FillStiffness::Homogenised)
    ->Apply(shell_args)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();
// The same on the square lattice: a third, anisotropic part per membrane and bend, folded into the
// same evaluation; the membrane then takes the general constitutive matrix instead of Lamé's.
BENCHMARK_CAPTURE(BM_Assembly_Shell, HomogenisedSquare, FillStiffness::Homogenised, PerforationLattice::Square)
    ->Apply(shell_args)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();

}  // namespace
}  // namespace cutwork
