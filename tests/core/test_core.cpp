// The core helpers every library shares: the one number formatter and the one
// thread-count policy (atmosh/format.hpp, atmosh/parallel.hpp).
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/parallel.hpp"

namespace {

// Shortest round trip: the C++17 std::to_chars contract ([charconv.to.chars]: the
// shortest representation that reads back to the same value), in printf %g style
// for the exponent (sign and at least two digits).
TEST(FormatDouble, ShortestFormRoundTrips) {
  EXPECT_EQ(atmosh::format_double(8e-6), "8e-06");
  EXPECT_EQ(std::strtod(atmosh::format_double(8e-6).c_str(), nullptr), 8e-6);
  EXPECT_EQ(atmosh::format_double(0.1), "0.1");
  EXPECT_EQ(atmosh::format_double(2.5), "2.5");
  EXPECT_EQ(atmosh::format_double(16.0), "16");
  EXPECT_EQ(atmosh::format_double(-3.996e-6), "-3.996e-06");
  EXPECT_EQ(atmosh::format_double(6360e3), "6360000");
  EXPECT_EQ(atmosh::format_double(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(atmosh::format_double(std::nan("")), "nan");
  EXPECT_EQ(atmosh::format_double(-HUGE_VAL), "-inf");
  // 0.1 + 0.2 is a different double from 0.3: it keeps all the digits that tell them apart.
  EXPECT_EQ(atmosh::format_double(0.1 + 0.2), "0.30000000000000004");
  std::mt19937_64 rng(7);
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    const std::string s = atmosh::format_double(v);
    ASSERT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
    ASSERT_LE(s.size(), 24u) << s;
  }
}

TEST(Threads, NegativeCountRefused) {
  EXPECT_THROW(atmosh::resolve_threads(-1), atmosh::InputError);
  EXPECT_EQ(atmosh::resolve_threads(5), 5);
  EXPECT_GE(atmosh::available_cpus(), 1);
  EXPECT_EQ(atmosh::resolve_threads(0), atmosh::available_cpus());
}

// One policy everywhere: 0..1024, the message names what the caller calls the count
// (an option such as --threads, a scene key) and the value, on one line.
TEST(Threads, OutOfRangeNamesTheCountAndTheValue) {
  EXPECT_EQ(atmosh::resolve_threads(atmosh::kMaxThreads), 1024);
  for (int bad : {-1, 1025, -2147483647 - 1}) {
    try {
      atmosh::resolve_threads(bad, "--threads");
      ADD_FAILURE() << bad << " accepted";
    } catch (const atmosh::InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("--threads " + std::to_string(bad) + ": must be in 0..1024 (0 = the ", 0), 0u) << m;
      EXPECT_NE(m.find(std::to_string(atmosh::available_cpus()) + " CPUs this process may use"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

// Under an affinity mask of one CPU (what `taskset -c 0` or a one-CPU Slurm job
// gives), 0 threads means one worker, not the machine's core count.
TEST(Threads, ZeroMeansTheCpusThisProcessMayUse) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) _exit(3);
    _exit(atmosh::available_cpus() == 1 && atmosh::resolve_threads(0) == 1 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "resolve_threads(0) under a one-CPU affinity mask is not 1";
}

// cgroup v2 CPU bandwidth limit (Linux Documentation/admin-guide/cgroup-v2.rst,
// "cpu.max": "$MAX $PERIOD", MAX "max" for no limit): a quota of 1.5 CPUs on the way
// up from the process's cgroup allows 2 workers; the smallest limit on the path wins.
TEST(Threads, CgroupQuotaLimitsTheCpus) {
  namespace fs = std::filesystem;
  const fs::path d = fs::temp_directory_path() / ("atmosh_cgroup_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d / "root" / "a" / "b");
  std::ofstream(d / "cgroup") << "0::/a/b\n";
  const std::string cg = (d / "cgroup").string(), root = (d / "root").string();
  EXPECT_EQ(atmosh::detail::cgroup_cpu_limit(cg, root), 0);  // no cpu.max anywhere: no limit
  std::ofstream(d / "root" / "a" / "b" / "cpu.max") << "max 100000\n";
  std::ofstream(d / "root" / "a" / "cpu.max") << "150000 100000\n";
  EXPECT_EQ(atmosh::detail::cgroup_cpu_limit(cg, root), 2);
  std::ofstream(d / "root" / "a" / "b" / "cpu.max") << "50000 100000\n";
  EXPECT_EQ(atmosh::detail::cgroup_cpu_limit(cg, root), 1);
  std::ofstream(d / "root" / "cpu.max") << "max 100000\n";
  std::ofstream(d / "root" / "a" / "cpu.max") << "max 100000\n";
  std::ofstream(d / "root" / "a" / "b" / "cpu.max") << "400000 100000\n";
  EXPECT_EQ(atmosh::detail::cgroup_cpu_limit(cg, root), 4);
  fs::remove_all(d);
}

}  // namespace
