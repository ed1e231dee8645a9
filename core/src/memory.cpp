// The memory policy (atmosh/memory.hpp).
#include "atmosh/memory.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>

#include "atmosh/error.hpp"

namespace atmosh {

namespace {
std::optional<std::size_t> read_number_file(const std::filesystem::path& path) {
  std::ifstream f(path);
  std::string s;
  if (!(f >> s) || s == "max") return std::nullopt;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (end == s.c_str()) return std::nullopt;
  return static_cast<std::size_t>(v);
}

std::optional<std::size_t> meminfo_available(const std::filesystem::path& root) {
  std::ifstream f(root / "proc/meminfo");
  std::string key, unit;
  unsigned long long kb = 0;
  while (f >> key >> kb >> unit)
    if (key == "MemAvailable:") return static_cast<std::size_t>(kb) * 1024;
  return std::nullopt;
}

// What the cgroup still allows this process: limit less usage (v2, else v1).
std::optional<std::size_t> cgroup_available(const std::filesystem::path& root) {
  auto left = [](std::optional<std::size_t> limit, std::optional<std::size_t> used) -> std::optional<std::size_t> {
    if (!limit || *limit >= (std::size_t{1} << 60)) return std::nullopt;  // v1 "unlimited" is a huge number
    const std::size_t u = used.value_or(0);
    return *limit > u ? *limit - u : 0;
  };
  const std::filesystem::path cg = root / "sys/fs/cgroup";
  if (auto v2 = left(read_number_file(cg / "memory.max"), read_number_file(cg / "memory.current"))) return v2;
  return left(read_number_file(cg / "memory/memory.limit_in_bytes"), read_number_file(cg / "memory/memory.usage_in_bytes"));
}
}  // namespace

AvailableMemory available_memory(const std::filesystem::path& root) {
  const auto mem = meminfo_available(root), cg = cgroup_available(root);
  AvailableMemory a{std::numeric_limits<std::size_t>::max(), AvailableMemory::Source::unknown};
  if (mem) a = {*mem, AvailableMemory::Source::meminfo};
  if (cg && (!mem || *cg < *mem)) a = {*cg, AvailableMemory::Source::cgroup};
  return a;
}

std::size_t parse_memory_size(const std::string& text, const std::string& what) {
  const char* b = text.c_str();
  char* e = nullptr;
  const double v = std::strtod(b, &e);
  std::string unit(e);
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!unit.empty() && unit.back() == 'b') unit.pop_back();  // "GB", "GiB"
  if (!unit.empty() && unit.back() == 'i') unit.pop_back();
  double scale = 0;
  if (unit.empty()) scale = 1;
  else if (unit == "k") scale = 1024.0;
  else if (unit == "m") scale = 1024.0 * 1024;
  else if (unit == "g") scale = 1024.0 * 1024 * 1024;
  else if (unit == "t") scale = 1024.0 * 1024 * 1024 * 1024;
  if (e == b || scale == 0 || !std::isfinite(v) || v <= 0 || v * scale > 1e19)
    throw InputError(what + ": '" + text + "' is not a size such as 2G, 512M or 800000000 (bytes)");
  return static_cast<std::size_t>(v * scale);
}

std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= 1024.0 * 1024 * 1024) std::snprintf(buf, sizeof buf, "%.3g GiB", bytes / (1024.0 * 1024 * 1024));
  else if (bytes >= 1024.0 * 1024) std::snprintf(buf, sizeof buf, "%.3g MiB", bytes / (1024.0 * 1024));
  else std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  return buf;
}

std::size_t mul_bytes(std::size_t a, std::size_t b) {
  if (a != 0 && b > std::numeric_limits<std::size_t>::max() / a) return std::numeric_limits<std::size_t>::max();
  return a * b;
}
std::size_t mul_bytes(std::size_t a, std::size_t b, std::size_t c) { return mul_bytes(mul_bytes(a, b), c); }

}  // namespace atmosh
