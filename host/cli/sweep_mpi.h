#pragma once
/// `cutwork sweep` across MPI ranks (OpenMPI; built with CUTWORK_WITH_MPI). Without MPI, or when
/// not started by mpirun, MpiSession is a single rank and the sweep runs locally.
#include <cstddef>
#include <string>
#include <utility>

#include "host/cli/sweep_runner.h"

namespace cutwork::cli {

/// MPI for the life of the object: initialised (MPI_THREAD_FUNNELED: only the main thread
/// talks) when the process was started by mpirun, finalised at the end.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return m_rank; }
  int size() const { return m_size; }

  /// Runs `f`, which every rank runs alike and which fails alike on every rank (validating the
  /// sweep): on failure rank 0 rethrows (one error line, exit code 2) and the other ranks end
  /// quietly with exit code 2.
  template <typename F>
  auto guard(F&& f) -> decltype(f()) {
    try {
      return f();
    } catch (...) {
      if (m_rank != 0) quiet_exit();
      m_collective_failure = true;
      throw;
    }
  }

  /// Ends this rank with exit code 2 and no message (another rank reports the error).
  [[noreturn]] void quiet_exit();
  /// Marks a failure every rank shares: ending without MPI_Abort is safe.
  void collective_failure() { m_collective_failure = true; }
  bool failed_collectively() const { return m_collective_failure; }
  /// One rank failed part way (a disk error): says so in one line on stderr and ends every rank
  /// with exit code 2 (MPI_Abort), since the others may wait on this one for ever.
  [[noreturn]] void abort(const std::string& message);

 private:
  int m_rank = 0, m_size = 1;
  bool m_initialised = false, m_collective_failure = false;
};

/// Runs the sweep over all ranks with dynamic load balancing: rank 0's main thread hands out one
/// variant at a time to any rank that asks (itself included, through a worker thread), so a rank
/// that drew cheap designs asks again sooner. Every rank runs one variant at a time with
/// --threads threads (0: the hardware threads divided by the ranks on its node) and writes its
/// variants' folders under DIR; rank 0 writes every completion marker (the result travels with the
/// next request) and, after the run, the tables. Returns the number of variants run (rank 0).
size_t run_sweep_mpi(MpiSession& mpi, const SweepPlan& plan, const SweepOptions& options);

}  // namespace cutwork::cli
