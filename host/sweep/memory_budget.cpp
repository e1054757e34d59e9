#include "host/sweep/memory_budget.h"

#include <algorithm>
#include <vector>

#include "host/core/internal_error.h"

namespace cutwork {

MemoryBudget::MemoryBudget(size_t total, size_t set_aside)
    : m_total(total == 0 ? 0 : std::max<size_t>(1, total - std::min(total, set_aside))) {}

size_t MemoryBudget::free_locked() const { return m_total - m_used; }

size_t MemoryBudget::free() const {
  std::lock_guard lock(m_mutex);
  return free_locked();
}

bool MemoryBudget::admissible(size_t held, size_t on_demand) const {
  if (m_waiting_top_ups > 0 || m_used + held > m_total) return false;
  // The banker's rule: with the new claim counted, the claims must be able to finish one after
  // another, each taking the rest of its on_demand from what is free then and returning all it
  // holds. Taking them by increasing remaining on_demand finds such an order if one exists.
  std::vector<Entry> claims;
  claims.reserve(m_claims.size() + 1);
  for (const auto& [id, e] : m_claims) claims.push_back(e);
  claims.push_back({held, on_demand});
  std::sort(claims.begin(), claims.end(), [](const Entry& a, const Entry& b) { return a.remaining < b.remaining; });
  size_t free = m_total - m_used - held;
  for (const Entry& e : claims) {
    if (e.remaining > free) return false;
    free += e.held;
  }
  return true;
}

std::optional<MemoryBudget::Claim> MemoryBudget::try_reserve(size_t held, size_t on_demand) {
  if (m_total == 0) return Claim(0);
  held = std::min(held, m_total);
  on_demand = std::min(on_demand, m_total - held);
  std::lock_guard lock(m_mutex);
  if (!admissible(held, on_demand)) return std::nullopt;
  const Claim id = m_next++;
  m_claims[id] = {held, on_demand};
  m_used += held;
  return id;
}

MemoryBudget::Claim MemoryBudget::reserve(size_t held, size_t on_demand) {
  if (m_total == 0) return 0;
  held = std::min(held, m_total);
  on_demand = std::min(on_demand, m_total - held);
  std::unique_lock lock(m_mutex);
  m_cv.wait(lock, [&] { return admissible(held, on_demand); });
  const Claim id = m_next++;
  m_claims[id] = {held, on_demand};
  m_used += held;
  return id;
}

bool MemoryBudget::try_top_up(Claim claim) {
  if (m_total == 0) return true;
  std::lock_guard lock(m_mutex);
  const auto it = m_claims.find(claim);
  if (it == m_claims.end()) throw InternalError("MemoryBudget::try_top_up: no such claim");
  Entry& e = it->second;
  if (e.remaining > free_locked()) return false;
  m_used += e.remaining;
  e.held += e.remaining;
  e.remaining = 0;
  return true;
}

void MemoryBudget::top_up(Claim claim) {
  if (m_total == 0) return;
  std::unique_lock lock(m_mutex);
  const auto it = m_claims.find(claim);
  if (it == m_claims.end()) throw InternalError("MemoryBudget::top_up: no such claim");
  Entry& e = it->second;
  if (e.remaining == 0) return;
  ++m_waiting_top_ups;
  m_cv.wait(lock, [&] { return e.remaining <= free_locked(); });
  --m_waiting_top_ups;
  m_used += e.remaining;
  e.held += e.remaining;
  e.remaining = 0;
  lock.unlock();
  m_cv.notify_all();  // admissions held back while this top-up waited may go now
}

void MemoryBudget::release(Claim claim) {
  if (m_total == 0) return;
  {
    std::lock_guard lock(m_mutex);
    const auto it = m_claims.find(claim);
    if (it == m_claims.end()) throw InternalError("MemoryBudget::release: no such claim");
    m_used -= it->second.held;
    m_claims.erase(it);
  }
  m_cv.notify_all();
}

}  // namespace cutwork
