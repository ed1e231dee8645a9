// atmosh/atmo/time_utc.hpp — UTC instants, ISO 8601 parsing/formatting, Julian
// days, durations and the ΔT model used by the sun-position code.
//
// Calendar: ISO 8601, i.e. the proleptic Gregorian calendar with astronomical
// year numbering (year 0 = 1 BC, year -1 = 2 BC), for every year. Note that the
// SPA report (Reda & Andreas 2008, eq. 4) switches to the Julian calendar before
// 1582-10-15; ISO 8601 strings are Gregorian by definition, so atmosh converts
// them as Gregorian dates for all years. Both agree from 1582-10-15 on.
//
// Time scale: an instant is carried as a Julian day number on the UTC scale
// (`jd_utc`, days; JD 2451545.0 = 2000-01-01T12:00:00Z). A double holds it to
// about 40 µs at year 2000 and 80 µs at year 6000.
//
// Leap seconds: a seconds field of 60 is rejected. The Julian-day mapping used by
// SPA (and by every formula here) counts 86400 s per day, so 23:59:60 has no
// distinct Julian day; accepting it would silently alias it to the next day's
// 00:00:00. The message names the value and suggests 59.999 or the next second.
//
// Valid years: -2000 .. 6000 (the range of NREL SPA); anything outside throws
// atmosh::InputError naming the value.
#pragma once

#include <string>

namespace atmosh::atmo {

inline constexpr int kMinSunYear = -2000;
inline constexpr int kMaxSunYear = 6000;
inline constexpr double kJ2000 = 2451545.0;  // JD of 2000-01-01T12:00:00 TT/UTC

// A broken-down civil time (no zone). second in [0, 60).
struct CalendarTime {
  int year = 2000;
  int month = 1;   // 1..12
  int day = 1;     // 1..31
  int hour = 0;    // 0..23
  int minute = 0;  // 0..59
  double second = 0.0;
};

// Result of parsing an ISO 8601 string.
struct ParsedTime {
  double jd_utc = kJ2000;     // the instant, UTC Julian day
  int offset_minutes = 0;     // the zone offset written in the string (Z or none: 0)
  CalendarTime local;         // the civil time as written (in that offset)
};

// Parses "YYYY-MM-DDThh:mm[:ss[.fff]][Z|±hh:mm|±hhmm|±hh]", also a space instead
// of 'T', a bare date "YYYY-MM-DD" (midnight), and signed/expanded years such as
// "-0500-03-01T00:00Z" or "+2003-10-17T12:30:30-07:00". No zone means UTC.
// Throws InputError naming the string on any malformed field, a seconds value of
// 60 (leap second, see above), an invalid day of month, an offset beyond ±18 h, or
// a UTC year outside -2000..6000.
ParsedTime parse_iso8601(const std::string& text);

// Julian day of a proleptic-Gregorian civil time (UTC). Exact integer arithmetic
// for the date part. No range check (callers validate).
double julian_day(const CalendarTime& t);

// Inverse of julian_day (proleptic Gregorian); seconds rounded to 1 µs.
CalendarTime calendar_from_julian_day(double jd);

// "2003-10-17T18:30:30Z" (decimals = digits of the seconds fraction, 0..6).
// Years outside 0..9999 are written with a sign and at least 4 digits.
std::string format_iso8601_utc(double jd_utc, int decimals = 0);

// Decimal year of an instant, y = year + (month - 0.5)/12 style continuous value:
// year + (day of year + fraction) / days in year.
double decimal_year(double jd_utc);

// Throws InputError unless the UTC year of jd_utc is within -2000..6000.
void require_sun_year_range(double jd_utc, const std::string& what);
// True when the UTC year of jd_utc is within -2000..6000 (no allocation).
bool sun_year_in_range(double jd_utc);

// Durations: "90" or "90s", "10min", "1.5h", "2d" -> seconds (> 0, finite).
// Throws InputError naming the text otherwise.
double parse_duration_s(const std::string& text);

// ΔT = TT − UT1 in seconds from the polynomial expressions of Espenak & Meeus
// ("Five Millennium Canon of Solar Eclipses", NASA/TP-2006-214141; published at
// eclipse.gsfc.nasa.gov/SEcat5/deltatpoly.html), evaluated at the decimal year
// y. The polynomials cover -1999..3000; outside that span the long-term parabola
// -20 + 32 u², u = (y - 1820)/100 (Morrison & Stephenson 2004), which the same
// page gives for y < -500 and y > 2150, is used for the whole SPA range.
// Accuracy: the polynomials follow the observed ΔT within ~1 s for 1620–2005;
// predictions after 2005 drift from the observed values (the 2005–2050
// polynomial gives 74.8 s for mid-2025 where IERS measured about 69.2 s; see
// docs/sun.md). Historical uncertainty grows to hours
// before -1000. Pass a measured ΔT (IERS Bulletin A) for the stated SPA
// accuracy.
double delta_t_espenak_meeus(double decimal_year);

}  // namespace atmosh::atmo
