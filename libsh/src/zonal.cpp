// Zonal SH coefficients by Gauss–Legendre quadrature; Legendre polynomials.
#include "atmosh/sh/zonal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::sh {

std::vector<double> legendre_polynomials(double mu, int bands) {
  if (bands < 1) throw InputError("legendre_polynomials: bands must be >= 1, got " + std::to_string(bands));
  if (!std::isfinite(mu)) throw InputError("legendre_polynomials: mu is not finite");
  std::vector<double> p(bands);
  p[0] = 1.0;
  if (bands > 1) p[1] = mu;
  for (int l = 2; l < bands; ++l) p[l] = ((2.0 * l - 1.0) * mu * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
  return p;
}

std::vector<double> zonal_coefficients(const std::function<double(double)>& f, int bands,
                                       int quadrature_points) {
  if (bands < 1) throw InputError("zonal_coefficients: bands must be >= 1, got " + std::to_string(bands));
  if (quadrature_points < 0)
    throw InputError("zonal_coefficients: quadrature_points must be >= 0, got " + std::to_string(quadrature_points));
  const int n = quadrature_points > 0 ? quadrature_points : std::max(64, bands + 1);
  const GaussLegendre g = gauss_legendre(n);
  std::vector<double> z(bands, 0.0);
  std::vector<double> p(bands);
  for (int i = 0; i < n; ++i) {
    const double mu = g.nodes[i];
    const double fw = f(mu) * g.weights[i];
    p[0] = 1.0;
    if (bands > 1) p[1] = mu;
    for (int l = 2; l < bands; ++l) p[l] = ((2.0 * l - 1.0) * mu * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
    for (int l = 0; l < bands; ++l) z[l] += fw * p[l];
  }
  const double pi = std::numbers::pi;
  for (int l = 0; l < bands; ++l) z[l] *= 2.0 * pi * std::sqrt((2.0 * l + 1.0) / (4.0 * pi));
  return z;
}

std::vector<double> zonal_coefficients(const std::function<double(double)>& f, int bands,
                                       const std::vector<double>& breaks, int min_points) {
  if (bands < 1) throw InputError("zonal_coefficients: bands must be >= 1, got " + std::to_string(bands));
  if (min_points < 1) throw InputError("zonal_coefficients: min_points must be >= 1, got " + std::to_string(min_points));
  if (breaks.size() < 2) throw InputError("zonal_coefficients: need >= 2 breaks, got " + std::to_string(breaks.size()));
  for (std::size_t i = 0; i < breaks.size(); ++i)
    if (!(breaks[i] >= -1.0 && breaks[i] <= 1.0) || (i > 0 && !(breaks[i] > breaks[i - 1])))
      throw InputError("zonal_coefficients: breaks[" + std::to_string(i) + "] = " + std::to_string(breaks[i]) +
                       ": must be ascending in [-1, 1]");
  const double pi = std::numbers::pi;
  std::vector<double> z(bands, 0.0), p(bands);
  for (std::size_t i = 1; i < breaks.size(); ++i) {
    const double a = breaks[i - 1], b = breaks[i];
    const double dtheta = std::acos(a) - std::acos(b);
    const int m = min_points + static_cast<int>(std::ceil(bands * dtheta / pi));
    const GaussLegendre g = gauss_legendre(m);
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    for (int j = 0; j < m; ++j) {
      const double mu = c + h * g.nodes[j];
      const double fw = f(mu) * g.weights[j] * h;
      p[0] = 1.0;
      if (bands > 1) p[1] = mu;
      for (int l = 2; l < bands; ++l) p[l] = ((2.0 * l - 1.0) * mu * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
      for (int l = 0; l < bands; ++l) z[l] += fw * p[l];
    }
  }
  for (int l = 0; l < bands; ++l) z[l] *= 2.0 * pi * std::sqrt((2.0 * l + 1.0) / (4.0 * pi));
  return z;
}

}  // namespace atmosh::sh
