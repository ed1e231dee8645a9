// atmosh/work.hpp — the work policy of the toolkit: how long a request will compute,
// estimated from its sizes before it starts, and durations as people write them.
//
// Like the memory policy (memory.hpp), long work estimates itself first and is refused
// (InputError, exit 2 at the command line) when the estimate exceeds the time budget:
// the caller's own (the CLI's --max-time) or kDefaultTimeBudgetS. An estimate is a count
// of the request's inner steps (rays x view-ray nodes x wavelengths, table entries,
// samples x SH terms, ...) times the cost of one step on one core, measured on the
// reference machine for the estimator that uses it (the constants, the machine and the
// spread of the measurements are in docs/hostile-input.md). The estimators live next to
// what they estimate; they are order-of-magnitude guards against requests of hours or
// years, not predictions: they count the main loop only, assume every worker is busy,
// and a faster or slower machine scales them.
#pragma once

#include <string>

namespace atmosh {

/// The estimated work of one request.
struct WorkEstimate {
  double units = 0;             ///< inner steps of the main loop (saturates at +inf, never wraps)
  double seconds_per_unit = 0;  ///< one step on one core of the reference machine [s]
  std::string unit;             ///< what a step is, for messages: "ray nodes x wavelengths"
  /// units x seconds_per_unit: CPU time on one core of the reference machine [s].
  double cpu_seconds() const { return units * seconds_per_unit; }
  /// Wall time with `workers` busy workers (>= 1) [s]: cpu_seconds() / workers.
  double wall_seconds(int workers) const { return cpu_seconds() / (workers > 1 ? workers : 1); }
};

/// Two pieces of work one after the other: their CPU times add; the result counts the
/// larger piece's units (its unit and cost per unit stay, scaled so that cpu_seconds()
/// is the sum).
WorkEstimate operator+(const WorkEstimate& a, const WorkEstimate& b);

/// The default time budget: 24 h of wall time on the reference machine.
inline constexpr double kDefaultTimeBudgetS = 24.0 * 3600.0;

/// "24h", "90m", "90min", "45s", "2d", "1.5h", "3600" (seconds without a unit) -> seconds.
/// InputError "<what>: '<text>' is not a duration such as 24h, 90m, 45s or 3600 (seconds)"
/// for anything else, a duration <= 0, or one above 1e12 s.
double parse_time_budget(const std::string& text, const std::string& what = "--max-time");

/// For messages: "%.3g s" below 2 min, "%.3g min" below 2 h, "%.3g h" below 2 days,
/// "%.3g days" below 2 years, else "%.3g years"; "forever" for +inf.
std::string format_duration(double seconds);

/// a x b (x c) in double, each factor clamped at >= 0: a step count that cannot wrap.
double mul_units(double a, double b);
double mul_units(double a, double b, double c);

}  // namespace atmosh
