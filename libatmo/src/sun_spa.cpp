// sun_spa.cpp — NREL SPA (Reda & Andreas 2008); equation numbers refer to that report.
#include "atmosh/atmo/sun_spa.hpp"

#include <array>
#include <cmath>
#include <string>

#include "atmosh/atmo/sun_refraction.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"
#include "sun_spa_impl.hpp"
#include "sun_spa_tables.hpp"

// The loops over the periodic terms are built twice, for the x86-64 baseline
// (SSE2: 2 doubles per vector) and for AVX2 (4 doubles per vector), and the
// loader picks one for the running CPU (function multiversioning, an ifunc).
// Neither version uses fused multiply-add, so both round every operation as the
// scalar code does and give bit-identical results on every x86-64 CPU.

namespace atmosh::atmo {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kRad = 180.0 / kPi;

// x reduced to [0, 360). The same value as fmod(x, 360) (+360 when negative),
// without the library call: for |x| < 2^44 both x − 360·q and 360·q are exact,
// and a quotient x/360 rounded up to the next integer is stepped back.
double limit360(double x) {
  const double q = std::trunc(x / 360.0);
  double r = x - q * 360.0;
  if (x >= 0.0 ? r < 0.0 : r > 0.0) r = x - (q - std::copysign(1.0, x)) * 360.0;
  return r < 0.0 ? r + 360.0 : r;
}
double limit180pm(double x) {
  x = limit360(x);
  return x > 180.0 ? x - 360.0 : x;
}
double limit01(double x) { return x - std::floor(x); }

// All Earth periodic terms in structure-of-arrays form, one contiguous run per
// series (L0..L5, B0..B1, R0..R4), built at compile time. The run is padded with
// zero terms to a multiple of 8 so that the sum loop has a fixed trip count and
// no remainder; the padding lies after the last series and is never summed.
struct EarthTerms {
  static constexpr int kSeries = 13;
  static constexpr int kCount = 195;
  static constexpr int kPadded = (kCount + 7) / 8 * 8;
  alignas(64) double a[kPadded]{}, b[kPadded]{}, c[kPadded]{};
  int start[kSeries + 1]{};
};
consteval EarthTerms make_earth_terms() {
  using namespace spa_tables;
  EarthTerms t;
  int n = 0, s = 0;
  auto add = [&](const auto& terms) {
    t.start[s++] = n;
    for (const Term& x : terms) {
      t.a[n] = x.a;
      t.b[n] = x.b;
      t.c[n] = x.c;
      ++n;
    }
    t.start[s] = n;
  };
  add(kL0); add(kL1); add(kL2); add(kL3); add(kL4); add(kL5);
  add(kB0); add(kB1);
  add(kR0); add(kR1); add(kR2); add(kR3); add(kR4);
  if (n != EarthTerms::kCount || s != EarthTerms::kSeries) throw "Earth periodic term count mismatch";
  return t;
}
constexpr EarthTerms kEarth = make_earth_terms();

// The nutation terms (Table A4.3) in structure-of-arrays form, padded with zero
// terms to a multiple of 8. y[j][i] = 6·j + k + 2 indexes the power
// exp(i·k·X_j), k = -2..3, of the term's multiplier k of X_j.
struct NutationTerms {
  static constexpr int kCount = 63;
  static constexpr int kPadded = (kCount + 7) / 8 * 8;
  alignas(64) int y[5][kPadded]{};
  alignas(64) double a[kPadded]{}, b[kPadded]{}, c[kPadded]{}, d[kPadded]{};
};
consteval NutationTerms make_nutation_terms() {
  NutationTerms t;
  int n = 0;
  for (const auto& x : spa_tables::kNutation) {
    for (int j = 0; j < 5; ++j) t.y[j][n] = 6 * j + x.y[j] + 2;
    t.a[n] = x.a;
    t.b[n] = x.b;
    t.c[n] = x.c;
    t.d[n] = x.d;
    ++n;
  }
  for (int i = n; i < NutationTerms::kPadded; ++i)
    for (int j = 0; j < 5; ++j) t.y[j][i] = 6 * j + 2;  // exp(0) = 1, zero coefficients
  if (n != NutationTerms::kCount) throw "nutation term count mismatch";
  return t;
}
constexpr NutationTerms kNut = make_nutation_terms();

void check_finite(double v, const char* what) {
  if (!std::isfinite(v)) throw InputError(std::string(what) + " is not finite");
}

// (-1)^n/(2n)!, n = 0..15, evaluated exactly in long double at compile time.
constexpr std::array<double, 16> kCosCoef = [] {
  std::array<double, 16> c{};
  long double f = 1.0L;
  for (int n = 0; n < 16; ++n) {
    if (n > 0) f *= static_cast<long double>((2 * n - 1) * (2 * n));
    c[n] = static_cast<double>(((n % 2) ? -1.0L : 1.0L) / f);
  }
  return c;
}();

// Branch-free, call-free cosine, so that loops over it vectorise. Cody–Waite
// reduction to r in [-pi, pi] with a three-part 2*pi (the first part has 8
// significant bits, so k*kC1 is exact for |k| < 2^45), then the Taylor series of
// cos to r^30 (truncation < 3e-18 at |r| = pi).
[[gnu::always_inline]] inline double cos_poly(double x) {
  constexpr double kInv2Pi = 0.15915494309189533577;
  constexpr double kC1 = 6.28125;
  constexpr double kC2 = 0.001935307179586477;
  constexpr double kC3 = -1.0033115225336665e-19;  // 2*pi - kC1 - kC2
  constexpr double kRound = 6755399441055744.0;    // 1.5 * 2^52: round to nearest integer
  const double k = (x * kInv2Pi + kRound) - kRound;
  const double r = ((x - k * kC1) - k * kC2) - k * kC3;
  const double z = r * r;
  double q = kCosCoef[15];
#pragma GCC unroll 16
  for (int n = 14; n >= 0; --n) q = q * z + kCosCoef[n];
  return q;
}

// Both loops over the periodic terms for one instant (τ = JME, T = JCE):
//  v[i]   = A·cos(B + C·τ) for every Earth periodic term, in table order (eq. 9);
//  psi[i] = (a + b·T)·sin(ΣX·Y), eps[i] = (c + d·T)·cos(ΣX·Y) per nutation term
//           (eqs. 21–23). re/im[6·j + k] hold exp(i·(k-2)·X_j); the argument's
//           sine and cosine are the imaginary and real parts of the product over
//           j of those powers.
// Both loops vectorise (GCC 12, -O3 -fopt-info-vec: 16-byte vectors in the
// baseline version, 32-byte in the AVX2 one).
struct TermOutputs {
  alignas(64) double v[EarthTerms::kPadded];
  alignas(64) double psi[NutationTerms::kPadded];
  alignas(64) double eps[NutationTerms::kPadded];
};
ATMOSH_DISPATCH_NO_FMA void periodic_terms(double tau, double T, const double* __restrict re,
                                      const double* __restrict im, TermOutputs& o) {
  for (int i = 0; i < EarthTerms::kPadded; ++i) o.v[i] = kEarth.a[i] * cos_poly(kEarth.b[i] + kEarth.c[i] * tau);
  for (int i = 0; i < NutationTerms::kPadded; ++i) {
    double zr = re[kNut.y[0][i]], zi = im[kNut.y[0][i]];
#pragma GCC unroll 4
    for (int j = 1; j < 5; ++j) {
      const double wr = re[kNut.y[j][i]], wi = im[kNut.y[j][i]];
      const double tr = zr * wr - zi * wi;
      zi = zr * wi + zi * wr;
      zr = tr;
    }
    o.psi[i] = (kNut.a[i] + kNut.b[i] * T) * zi;
    o.eps[i] = (kNut.c[i] + kNut.d[i] * T) * zr;
  }
}
}  // namespace

namespace detail {
double spa_cos(double x) { return cos_poly(x); }
}  // namespace detail

SpaGeocentric spa_geocentric(double jd, double delta_t_s) {
  SpaGeocentric g;
  g.jd = jd;                                   // eq. 4 (computed by the caller)
  g.jde = jd + delta_t_s / 86400.0;            // eq. 5
  g.jc = (jd - 2451545.0) / 36525.0;           // eq. 6
  g.jce = (g.jde - 2451545.0) / 36525.0;       // eq. 7
  g.jme = g.jce / 10.0;                        // eq. 8
  const double tau = g.jme;

  const double T = g.jce;  // eqs. 16–20
  g.x_deg[0] = 297.85036 + T * (445267.111480 + T * (-0.0019142 + T / 189474.0));
  g.x_deg[1] = 357.52772 + T * (35999.050340 + T * (-0.0001603 - T / 300000.0));
  g.x_deg[2] = 134.96298 + T * (477198.867398 + T * (0.0086972 + T / 56250.0));
  g.x_deg[3] = 93.27191 + T * (483202.017538 + T * (-0.0036825 + T / 327270.0));
  g.x_deg[4] = 125.04452 + T * (-1934.136261 + T * (0.0020708 + T / 450000.0));

  // eqs. 21–23. Each argument Σ X_j·Y_ij is an integer combination of the five
  // X_j, so its sine and cosine are products of the unit complex numbers
  // exp(i·k·X_j), k = -2..3, computed once: exact to rounding, no trig per term.
  double re[5][6], im[5][6];
  double arg[10], cs[10];  // cos X_j and sin X_j = cos(X_j - pi/2): one call-free loop
  for (int j = 0; j < 5; ++j) {
    arg[j] = limit360(g.x_deg[j]) * kDeg;
    arg[5 + j] = arg[j] - 0.5 * kPi;
  }
  for (int i = 0; i < 10; ++i) cs[i] = cos_poly(arg[i]);
  for (int j = 0; j < 5; ++j) {
    const double c1 = cs[j], s1 = cs[5 + j];
    const double c2 = c1 * c1 - s1 * s1, s2 = c1 * s1 + s1 * c1;  // exp(2i·X)
    re[j][2] = 1.0;  // k = 0
    im[j][2] = 0.0;
    re[j][3] = c1;   // k = 1
    im[j][3] = s1;
    re[j][4] = c2;   // k = 2
    im[j][4] = s2;
    re[j][5] = c2 * c1 - s2 * s1;  // k = 3
    im[j][5] = c2 * s1 + s2 * c1;
    re[j][1] = c1;  // k = -1
    im[j][1] = -s1;
    re[j][0] = c2;  // k = -2
    im[j][0] = -s2;
  }

  TermOutputs t;
  periodic_terms(tau, T, &re[0][0], &im[0][0], t);

  double s[EarthTerms::kSeries];  // the 13 series sums L0..L5, B0..B1, R0..R4
  for (int k = 0; k < EarthTerms::kSeries; ++k) {
    double sum = 0.0;
    for (int i = kEarth.start[k]; i < kEarth.start[k + 1]; ++i) sum += t.v[i];
    s[k] = sum;
  }
  auto poly = [tau](const double* c, int n) {  // eq. 10: (X0 + X1 τ + X2 τ² + ...)/1e8
    double r = 0.0;
    for (int i = n - 1; i >= 0; --i) r = r * tau + c[i];
    return r / 1e8;
  };
  g.l_deg = limit360(poly(s + 0, 6) * kRad);   // eqs. 9–11
  g.b_deg = poly(s + 6, 2) * kRad;             // eq. 12
  g.r_au = poly(s + 8, 5);                     // eq. 13
  g.theta_deg = limit360(g.l_deg + 180.0);     // eq. 14
  g.beta_deg = -g.b_deg;                       // eq. 15

  double sum_psi = 0.0, sum_eps = 0.0;
  for (int i = 0; i < NutationTerms::kCount; ++i) {
    sum_psi += t.psi[i];
    sum_eps += t.eps[i];
  }
  g.delta_psi_deg = sum_psi / 36000000.0;
  g.delta_epsilon_deg = sum_eps / 36000000.0;

  const double U = g.jme / 10.0;  // eq. 24
  g.epsilon0_arcsec =
      84381.448 +
      U * (-4680.93 + U * (-1.55 + U * (1999.25 + U * (-51.38 + U * (-249.67 + U * (-39.05 + U * (7.12 + U * (27.87 + U * (5.79 + U * 2.45)))))))));
  g.epsilon_deg = g.epsilon0_arcsec / 3600.0 + g.delta_epsilon_deg;  // eq. 25
  g.delta_tau_deg = -20.4898 / (3600.0 * g.r_au);                   // eq. 26
  g.lambda_deg = g.theta_deg + g.delta_psi_deg + g.delta_tau_deg;   // eq. 27
  g.nu0_deg = limit360(280.46061837 + 360.98564736629 * (jd - 2451545.0) +
                       g.jc * g.jc * (0.000387933 - g.jc / 38710000.0));  // eq. 28
  g.nu_deg = g.nu0_deg + g.delta_psi_deg * std::cos(g.epsilon_deg * kDeg);  // eq. 29

  const double lam = g.lambda_deg * kDeg, eps = g.epsilon_deg * kDeg, beta = g.beta_deg * kDeg;
  g.alpha_deg = limit360(std::atan2(std::sin(lam) * std::cos(eps) - std::tan(beta) * std::sin(eps), std::cos(lam)) *
                         kRad);  // eq. 30
  g.delta_deg = std::asin(std::sin(beta) * std::cos(eps) + std::cos(beta) * std::sin(eps) * std::sin(lam)) *
                kRad;  // eq. 31
  return g;
}

SpaResult spa_compute(const SpaInput& in) {
  check_finite(in.jd_utc, "time");
  check_finite(in.delta_ut1_s, "UT1-UTC");
  check_finite(in.delta_t_s, "delta T");
  check_finite(in.latitude_deg, "latitude");
  check_finite(in.longitude_deg, "longitude");
  check_finite(in.elevation_m, "height");
  check_finite(in.pressure_hpa, "pressure");
  check_finite(in.temperature_c, "temperature");
  if (std::fabs(in.latitude_deg) > 90.0)
    throw InputError("latitude " + std::to_string(in.latitude_deg) + " deg is outside -90..90");
  if (std::fabs(in.longitude_deg) > 180.0)
    throw InputError("longitude " + std::to_string(in.longitude_deg) + " deg is outside -180..180");
  if (std::fabs(in.delta_t_s) > 8000.0 * 3600.0)
    throw InputError("delta T " + std::to_string(in.delta_t_s) + " s is implausible");
  if (in.elevation_m < -6500000.0)
    throw InputError("height " + std::to_string(in.elevation_m) + " m is below the Earth's centre");
  if (in.pressure_hpa < 0.0 || in.pressure_hpa > 5000.0)
    throw InputError("pressure " + std::to_string(in.pressure_hpa) + " hPa is outside 0..5000");
  if (in.temperature_c <= -273.0 || in.temperature_c > 6000.0)
    throw InputError("temperature " + std::to_string(in.temperature_c) + " C is outside -273..6000");
  if (!sun_year_in_range(in.jd_utc)) require_sun_year_range(in.jd_utc, "time");

  SpaResult r;
  const double jd_ut1 = in.jd_utc + in.delta_ut1_s / 86400.0;  // eq. 4 uses UT = UTC + ΔUT1
  r.geo = spa_geocentric(jd_ut1, in.delta_t_s);
  const SpaGeocentric& g = r.geo;

  r.h_deg = limit360(g.nu_deg + in.longitude_deg - g.alpha_deg);  // eq. 32
  r.xi_deg = 8.794 / (3600.0 * g.r_au);                          // eq. 33
  const double phi = in.latitude_deg * kDeg;
  const double u = std::atan(0.99664719 * std::tan(phi));         // eq. 34
  const double x = std::cos(u) + in.elevation_m / 6378140.0 * std::cos(phi);            // eq. 35
  const double y = 0.99664719 * std::sin(u) + in.elevation_m / 6378140.0 * std::sin(phi);  // eq. 36
  const double xi = r.xi_deg * kDeg, H = r.h_deg * kDeg, delta = g.delta_deg * kDeg;
  const double den = std::cos(delta) - x * std::sin(xi) * std::cos(H);
  const double dalpha = std::atan2(-x * std::sin(xi) * std::sin(H), den);  // eq. 37
  r.delta_alpha_deg = dalpha * kRad;
  r.alpha_prime_deg = g.alpha_deg + r.delta_alpha_deg;                         // eq. 38
  const double dprime = std::atan2((std::sin(delta) - y * std::sin(xi)) * std::cos(dalpha), den);  // eq. 39
  r.delta_prime_deg = dprime * kRad;
  r.h_prime_deg = r.h_deg - r.delta_alpha_deg;  // eq. 40
  const double Hp = r.h_prime_deg * kDeg;
  double s = std::sin(phi) * std::sin(dprime) + std::cos(phi) * std::cos(dprime) * std::cos(Hp);
  s = std::fmax(-1.0, std::fmin(1.0, s));
  r.e0_deg = std::asin(s) * kRad;  // eq. 41
  r.delta_e_deg = refraction_deg(r.e0_deg, in.pressure_hpa, in.temperature_c);  // eq. 42 (continued)
  r.e_deg = r.e0_deg + r.delta_e_deg;  // eq. 43
  r.zenith_deg = 90.0 - r.e_deg;        // eq. 44
  r.azimuth_astro_deg =
      limit360(std::atan2(std::sin(Hp), std::cos(Hp) * std::sin(phi) - std::tan(dprime) * std::cos(phi)) * kRad);  // eq. 45
  r.azimuth_deg = limit360(r.azimuth_astro_deg + 180.0);  // eq. 46

  // Appendix A.1: equation of time.
  const double tau = g.jme;
  const double M = limit360(
      280.4664567 + tau * (360007.6982779 + tau * (0.03032028 + tau * (1.0 / 49931.0 + tau * (-1.0 / 15300.0 + tau * (-1.0 / 2000000.0))))));
  double E = 4.0 * (M - 0.0057183 - g.alpha_deg + g.delta_psi_deg * std::cos(g.epsilon_deg * kDeg));
  E = std::fmod(E, 1440.0);
  if (E > 20.0) E -= 1440.0;
  if (E < -20.0) E += 1440.0;
  r.eot_min = E;
  return r;
}

SpaRiseTransitSet spa_rise_transit_set(int year, int month, int day, double offset_hours, double latitude_deg,
                                       double longitude_deg, double delta_t_s, double delta_ut1_s) {
  SpaRiseTransitSet out;
  const double h0p = -0.8333;  // h0' (A.2 step 4)
  // 0 UT of the date; UT1 - UTC shifts the UT1 Julian day used for sidereal time.
  const double jd0 = julian_day(CalendarTime{year, month, day, 0, 0, 0.0});
  // Step 1: apparent sidereal time at Greenwich at 0 UT.
  const double nu = spa_geocentric(jd0 + delta_ut1_s / 86400.0, delta_t_s).nu_deg;
  // Step 2: α, δ at 0 TT of the day before, the day and the day after (ΔT = 0).
  double alpha[3], delta[3];
  for (int i = 0; i < 3; ++i) {
    const SpaGeocentric gi = spa_geocentric(jd0 + (i - 1), 0.0);
    alpha[i] = gi.alpha_deg;
    delta[i] = gi.delta_deg;
  }
  const double phi = latitude_deg * kDeg;
  // Step 3: approximate transit time (fraction of the UT day).
  double m0 = (alpha[1] - longitude_deg - nu) / 360.0;
  // Step 4: local hour angle of the sun at h0'.
  const double arg = (std::sin(h0p * kDeg) - std::sin(phi) * std::sin(delta[1] * kDeg)) /
                     (std::cos(phi) * std::cos(delta[1] * kDeg));
  auto interp = [](const double v[3], double n) {  // steps 8–9
    double a = v[1] - v[0], b = v[2] - v[1];
    if (std::fabs(a) >= 2.0) a = limit01(a);
    if (std::fabs(b) >= 2.0) b = limit01(b);
    const double c = b - a;
    return v[1] + n * (a + b + c * n) / 2.0;
  };
  auto to_local = [offset_hours](double frac_ut) { return limit01(frac_ut + offset_hours / 24.0); };

  const bool rises = std::isfinite(arg) && std::fabs(arg) <= 1.0;
  if (!rises) out.polar = (std::isfinite(arg) && arg < -1.0) ? +1 : -1;
  const double H0 = rises ? std::acos(arg) * kRad : 0.0;

  double m[3] = {limit01(m0), limit01(m0 - H0 / 360.0), limit01(m0 + H0 / 360.0)};  // step 5
  double hp[3], h[3], dp[3];
  for (int i = 0; i < 3; ++i) {
    const double nui = nu + 360.985647 * m[i];      // step 6
    const double n = m[i] + delta_t_s / 86400.0;   // step 7
    const double ap = interp(alpha, n);
    dp[i] = interp(delta, n);
    hp[i] = limit180pm(nui + longitude_deg - ap);  // step 10
    h[i] = std::asin(std::sin(phi) * std::sin(dp[i] * kDeg) +
                     std::cos(phi) * std::cos(dp[i] * kDeg) * std::cos(hp[i] * kDeg)) * kRad;  // step 11
  }
  out.transit_day_fraction = to_local(m[0] - hp[0] / 360.0);  // step 12
  if (rises) {
    auto corr = [&](int i) {  // steps 13–14
      return m[i] + (h[i] - h0p) / (360.0 * std::cos(dp[i] * kDeg) * std::cos(phi) * std::sin(hp[i] * kDeg));
    };
    out.rise_day_fraction = to_local(corr(1));
    out.set_day_fraction = to_local(corr(2));
  }
  return out;
}

}  // namespace atmosh::atmo
