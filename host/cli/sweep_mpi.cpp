#include "host/cli/sweep_mpi.h"

#include <cstdlib>
#include <iostream>

#include "host/core/error.h"

#ifdef CUTWORK_WITH_MPI
#include <mpi.h>

#include <tbb/global_control.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <mutex>
#include <thread>
#endif

namespace cutwork::cli {

#ifndef CUTWORK_WITH_MPI

MpiSession::MpiSession() = default;
MpiSession::~MpiSession() = default;
void MpiSession::quiet_exit() { std::exit(2); }
void MpiSession::abort(const std::string& message) {
  std::cerr << "cutwork: " << message << "\n";
  std::exit(2);
}

size_t run_sweep_mpi(MpiSession&, const SweepPlan& plan, const SweepOptions& options) {
  plan.prepare_folder();
  return run_sweep_local(plan, options);
}

#else

namespace {

constexpr int kRequestTag = 1;  ///< worker → 0: the previous variant's result (JSON), or empty
constexpr int kAssignTag = 2;   ///< 0 → worker: the next variant's index, or −1: stop

bool started_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
    if (std::getenv(v)) return true;
  return false;
}

int threads_per_rank(const SweepOptions& options) {
  if (options.threads > 0) return options.threads;
  int local = 1;
  if (const char* s = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE")) local = std::max(1, std::atoi(s));
  return std::max(1, int(std::thread::hardware_concurrency()) / local);
}

void send_string(const std::string& s, int to, int tag) {
  MPI_Send(s.data(), int(s.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD);
}

std::string receive_string(int from, int tag, int* source) {
  MPI_Status status;
  MPI_Probe(from, tag, MPI_COMM_WORLD, &status);
  int n = 0;
  MPI_Get_count(&status, MPI_CHAR, &n);
  std::string s(size_t(n), '\0');
  MPI_Recv(s.data(), n, MPI_CHAR, status.MPI_SOURCE, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  if (source) *source = status.MPI_SOURCE;
  return s;
}

/// Rank ≥ 1: ask for a variant, run it, send its result with the next request, until told to stop.
void serve_as_worker(const MpiSession& mpi, const SweepPlan& plan, const SweepOptions& options) {
  std::string result;
  for (;;) {
    send_string(result, 0, kRequestTag);
    int index = -1;
    MPI_Recv(&index, 1, MPI_INT, 0, kAssignTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (index < 0) return;
    VariantResult r = run_variant(plan, size_t(index), options.device);
    r.rank = mpi.rank();
    result = r.to_json().dump();
  }
}

/// Rank 0: hands out `todo` to the other ranks and to a local worker thread, records every result.
void coordinate(const MpiSession& mpi, const SweepPlan& plan, const SweepOptions& options,
                const std::vector<size_t>& todo) {
  std::mutex mutex;
  std::deque<size_t> queue(todo.begin(), todo.end());
  std::vector<VariantResult> local_done;
  SweepProgress progress(options.quiet, plan.variants.size(), plan.variants.size() - todo.size());
  const auto take = [&]() -> int {
    std::lock_guard lock(mutex);
    if (queue.empty()) return -1;
    const int i = int(queue.front());
    queue.pop_front();
    return i;
  };
  std::exception_ptr local_error;
  std::atomic<bool> local_finished{false};
  std::thread local([&] {
    try {
      for (int i = take(); i >= 0; i = take()) {
        progress.started();
        VariantResult r = run_variant(plan, size_t(i), options.device);
        progress.finished(r.ok);  // counted here, recorded by the main thread
        std::lock_guard lock(mutex);
        local_done.push_back(std::move(r));
      }
    } catch (...) {
      local_error = std::current_exception();
    }
    local_finished = true;
  });
  const auto drain_local = [&] {
    std::vector<VariantResult> finished;
    {
      std::lock_guard lock(mutex);
      finished.swap(local_done);
    }
    for (const VariantResult& r : finished) plan.record(r);
    return !finished.empty();
  };
  int workers = mpi.size() - 1;
  while (workers > 0 || !local_finished) {
    int pending = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kRequestTag, MPI_COMM_WORLD, &pending, &status);
    if (pending) {
      int from = 0;
      const std::string payload = receive_string(status.MPI_SOURCE, kRequestTag, &from);
      if (!payload.empty()) {
        const VariantResult r = VariantResult::from_json(nlohmann::json::parse(payload), "a result from a rank");
        plan.record(r);
        progress.finished(r.ok);
      }
      const int next = take();
      if (next >= 0) progress.started();
      else --workers;
      MPI_Send(&next, 1, MPI_INT, from, kAssignTag, MPI_COMM_WORLD);
    }
    const bool drained = drain_local();
    if (!pending && !drained) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  local.join();
  drain_local();
  if (local_error) std::rethrow_exception(local_error);
}

}  // namespace

MpiSession::MpiSession() {
  if (!started_by_mpirun()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  m_initialised = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &m_size);
}

MpiSession::~MpiSession() {
  if (!m_initialised) return;
  if (std::uncaught_exceptions() > 0 && m_size > 1 && !m_collective_failure) {
    // A rank failing part way (a disk error): the others may wait on it for ever.
    std::cerr << "cutwork: rank " << m_rank << " failed; aborting the other ranks\n";
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  MPI_Finalize();
}

void MpiSession::quiet_exit() {
  if (m_initialised) MPI_Finalize();
  std::exit(2);
}

void MpiSession::abort(const std::string& message) {
  std::cerr << "cutwork: rank " << m_rank << ": " << message << "\n" << std::flush;
  MPI_Abort(MPI_COMM_WORLD, 2);
  std::exit(2);
}

size_t run_sweep_mpi(MpiSession& mpi, const SweepPlan& plan, const SweepOptions& options) {
  // Rank 0 prepares the folder and says whether it could; the others end quietly if not.
  int ok = 1;
  std::vector<size_t> todo;
  std::exception_ptr error;
  if (mpi.rank() == 0) {
    try {
      plan.prepare_folder();
      todo = plan.pending();
    } catch (...) {
      error = std::current_exception();
      ok = 0;
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (!ok) {
    if (mpi.rank() == 0) {
      mpi.collective_failure();  // every rank is here: the session finalises without aborting
      std::rethrow_exception(error);
    }
    mpi.quiet_exit();
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads_per_rank(options)));
  single_threaded_blas();
  if (mpi.rank() == 0) coordinate(mpi, plan, options, todo);
  else serve_as_worker(mpi, plan, options);
  MPI_Barrier(MPI_COMM_WORLD);
  return todo.size();
}

#endif

}  // namespace cutwork::cli
