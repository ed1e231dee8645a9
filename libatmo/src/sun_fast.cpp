// sun_fast.cpp — Grena (2012) algorithms 1, 3 and 5; see sun_fast.hpp.
#include "atmosh/atmo/sun_fast.hpp"

#include <cmath>
#include <string>

#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = 180.0 / kPi;
constexpr double kDeg = kPi / 180.0;
// Grena's time origin: t = 0 at 2060-01-01T00:00 UT = JD 2473459.5.
constexpr double kGrenaEpochJd = 2473459.5;

// sin and cos for algorithm 5: reduction to [-pi/2, pi/2] (x - 2 pi round(x / 2 pi),
// exact to ~1e-16 |x|; |x| < 2e5 here) and the degree-15 Taylor
// polynomial, absolute error < 6e-12 (the first omitted term, (pi/2)^17 / 17!).
// Summed over the 20 sines and cosines of one evaluation this is < 1.2e-10 rad
// (7e-9 degrees), far below the algorithm's own 0.0027 degrees; inlined, each costs a
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
                 r2 * (-1.0 / 39916800 + r2 * (1.0 / 6227020800.0 + r2 * (-1.0 / 1307674368000.0))))))));
}
// out[i] = fast_sin(x[i]) in one loop the compiler vectorises (independent sines overlap).
template <int N>
inline void fast_sines(const double (&x)[N], double (&out)[N]) {
  for (int i = 0; i < N; ++i) out[i] = fast_sin(x[i]);
}

// atan2(y, x) for algorithm 5, inlined: |y|/|x| or its inverse in [0, 1], reduced to
// |t| <= tan(pi/8) by atan a = pi/4 + atan((a - 1)/(a + 1)), then t P(t^2) with P the
// degree-7 polynomial interpolating atan(t)/t at the Chebyshev nodes of t^2 in
// [0, tan^2(pi/8)] (coefficients fitted in 40-digit arithmetic): absolute error
// < 3e-13 rad on that interval, < 1e-12 rad after the reduction. atan2(0, 0) = 0; the
// sign of a zero y is kept as libm does. (tests/sun compares the whole algorithm with
// a libm evaluation of the printed formulas.)
inline double fast_atan2(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;  // (not fmax / fmin: they are calls)
  constexpr double kTanPi8 = 0.41421356237309504880;
  const bool big = lo > kTanPi8 * hi;                        // lo / hi > tan(pi/8)
  // Both quotients, side by side (not one after the other), so the loop vectorises:
  // a = lo / hi and (a - 1) / (a + 1) = (lo - hi) / (lo + hi).
  const double a = lo / (hi > 0.0 ? hi : 1.0);               // [0, 1]
  const double q = (lo - hi) / (lo + hi > 0.0 ? lo + hi : 1.0);
  const double t = big ? q : a;                              // |t| <= tan(pi/8)
  const double u = t * t;
  const double p = 0.99999999999924472 +
                   u * (-0.33333333276922494 +
                        u * (0.19999993053555815 +
                             u * (-0.14285386553752139 +
                                  u * (0.11103456908947464 +
                                       u * (-0.089925529061509121 +
                                            u * (0.069741976865952654 + u * -0.037655106012914018))))));
  double r = (big ? 0.25 * kPi : 0.0) + t * p;               // atan(lo / hi) in [0, pi/4]
  r = ay > ax ? 0.5 * kPi - r : r;                           // [0, pi/2]
  r = x < 0.0 ? kPi - r : r;                                 // [0, pi]
  return std::copysign(r, y);
}
// out[i] = fast_atan2(y[i], x[i]), vectorised like fast_sines.
template <int N>
inline void fast_atan2s(const double (&y)[N], const double (&x)[N], double (&out)[N]) {
  for (int i = 0; i < N; ++i) out[i] = fast_atan2(y[i], x[i]);
}

// Algorithm 5 after the checks: every sine and arctangent inlined (fast_sin,
// fast_atan2) in two batches — the sines of arguments that depend on time and
// place only, and the five arctangents of the outputs. In between, only short
// polynomials:
//  * the ecliptic longitude lambda = lambda0 + delta, with lambda0 the part linear
//    in time (first batch) and |delta| < 0.037 rad the periodic terms: sin and cos
//    of delta by Taylor to delta^7 (omitted < 1e-18);
//  * the obliquity eps = eps0 + eta with |eta| <= 4.46e-5: to second order in eta
//    (omitted < 2e-14);
//  * the right ascension alpha enters the hour angle H = H0 - alpha only through
//    sin H and cos H, which come from the angle-difference formulas
//    (sin alpha = sin(lambda) cos(eps) / cos(delta), cos alpha = cos(lambda) / cos(delta))
//    and sin H0, cos H0 of the first batch.
// No libm call on the way to the zenith and azimuth. Compiled for AVX2/FMA as well
// (atmosh/dispatch.hpp).
ATMOSH_DISPATCH GrenaResult grena5(double t, double te, double lon, double latitude_deg) {
  constexpr double h = 0.5 * kPi;
  const double w = 0.0172019715 * te;
  const double nu = 9.282e-4 * te - 0.8, phi = latitude_deg * kDeg;
  // Hour angle without the right ascension and the nutation term 0.92 dlam (added below).
  const double H0 = 1.7528311 + 6.300388099 * t + lon;
  const double lambda0 = 1.7527901 + 1.7202792159e-2 * te + kPi;
  const double eps0 = 4.089567e-1 - 6.19e-9 * te;
  const double arg[20] = {w, w + h, 2.92e-5 * te, 1.49e-3 * te - 2.337, 4.31e-3 * te + 3.065,
                          1.076e-2 * te - 1.533, 1.575e-2 * te - 2.358, 2.152e-2 * te + 0.074,
                          3.152e-2 * te + 1.547, 2.1277e-1 * te - 0.488, nu, nu + h, phi, phi + h, H0, H0 + h,
                          lambda0, lambda0 + h, eps0, eps0 + h};
  double sn[20];
  fast_sines(arg, sn);
  const double s1 = sn[0], c1 = sn[1];
  const double s2 = 2.0 * s1 * c1, c2 = (c1 + s1) * (c1 - s1);
  const double s3 = s2 * c1 + c2 * s1, c3 = c2 * c1 - s2 * s1;
  const double dlam = 8.34e-5 * sn[10];
  // lambda - lambda0: Grena's periodic terms of L, and the nutation in longitude.
  // (summed as four independent partial sums: a shorter chain of dependent adds)
  const double dl = ((3.33024e-2 * s1 - 2.0582e-3 * c1 + 3.512e-4 * s2 - 4.07e-5 * c2) +
                     (5.2e-6 * s3 - 9e-7 * c3 - 8.23e-5 * s1 * sn[2] + 1.27e-5 * sn[3])) +
                    ((1.21e-5 * sn[4] + 2.33e-5 * sn[5] + 3.49e-5 * sn[6] + 2.67e-5 * sn[7]) +
                     (1.28e-5 * sn[8] + 3.14e-5 * sn[9] + dlam));
  const double eta = 4.46e-5 * sn[11];  // eps - eps0
  const double sp = sn[12], cp = sn[13];
  // H0 + 0.92 dlam: |0.92 dlam| < 7.7e-5 rad, so cos = 1 - e^2/2 and sin = e leave < 1e-13.
  const double e = 0.92 * dlam, ce2 = 1.0 - 0.5 * e * e;
  const double sH0 = sn[14] * ce2 + sn[15] * e, cH0 = sn[15] * ce2 - sn[14] * e;
  const double d2 = dl * dl;
  const double sdl = dl * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0))));
  const double cdl =
      1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))));
  const double sl = sn[16] * cdl + sn[17] * sdl, cl = sn[17] * cdl - sn[16] * sdl;
  const double ceta = 1.0 - 0.5 * eta * eta;
  const double se = sn[18] * ceta + sn[19] * eta, ce = sn[19] * ceta - sn[18] * eta;
  const double sd = sl * se;                     // sin delta
  const double cd = std::sqrt(1.0 - sd * sd);    // cos delta = |(cos lambda, sin lambda cos eps)| > 0.9
  const double ya = sl * ce, xa = cl;            // alpha = atan2(ya, xa); cos delta sin/cos alpha
  const double icd = 1.0 / cd;
  const double sa = ya * icd, ca = xa * icd;
  const double sH = sH0 * ca - cH0 * sa, cH = cH0 * ca + sH0 * sa;
  double se0 = sp * sd + cp * cd * cH;           // sine of the geocentric elevation
  se0 = se0 > 1.0 ? 1.0 : (se0 < -1.0 ? -1.0 : se0);
  const double ce0 = std::sqrt(1.0 - se0 * se0);
  // Azimuth from south towards west (Grena), turned to north-based below: +pi.
  const double yv[8] = {se0, sH, sd, ya, sH, 0.0, 0.0, 0.0};  // padded to two AVX2 vectors
  const double xv[8] = {ce0, cH * sp - sd * cp * icd, cd, xa, cH, 1.0, 1.0, 1.0};
  double at[8];
  fast_atan2s(yv, xv, at);
  const double ep = at[0] - 4.26e-5 * ce0;       // parallax
  double az = at[1] + kPi;
  if (az >= 2.0 * kPi) az -= 2.0 * kPi;
  double alpha = at[3];
  if (alpha < 0) alpha += 2.0 * kPi;
  GrenaResult r;
  r.zenith_deg = 90.0 - ep * kRad;
  r.azimuth_deg = az * kRad;
  r.declination_deg = at[2] * kRad;
  r.hour_angle_deg = at[4] * kRad;
  r.right_ascension_deg = alpha * kRad;
  return r;
}
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
  if (variant == 5) return grena5(t, te, lon, latitude_deg);

  double alpha, delta, H, sd, cd;  // sd, cd: sine and cosine of the declination
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
  } else {  // algorithm 3
    const double w = 0.0172019715 * te;
    const double lambda =
        -1.388803 + 1.720279216e-2 * te + 3.3366e-2 * std::sin(w - 0.06172) + 3.53e-4 * std::sin(2.0 * w - 0.1163);
    const double eps = 4.089567e-1 - 6.19e-9 * te;
    const double sl = std::sin(lambda), cl = std::cos(lambda), se = std::sin(eps);
    const double ce = std::sqrt(1.0 - se * se);
    alpha = std::atan2(sl * ce, cl);
    if (alpha < 0) alpha += 2.0 * kPi;
    sd = sl * se;
    cd = std::sqrt(1.0 - sd * sd);  // |delta| < 24 degrees: cos > 0
    delta = std::asin(sd);
    H = 1.7528311 + 6.300388099 * t + lon - alpha;
  }
  H = std::remainder(H, 2.0 * kPi);  // -pi..pi
  const double sp = std::sin(latitude_deg * kDeg), cp = std::cos(latitude_deg * kDeg);
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
