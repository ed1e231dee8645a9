#include "atmosh/parallel.hpp"

#include <sched.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "atmosh/error.hpp"

namespace atmosh {

int detail::cgroup_cpu_limit(const std::string& proc_self_cgroup, const std::string& cgroup_root) {
  std::ifstream cg(proc_self_cgroup);
  std::string line, path;
  while (std::getline(cg, line))
    if (line.rfind("0::", 0) == 0) path = line.substr(3);
  if (path.empty()) path = "/";
  int best = 0;
  for (;;) {
    std::ifstream f(cgroup_root + (path == "/" ? std::string() : path) + "/cpu.max");
    std::string quota;
    double period = 0;
    if (f >> quota >> period && quota != "max" && period > 0) {
      try {
        const double q = std::stod(quota);
        if (q > 0) {
          const int n = std::max(1, static_cast<int>(std::ceil(q / period)));
          if (best == 0 || n < best) best = n;
        }
      } catch (const std::exception&) {
      }
    }
    if (path == "/" || path.empty()) break;
    const auto slash = path.rfind('/');
    path = slash == 0 || slash == std::string::npos ? "/" : path.substr(0, slash);
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

int resolve_threads(int requested, const std::string& what) {
  if (requested < 0 || requested > kMaxThreads)
    throw InputError(what + " " + std::to_string(requested) + ": must be in 0.." + std::to_string(kMaxThreads) +
                     " (0 = the " + std::to_string(available_cpus()) + " CPUs this process may use)");
  return requested > 0 ? requested : available_cpus();
}

}  // namespace atmosh
