#include "cli_common.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "atmosh/device.hpp"
#include "atmosh/error.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/netcdf.hpp"
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
}  // namespace

// The budget: --max-memory, else what this process may still take (atmosh/memory.hpp).
std::size_t memory_budget() { return g_budget ? *g_budget : available_memory().bytes; }

void set_memory_budget(std::size_t bytes) { g_budget = bytes; }

void check_memory(std::size_t bytes, const std::string& what) {
  const std::size_t budget = memory_budget();
  if (bytes > budget)
    throw InputError(what + " needs about " + format_bytes(static_cast<double>(bytes)) +
                     " of memory (estimate), more than the budget of " + format_bytes(static_cast<double>(budget)) +
                     " (" +
                     (g_budget ? std::string("--max-memory")
                      : available_memory().source == AvailableMemory::Source::cgroup
                          ? std::string("the cgroup's memory.max less its usage; set with --max-memory")
                          : std::string("MemAvailable; set with --max-memory")) +
                     ")");
}

void add_format_option(CLI::App* c, bool& netcdf) {
  c->add_option_function<std::string>("--format", [&netcdf](const std::string& v) { netcdf = io::parse_table_format(v); },
                                      "csv (default) | netcdf: the table also as netCDF-CF (.nc beside the .csv)");
}

void add_format_option(CLI::App* c, std::string& stem) {
  static std::deque<bool> flags;  // one per command, alive as long as the program
  bool& netcdf = flags.emplace_back(false);
  add_format_option(c, netcdf);
  c->parse_complete_callback([&netcdf, &stem] { if (netcdf && !stem.ends_with(".nc")) stem += ".nc"; });
}

}  // namespace atmosh::cli

// ---- the time budget -----------------------------------------------------------------
namespace atmosh::cli {

namespace {
std::optional<double> g_time_budget;  // --max-time
std::string estimate_detail(const WorkEstimate& w, int workers) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.3g %s at %.3g s each on one core, %d worker%s", w.units, w.unit.c_str(),
                w.seconds_per_unit, std::max(workers, 1), workers > 1 ? "s" : "");
  return buf;
}
}  // namespace

double time_budget() { return g_time_budget ? *g_time_budget : kDefaultTimeBudgetS; }

void set_time_budget(double seconds) { g_time_budget = seconds; }

std::string describe_work(const WorkEstimate& w, int workers) {
  if (workers <= 0) workers = available_cpus();
  return "about " + format_duration(w.wall_seconds(workers)) + " (estimate: " + estimate_detail(w, workers) + ")";
}

void check_time(const WorkEstimate& w, int workers, const std::string& what) {
  if (workers <= 0) workers = available_cpus();
  const double wall = w.wall_seconds(workers);
  if (!(wall <= time_budget()))
    throw InputError(what + " needs about " + format_duration(wall) + " of computing (estimate: " +
                     estimate_detail(w, workers) + "), more than the time budget of " + format_duration(time_budget()) +
                     (g_time_budget ? " (--max-time)" : " (the default; set with --max-time)"));
}

}  // namespace atmosh::cli
