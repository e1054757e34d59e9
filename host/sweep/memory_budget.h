#pragma once
/// Bytes of a budget shared by concurrent sweep variants (`cutwork sweep --memory`,
/// host/cli/sweep_runner.cpp; docs/SWEEP.md "Memory").
///
/// A variant claims what it holds throughout (`held`) and what it may ask for later
/// (`on_demand`: the discretisation estimate's h/8 level, which a design solves only where the
/// levels before it have not settled). Counting on_demand from the start held the budget for a
/// level most designs never solve (the bowl, table and chair reserved 3–7× their peak); counting it
/// only when asked can deadlock: two variants each holding part of the budget, each waiting for
/// the other's share. So claims are admitted by the banker's rule: a claim is admitted only if,
/// afterwards, the variants can still finish one after another — some order exists in which
/// each one's on_demand fits in what is free plus what the ones before it release. A top-up then
/// waits at most until some running variant finishes, and never forever. While a top-up waits,
/// no new claim is admitted (else a stream of small variants could keep it waiting).
///
/// A claim larger than the budget is cut to it (the variant waits until it runs alone, and is
/// given all of it). With total 0 there is no budget: nothing waits and nothing is counted.
#include <condition_variable>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>

namespace cutwork {

class MemoryBudget {
 public:
  using Claim = size_t;

  /// `total` bytes less `set_aside` (what the process holds whatever its variants; at least one
  /// byte is left to share). total 0: no budget.
  MemoryBudget(size_t total, size_t set_aside);

  /// Bytes the variants share (0: no budget).
  size_t total() const { return m_total; }

  /// Blocks until the claim can be admitted (see the class comment); returns its handle.
  Claim reserve(size_t held, size_t on_demand);
  /// The same without waiting: nothing if the claim cannot be admitted now.
  std::optional<Claim> try_reserve(size_t held, size_t on_demand);

  /// Grants the rest of the claim's on_demand, blocking until it is free (a no-op once granted).
  void top_up(Claim claim);
  /// The same without waiting: false if it is not free now.
  bool try_top_up(Claim claim);

  /// Returns everything the claim holds (held and any top-up) and forgets it.
  void release(Claim claim);

  /// Bytes not held by any claim.
  size_t free() const;

 private:
  struct Entry {
    size_t held = 0;       ///< counted now (held, plus on_demand once granted)
    size_t remaining = 0;  ///< on_demand not yet granted
  };
  bool admissible(size_t held, size_t on_demand) const;  ///< m_mutex held
  size_t free_locked() const;

  size_t m_total;
  size_t m_used = 0;
  size_t m_next = 1;
  int m_waiting_top_ups = 0;
  std::map<Claim, Entry> m_claims;
  mutable std::mutex m_mutex;
  std::condition_variable m_cv;
};

}  // namespace cutwork
