#include "solvers/linear/thread_policy.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>

namespace cutwork::solvers {

namespace {

using SetInt = void (*)(int);

/// The thread controls of OpenBLAS and the OpenMP runtime, looked up once in the whole process
/// (whichever library CHOLMOD was linked against provides them); null when absent.
struct Controls {
  SetInt openblas_set_num_threads = nullptr;
  SetInt omp_set_max_active_levels = nullptr;
  /// Stops OpenBLAS's worker threads (OpenBLAS starts them again on its next parallel call).
  int (*blas_thread_shutdown)() = nullptr;
  Controls() {
    blas_thread_shutdown = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"));
    openblas_set_num_threads = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    omp_set_max_active_levels = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  }
};

const Controls& controls() {
  static const Controls c;
  return c;
}

/// The OpenBLAS thread count last set by this process (0: never set). OpenBLAS starts with one
/// thread per core; the first factorisation sets it.
std::atomic<int> g_blas_threads{0};
std::atomic<double> g_parallel_flops{kParallelFactorFlops};
/// The calling thread's last OpenMP max-active-levels (-1: never set on this thread).
thread_local int t_omp_levels = -1;
/// Regions the gate ran inline on this thread.
thread_local long t_regions_inlined = 0;

}  // namespace

double parallel_factor_flops() { return g_parallel_flops.load(); }
void set_parallel_factor_flops(double flops) { g_parallel_flops.store(flops); }

int thread_budget() {
  const auto limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return std::max(1, std::min(int(limit), tbb::this_task_arena::max_concurrency()));
}

FactorizationThreads factorization_threads(double flops, int budget) {
  FactorizationThreads t;
  const bool large = flops >= parallel_factor_flops();
  t.blas = large && budget >= kMinParallelBlasThreads ? budget : 1;
  t.openmp = large && budget >= CHOLMOD_OMP_NUM_THREADS ? CHOLMOD_OMP_NUM_THREADS : 1;
  return t;
}

FactorizationThreads set_factorization_threads(double flops) {
  const FactorizationThreads t = factorization_threads(flops, thread_budget());
  const Controls& c = controls();
  if (c.openblas_set_num_threads && g_blas_threads.exchange(t.blas) != t.blas) {
    c.openblas_set_num_threads(t.blas);
    // OpenBLAS starts a worker per core when it loads, and idle workers spin on sched_yield for
    // ~0.1 s before they sleep: stop them while BLAS is serial.
    if (t.blas == 1 && c.blas_thread_shutdown) c.blas_thread_shutdown();
  }
  const int levels = t.openmp > 1 ? 1 : 0;
  if (c.omp_set_max_active_levels && t_omp_levels != levels) {
    c.omp_set_max_active_levels(levels);
    t_omp_levels = levels;
  }
  return t;
}

bool blas_threads_controllable() { return controls().openblas_set_num_threads != nullptr; }

void settle_library_threads() {
  const Controls& c = controls();
  if (!c.openblas_set_num_threads) return;
  g_blas_threads.store(1);
  c.openblas_set_num_threads(1);
  if (c.blas_thread_shutdown) c.blas_thread_shutdown();
}

long openmp_regions_inlined() { return t_regions_inlined; }

namespace {

using ParallelEntry = void (*)(void (*)(void*), void*, unsigned, unsigned);

/// libgomp's GOMP_parallel (null without an OpenMP runtime).
ParallelEntry libgomp_parallel() {
  static const ParallelEntry entry = [] {
    void* f = dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0");
    return reinterpret_cast<ParallelEntry>(f ? f : dlsym(RTLD_NEXT, "GOMP_parallel"));
  }();
  return entry;
}

}  // namespace

}  // namespace cutwork::solvers

/// The OpenMP gate (thread_policy.h). GCC compiles `#pragma omp parallel` into a call of this
/// function with the region's body outlined into fn.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data,
                                                                     unsigned num_threads, unsigned flags) {
  using namespace cutwork::solvers;
  const ParallelEntry forward = t_omp_levels == 0 ? nullptr : libgomp_parallel();
  if (!forward) {
    ++t_regions_inlined;
    fn(data);
    return;
  }
  forward(fn, data, num_threads, flags);
}

namespace cutwork::solvers {

bool openmp_gate_installed() {
  return dlsym(RTLD_DEFAULT, "GOMP_parallel") == reinterpret_cast<void*>(&GOMP_parallel);
}

std::string blas_kernels() {
  using Name = char* (*)();
  static const Name name = reinterpret_cast<Name>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  if (!name) return {};
  const char* n = name();
  return n ? std::string(n) : std::string();
}

std::string preferred_blas_kernels(const std::string& kernels) {
  // OpenBLAS's generic x86-64 targets: what it falls back to on a CPU model it does not know.
  static const std::array<const char*, 6> generic = {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem", "Katmai"};
  if (std::find(generic.begin(), generic.end(), kernels) == generic.end()) return {};
#if defined(__x86_64__) || defined(__i386__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
#endif
  return {};
}

void ensure_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return;
  const std::string preferred = preferred_blas_kernels(blas_kernels());
  if (preferred.empty() || argv == nullptr) return;
  if (setenv("OPENBLAS_CORETYPE", preferred.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Still here: the re-execution failed; go on with the kernels OpenBLAS chose.
  unsetenv("OPENBLAS_CORETYPE");
}

}  // namespace cutwork::solvers
