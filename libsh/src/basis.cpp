// Real SH basis of any band: scaled column recurrences of Pbar_lm.
#include "atmosh/sh/basis.hpp"

#include <cmath>
#include <mutex>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "legendre_impl.hpp"

namespace atmosh::sh {

void check_bands(int bands, const char* where, int max_bands) {
  if (bands < 1 || bands > max_bands)
    throw InputError(std::string(where) + ": bands must be in [1, " + std::to_string(max_bands) +
                     "], got " + std::to_string(bands));
}

glm::dvec3 checked_direction(const glm::dvec3& d, const char* where) {
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
    throw InputError(std::string(where) + ": direction has a NaN or infinite component");
  const double n = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  if (!(n > 0.0) || !std::isfinite(n))
    throw InputError(std::string(where) + ": direction (0,0,0) has no length");
  return d / n;
}

LegendreTable::LegendreTable(int bands) : bands_(bands) {
  const std::size_t n = tri_index(bands, 0);
  a_.assign(n, 0.0);
  b_.assign(n, 0.0);
  s_.assign(bands + 1, 0.0);
  for (int m = 1; m <= bands; ++m) s_[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
  for (int l = 2; l < bands; ++l) {
    for (int m = 0; m <= l - 2; ++m) {
      const double ll = l, mm = m;
      const double den = ll * ll - mm * mm;
      a_[tri_index(l, m)] = std::sqrt((4.0 * ll * ll - 1.0) / den);
      b_[tri_index(l, m)] =
          std::sqrt((2.0 * ll + 1.0) * ((ll - 1.0) * (ll - 1.0) - mm * mm) / ((2.0 * ll - 3.0) * den));
    }
  }
}

std::shared_ptr<const LegendreTable> legendre_table(int bands) {
  static std::mutex mu;
  static std::shared_ptr<const LegendreTable> cached;
  std::lock_guard<std::mutex> lock(mu);
  if (!cached || cached->bands() < bands) cached = std::make_shared<const LegendreTable>(std::max(bands, 32));
  return cached;
}

void legendre_normalized(int bands, double cos_t, double sin_t, double* out) {
  check_bands(bands, "legendre_normalized");
  if (!std::isfinite(cos_t) || !std::isfinite(sin_t))
    throw InputError("legendre_normalized: cos/sin of the polar angle is not finite");
  const auto table = legendre_table(bands);
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  for (int m = 0; m < bands; ++m) {
    if (m > 0) pmm = detail::next_sectoral(pmm, table->sectoral()[m], sin_t);
    detail::legendre_column(bands, m, cos_t, pmm, table->a(), table->b(),
                            [&](int l, double v) { out[tri_index(l, m)] = v; });
  }
}

void legendre_column(int bands, int m, double cos_t, double sin_t, double* out) {
  check_bands(bands, "legendre_column");
  if (m < 0 || m >= bands) throw InputError("legendre_column: m = " + std::to_string(m) + " out of range");
  if (!std::isfinite(cos_t) || !std::isfinite(sin_t))
    throw InputError("legendre_column: cos/sin of the polar angle is not finite");
  const auto table = legendre_table(bands);
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  for (int k = 1; k <= m; ++k) pmm = detail::next_sectoral(pmm, table->sectoral()[k], sin_t);
  detail::legendre_column(bands, m, cos_t, pmm, table->a(), table->b(), [&](int l, double v) { out[l - m] = v; });
}

namespace {
void evaluate_unit(int bands, const glm::dvec3& d, double* out, const LegendreTable& table) {
  const double rho = std::sqrt(d.x * d.x + d.y * d.y);
  const double ct = d.z, st = rho;
  double c1 = 1.0, s1 = 0.0;  // cos p, sin p
  if (rho > 0.0) {
    c1 = d.x / rho;
    s1 = d.y / rho;
  }
  const double* a = table.a();
  const double* b = table.b();
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  detail::legendre_column(bands, 0, ct, pmm, a, b, [&](int l, double v) { out[sh_index(l, 0)] = v; });
  double cm = 1.0, sm = 0.0;
  const double r2 = std::numbers::sqrt2;
  for (int m = 1; m < bands; ++m) {
    pmm = detail::next_sectoral(pmm, table.sectoral()[m], st);
    const double cn = cm * c1 - sm * s1;
    sm = sm * c1 + cm * s1;
    cm = cn;
    const double fc = r2 * cm, fs = r2 * sm;
    detail::legendre_column(bands, m, ct, pmm, a, b, [&](int l, double v) {
      const int i = l * (l + 1);
      out[i + m] = v * fc;
      out[i - m] = v * fs;
    });
  }
}
}  // namespace

void evaluate(int bands, const glm::dvec3& dir, double* out) {
  check_bands(bands, "evaluate");
  const glm::dvec3 d = checked_direction(dir, "evaluate");
  const auto table = legendre_table(bands);
  evaluate_unit(bands, d, out, *table);
}

std::vector<double> evaluate(int bands, const glm::dvec3& dir) {
  check_bands(bands, "evaluate");
  std::vector<double> y(sh_count(bands));
  evaluate(bands, dir, y.data());
  return y;
}

glm::dvec3 direction_from_angles(double theta, double phi) {
  const double st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

void evaluate_angles(int bands, double theta, double phi, double* out) {
  if (!std::isfinite(theta) || !std::isfinite(phi))
    throw InputError("evaluate_angles: angle is not finite");
  check_bands(bands, "evaluate_angles");
  const auto table = legendre_table(bands);
  // use |sin t| and sign-adjusted phi so that theta outside [0, pi] still works
  glm::dvec3 d = direction_from_angles(theta, phi);
  evaluate_unit(bands, d, out, *table);
}

double reconstruct(int bands, const double* coeffs, const glm::dvec3& dir) {
  std::vector<double> y = evaluate(bands, dir);
  double s = 0.0;
  for (int i = 0; i < sh_count(bands); ++i) s += coeffs[i] * y[i];
  return s;
}

}  // namespace atmosh::sh
