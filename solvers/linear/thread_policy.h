#pragma once
/// One thread policy for the three thread pools a cutwork process holds: TBB's (assembly, kernels,
/// everything cutwork parallelises itself), OpenBLAS's pthreads (the dense blocks of CHOLMOD's
/// supernodal factorisation) and libgomp's (CHOLMOD's own OpenMP loops).
///
/// TBB owns the cores. Its limit — `tbb::global_control` (the CLI's `--threads N`) or the calling
/// task_arena (the benchmarks) — is the thread budget of the whole process. The other two pools get
/// threads only while a factorisation is large enough to pay for them, and only up to the budget:
///   - OpenBLAS: the budget when the factorisation has at least parallel_factor_flops()
///     floating-point operations and the budget is at least kMinParallelBlasThreads, else one
///     thread. OpenBLAS's idle workers spin (sched_yield) for ~0.1 s after each parallel call, so
///     a pool that is woken for sub-millisecond BLAS calls costs more system time than it saves;
///     above the threshold one factorisation takes long enough to amortise it. On two cores a
///     second BLAS thread never paid: measured on the 2-core build machine (BM_Factorize_Threads,
///     30k DOFs, 1.95 GFlop, METIS) 1 thread took 1.37 s and 0.14 s CPU, 2 threads 14.6 s and
///     0.34 s CPU (the spinning peer waits for a core the other pools hold); the issue's own
///     measurement found equal wall time at 40% more CPU. On a quiet machine with the gate below,
///     two BLAS threads gave 115 → 114 ms at 30k DOFs and 4.74 → 3.95 s at 300k DOFs, for 1.6×
///     the CPU: still not worth a second core's CPU.
///   - OpenMP: CHOLMOD 5 asks for a fixed team of CHOLMOD_OMP_NUM_THREADS (4) in its supernodal
///     copy loops, whatever omp_set_num_threads says. Those loops are memory-bound copies; on fewer
///     cores than that the team oversubscribes and spends its time in futex/spin waits. OpenMP
///     regions are therefore made inactive (max-active-levels 0) unless the budget covers the team
///     and the factorisation is large.
///   - The OpenMP gate: an inactive region still costs libgomp a team of one, ended with futex
///     wake-ups (two syscalls per region: 20,000 per factorisation of 30k DOFs, a quarter of its
///     time; 185,000 in one design of the bowl). cutwork therefore defines GOMP_parallel, the one
///     OpenMP entry point CHOLMOD imports; the executable's definition comes first in the dynamic
///     linker's search order. On a thread where this policy made the regions inactive it runs the
///     region's body directly — what libgomp's team of one computes, since outside a team
///     omp_get_num_threads() is 1, omp_get_thread_num() 0, and orphaned worksharing and barriers
///     are valid —; on every other thread it forwards to libgomp's.
/// Both libraries are reached through dlsym, so a BLAS without OpenBLAS's API (the reference BLAS,
/// BLIS) or a CHOLMOD built without OpenMP simply leaves that pool alone.
///
/// Thread safety: set_factorization_threads() changes process-global settings of OpenBLAS; call it
/// from the thread that is about to factorise (CholmodSolver does). Concurrent factorisations in
/// different threads each set the same policy for their own size; the last writer wins.
#include <cstdint>
#include <string>

namespace cutwork::solvers {

/// Floating-point operations of one factorisation from which OpenBLAS gets the thread budget
/// (≈ 0.1 s of one core). Measured on the bench cap (bench/linear_benchmark.cpp, BM_Factorize_Threads).
inline constexpr double kParallelFactorFlops = 2e9;
/// Smallest thread budget at which OpenBLAS gets more than one thread (see above).
inline constexpr int kMinParallelBlasThreads = 4;
/// The threshold in force (kParallelFactorFlops unless set; the benchmarks move it to compare
/// serial and parallel factorisations of one size: 0 always parallel, +∞ never).
double parallel_factor_flops();
void set_parallel_factor_flops(double flops);

/// The process's thread budget as TBB sees it from the calling thread: the smaller of the
/// global_control limit and the current arena's concurrency (≥ 1).
int thread_budget();

/// What set_factorization_threads() chose.
struct FactorizationThreads {
  int blas = 1;    ///< OpenBLAS threads
  int openmp = 1;  ///< 1: OpenMP regions inactive; else CHOLMOD's fixed team size
};

/// The policy above for a factorisation of `flops` operations with `budget` threads (pure).
FactorizationThreads factorization_threads(double flops, int budget);

/// Applies factorization_threads(flops, thread_budget()) to OpenBLAS and OpenMP (the latter on the
/// calling thread) and returns it. Cheap: changes nothing when the settings are already in place.
FactorizationThreads set_factorization_threads(double flops);

/// Whether OpenBLAS's thread control was found in the process (false for other BLAS libraries).
bool blas_threads_controllable();

/// Puts OpenBLAS in the serial setting before any factorisation: its library constructor starts a
/// worker per core, and an idle worker spins on sched_yield for ~0.13 s (OpenBLAS' thread timeout,
/// 2²⁸ cycles) before it sleeps — 28,000 syscalls at the start of every process, measured on
/// `cutwork design bowl`. Programs call it first thing in main(); factorisations that earn the
/// parallel setting start the workers again.
void settle_library_threads();

/// The OpenBLAS kernels in use (openblas_get_corename: "Haswell", "SkylakeX", "Prescott", …); empty
/// when the BLAS is not OpenBLAS.
std::string blas_kernels();

/// The kernels OpenBLAS should use on this CPU when it fell back to generic ones, else empty.
/// OpenBLAS (DYNAMIC_ARCH) picks its kernels from the CPU model when it is loaded; Debian 12's 0.3.21
/// does not know recent Xeons (this project's build machine: family 6, model 207, AVX-512) and falls
/// back to "Prescott" (SSE3). Under those kernels cutwork's numbers moved on that machine — the
/// Kirsch hole's graded mesh came out with 15694 instead of 15715 faces and its largest face W at
/// 1.023 instead of 1.080 of the closed form, and CHOLMOD refused a peak-zoom submodel's stiffness
/// as not positive definite where its smallest eigenvalue is +9.0e3 N/m (largest 1.0e10): two tests
/// failed — while the BLAS calls themselves checked out correct (dgemm, dsyrk, dtrsm to 1e-13).
/// Whatever the path, the fallback is not the configuration cutwork is tested in. "Haswell"
/// (AVX2 + FMA) where the CPU has both and `kernels` is one of OpenBLAS's generic x86 targets.
std::string preferred_blas_kernels(const std::string& kernels);

/// Programs call this first thing in main(), with their argv: where preferred_blas_kernels() names
/// kernels and OPENBLAS_CORETYPE is not set, the program runs itself again (execv of
/// /proc/self/exe, same arguments) with OPENBLAS_CORETYPE set to them — OpenBLAS reads it only when
/// it is loaded. Returns when nothing needs doing, when OPENBLAS_CORETYPE is already set (the user's
/// choice stands), or when the re-execution fails (the process goes on with the fallback).
void ensure_blas_kernels(char** argv);

/// Whether OpenMP regions entered through GOMP_parallel reach cutwork's gate (false when the
/// symbol is bound elsewhere, e.g. a program that does not export it).
bool openmp_gate_installed();
/// OpenMP regions the gate ran inline on the calling thread so far (the test's evidence).
long openmp_regions_inlined();

}  // namespace cutwork::solvers
