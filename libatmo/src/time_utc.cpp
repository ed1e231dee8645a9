// time_utc.cpp — ISO 8601 parsing and formatting, Julian days, ΔT.
#include "atmosh/atmo/time_utc.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "atmosh/error.hpp"

namespace atmosh::atmo {
namespace {

// Days since 1970-01-01 of a proleptic-Gregorian date (era arithmetic on 400-year
// cycles of 146097 days; valid for any int year).
std::int64_t days_from_civil(std::int64_t y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t yoe = y - era * 400;                                  // [0, 399]
  const std::int64_t mp = (m + 9) % 12;                                    // March = 0
  const std::int64_t doy = (153 * mp + 2) / 5 + d - 1;                     // [0, 365]
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;          // [0, 146096]
  return era * 146097 + doe - 719468;
}

void civil_from_days(std::int64_t z, std::int64_t& y, int& m, int& d) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  d = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  m = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  y = yoe + era * 400 + (m <= 2 ? 1 : 0);
}

bool is_leap(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int days_in_month(std::int64_t y, int m) {
  static const int k[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && is_leap(y) ? 29 : k[m - 1];
}

constexpr double kJdUnixEpoch = 2440587.5;  // JD of 1970-01-01T00:00:00

[[noreturn]] void bad(const std::string& text, const std::string& why) {
  throw InputError("time '" + text + "': " + why);
}

// Reads exactly n digits at pos.
int read_digits(const std::string& s, std::size_t& pos, int n, const std::string& text, const char* field) {
  int v = 0;
  for (int i = 0; i < n; ++i) {
    if (pos >= s.size() || !std::isdigit(static_cast<unsigned char>(s[pos])))
      bad(text, std::string("expected ") + std::to_string(n) + " digits for the " + field +
                    " (format YYYY-MM-DDThh:mm:ss[.fff][Z|+hh:mm])");
    v = v * 10 + (s[pos++] - '0');
  }
  return v;
}

void expect(const std::string& s, std::size_t& pos, char c, const std::string& text) {
  if (pos >= s.size() || s[pos] != c)
    bad(text, std::string("expected '") + c + "' at character " + std::to_string(pos + 1) +
                  " (format YYYY-MM-DDThh:mm:ss[.fff][Z|+hh:mm])");
  ++pos;
}

}  // namespace

double julian_day(const CalendarTime& t) {
  const std::int64_t days = days_from_civil(t.year, t.month, t.day);
  const double frac = (t.hour * 3600.0 + t.minute * 60.0 + t.second) / 86400.0;
  return kJdUnixEpoch + static_cast<double>(days) + frac;
}

CalendarTime calendar_from_julian_day(double jd) {
  const double x = jd - kJdUnixEpoch;
  double days = std::floor(x);
  // Work in integer microseconds of the day to avoid 59.9999999 s artefacts.
  auto us = static_cast<std::int64_t>(std::llround((x - days) * 86400e6));
  if (us >= 86400LL * 1000000LL) {
    us -= 86400LL * 1000000LL;
    days += 1.0;
  }
  CalendarTime c;
  std::int64_t y;
  civil_from_days(static_cast<std::int64_t>(days), y, c.month, c.day);
  c.year = static_cast<int>(y);
  c.hour = static_cast<int>(us / 3600000000LL);
  c.minute = static_cast<int>((us / 60000000LL) % 60);
  c.second = static_cast<double>(us % 60000000LL) * 1e-6;
  return c;
}

std::string format_iso8601_utc(double jd_utc, int decimals) {
  if (!std::isfinite(jd_utc) || std::fabs(jd_utc) > 1e9) return "invalid";
  if (decimals < 0) decimals = 0;
  if (decimals > 6) decimals = 6;
  // Count whole units of 10^-decimals s since 1970 once, then split with integer
  // arithmetic, so rounding can never produce a seconds field of 60.
  std::int64_t per_s = 1;
  for (int i = 0; i < decimals; ++i) per_s *= 10;
  const std::int64_t per_day = 86400 * per_s;
  const auto units = static_cast<std::int64_t>(std::llround((jd_utc - kJdUnixEpoch) * 86400.0 * static_cast<double>(per_s)));
  std::int64_t days = units / per_day, rem = units % per_day;
  if (rem < 0) {
    rem += per_day;
    days -= 1;
  }
  std::int64_t y;
  int m, d;
  civil_from_days(days, y, m, d);
  const std::int64_t secs = rem / per_s, frac = rem % per_s;
  char year[32];
  if (y >= 0 && y <= 9999)
    std::snprintf(year, sizeof year, "%04lld", static_cast<long long>(y));
  else
    std::snprintf(year, sizeof year, "%+05lld", static_cast<long long>(y));
  char buf[112];
  const int hh = static_cast<int>(secs / 3600), mm = static_cast<int>((secs / 60) % 60), ss = static_cast<int>(secs % 60);
  if (decimals == 0)
    std::snprintf(buf, sizeof buf, "%s-%02d-%02dT%02d:%02d:%02dZ", year, m, d, hh, mm, ss);
  else
    std::snprintf(buf, sizeof buf, "%s-%02d-%02dT%02d:%02d:%02d.%0*lldZ", year, m, d, hh, mm, ss, decimals,
                  static_cast<long long>(frac));
  return buf;
}

ParsedTime parse_iso8601(const std::string& text) {
  std::string s = text;
  // Trim surrounding blanks.
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t pos = 0;
  while (pos < s.size() && std::isspace(static_cast<unsigned char>(s[pos]))) ++pos;
  if (pos == s.size()) bad(text, "empty time");

  int sign = 1;
  if (s[pos] == '+' || s[pos] == '-') {
    sign = s[pos] == '-' ? -1 : 1;
    ++pos;
  }
  // Year: at least 4 digits.
  std::size_t y0 = pos;
  std::int64_t year = 0;
  while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos]))) {
    year = year * 10 + (s[pos++] - '0');
    if (year > 1000000) bad(text, "year too large");
  }
  if (pos - y0 < 4) bad(text, "expected a year of at least 4 digits (format YYYY-MM-DDThh:mm:ss[Z|+hh:mm])");
  year *= sign;
  expect(s, pos, '-', text);
  CalendarTime c;
  c.month = read_digits(s, pos, 2, text, "month");
  expect(s, pos, '-', text);
  c.day = read_digits(s, pos, 2, text, "day");
  if (c.month < 1 || c.month > 12) bad(text, "month " + std::to_string(c.month) + " is not in 1..12");
  if (c.day < 1 || c.day > days_in_month(year, c.month))
    bad(text, "day " + std::to_string(c.day) + " does not exist in that month");

  int offset_min = 0;
  if (pos < s.size()) {
    if (s[pos] != 'T' && s[pos] != 't' && s[pos] != ' ') bad(text, "expected 'T' between date and time");
    ++pos;
    c.hour = read_digits(s, pos, 2, text, "hour");
    expect(s, pos, ':', text);
    c.minute = read_digits(s, pos, 2, text, "minute");
    int sec_int = 0;
    double frac = 0.0;
    if (pos < s.size() && s[pos] == ':') {
      ++pos;
      sec_int = read_digits(s, pos, 2, text, "second");
      if (pos < s.size() && (s[pos] == '.' || s[pos] == ',')) {
        ++pos;
        double scale = 0.1;
        const std::size_t f0 = pos;
        while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos]))) {
          frac += (s[pos++] - '0') * scale;
          scale *= 0.1;
        }
        if (pos == f0) bad(text, "expected digits after the decimal point of the seconds");
      }
    }
    if (c.hour > 23) bad(text, "hour " + std::to_string(c.hour) + " is not in 0..23");
    if (c.minute > 59) bad(text, "minute " + std::to_string(c.minute) + " is not in 0..59");
    if (sec_int == 60)
      bad(text,
          "seconds value 60 (a leap second) is not supported: the Julian-day time scale of SPA has "
          "86400 s per day, so 23:59:60 has no distinct instant; use 23:59:59.999 or the next second");
    if (sec_int > 60) bad(text, "seconds value " + std::to_string(sec_int) + " is not in 0..59");
    c.second = sec_int + frac;
    // Zone.
    if (pos < s.size()) {
      if (s[pos] == 'Z' || s[pos] == 'z') {
        ++pos;
      } else if (s[pos] == '+' || s[pos] == '-') {
        const int osign = s[pos] == '-' ? -1 : 1;
        ++pos;
        const int oh = read_digits(s, pos, 2, text, "offset hours");
        int om = 0;
        if (pos < s.size() && s[pos] == ':') {
          ++pos;
          om = read_digits(s, pos, 2, text, "offset minutes");
        } else if (pos < s.size()) {
          om = read_digits(s, pos, 2, text, "offset minutes");
        }
        if (oh > 18 || om > 59 || oh * 60 + om > 18 * 60)
          bad(text, "zone offset beyond ±18:00");
        offset_min = osign * (oh * 60 + om);
      } else {
        bad(text, "unexpected '" + std::string(1, s[pos]) + "' after the time (expected Z or ±hh:mm)");
      }
    }
    if (pos != s.size()) bad(text, "unexpected trailing characters '" + s.substr(pos) + "'");
  }
  if (year < kMinSunYear - 1 || year > kMaxSunYear + 1)
    bad(text, "year " + std::to_string(year) + " is outside the supported range -2000..6000");
  c.year = static_cast<int>(year);

  ParsedTime r;
  r.local = c;
  r.offset_minutes = offset_min;
  r.jd_utc = julian_day(c) - offset_min / 1440.0;
  require_sun_year_range(r.jd_utc, "time '" + text + "'");
  return r;
}

void require_sun_year_range(double jd_utc, const std::string& what) {
  if (!std::isfinite(jd_utc)) throw InputError(what + ": not a finite time");
  if (!sun_year_in_range(jd_utc)) {
    const CalendarTime c = calendar_from_julian_day(jd_utc);
    throw InputError(what + ": UTC year " + std::to_string(c.year) +
                     " is outside the supported range -2000..6000");
  }
}

bool sun_year_in_range(double jd_utc) {
  static const double lo = julian_day(CalendarTime{kMinSunYear, 1, 1, 0, 0, 0.0});
  static const double hi = julian_day(CalendarTime{kMaxSunYear + 1, 1, 1, 0, 0, 0.0});
  return jd_utc >= lo && jd_utc < hi;
}

double decimal_year(double jd_utc) {
  const CalendarTime c = calendar_from_julian_day(jd_utc);
  const double start = julian_day(CalendarTime{c.year, 1, 1, 0, 0, 0.0});
  const double len = is_leap(c.year) ? 366.0 : 365.0;
  return c.year + (jd_utc - start) / len;
}

double parse_duration_s(const std::string& text) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (...) {
    throw InputError("duration '" + text + "': expected a number with a unit s, min, h or d (e.g. 10min)");
  }
  std::string unit = text.substr(used);
  while (!unit.empty() && std::isspace(static_cast<unsigned char>(unit.front()))) unit.erase(unit.begin());
  double scale = 0.0;
  if (unit.empty() || unit == "s") scale = 1.0;
  else if (unit == "min" || unit == "m") scale = 60.0;
  else if (unit == "h") scale = 3600.0;
  else if (unit == "d") scale = 86400.0;
  else throw InputError("duration '" + text + "': unknown unit '" + unit + "' (use s, min, h or d)");
  const double s = v * scale;
  if (!std::isfinite(s) || s <= 0.0) throw InputError("duration '" + text + "': must be positive and finite");
  return s;
}

double delta_t_espenak_meeus(double y) {
  // Espenak & Meeus (2006), NASA/TP-2006-214141; coefficients as printed on
  // eclipse.gsfc.nasa.gov/SEcat5/deltatpoly.html.
  auto parabola = [](double yr) {
    const double u = (yr - 1820.0) / 100.0;
    return -20.0 + 32.0 * u * u;
  };
  if (y < -500.0) return parabola(y);
  if (y < 500.0) {
    const double u = y / 100.0;
    return 10583.6 + u * (-1014.41 + u * (33.78311 + u * (-5.952053 + u * (-0.1798452 + u * (0.022174192 + u * 0.0090316521)))));
  }
  if (y < 1600.0) {
    const double u = (y - 1000.0) / 100.0;
    return 1574.2 + u * (-556.01 + u * (71.23472 + u * (0.319781 + u * (-0.8503463 + u * (-0.005050998 + u * 0.0083572073)))));
  }
  if (y < 1700.0) {
    const double t = y - 1600.0;
    return 120.0 + t * (-0.9808 + t * (-0.01532 + t / 7129.0));
  }
  if (y < 1800.0) {
    const double t = y - 1700.0;
    return 8.83 + t * (0.1603 + t * (-0.0059285 + t * (0.00013336 - t / 1174000.0)));
  }
  if (y < 1860.0) {
    const double t = y - 1800.0;
    return 13.72 + t * (-0.332447 + t * (0.0068612 + t * (0.0041116 + t * (-0.00037436 + t * (0.0000121272 + t * (-0.0000001699 + t * 0.000000000875))))));
  }
  if (y < 1900.0) {
    const double t = y - 1860.0;
    return 7.62 + t * (0.5737 + t * (-0.251754 + t * (0.01680668 + t * (-0.0004473624 + t / 233174.0))));
  }
  if (y < 1920.0) {
    const double t = y - 1900.0;
    return -2.79 + t * (1.494119 + t * (-0.0598939 + t * (0.0061966 - t * 0.000197)));
  }
  if (y < 1941.0) {
    const double t = y - 1920.0;
    return 21.20 + t * (0.84493 + t * (-0.076100 + t * 0.0020936));
  }
  if (y < 1961.0) {
    const double t = y - 1950.0;
    return 29.07 + t * (0.407 + t * (-1.0 / 233.0 + t / 2547.0));
  }
  if (y < 1986.0) {
    const double t = y - 1975.0;
    return 45.45 + t * (1.067 + t * (-1.0 / 260.0 - t / 718.0));
  }
  if (y < 2005.0) {
    const double t = y - 2000.0;
    return 63.86 + t * (0.3345 + t * (-0.060374 + t * (0.0017275 + t * (0.000651814 + t * 0.00002373599))));
  }
  if (y < 2050.0) {
    const double t = y - 2000.0;
    return 62.92 + t * (0.32217 + t * 0.005589);
  }
  if (y < 2150.0) return parabola(y) - 0.5628 * (2150.0 - y);
  return parabola(y);
}

}  // namespace atmosh::atmo
