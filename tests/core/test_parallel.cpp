// atmosh/parallel.hpp: every index is visited exactly once for any thread count and
// range size, a body's exception reaches the caller, progress is reported monotonically,
// each worker builds its scratch once and results do not depend on the thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "atmosh/error.hpp"
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
                                      // Indices after 10 wait for the throw (at most 10 s), then run
                                      // slowly, so that a thrower descheduled before or after its
                                      // throw (a loaded machine) cannot let the other worker finish
                                      // every index before the stop is seen.
                                      for (int k = 0; i > 10 && !thrown && k < 200000; ++k)
                                        std::this_thread::sleep_for(std::chrono::microseconds(50));
                                      std::this_thread::sleep_for(std::chrono::microseconds(thrown ? 50 : 0));
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

TEST(ParallelFor, PerIndexFormVisitsEveryIndexOnce) {
  for (std::size_t n : {0u, 1u, 2u, 5u, 1000u})
    for (int threads : {0, 1, 2, 4, 16}) {
      std::vector<std::atomic<int>> hits(n);
      atmosh::parallel_for(n, threads, [&](std::size_t i) { hits[i].fetch_add(1); });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << n << " " << threads;
    }
}

// Each worker calls make_local once (before its first range) and sees only its own
// scratch; no more workers run than there are ranges or requested threads.
TEST(ParallelFor, EachWorkerBuildsItsScratchOnce) {
  for (std::size_t n : {0u, 1u, 3u, 500u})
    for (int threads : {1, 2, 3, 8}) {
      std::atomic<int> made{0};
      std::vector<std::atomic<int>> hits(n);
      struct Local {
        int id;
        std::thread::id owner;
      };
      std::atomic<int> foreign{0};
      atmosh::parallel_for_ranges_local(
          n, 7, threads, [&] { return Local{made.fetch_add(1), std::this_thread::get_id()}; },
          [&](Local& l, std::size_t b, std::size_t e) {
            if (l.owner != std::this_thread::get_id()) foreign.fetch_add(1);
            for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
          });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << n << " " << threads;
      const std::size_t ranges = (n + 6) / 7;
      EXPECT_LE(static_cast<std::size_t>(made.load()), std::min<std::size_t>(ranges, static_cast<std::size_t>(threads)));
      if (n > 0) {
        EXPECT_GE(made.load(), 1);
      }
      EXPECT_EQ(foreign.load(), 0);
    }
}

// A reduction written per index (each index writes its own slot, the caller sums in
// index order) gives the same bits on any thread count: the loop's contract for the
// transforms and bakes that use it. The reference is the plain serial loop.
TEST(ParallelFor, PerIndexResultsDoNotDependOnTheThreadCount) {
  const std::size_t n = 4097;
  auto term = [](std::size_t i) { return 1.0 / (1.0 + static_cast<double>(i) * 0.37); };
  std::vector<double> serial(n);
  for (std::size_t i = 0; i < n; ++i) serial[i] = term(i);
  for (int threads : {1, 2, 3, 7}) {
    std::vector<double> out(n, -1.0);
    atmosh::parallel_for_ranges_local(n, 16, threads, [] { return std::vector<double>(3); },
                                      [&](std::vector<double>& scratch, std::size_t b, std::size_t e) {
                                        for (std::size_t i = b; i < e; ++i) {
                                          scratch[i % 3] = term(i);  // scratch reused across indices
                                          out[i] = scratch[i % 3];
                                        }
                                      });
    EXPECT_EQ(out, serial) << threads;
  }
}

TEST(ParallelFor, ExceptionFromScratchOrBodyReachesTheCaller) {
  EXPECT_THROW(atmosh::parallel_for_ranges_local(
                   100, 1, 3, []() -> int { throw std::runtime_error("no scratch"); },
                   [](int&, std::size_t, std::size_t) {}),
               std::runtime_error);
  // a single worker (threads = 1) runs on the calling thread; the exception still arrives once
  std::atomic<int> calls{0};
  EXPECT_THROW(atmosh::parallel_for(10, 1,
                                    [&](std::size_t i) {
                                      calls.fetch_add(1);
                                      if (i == 3) throw std::out_of_range("index 3");
                                    }),
               std::out_of_range);
  EXPECT_EQ(calls.load(), 4);  // one worker stops at the first failure
  EXPECT_THROW(atmosh::parallel_for(10, -1, [](std::size_t) {}), atmosh::InputError);
}

TEST(ParallelFor, ResolvesThreadCounts) {
  EXPECT_EQ(atmosh::resolve_threads(3), 3);
  EXPECT_GE(atmosh::resolve_threads(0), 1);
}

}  // namespace

// Without progress, the workers besides the calling thread are kept from one loop to the
// next (parallel.hpp, "Workers"): a thread that takes part in a loop has taken part in an
// earlier one. Threads started per loop would each see one loop only.
TEST(ParallelFor, WorkersAreKeptFromOneLoopToTheNext) {
  static thread_local int loops_seen = 0;
  const auto caller = std::this_thread::get_id();
  std::atomic<int> most{0};
  for (int loop = 0; loop < 20; ++loop) {
    std::atomic<int> hits{0};
    atmosh::parallel_for_ranges_local(
        16, 1, 2, [&] { return ++loops_seen; },
        [&](int& seen, std::size_t b, std::size_t e) {
          if (std::this_thread::get_id() != caller) {
            int m = most.load();
            while (seen > m && !most.compare_exchange_weak(m, seen)) {
            }
          }
          // long enough that a worker woken from sleep still finds ranges left
          std::this_thread::sleep_for(std::chrono::microseconds(500));
          hits.fetch_add(static_cast<int>(e - b));
        });
    ASSERT_EQ(hits.load(), 16);
  }
  EXPECT_GE(most.load(), 2);
}

// Many short loops back to back on the kept workers, with changing thread counts (the pool
// grows), loops inside a loop's body and loops from two threads at once (one of them
// starts threads of its own), and a loop after one that threw: every index exactly once.
TEST(ParallelFor, BackToBackNestedAndConcurrentLoopsVisitEveryIndexOnce) {
  auto many = [](int rounds, int salt) {
    for (int r = 0; r < rounds; ++r) {
      const std::size_t n = 1 + static_cast<std::size_t>((r * 7 + salt) % 61);
      const int threads = 2 + (r + salt) % 4;
      std::vector<std::atomic<int>> hits(n);
      atmosh::parallel_for(n, threads, [&](std::size_t i) { hits[i].fetch_add(1); });
      for (std::size_t i = 0; i < n; ++i)
        if (hits[i].load() != 1) return false;
    }
    return true;
  };
  EXPECT_TRUE(many(3000, 0));

  std::vector<std::atomic<int>> outer(8), inner(8 * 50);
  atmosh::parallel_for(8, 3, [&](std::size_t o) {
    outer[o].fetch_add(1);
    atmosh::parallel_for(50, 2, [&](std::size_t i) { inner[o * 50 + i].fetch_add(1); });
  });
  for (auto& h : outer) ASSERT_EQ(h.load(), 1);
  for (auto& h : inner) ASSERT_EQ(h.load(), 1);

  bool a = false, b = false;
  std::thread other([&] { b = many(1000, 3); });
  a = many(1000, 5);
  other.join();
  EXPECT_TRUE(a);
  EXPECT_TRUE(b);

  EXPECT_THROW(atmosh::parallel_for(64, 2,
                                    [](std::size_t i) {
                                      if (i == 5) throw std::runtime_error("index 5");
                                    }),
               std::runtime_error);
  EXPECT_TRUE(many(200, 1));
}
