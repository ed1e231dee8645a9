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

// sin and cos for algorithm 5: reduction to [-pi/2, pi/2] (x - 2 pi round(x / 2 pi),
// exact to ~1e-16 |x|; |x| < 4000 here) and the degree-13 Taylor
// polynomial, absolute error < 7e-10 (the first omitted term, (pi/2)^15 / 15!).
// Summed over the ~15 sines and cosines of one evaluation this is < 1e-8 rad
// (6e-7 degrees), far below the algorithm's own 0.0027 degrees; inlined, each costs a
// few ns against ~15 ns for a libm call, which is what makes the fast path fast.
inline double fast_sin(double x) {
  constexpr double kTwoPi = 2.0 * kPi, kInvTwoPi = 1.0 / kTwoPi;
  constexpr double kRound = 6755399441055744.0;             // 1.5 * 2^52: adding it rounds to an integer
  const double n = (x * kInvTwoPi + kRound) - kRound;        // nearest integer to x / 2 pi (|x| < 2^50)
  double r = x - kTwoPi * n;                                 // [-pi, pi]
  const double folded = std::copysign(kPi, r) - r;           // sin(pi - r) = sin r
  r = std::fabs(r) > 0.5 * kPi ? folded : r;                 // [-pi/2, pi/2]
  const double r2 = r * r;
  return r * (1.0 + r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880 +
                 r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800.0)))))));
}
// out[i] = fast_sin(x[i]) in one loop the compiler vectorises (independent sines overlap).
template <int N>
inline void fast_sines(const double (&x)[N], double (&out)[N]) {
  for (int i = 0; i < N; ++i) out[i] = fast_sin(x[i]);
}
inline double fast_cos(double x) { return fast_sin(x + 0.5 * kPi); }
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
  double alpha, delta, H, sd, cd;  // sd, cd: sine and cosine of the declination
  double sp = 0, cp = 0;           // of the latitude (algorithm 5 computes them in its batch)

  if (variant == 1) {
    const double w = 0.017202786 * te;
    const double s1 = std::sin(w), c1 = std::cos(w);
    const double s2 = 2.0 * s1 * c1, c2 = (c1 + s1) * (c1 - s1);
    alpha = -1.38880 + 1.72027920e-2 * te + 3.199e-2 * s1 - 2.65e-3 * c1 + 4.050e-2 * s2 + 1.525e-2 * c2;
    alpha = std::fmod(alpha, 2.0 * kPi);
    if (alpha < 0) alpha += 2.0 * kPi;
    delta = 6.57e-3 + 7.347e-2 * s1 - 3.9919e-1 * c1 + 7.3e-4 * s2 - 6.60e-3 * c2;
    sd = std::sin(delta);
    cd = std::cos(delta);
    H = 1.75283 + 6.3003881 * t + lon - alpha;
  } else {
    const double w = 0.0172019715 * te;
    double lambda, eps, dlam = 0.0;
    if (variant == 3) {
      lambda = -1.388803 + 1.720279216e-2 * te + 3.3366e-2 * std::sin(w - 0.06172) + 3.53e-4 * std::sin(2.0 * w - 0.1163);
      eps = 4.089567e-1 - 6.19e-9 * te;
    } else {
      // All sines that depend on the time only, and the latitude's, in one batch.
      constexpr double h = 0.5 * kPi;
      const double nu = 9.282e-4 * te - 0.8, phi = latitude_deg * kDeg;
      const double arg[14] = {w, w + h, 2.92e-5 * te, 1.49e-3 * te - 2.337, 4.31e-3 * te + 3.065,
                              1.076e-2 * te - 1.533, 1.575e-2 * te - 2.358, 2.152e-2 * te + 0.074,
                              3.152e-2 * te + 1.547, 2.1277e-1 * te - 0.488, nu, nu + h, phi, phi + h};
      double sn[14];
      fast_sines(arg, sn);
      const double s1 = sn[0], c1 = sn[1];
      const double s2 = 2.0 * s1 * c1, c2 = (c1 + s1) * (c1 - s1);
      const double s3 = s2 * c1 + c2 * s1, c3 = c2 * c1 - s2 * s1;
      const double L = 1.7527901 + 1.7202792159e-2 * te + 3.33024e-2 * s1 - 2.0582e-3 * c1 + 3.512e-4 * s2 -
                       4.07e-5 * c2 + 5.2e-6 * s3 - 9e-7 * c3 - 8.23e-5 * s1 * sn[2] + 1.27e-5 * sn[3] +
                       1.21e-5 * sn[4] + 2.33e-5 * sn[5] + 3.49e-5 * sn[6] + 2.67e-5 * sn[7] + 1.28e-5 * sn[8] +
                       3.14e-5 * sn[9];
      dlam = 8.34e-5 * sn[10];
      lambda = L + kPi + dlam;
      eps = 4.089567e-1 - 6.19e-9 * te + 4.46e-5 * sn[11];
      sp = sn[12];
      cp = sn[13];
    }
    const bool fast = variant == 5;  // algorithm 3 keeps libm
    double sl, cl, se;
    if (fast) {
      const double arg[4] = {lambda, lambda + 0.5 * kPi, eps, 0.0};
      double sn[4];
      fast_sines(arg, sn);
      sl = sn[0], cl = sn[1], se = sn[2];
    } else {
      sl = std::sin(lambda), cl = std::cos(lambda), se = std::sin(eps);
    }
    const double ce = std::sqrt(1.0 - se * se);
    alpha = std::atan2(sl * ce, cl);
    if (alpha < 0) alpha += 2.0 * kPi;
    sd = sl * se;
    cd = std::sqrt(1.0 - sd * sd);  // |delta| < 24 degrees: cos > 0
    delta = std::asin(sd);
    H = 1.7528311 + 6.300388099 * t + lon - alpha + 0.92 * dlam;
  }
  H = std::remainder(H, 2.0 * kPi);  // -pi..pi

  const bool fast = variant == 5;
  if (!fast) sp = std::sin(latitude_deg * kDeg), cp = std::cos(latitude_deg * kDeg);
  const double sH = fast ? fast_sin(H) : std::sin(H), cH = fast ? fast_cos(H) : std::cos(H);
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
