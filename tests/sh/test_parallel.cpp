// atmosh/parallel.hpp: every index is visited exactly once for any thread count and
// range size, a body's exception reaches the caller, progress is reported monotonically.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "atmosh/parallel.hpp"

namespace {

TEST(ParallelFor, VisitsEveryIndexExactlyOnce) {
  for (std::size_t n : {0u, 1u, 7u, 64u, 1001u})
    for (std::size_t chunk : {1u, 3u, 16u, 5000u})
      for (int threads : {1, 2, 3, 8}) {
        std::vector<std::atomic<int>> hits(n);
        atmosh::parallel_for_ranges(n, chunk, threads, [&](std::size_t b, std::size_t e) {
          ASSERT_LT(b, e);
          ASSERT_LE(e - b, chunk);
          for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
        });
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << n << " " << chunk << " " << threads;
      }
}

TEST(ParallelFor, RethrowsTheFirstExceptionAndStops) {
  std::atomic<int> calls{0};
  std::atomic<bool> thrown{false};
  EXPECT_THROW(atmosh::parallel_for(100000, 2,
                                    [&](std::size_t i) {
                                      calls.fetch_add(1);
                                      if (i == 10) {
                                        thrown = true;
                                        throw std::invalid_argument("bad index 10");
                                      }
                                      // After the throw, the other worker is slowed down so that a
                                      // descheduled thrower (a loaded machine) cannot let it finish
                                      // every index before the stop is seen.
                                      if (thrown) std::this_thread::sleep_for(std::chrono::microseconds(50));
                                    }),
               std::invalid_argument);
  EXPECT_LT(calls.load(), 100000);  // the others stop taking new indices
}

TEST(ParallelFor, ReportsProgressFromTheCallingThread) {
  std::vector<double> seen;
  std::vector<std::atomic<int>> hits(200);
  atmosh::parallel_for_ranges(
      200, 1, 2,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
        std::this_thread::sleep_for(std::chrono::microseconds(300));
      },
      [&](double f) { seen.push_back(f); });
  for (auto& h : hits) ASSERT_EQ(h.load(), 1);
  ASSERT_FALSE(seen.empty());
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_LE(seen.back(), 1.0);
}

TEST(ParallelFor, ResolvesThreadCounts) {
  EXPECT_EQ(atmosh::resolve_threads(3), 3);
  EXPECT_GE(atmosh::resolve_threads(0), 1);
}

}  // namespace
