// The sweep's memory budget (host/sweep/memory_budget.h): claims with an on-demand part are
// admitted by the banker's rule, so that top-ups never wait on each other.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "host/sweep/memory_budget.h"

namespace cutwork {
namespace {

using namespace std::chrono_literals;

TEST(MemoryBudget, SetsAsideWhatTheProcessHolds) {
  EXPECT_EQ(MemoryBudget(100, 30).total(), 70u);
  EXPECT_EQ(MemoryBudget(100, 300).total(), 1u);  // at least a byte: variants then run one at a time
  EXPECT_EQ(MemoryBudget(0, 30).total(), 0u);     // no budget
}

// Two claims that each hold part of the budget and each need more later: admitting both would let
// each wait for the other's share forever (held 4 + 4 of 10, each then asking 5 more).
TEST(MemoryBudget, AClaimWhoseTopUpCouldDeadlockWaits) {
  MemoryBudget b(10, 0);
  const auto a = b.try_reserve(4, 5);
  ASSERT_TRUE(a);
  EXPECT_FALSE(b.try_reserve(4, 5)) << "both admitted, neither's top-up could ever be granted";
  EXPECT_TRUE(b.try_reserve(1, 0)) << "a claim that needs nothing more leaves a safe order";
  EXPECT_TRUE(b.try_top_up(*a));
  EXPECT_EQ(b.free(), 0u);
  b.release(*a);
  EXPECT_EQ(b.free(), 9u);
  const auto c = b.try_reserve(4, 5);
  EXPECT_TRUE(c) << "admitted once the first has gone";
}

// Claims whose top-ups fit together are admitted together: the on-demand part is not held before
// it is asked for (held 3 + 3 of 10, each asking 2 more).
TEST(MemoryBudget, OnDemandIsNotHeldUntilAskedFor) {
  MemoryBudget b(10, 0);
  const auto a = b.try_reserve(3, 2), c = b.try_reserve(3, 2);
  ASSERT_TRUE(a && c);
  EXPECT_EQ(b.free(), 4u);
  EXPECT_TRUE(b.try_top_up(*a));
  EXPECT_TRUE(b.try_top_up(*c));
  EXPECT_EQ(b.free(), 0u);
  EXPECT_TRUE(b.try_top_up(*a)) << "a second top-up asks for nothing";
  b.release(*a);
  b.release(*c);
  EXPECT_EQ(b.free(), 10u);
}

// A claim larger than the budget is cut to it: given all of it once topped up, so it runs alone
// then. A small claim that finishes without asking for more may run beside it before.
TEST(MemoryBudget, AClaimLargerThanTheBudgetIsCutToIt) {
  MemoryBudget b(10, 0);
  const auto a = b.try_reserve(6, 20);
  ASSERT_TRUE(a);
  const auto small = b.try_reserve(1, 0);
  ASSERT_TRUE(small) << "safe: it finishes first, then a's 4 fit";
  // Another asking 5 more: with 2 free, the small one's return makes 3, which neither top-up fits.
  EXPECT_FALSE(b.try_reserve(1, 5)) << "no order lets both top-ups through";
  EXPECT_FALSE(b.try_top_up(*a)) << "3 free, 4 asked";
  b.release(*small);
  EXPECT_TRUE(b.try_top_up(*a));
  EXPECT_EQ(b.free(), 0u);
  b.release(*a);
  const auto big = b.try_reserve(50, 0);
  ASSERT_TRUE(big);
  EXPECT_EQ(b.free(), 0u);
}

// A top-up that is not free waits until a claim is released; while it waits no new claim is
// admitted, even one that would fit.
TEST(MemoryBudget, ATopUpWaitsForAReleaseAndHoldsBackAdmissions) {
  MemoryBudget b(10, 0);
  const auto a = b.try_reserve(5, 5);
  const auto c = b.try_reserve(2, 0);  // safe: c finishes first, then a's 5 fit
  ASSERT_TRUE(a && c);
  EXPECT_FALSE(b.try_top_up(*a));
  std::atomic<bool> granted{false};
  std::thread t([&] {
    b.top_up(*a);
    granted = true;
  });
  std::this_thread::sleep_for(50ms);
  EXPECT_FALSE(granted) << "3 free, 5 asked";
  EXPECT_FALSE(b.try_reserve(1, 0)) << "admitted while a top-up waits";
  b.release(*c);
  t.join();
  EXPECT_TRUE(granted);
  EXPECT_EQ(b.free(), 0u);
  b.release(*a);
  EXPECT_EQ(b.free(), 10u);
}

// Many variants on threads, each claiming and then topping up, all finish (a deadlock would hang
// here: ctest's timeout), and the budget is never exceeded.
TEST(MemoryBudget, ConcurrentClaimsAndTopUpsAllFinish) {
  MemoryBudget b(100, 0);
  std::atomic<long> in_use{0}, peak{0};
  const auto raise_peak = [&](long now) {
    for (long p = peak.load(); now > p && !peak.compare_exchange_weak(p, now);) {
    }
  };
  std::vector<std::thread> threads;
  for (int i = 0; i < 16; ++i)
    threads.emplace_back([&, i] {
      const size_t held = 10 + size_t(i % 5) * 7, more = size_t(i % 3) * 20;
      const MemoryBudget::Claim c = b.reserve(held, more);
      raise_peak(in_use += long(held));
      std::this_thread::sleep_for(1ms);
      b.top_up(c);
      raise_peak(in_use += long(more));
      std::this_thread::sleep_for(1ms);
      in_use -= long(held + more);
      b.release(c);
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(b.free(), 100u);
  EXPECT_LE(peak.load(), 100);
}

}  // namespace
}  // namespace cutwork
