#include "atmosh/atmo/chapman.hpp"

#include <cmath>
#include <string>

#include "integrate.hpp"
#include "atmosh/error.hpp"

namespace atmosh::atmo {

namespace {
constexpr double kPi = 3.14159265358979323846;

void check(double x, double mu) {
  if (!std::isfinite(x) || x <= 0.0) throw InputError("chapman: x = " + std::to_string(x) + ": must be > 0");
  if (!std::isfinite(mu) || mu < -1.0 || mu > 1.0)
    throw InputError("chapman: mu = " + std::to_string(mu) + ": must be in [-1, 1]");
}

double sin_from_cos(double mu) { return std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu))); }

// exp(y^2) with y^2 = hi + lo exactly (Dekker split), so that large y keep their
// relative accuracy.
double exp_y2(double y) {
  double hi = y * y;
  double lo = std::fma(y, y, -hi);
  return std::exp(hi) * (1.0 + lo);
}

double erfcx_pos(double y) {  // y >= 0
  if (y < 26.0) return exp_y2(y) * std::erfc(y);
  // Asymptotic series: erfcx(y) = 1/(y sqrt(pi)) sum_k (-1)^k (2k-1)!! / (2 y^2)^k.
  double z = 1.0 / (2.0 * y * y), term = 1.0, sum = 1.0;
  for (int k = 1; k < 30; ++k) {
    term *= -(2.0 * k - 1.0) * z;
    sum += term;
    if (std::abs(term) < 1e-17) break;
  }
  return sum / (y * std::sqrt(kPi));
}

// Ch(x, mu) for mu >= 0 by the Huestis integral.
double chapman_up_exact(double x, double mu) {
  if (mu >= 1.0) return 1.0;
  double s = sin_from_cos(mu);
  double chi = std::atan2(s, mu);
  auto f = [&](double l) {
    double sl = std::sin(l);
    if (!(sl > 0.0)) return 0.0;
    return std::exp(x * (1.0 - s / sl)) / (1.0 + std::cos(l));
  };
  // The integrand is concentrated within ~ tan(chi)/x .. sqrt(2/x) below chi.
  std::vector<double> pts;
  double w = std::max(1e-12, std::min(std::sqrt(2.0 / x), std::tan(chi) / x + 1e-12));
  for (double k : {1.0, 2.0, 4.0, 8.0, 16.0, 32.0})
    if (chi - k * w > 0.0) pts.push_back(chi - k * w);
  auto r = integrate_adaptive<double>(f, 0.0, chi, pts, 1e-300, 1e-14, 2000);
  return 1.0 + x * s * r.value;
}
}  // namespace

double erfcx(double y) {
  if (std::isnan(y)) throw InputError("erfcx: argument is NaN");
  if (y >= 0.0) return erfcx_pos(y);
  return 2.0 * exp_y2(y) - erfcx_pos(-y);
}

double chapman_horizontal_exact(double x) {
  check(x, 0.0);
  if (x < 50.0) return x * std::exp(x) * std::cyl_bessel_k(1.0, x);
  // e^x K_1(x) ~ sqrt(pi/(2x)) sum_k prod_{j<=k} (4 - (2j-1)^2) / (j 8x)  (A&S 9.7.2)
  double term = 1.0, sum = 1.0;
  for (int j = 1; j < 60; ++j) {
    double t = (4.0 - (2.0 * j - 1.0) * (2.0 * j - 1.0)) / (8.0 * j * x);
    term *= t;
    sum += term;
    if (std::abs(term) < 1e-17 * std::abs(sum)) break;
  }
  return std::sqrt(kPi * x / 2.0) * sum;
}

double chapman_horizontal_asymptotic(double x, int terms) {
  double term = 1.0, sum = 1.0;
  for (int j = 1; j < terms; ++j) {
    term *= (4.0 - (2.0 * j - 1.0) * (2.0 * j - 1.0)) / (8.0 * j * x);
    sum += term;
  }
  return std::sqrt(kPi * x / 2.0) * sum;
}

double chapman_exact(double x, double mu) {
  check(x, mu);
  if (mu >= 0.0) return chapman_up_exact(x, mu);
  double s = sin_from_cos(mu);
  // 1 - sin chi = (1 - sin^2 chi) / (1 + sin chi) = mu^2 / (1 + s), no cancellation.
  double e = std::exp(x * mu * mu / (1.0 + s));
  return 2.0 * e * chapman_horizontal_exact(x * s) - chapman_up_exact(x, -mu);
}

double chapman_erfcx(double x, double mu) {
  check(x, mu);
  auto up = [](double x, double mu) {
    double s = sin_from_cos(mu);
    double a = std::sqrt(x / 2.0);
    if (mu * a > 1e3 * s) {  // erfcx asymptotic in z = s / (mu a): Ch = (1/mu)(1 - z^2/2 + 3 z^4/4 - ...)
      double z2 = (s / (mu * a)) * (s / (mu * a));
      return (1.0 - 0.5 * z2 + 0.75 * z2 * z2) / mu;
    }
    return std::sqrt(kPi) * a / s * erfcx(mu * a / s);
  };
  if (mu >= 0.0) return up(x, mu);
  double s = sin_from_cos(mu);
  double e = std::exp(x * mu * mu / (1.0 + s));
  return 2.0 * e * std::sqrt(kPi * x * s / 2.0) - up(x, -mu);
}

}  // namespace atmosh::atmo
