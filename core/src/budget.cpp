// The memory and time budgets (atmosh/budget.hpp).
#include "atmosh/budget.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "atmosh/error.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh {

namespace {
std::optional<std::size_t> g_memory_budget;
std::optional<double> g_time_budget;

std::string estimate_detail(const WorkEstimate& w, int workers) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.3g %s at %.3g s each on one core, %d worker%s", w.units, w.unit.c_str(),
                w.seconds_per_unit, std::max(workers, 1), workers > 1 ? "s" : "");
  return buf;
}
}  // namespace

std::size_t memory_budget() { return g_memory_budget ? *g_memory_budget : available_memory().bytes; }

void set_memory_budget(std::size_t bytes) { g_memory_budget = bytes; }

void check_memory(std::size_t bytes, const std::string& what) {
  const std::size_t budget = memory_budget();
  if (bytes > budget)
    throw InputError(what + " needs about " + format_bytes(static_cast<double>(bytes)) +
                     " of memory (estimate), more than the budget of " + format_bytes(static_cast<double>(budget)) +
                     " (" +
                     (g_memory_budget ? std::string("--max-memory")
                      : available_memory().source == AvailableMemory::Source::cgroup
                          ? std::string("the cgroup's memory.max less its usage; set with --max-memory")
                          : std::string("MemAvailable; set with --max-memory")) +
                     ")");
}

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

}  // namespace atmosh
