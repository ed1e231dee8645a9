// Funk–Hecke convolution, irradiance, windows, band energy, conversions.
#include "atmosh/sh/convolution.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/sh/zonal.hpp"

namespace atmosh::sh {

namespace {
constexpr double kPi = std::numbers::pi;
void check_size(const std::vector<double>& c, int bands, const char* where) {
  check_bands(bands, where);
  if (static_cast<long long>(c.size()) < static_cast<long long>(bands) * bands)
    throw InputError(std::string(where) + ": need " + std::to_string(bands * bands) + " coefficients, got " +
                     std::to_string(c.size()));
}
}  // namespace

std::vector<double> clamped_cosine_zonal(int bands) {
  check_bands(bands, "clamped_cosine_zonal");
  // integrand mu P_l(mu) on [0, 1] is a polynomial of degree l+1: n = bands/2 + 2 is exact
  const int n = bands / 2 + 2;
  const GaussLegendre g = gauss_legendre(n);
  std::vector<double> z(bands, 0.0);
  for (int i = 0; i < n; ++i) {
    const double mu = 0.5 * (g.nodes[i] + 1.0), w = 0.5 * g.weights[i];
    const std::vector<double> p = legendre_polynomials(mu, bands);
    for (int l = 0; l < bands; ++l) z[l] += w * mu * p[l];
  }
  for (int l = 0; l < bands; ++l) z[l] *= 2.0 * kPi * std::sqrt((2.0 * l + 1.0) / (4.0 * kPi));
  return z;
}

std::vector<double> funk_hecke_factors(const std::function<double(double)>& kernel, int bands,
                                       int quadrature_points) {
  std::vector<double> z = zonal_coefficients(kernel, bands, quadrature_points);
  for (int l = 0; l < bands; ++l) z[l] *= std::sqrt(4.0 * kPi / (2.0 * l + 1.0));
  return z;
}

std::vector<double> irradiance_factors(int bands) {
  std::vector<double> z = clamped_cosine_zonal(bands);
  for (int l = 0; l < bands; ++l) z[l] *= std::sqrt(4.0 * kPi / (2.0 * l + 1.0));
  return z;
}

void convolve_zonal(std::vector<double>& c, int bands, const std::vector<double>& factor) {
  check_size(c, bands, "convolve_zonal");
  if (static_cast<int>(factor.size()) < bands)
    throw InputError("convolve_zonal: need " + std::to_string(bands) + " factors, got " + std::to_string(factor.size()));
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) c[sh_index(l, m)] *= factor[l];
}

std::vector<double> irradiance(const std::vector<double>& radiance, int bands) {
  check_size(radiance, bands, "irradiance");
  std::vector<double> c(radiance.begin(), radiance.begin() + sh_count(bands));
  convolve_zonal(c, bands, irradiance_factors(bands));
  return c;
}

double irradiance_at(const std::vector<double>& radiance, int bands, const glm::dvec3& normal) {
  const std::vector<double> e = irradiance(radiance, bands);
  return reconstruct(bands, e.data(), normal);
}

Window parse_window(const std::string& name) {
  if (name == "none") return Window::none;
  if (name == "hanning") return Window::hanning;
  if (name == "lanczos") return Window::lanczos;
  if (name == "nonnegative") return Window::nonnegative;
  throw InputError("unknown window '" + name + "' (none, hanning, lanczos, nonnegative)");
}

double windowed_delta_min(const std::vector<double>& w) {
  const int L = static_cast<int>(w.size());
  const int n = 8 * L + 64;
  double top = 0;
  for (int l = 0; l < L; ++l) top += (2.0 * l + 1.0) / (4.0 * kPi) * w[l];
  double mn = 1e300;
  std::vector<double> p(L);
  for (int i = 0; i <= 2 * n; ++i) {
    const double mu = -1.0 + static_cast<double>(i) / n;
    double s = 0, p0 = 1, p1 = mu;
    for (int l = 0; l < L; ++l) {
      double pl;
      if (l == 0)
        pl = 1;
      else if (l == 1)
        pl = mu;
      else {
        pl = ((2.0 * l - 1.0) * mu * p1 - (l - 1.0) * p0) / l;
        p0 = p1;
        p1 = pl;
      }
      s += (2.0 * l + 1.0) / (4.0 * kPi) * w[l] * pl;
    }
    mn = std::min(mn, s);
  }
  return mn / top;
}

std::vector<double> window_weights(Window win, int bands) {
  check_bands(bands, "window_weights");
  std::vector<double> w(bands, 1.0);
  const double L = bands;
  switch (win) {
    case Window::none: break;
    case Window::hanning:
      for (int l = 0; l < bands; ++l) w[l] = 0.5 * (1.0 + std::cos(kPi * l / L));
      break;
    case Window::lanczos:
      for (int l = 1; l < bands; ++l) w[l] = std::sin(kPi * l / L) / (kPi * l / L);
      break;
    case Window::nonnegative: {
      if (bands <= 2) {
        // L <= 2: delta approx 1/(4pi) (1 + 3 w1 mu) >= 0 needs w1 <= 1/3
        if (bands == 2) w[1] = 1.0 / 3.0;
        break;
      }
      auto make = [&](double h) {
        std::vector<double> v(bands);
        for (int l = 0; l < bands; ++l) v[l] = std::exp(-h * l * (l + 1.0));
        return v;
      };
      double lo = 0.0, hi = 1.0;
      while (windowed_delta_min(make(hi)) < -1e-9) hi *= 2.0;
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (windowed_delta_min(make(mid)) < -1e-9)
          lo = mid;
        else
          hi = mid;
      }
      w = make(hi);
      break;
    }
  }
  return w;
}

std::vector<double> band_energy(const std::vector<double>& c, int bands) {
  check_size(c, bands, "band_energy");
  std::vector<double> e(bands, 0.0);
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) e[l] += c[sh_index(l, m)] * c[sh_index(l, m)];
  return e;
}

std::vector<double> cumulative_energy_fraction(const std::vector<double>& e) {
  double total = 0;
  for (double v : e) total += v;
  std::vector<double> f(e.size(), 0.0);
  double run = 0;
  for (std::size_t l = 0; l < e.size(); ++l) {
    run += e[l];
    f[l] = total > 0 ? run / total : 0.0;
  }
  return f;
}

std::vector<double> convert(const std::vector<double>& c, int bands, Normalization from, bool from_cs,
                            Normalization to, bool to_cs) {
  check_size(c, bands, "convert");
  // scale s(norm, l): Y_norm = s * Y_ortho  ->  c_norm = c_ortho / s
  auto s = [](Normalization n, int l) {
    switch (n) {
      case Normalization::orthonormal: return 1.0;
      case Normalization::four_pi: return std::sqrt(4.0 * kPi);
      case Normalization::schmidt: return std::sqrt(4.0 * kPi / (2.0 * l + 1.0));
    }
    return 1.0;
  };
  std::vector<double> out(sh_count(bands));
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) {
      const double sign = (from_cs != to_cs && (std::abs(m) & 1)) ? -1.0 : 1.0;
      out[sh_index(l, m)] = c[sh_index(l, m)] * s(from, l) / s(to, l) * sign;
    }
  return out;
}

std::vector<std::complex<double>> to_complex(const std::vector<double>& c, int bands) {
  check_size(c, bands, "to_complex");
  std::vector<std::complex<double>> a(sh_count(bands));
  const double r = 1.0 / std::numbers::sqrt2;
  for (int l = 0; l < bands; ++l) {
    a[sh_index(l, 0)] = c[sh_index(l, 0)];
    for (int m = 1; m <= l; ++m) {
      const std::complex<double> am(c[sh_index(l, m)] * r, -c[sh_index(l, -m)] * r);
      a[sh_index(l, m)] = am;
      a[sh_index(l, -m)] = ((m & 1) ? -1.0 : 1.0) * std::conj(am);
    }
  }
  return a;
}

std::vector<double> from_complex(const std::vector<std::complex<double>>& a, int bands) {
  check_bands(bands, "from_complex");
  if (static_cast<int>(a.size()) < sh_count(bands)) throw InputError("from_complex: too few coefficients");
  std::vector<double> c(sh_count(bands));
  for (int l = 0; l < bands; ++l) {
    c[sh_index(l, 0)] = a[sh_index(l, 0)].real();
    for (int m = 1; m <= l; ++m) {
      c[sh_index(l, m)] = std::numbers::sqrt2 * a[sh_index(l, m)].real();
      c[sh_index(l, -m)] = -std::numbers::sqrt2 * a[sh_index(l, m)].imag();
    }
  }
  return c;
}

}  // namespace atmosh::sh
