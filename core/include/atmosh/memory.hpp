// atmosh/memory.hpp — the memory policy of the toolkit: how much memory this process
// may still take, sizes as people write them, and byte counts that cannot overflow.
//
// Long work estimates its largest holding first and is refused (InputError, exit 2
// at the command line) when the estimate exceeds the budget: the caller's own budget
// (the CLI's --max-memory) or, by default, available_memory().
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace atmosh {

/// What this process may still allocate [bytes] and where the figure comes from.
struct AvailableMemory {
  enum class Source {
    unknown,  ///< neither figure could be read: bytes = SIZE_MAX
    meminfo,  ///< /proc/meminfo MemAvailable (kB x 1024)
    cgroup,   ///< the cgroup's limit less its usage (v2 memory.max - memory.current, else v1
              ///< memory.limit_in_bytes - memory.usage_in_bytes), where smaller than MemAvailable
  };
  std::size_t bytes = 0;
  Source source = Source::unknown;
};

/// The smaller of MemAvailable and the cgroup's limit less its usage (a limit of
/// "max" or >= 2^60, v1's "unlimited", is no limit; usage above the limit leaves 0).
/// `root`: where /proc and /sys are found ("/"; tests pass a folder of fake files).
AvailableMemory available_memory(const std::filesystem::path& root = "/");

/// "2G", "512M", "1.5GiB", "64k", "800000000": binary multiples k, M, G, T (case and
/// a trailing "B" / "iB" ignored), plain bytes without a unit; truncated to whole bytes.
/// InputError "<what>: '<text>' is not a size such as 2G, 512M or 800000000 (bytes)" for
/// anything else, a size <= 0, or one above 1e19 bytes.
std::size_t parse_memory_size(const std::string& text, const std::string& what = "--max-memory");

/// For messages: "%.3g GiB" from 1 GiB, "%.3g MiB" from 1 MiB, else "%.0f bytes".
std::string format_bytes(double bytes);

/// a * b (* c), saturating at SIZE_MAX instead of wrapping: estimates of absurd
/// requests stay absurd and are refused.
std::size_t mul_bytes(std::size_t a, std::size_t b);
std::size_t mul_bytes(std::size_t a, std::size_t b, std::size_t c);

}  // namespace atmosh
