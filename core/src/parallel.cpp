#include "atmosh/parallel.hpp"

#include <sched.h>

#include <algorithm>
#include <cctype>
#include <condition_variable>
#include <memory>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "atmosh/error.hpp"

namespace atmosh {

namespace {

// The folders from cgroup_root + path up to cgroup_root itself, innermost first.
std::vector<std::string> cgroup_dirs(const std::string& cgroup_root, std::string path) {
  std::vector<std::string> dirs;
  if (path.empty() || path[0] != '/') path = "/" + path;
  for (;;) {
    dirs.push_back(cgroup_root + (path == "/" ? std::string() : path));
    if (path == "/") break;
    const auto slash = path.rfind('/');
    path = slash == 0 || slash == std::string::npos ? "/" : path.substr(0, slash);
  }
  return dirs;
}

// ceil(quota / period) >= 1 for a positive quota and period, else 0 (no limit).
int quota_cpus(double quota, double period) {
  if (!(quota > 0) || !(period > 0) || !std::isfinite(quota / period)) return 0;
  const double n = std::ceil(quota / period);
  return n >= kMaxThreads ? kMaxThreads : std::max(1, static_cast<int>(n));
}

void keep_smaller(int& best, int n) {
  if (n > 0 && (best == 0 || n < best)) best = n;
}

// One number from a file, or nullopt (missing, empty, not a number).
std::optional<double> read_number(const std::string& file) {
  std::ifstream f(file);
  std::string s;
  if (!(f >> s)) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') return std::nullopt;
  return v;
}

}  // namespace

int detail::count_cpu_list(const std::string& list) {
  int count = 0;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    while (!item.empty() && std::isspace(static_cast<unsigned char>(item.back()))) item.pop_back();
    if (item.empty()) continue;
    char* end = nullptr;
    const long a = std::strtol(item.c_str(), &end, 10);
    long b = a;
    if (end == item.c_str() || a < 0) return 0;
    if (*end == '-') {
      const char* s = end + 1;
      b = std::strtol(s, &end, 10);
      if (end == s) return 0;
    }
    if (*end != '\0' || b < a || b - a > 1 << 20) return 0;
    count += static_cast<int>(b - a + 1);
    if (count > 1 << 20) return 0;
  }
  return count;
}

int detail::cgroup_cpu_limit(const std::string& proc_self_cgroup, const std::string& cgroup_root) {
  std::ifstream cg(proc_self_cgroup);
  std::string line, v2_path;
  std::vector<std::pair<std::string, std::string>> v1;  // (controllers, path): "4:cpu,cpuacct:/a" -> ("cpu,cpuacct", "/a")
  while (std::getline(cg, line)) {
    const auto c1 = line.find(':');
    const auto c2 = c1 == std::string::npos ? std::string::npos : line.find(':', c1 + 1);
    if (c2 == std::string::npos) continue;
    const std::string id = line.substr(0, c1), controllers = line.substr(c1 + 1, c2 - c1 - 1), path = line.substr(c2 + 1);
    if (id == "0" && controllers.empty()) v2_path = path;
    else v1.emplace_back(controllers, path);
  }
  int best = 0;
  // cgroup v2 (Documentation/admin-guide/cgroup-v2.rst): "cpu.max" is "$MAX $PERIOD", MAX "max" for no limit.
  for (const auto& dir : cgroup_dirs(cgroup_root, v2_path.empty() ? "/" : v2_path)) {
    std::ifstream f(dir + "/cpu.max");
    std::string quota;
    double period = 0;
    if (f >> quota >> period && quota != "max") {
      char* end = nullptr;
      const double q = std::strtod(quota.c_str(), &end);
      if (end != quota.c_str() && *end == '\0') keep_smaller(best, quota_cpus(q, period));
    }
  }
  // cgroup v1: each controller's hierarchy is mounted at cgroup_root/<controllers> (often
  // also as cgroup_root/cpu, a link). CFS bandwidth (Documentation/scheduler/sched-bwc.rst):
  // cpu.cfs_quota_us in microseconds, -1 for no limit, per cpu.cfs_period_us; cpusets
  // (Documentation/admin-guide/cgroup-v1/cpusets.rst): cpuset.cpus, a list such as "0-3,8".
  for (const auto& [controllers, path] : v1) {
    std::vector<std::string> names;
    std::stringstream ss(controllers);
    for (std::string c; std::getline(ss, c, ',');) names.push_back(c);
    const bool cpu = std::find(names.begin(), names.end(), "cpu") != names.end();
    const bool cpuset = std::find(names.begin(), names.end(), "cpuset") != names.end();
    if (!cpu && !cpuset) continue;
    std::vector<std::string> mounts{cgroup_root + "/" + controllers};
    if (cpu && controllers != "cpu") mounts.push_back(cgroup_root + "/cpu");
    if (cpuset && controllers != "cpuset") mounts.push_back(cgroup_root + "/cpuset");
    for (const auto& mount : mounts) {
      std::error_code ec;
      if (!std::filesystem::is_directory(mount, ec)) continue;
      for (const auto& dir : cgroup_dirs(mount, path)) {
        if (cpu) {
          const auto quota = read_number(dir + "/cpu.cfs_quota_us"), period = read_number(dir + "/cpu.cfs_period_us");
          if (quota && period) keep_smaller(best, quota_cpus(*quota, *period));
        }
        if (cpuset) {
          std::ifstream f(dir + "/cpuset.cpus");
          std::string list;
          if (std::getline(f, list)) keep_smaller(best, count_cpu_list(list));
        }
      }
      break;  // the first mount found holds the hierarchy
    }
  }
  return best;
}

namespace {

int cgroup_cpu_limit() { return detail::cgroup_cpu_limit("/proc/self/cgroup", "/sys/fs/cgroup"); }

}  // namespace

int available_cpus() {
  int n = 0;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
  if (n < 1) n = static_cast<int>(std::thread::hardware_concurrency());
  // The cgroup files are read once per process; the affinity mask (one system call)
  // every time, as a process may be moved (sched_setaffinity, taskset -p).
  static const int limit = cgroup_cpu_limit();
  if (limit > 0 && (n < 1 || limit < n)) n = limit;
  return std::max(1, n);
}

namespace {

// The loops' persistent workers (parallel.hpp, "Workers").
struct PoolJob {
  const std::function<void()>* task = nullptr;
  int slots = 0;
  std::atomic<int> next{0};     // slots claimed: by pool threads, and at the end by the caller
  std::atomic<int> running{0};  // pool threads between their claim attempt and its end
  std::mutex m;
  std::condition_variable done;
};

thread_local bool t_pool_thread = false;

class Pool {
 public:
  bool run(int extra, const std::function<void()>& task) {
    if (t_pool_thread || extra < 1) return false;
    bool idle = false;
    if (!busy_.compare_exchange_strong(idle, true)) return false;
    struct Release {
      std::atomic<bool>& busy;
      ~Release() { busy.store(false); }
    } release{busy_};
    grow(extra);
    if (threads_.empty()) return false;
    auto job = std::make_shared<PoolJob>();
    job->task = &task;
    job->slots = std::min(extra, static_cast<int>(threads_.size()));
    bool wake = false;
    {
      const std::lock_guard<std::mutex> lock(m_);
      job_ = job;
      gen_.fetch_add(1);
      wake = sleepers_ > 0;
    }
    if (wake) cv_.notify_all();  // (a system call: skipped while every thread still spins)
    auto drain = [&] {
      // The slots no pool thread has claimed are dropped (their task would find no range).
      while (job->next.fetch_add(1) < job->slots) {
      }
      // A pool thread counts itself running before it claims, so every claimed slot is
      // counted here: spin briefly for them, then sleep.
      const auto t0 = std::chrono::steady_clock::now();
      while (job->running.load() > 0 && std::chrono::steady_clock::now() - t0 < std::chrono::microseconds(50)) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
      if (job->running.load() > 0) {
        std::unique_lock<std::mutex> lock(job->m);
        job->done.wait(lock, [&] { return job->running.load() == 0; });
      }
      const std::lock_guard<std::mutex> lock(m_);
      if (job_ == job) job_.reset();
    };
    try {
      task();
    } catch (...) {  // (the loops' tasks catch their own; another caller's must not leave one running)
      drain();
      throw;
    }
    drain();
    return true;
  }

 private:
  void grow(int extra) {
    while (static_cast<int>(threads_.size()) < extra) {
      try {
        const unsigned seen = gen_.load();
        threads_.emplace_back([this, seen] { loop(seen); });
        threads_.back().detach();
      } catch (...) {  // no more threads: run with those there are
        return;
      }
    }
  }

  void loop(unsigned seen) {
    t_pool_thread = true;
    for (;;) {
      // about 50 us of spinning for the next loop (back-to-back loops of a transform),
      // then sleep
      const auto t0 = std::chrono::steady_clock::now();
      while (gen_.load(std::memory_order_acquire) == seen &&
             std::chrono::steady_clock::now() - t0 < std::chrono::microseconds(50)) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
      std::shared_ptr<PoolJob> job;
      {
        std::unique_lock<std::mutex> lock(m_);
        ++sleepers_;
        cv_.wait(lock, [&] { return gen_.load() != seen; });
        --sleepers_;
        seen = gen_.load();
        job = job_;
      }
      if (!job) continue;
      job->running.fetch_add(1);
      if (job->next.fetch_add(1) < job->slots) (*job->task)();
      if (job->running.fetch_sub(1) == 1) {
        const std::lock_guard<std::mutex> lock(job->m);
        job->done.notify_all();
      }
    }
  }

  std::atomic<bool> busy_{false};
  std::vector<std::thread> threads_;  // detached; kept for their count
  std::mutex m_;
  std::condition_variable cv_;
  std::atomic<unsigned> gen_{0};
  int sleepers_ = 0;  // threads in cv_.wait (under m_)
  std::shared_ptr<PoolJob> job_;
};

}  // namespace

bool detail::pool_run(int extra, const std::function<void()>& task) {
  // Never destroyed: its threads may still wait on it while the process exits.
  static Pool* const pool = new Pool;
  return pool->run(extra, task);
}

int resolve_threads(int requested, const std::string& what) {
  if (requested < 0 || requested > kMaxThreads)
    throw InputError(what + " " + std::to_string(requested) + ": must be in 0.." + std::to_string(kMaxThreads) +
                     " (0 = the " + std::to_string(available_cpus()) + " CPUs this process may use)");
  return requested > 0 ? requested : available_cpus();
}

}  // namespace atmosh
