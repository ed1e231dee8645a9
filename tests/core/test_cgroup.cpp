// The CPU limits of cgroup v1 read by the one thread policy (atmosh/parallel.hpp),
// on fixture trees in data/cgroup_v1/ laid out as the kernel shows them:
//  * /proc/self/cgroup lines "hierarchy-ID:controller-list:cgroup-path" (man 7 cgroups);
//  * CFS bandwidth control, Documentation/scheduler/sched-bwc.rst: cpu.cfs_quota_us and
//    cpu.cfs_period_us in microseconds, a quota of -1 for none; the quota/period ratio is
//    the number of CPUs' worth of time the group may take per period;
//  * cpusets, Documentation/admin-guide/cgroup-v1/cpusets.rst: cpuset.cpus is a list of
//    CPU numbers and ranges ("0-4,9" = 0, 1, 2, 3, 4 and 9).
#include <gtest/gtest.h>

#include <string>

#include "atmosh/parallel.hpp"

namespace {

int limit_of(const std::string& fixture) {
  const std::string d = std::string(ATMOSH_TEST_DATA_DIR) + "/cgroup_v1/" + fixture;
  return atmosh::detail::cgroup_cpu_limit(d + "/proc_self_cgroup", d + "/root");
}

TEST(CgroupV1, CpusetListsAreCounted) {
  // sched-bwc / cpusets list syntax: comma-separated numbers and inclusive ranges.
  EXPECT_EQ(atmosh::detail::count_cpu_list("0-4,9"), 6);
  EXPECT_EQ(atmosh::detail::count_cpu_list("0,4-5"), 3);
  EXPECT_EQ(atmosh::detail::count_cpu_list("3\n"), 1);
  EXPECT_EQ(atmosh::detail::count_cpu_list("0-63"), 64);
  EXPECT_EQ(atmosh::detail::count_cpu_list(""), 0);        // an empty cpuset limits nothing here
  EXPECT_EQ(atmosh::detail::count_cpu_list("7-3"), 0);     // malformed: ignored
  EXPECT_EQ(atmosh::detail::count_cpu_list("0-x"), 0);
  EXPECT_EQ(atmosh::detail::count_cpu_list("-1"), 0);
}

// A batch job (Slurm's task/cgroup layout) with 150000 us of quota per 100000 us period
// three levels down: 1.5 CPUs' worth, so 2 workers; its cpuset of 8 CPUs allows more.
TEST(CgroupV1, QuotaThreeLevelsDownLimitsTheCpus) { EXPECT_EQ(limit_of("slurm"), 2); }

// A cpuset of CPUs 0, 4 and 5 with no quota; the cpu hierarchy found under its link
// name cpu/ although /proc/self/cgroup lists it as "cpuacct,cpu".
TEST(CgroupV1, CpusetLimitsTheCpus) { EXPECT_EQ(limit_of("cpuset"), 3); }

// In a container /proc/self/cgroup names the host's path, which does not exist under
// the container's mount: the quota at the mount's root (250000 / 50000 = 5 CPUs) counts.
TEST(CgroupV1, ContainerQuotaAtTheMountRoot) { EXPECT_EQ(limit_of("container"), 5); }

// Quota -1 (none), and files that are not numbers, a period of 0 and a reversed cpuset
// range: no limit, and no crash.
TEST(CgroupV1, NoQuotaAndMalformedFilesLimitNothing) { EXPECT_EQ(limit_of("unlimited"), 0); }

// A file that does not exist: no cgroup, no limit.
TEST(CgroupV1, MissingFilesLimitNothing) {
  EXPECT_EQ(atmosh::detail::cgroup_cpu_limit("/nonexistent/atmosh/cgroup", "/nonexistent/atmosh/root"), 0);
}

}  // namespace
