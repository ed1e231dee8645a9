#include "cli_common.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "atmosh/device.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::cli {

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const char* b = item.c_str();
    char* e = nullptr;
    const double v = std::strtod(b, &e);
    while (e && *e == ' ') ++e;
    if (e == b || *e != '\0' || !std::isfinite(v))
      throw InputError(what + ": '" + text + "' is not a list of finite numbers");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(what + ": '" + text + "' is empty");
  return out;
}

std::array<double, 3> parse_triple(const std::string& text, const std::string& what) {
  const auto v = parse_list(text, what);
  if (v.size() != 3) throw InputError(what + ": '" + text + "' is not three numbers x,y,z");
  return {v[0], v[1], v[2]};
}

std::array<int, 2> parse_size(const std::string& text, const std::string& what) {
  const auto x = text.find_first_of("xX");
  auto bad = [&] { return InputError(what + ": '" + text + "' is not a size WxH (each 1..65536)"); };
  if (x == std::string::npos) throw bad();
  try {
    std::size_t p1 = 0, p2 = 0;
    const std::string a = text.substr(0, x), b = text.substr(x + 1);
    const long w = std::stol(a, &p1), h = std::stol(b, &p2);
    if (p1 != a.size() || p2 != b.size() || w < 1 || h < 1 || w > 65536 || h > 65536) throw bad();
    return {static_cast<int>(w), static_cast<int>(h)};
  } catch (const std::logic_error&) {
    throw bad();
  }
}

double require_range(double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(what + ": " + io::format_double(v) + " is out of range [" + io::format_double(lo) + ", " +
                     io::format_double(hi) + "]");
  return v;
}

int threads_option(int requested, const std::string& option) {
  const int n = resolve_threads(requested, option);
  io::set_threads(n);
  return n;
}

DeviceRequest check_device(const std::string& device) { return parse_device_request(device, "--device"); }

void device_notice(const DeviceDecision& decision) {
  if (!decision.notice.empty()) std::cerr << "atmosh: " << decision.notice << "\n";
}

}  // namespace atmosh::cli

// ---- limits checked before work ------------------------------------------------------
namespace atmosh::cli {

namespace {
std::optional<std::size_t> g_budget;  // --max-memory

std::optional<std::size_t> read_number_file(const char* path) {
  std::ifstream f(path);
  std::string s;
  if (!(f >> s) || s == "max") return std::nullopt;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (end == s.c_str()) return std::nullopt;
  return static_cast<std::size_t>(v);
}

std::optional<std::size_t> meminfo_available() {
  std::ifstream f("/proc/meminfo");
  std::string key;
  unsigned long long kb = 0;
  std::string unit;
  while (f >> key >> kb >> unit)
    if (key == "MemAvailable:") return static_cast<std::size_t>(kb) * 1024;
  return std::nullopt;
}

// What the cgroup still allows this process: limit less usage (v2, else v1).
std::optional<std::size_t> cgroup_available() {
  auto left = [](std::optional<std::size_t> limit, std::optional<std::size_t> used) -> std::optional<std::size_t> {
    if (!limit || *limit >= (std::size_t{1} << 60)) return std::nullopt;  // v1 "unlimited" is a huge number
    const std::size_t u = used.value_or(0);
    return *limit > u ? *limit - u : 0;
  };
  if (auto v2 = left(read_number_file("/sys/fs/cgroup/memory.max"), read_number_file("/sys/fs/cgroup/memory.current")))
    return v2;
  return left(read_number_file("/sys/fs/cgroup/memory/memory.limit_in_bytes"),
              read_number_file("/sys/fs/cgroup/memory/memory.usage_in_bytes"));
}

std::string budget_source() {
  if (g_budget) return "--max-memory";
  const auto mem = meminfo_available(), cg = cgroup_available();
  if (cg && (!mem || *cg < *mem)) return "the cgroup's memory.max less its usage; set with --max-memory";
  return "MemAvailable; set with --max-memory";
}
}  // namespace

std::size_t memory_budget() {
  if (g_budget) return *g_budget;
  const auto mem = meminfo_available(), cg = cgroup_available();
  std::size_t b = std::numeric_limits<std::size_t>::max();
  if (mem) b = std::min(b, *mem);
  if (cg) b = std::min(b, *cg);
  return b;
}

void set_memory_budget(std::size_t bytes) { g_budget = bytes; }

std::size_t parse_memory_size(const std::string& text) {
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
    throw InputError("--max-memory: '" + text + "' is not a size such as 2G, 512M or 800000000 (bytes)");
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

void check_memory(std::size_t bytes, const std::string& what) {
  const std::size_t budget = memory_budget();
  if (bytes > budget)
    throw InputError(what + " needs about " + format_bytes(static_cast<double>(bytes)) +
                     " of memory (estimate), more than the budget of " + format_bytes(static_cast<double>(budget)) +
                     " (" + budget_source() + ")");
}

namespace {
// The nearest existing folder at or above p.
std::filesystem::path existing_ancestor(std::filesystem::path p) {
  std::error_code ec;
  if (p.empty()) p = ".";
  p = std::filesystem::absolute(p, ec);
  while (!p.empty() && !std::filesystem::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
  return p;
}
}  // namespace

void check_output_dir(const std::filesystem::path& dir, const std::string& what) {
  std::error_code ec;
  const std::string name = dir.string();
  if (std::filesystem::exists(dir, ec)) {
    if (!std::filesystem::is_directory(dir, ec)) throw InputError(what + " '" + name + "': exists and is not a folder");
    if (::access(dir.c_str(), W_OK | X_OK) != 0) throw InputError(what + " '" + name + "': folder is not writable");
    return;
  }
  const auto up = existing_ancestor(dir);
  if (!std::filesystem::is_directory(up, ec))
    throw InputError(what + " '" + name + "': '" + up.string() + "' is not a folder");
  if (::access(up.c_str(), W_OK | X_OK) != 0)
    throw InputError(what + " '" + name + "': cannot be created ('" + up.string() + "' is not writable)");
}

void check_output_file(const std::filesystem::path& file, const std::vector<std::string>& extensions,
                       const std::string& what) {
  std::error_code ec;
  const std::string name = file.string();
  if (file.empty() || !file.has_filename()) throw InputError(what + " '" + name + "': not a file name");
  if (std::filesystem::is_directory(file, ec)) throw InputError(what + " '" + name + "': is a folder, not a file");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!extensions.empty() && std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
    std::string list;
    for (const auto& x : extensions) list += (list.empty() ? "" : ", ") + x;
    throw InputError(what + " '" + name + "': extension '" + ext + "' is not " + list);
  }
  const auto parent = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  check_output_dir(parent, what);
}

}  // namespace atmosh::cli
