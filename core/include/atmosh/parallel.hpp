// atmosh/parallel.hpp — the one parallel loop of the toolkit and its thread-count policy,
// shared by every multithreaded pass (SH transforms, sky images, studies, sweeps, PRT bakes).
//
// parallel_for_ranges(n, chunk, threads, body, progress) calls body(begin, end) for
// consecutive ranges [begin, end) of at most `chunk` indices covering [0, n), each
// range exactly once, taken by `threads` workers (0 = the CPUs this process may use, see
// resolve_threads)
// from a shared atomic counter — so the result does not depend on the thread count as
// long as body(begin, end) writes only its own indices. Without `progress` the
// calling thread is one of the workers; with it, the calling thread only reports
// progress(fraction done in [0, 1]) about every 20 ms (the library never prints).
// The first exception a body throws stops the others from taking new ranges and is
// rethrown on the calling thread once all workers have finished.
//
// parallel_for_ranges_local(n, chunk, threads, make_local, body) is the same loop where
// every worker first builds its own scratch state, `auto local = make_local();`, and
// then calls body(local, begin, end) for the ranges it takes (FFT plans, work arrays
// allocated once per worker instead of once per range). Results must not depend on
// which worker's scratch a range sees.
//
// Workers. Without `progress`, the workers besides the calling thread come from a pool of
// threads kept for the process (started at the first loop that needs them, about 50 us
// each on a 2-core VM; that start per loop was most of a 2-thread SH transform at
// L = 256). A worker spins about 50 us after its last range and then sleeps. The calling
// thread never waits for a worker that has not started: when it runs out of ranges it
// takes the slots no worker has claimed. A loop inside a loop's body, a loop started
// while another thread's loop holds the pool, and a loop with `progress` start threads
// of their own, as before.
//
// Why not TBB (a dependency through Embree): its default arena follows the affinity
// mask but not a cgroup v2 cpu.max quota (resolve_threads reads both), its partitioners
// do not promise which ranges a body sees, and this loop with its kept workers is about
// 200 lines with no dependency; docs/core.md has the timings of the loops it replaced.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace atmosh {

/// The CPUs this process may run on (>= 1): the CPUs in its affinity mask
/// (sched_getaffinity: `taskset -c 0`, a Slurm allocation, numactl) and, where a cgroup
/// limits them (containers, systemd slices, batch schedulers), at most that many: the v2
/// `cpu.max` quota, the v1 `cpu.cfs_quota_us / cpu.cfs_period_us` quota (ceil) and the v1
/// `cpuset.cpus` list. std::thread::hardware_concurrency() when none can be read.
int available_cpus();

namespace detail {
/// Runs task() on `extra` of the pool's threads and on the calling thread, and returns when
/// every call that started has returned. Slots that no pool thread has claimed by the time
/// the calling thread's own task() returns are dropped. Such a slot's task() would have
/// found no range left, so dropping it is safe. Returns false without running anything
/// when the pool cannot take the loop: the calling thread is a pool thread, or another
/// loop holds the pool. The caller then starts threads of its own.
bool pool_run(int extra, const std::function<void()>& task);
/// The smallest CPU limit of this process's cgroups, read from the files under
/// cgroup_root (available_cpus() passes "/proc/self/cgroup" and "/sys/fs/cgroup"; tests
/// a folder of fixture files), every cgroup on the way from the process's own up to the
/// hierarchy's root counting; 0 when none limits the CPUs.
///  * v2, the "0::PATH" line of proc_self_cgroup: ceil(quota / period) of
///    cgroup_root/PATH/cpu.max ("$MAX $PERIOD", "max" = no limit).
///  * v1, lines "N:CONTROLLERS:PATH" naming cpu: ceil(cpu.cfs_quota_us / cpu.cfs_period_us)
///    (a quota of -1 = no limit); naming cpuset: the count of CPUs in cpuset.cpus
///    ("0-3,8" = 5). The hierarchy is cgroup_root/CONTROLLERS (e.g. "cpu,cpuacct"), else
///    cgroup_root/cpu or cgroup_root/cpuset.
/// Malformed files are ignored (no limit from them).
int cgroup_cpu_limit(const std::string& proc_self_cgroup, const std::string& cgroup_root);
/// CPUs in a cpuset list such as "0-3,8,10-11" (= 7); 0 for an empty or malformed list.
int count_cpu_list(const std::string& list);
}  // namespace detail

/// Most workers anyone may ask for (a guard against typos such as 100000).
inline constexpr int kMaxThreads = 1024;

/// The one thread-count policy of the toolkit: requested in 1..kMaxThreads as given;
/// 0 = available_cpus(). InputError otherwise, one line naming `what` (an option such
/// as "--threads" where the CLI passes one) and the value:
/// "threads -1: must be in 0..1024 (0 = the 2 CPUs this process may use)".
int resolve_threads(int requested, const std::string& what = "threads");

template <class MakeLocal, class Body>
void parallel_for_ranges_local(std::size_t n, std::size_t chunk, int threads, MakeLocal&& make_local, Body&& body,
                               const std::function<void(double)>& progress = {}) {
  if (n == 0) return;
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t ranges = (n + chunk - 1) / chunk;
  const int workers = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(resolve_threads(threads)), ranges));
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    try {
      auto local = make_local();
      for (std::size_t b; !failed.load(std::memory_order_relaxed) && (b = next.fetch_add(chunk)) < n;) {
        const std::size_t e = std::min(n, b + chunk);
        body(local, b, e);
        done.fetch_add(e - b, std::memory_order_relaxed);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      failed.store(true);
    }
  };
  if (!progress && workers > 1 && detail::pool_run(workers - 1, work)) {
    if (failure) std::rethrow_exception(failure);
    return;
  }
  std::vector<std::thread> pool;
  const int spawned = progress ? workers : workers - 1;
  pool.reserve(static_cast<std::size_t>(std::max(spawned, 0)));
  try {
    for (int i = 0; i < spawned; ++i) pool.emplace_back(work);
  } catch (...) {  // no more threads (std::system_error): stop, join those that run, rethrow
    failed.store(true);
    for (auto& t : pool) t.join();
    throw;
  }
  if (progress) {
    double last = -1;
    while (done.load() < n && !failed.load()) {
      const double f = static_cast<double>(done.load()) / static_cast<double>(n);
      if (f - last >= 0.01) {
        progress(f);
        last = f;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  } else {
    work();
  }
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

template <class Body>
void parallel_for_ranges(std::size_t n, std::size_t chunk, int threads, Body&& body,
                         const std::function<void(double)>& progress = {}) {
  struct None {};
  parallel_for_ranges_local(
      n, chunk, threads, [] { return None{}; }, [&](None&, std::size_t b, std::size_t e) { body(b, e); }, progress);
}

/// body(i) for every i in [0, n), one index per range (see parallel_for_ranges).
template <class Body>
void parallel_for(std::size_t n, int threads, Body&& body) {
  parallel_for_ranges(n, 1, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) body(i);
  });
}

}  // namespace atmosh
