// The memory policy (atmosh/memory.hpp) on fake /proc and /sys trees: file formats per
// Linux Documentation/filesystems/proc.rst (/proc/meminfo "MemAvailable: <n> kB") and
// Documentation/admin-guide/cgroup-v2.rst (memory.max: bytes or "max"; memory.current:
// bytes), cgroup v1 memory.limit_in_bytes / memory.usage_in_bytes (cgroup-v1/memory.rst;
// "unlimited" reads as 0x7FFFFFFFFFFFF000). Sizes in binary multiples (IEC 80000-13).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

#include "atmosh/error.hpp"
#include "atmosh/memory.hpp"

namespace fs = std::filesystem;
using atmosh::AvailableMemory;

namespace {
constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();

struct FakeRoot {
  fs::path root;
  explicit FakeRoot(const std::string& name) {
    root = fs::temp_directory_path() / ("atmosh_memory_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "proc");
    fs::create_directories(root / "sys/fs/cgroup/memory");
  }
  ~FakeRoot() { fs::remove_all(root); }
  void write(const std::string& rel, const std::string& text) const { std::ofstream(root / rel) << text; }
  void meminfo(std::size_t available_kb) const {
    write("proc/meminfo", "MemTotal:       16384000 kB\nMemFree:         1000000 kB\nMemAvailable:   " +
                              std::to_string(available_kb) + " kB\nBuffers:          20000 kB\n");
  }
};
}  // namespace

TEST(Memory, NothingReadableIsUnknownAndUnlimited) {
  const FakeRoot f("none");
  const AvailableMemory a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::unknown);
  EXPECT_EQ(a.bytes, kMax);
}

TEST(Memory, MemAvailableIsInKibibytes) {
  const FakeRoot f("meminfo");
  f.meminfo(2000000);
  const AvailableMemory a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::meminfo);
  EXPECT_EQ(a.bytes, std::size_t{2000000} * 1024);
}

TEST(Memory, CgroupV2LimitLessUsageWhenSmaller) {
  const FakeRoot f("v2");
  f.meminfo(2000000);                                  // 2.048e9 bytes
  f.write("sys/fs/cgroup/memory.max", "1073741824\n");  // 1 GiB
  f.write("sys/fs/cgroup/memory.current", "73741824\n");
  AvailableMemory a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::cgroup);
  EXPECT_EQ(a.bytes, std::size_t{1000000000});
  // Usage above the limit leaves nothing (not a wrapped-around huge number).
  f.write("sys/fs/cgroup/memory.current", "2000000000\n");
  EXPECT_EQ(atmosh::available_memory(f.root).bytes, 0u);
  // "max" is no limit: MemAvailable decides.
  f.write("sys/fs/cgroup/memory.max", "max\n");
  a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::meminfo);
  EXPECT_EQ(a.bytes, std::size_t{2000000} * 1024);
}

TEST(Memory, CgroupLargerThanMemAvailableLeavesMemAvailable) {
  const FakeRoot f("v2big");
  f.meminfo(1000);  // 1 024 000 bytes
  f.write("sys/fs/cgroup/memory.max", "1073741824\n");
  f.write("sys/fs/cgroup/memory.current", "0\n");
  const AvailableMemory a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::meminfo);
  EXPECT_EQ(a.bytes, 1024000u);
}

TEST(Memory, CgroupV1WhereV2IsAbsentAndItsUnlimitedValue) {
  const FakeRoot f("v1");
  f.meminfo(4000000);
  f.write("sys/fs/cgroup/memory/memory.limit_in_bytes", "536870912\n");  // 512 MiB
  f.write("sys/fs/cgroup/memory/memory.usage_in_bytes", "36870912\n");
  AvailableMemory a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::cgroup);
  EXPECT_EQ(a.bytes, std::size_t{500000000});
  f.write("sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");  // v1 "unlimited"
  a = atmosh::available_memory(f.root);
  EXPECT_EQ(a.source, AvailableMemory::Source::meminfo);
}

TEST(Memory, ParsesSizesInBinaryMultiples) {
  EXPECT_EQ(atmosh::parse_memory_size("800000000"), 800000000u);
  EXPECT_EQ(atmosh::parse_memory_size("64k"), 65536u);
  EXPECT_EQ(atmosh::parse_memory_size("512M"), 536870912u);
  EXPECT_EQ(atmosh::parse_memory_size("2G"), 2147483648u);
  EXPECT_EQ(atmosh::parse_memory_size("2GB"), 2147483648u);
  EXPECT_EQ(atmosh::parse_memory_size("1.5GiB"), 1610612736u);
  EXPECT_EQ(atmosh::parse_memory_size("1t"), std::size_t{1} << 40);
  for (const char* bad : {"", "abc", "0", "-1G", "2X", "1e30", "nan", "G"}) {
    try {
      atmosh::parse_memory_size(bad, "--budget");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const atmosh::InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                std::string("--budget: '") + bad + "' is not a size such as 2G, 512M or 800000000 (bytes)");
    }
  }
}

TEST(Memory, FormatsBytesForMessages) {
  EXPECT_EQ(atmosh::format_bytes(512), "512 bytes");
  EXPECT_EQ(atmosh::format_bytes(3.0 * 1024 * 1024), "3 MiB");
  EXPECT_EQ(atmosh::format_bytes(12.34 * 1024 * 1024 * 1024), "12.3 GiB");
}

TEST(Memory, ProductsSaturateInsteadOfWrapping) {
  EXPECT_EQ(atmosh::mul_bytes(0, kMax), 0u);
  EXPECT_EQ(atmosh::mul_bytes(65536, 65536, 64), std::size_t{1} << 38);
  EXPECT_EQ(atmosh::mul_bytes(std::size_t{1} << 32, std::size_t{1} << 32), kMax);
  EXPECT_EQ(atmosh::mul_bytes(std::size_t{1} << 40, std::size_t{1} << 20, 16), kMax);  // 2^64
  EXPECT_EQ(atmosh::mul_bytes(std::size_t{1} << 40, std::size_t{1} << 20, 8), std::size_t{1} << 63);
}
