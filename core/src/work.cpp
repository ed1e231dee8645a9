// The work policy (atmosh/work.hpp).
#include "atmosh/work.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "atmosh/error.hpp"

namespace atmosh {

WorkEstimate operator+(const WorkEstimate& a, const WorkEstimate& b) {
  const WorkEstimate& big = a.cpu_seconds() >= b.cpu_seconds() ? a : b;
  WorkEstimate sum = big;
  const double total = a.cpu_seconds() + b.cpu_seconds();
  if (big.units > 0) sum.seconds_per_unit = total / big.units;
  return sum;
}

double parse_time_budget(const std::string& text, const std::string& what) {
  const char* b = text.c_str();
  char* e = nullptr;
  const double v = std::strtod(b, &e);
  std::string unit(e);
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  double scale = 0;
  if (unit.empty() || unit == "s") scale = 1;
  else if (unit == "m" || unit == "min") scale = 60;
  else if (unit == "h") scale = 3600;
  else if (unit == "d") scale = 86400;
  if (e == b || scale == 0 || !std::isfinite(v) || v <= 0 || v * scale > 1e12)
    throw InputError(what + ": '" + text + "' is not a duration such as 24h, 90m, 45s or 3600 (seconds)");
  return v * scale;
}

std::string format_duration(double s) {
  if (std::isinf(s)) return "forever";
  char buf[64];
  if (s < 120) std::snprintf(buf, sizeof buf, "%.3g s", s);
  else if (s < 7200) std::snprintf(buf, sizeof buf, "%.3g min", s / 60);
  else if (s < 2 * 86400.0) std::snprintf(buf, sizeof buf, "%.3g h", s / 3600);
  else if (s < 2 * 365.25 * 86400) std::snprintf(buf, sizeof buf, "%.3g days", s / 86400);
  else std::snprintf(buf, sizeof buf, "%.3g years", s / (365.25 * 86400));
  return buf;
}

double mul_units(double a, double b) {
  const double r = std::max(a, 0.0) * std::max(b, 0.0);
  return std::isnan(r) ? std::numeric_limits<double>::infinity() : r;
}
double mul_units(double a, double b, double c) { return mul_units(mul_units(a, b), c); }

}  // namespace atmosh
