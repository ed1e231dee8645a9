// sun_fast.cpp — Grena (2012) algorithms 1, 3 and 5; see sun_fast.hpp.
#include "atmosh/atmo/sun_fast.hpp"

#include <cmath>
#include <string>

#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = 180.0 / kPi;
constexpr double kDeg = kPi / 180.0;
// Grena's time origin: t = 0 at 2060-01-01T00:00 UT = JD 2473459.5.
constexpr double kGrenaEpochJd = 2473459.5;
}  // namespace

GrenaResult grena_position(int variant, double jd_ut, double delta_t_s, double latitude_deg, double longitude_deg) {
  if (variant != 1 && variant != 3 && variant != 5)
    throw InputError("Grena algorithm " + std::to_string(variant) + " is not provided (use 1, 3 or 5)");
  if (!std::isfinite(jd_ut) || !std::isfinite(delta_t_s) || !std::isfinite(latitude_deg) ||
      !std::isfinite(longitude_deg))
    throw InputError("fast sun position: non-finite input");
  static const double lo = julian_day(CalendarTime{kGrenaMinYear, 1, 1, 0, 0, 0.0});
  static const double hi = julian_day(CalendarTime{kGrenaMaxYear + 1, 1, 1, 0, 0, 0.0});
  if (jd_ut < lo || jd_ut >= hi)
    throw InputError("time " + format_iso8601_utc(jd_ut) +
                     " is outside the validity range 2010..2110 of the fast algorithm (Grena 2012); use --algorithm spa");

  // Continuous day count (Grena's calendar formula rounds 1/24 to 0.0416667; the
  // exact JD difference is used instead, a difference below 0.02 s).
  const double t = jd_ut - kGrenaEpochJd;
  const double te = t + 1.1574e-5 * delta_t_s;
  const double lon = longitude_deg * kDeg;
  double alpha, delta, H;

  if (variant == 1) {
    const double w = 0.017202786 * te;
    const double s1 = std::sin(w), c1 = std::cos(w);
    const double s2 = 2.0 * s1 * c1, c2 = (c1 + s1) * (c1 - s1);
    alpha = -1.38880 + 1.72027920e-2 * te + 3.199e-2 * s1 - 2.65e-3 * c1 + 4.050e-2 * s2 + 1.525e-2 * c2;
    alpha = std::fmod(alpha, 2.0 * kPi);
    if (alpha < 0) alpha += 2.0 * kPi;
    delta = 6.57e-3 + 7.347e-2 * s1 - 3.9919e-1 * c1 + 7.3e-4 * s2 - 6.60e-3 * c2;
    H = 1.75283 + 6.3003881 * t + lon - alpha;
  } else {
    const double w = 0.0172019715 * te;
    double lambda, eps, dlam = 0.0;
    if (variant == 3) {
      lambda = -1.388803 + 1.720279216e-2 * te + 3.3366e-2 * std::sin(w - 0.06172) + 3.53e-4 * std::sin(2.0 * w - 0.1163);
      eps = 4.089567e-1 - 6.19e-9 * te;
    } else {
      const double s1 = std::sin(w), c1 = std::cos(w);
      const double s2 = 2.0 * s1 * c1, c2 = (c1 + s1) * (c1 - s1);
      const double s3 = s2 * c1 + c2 * s1, c3 = c2 * c1 - s2 * s1;
      const double L = 1.7527901 + 1.7202792159e-2 * te + 3.33024e-2 * s1 - 2.0582e-3 * c1 + 3.512e-4 * s2 -
                       4.07e-5 * c2 + 5.2e-6 * s3 - 9e-7 * c3 - 8.23e-5 * s1 * std::sin(2.92e-5 * te) +
                       1.27e-5 * std::sin(1.49e-3 * te - 2.337) + 1.21e-5 * std::sin(4.31e-3 * te + 3.065) +
                       2.33e-5 * std::sin(1.076e-2 * te - 1.533) + 3.49e-5 * std::sin(1.575e-2 * te - 2.358) +
                       2.67e-5 * std::sin(2.152e-2 * te + 0.074) + 1.28e-5 * std::sin(3.152e-2 * te + 1.547) +
                       3.14e-5 * std::sin(2.1277e-1 * te - 0.488);
      const double nu = 9.282e-4 * te - 0.8;
      dlam = 8.34e-5 * std::sin(nu);
      lambda = L + kPi + dlam;
      eps = 4.089567e-1 - 6.19e-9 * te + 4.46e-5 * std::cos(nu);
    }
    const double sl = std::sin(lambda), cl = std::cos(lambda);
    const double se = std::sin(eps), ce = std::sqrt(1.0 - se * se);
    alpha = std::atan2(sl * ce, cl);
    if (alpha < 0) alpha += 2.0 * kPi;
    delta = std::asin(sl * se);
    H = 1.7528311 + 6.300388099 * t + lon - alpha + 0.92 * dlam;
  }
  H = std::remainder(H, 2.0 * kPi);  // -pi..pi

  const double sp = std::sin(latitude_deg * kDeg), cp = std::cos(latitude_deg * kDeg);
  const double sd = std::sin(delta), cd = std::cos(delta);
  const double sH = std::sin(H), cH = std::cos(H);
  double se0 = sp * sd + cp * cd * cH;
  se0 = std::fmax(-1.0, std::fmin(1.0, se0));
  const double ep = std::asin(se0) - 4.26e-5 * std::sqrt(1.0 - se0 * se0);  // parallax
  // Azimuth from south towards west (Grena), turned to north-based: +pi.
  double az = std::atan2(sH, cH * sp - sd * cp / cd) + kPi;
  if (az >= 2.0 * kPi) az -= 2.0 * kPi;
  GrenaResult r;
  r.zenith_deg = 90.0 - ep * kRad;
  r.azimuth_deg = az * kRad;
  r.declination_deg = delta * kRad;
  r.hour_angle_deg = H * kRad;
  r.right_ascension_deg = alpha * kRad;
  return r;
}

}  // namespace atmosh::atmo
