// Gauss–Legendre nodes and weights by Newton iteration on the Legendre recurrence.
#include "atmosh/sh/quadrature.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"

namespace atmosh::sh {

namespace {
// P_n(x) and P_n'(x) by the three-term (Bonnet) recurrence.
inline void legendre_and_derivative(int n, double x, double& p, double& dp) {
  double p0 = 1.0, p1 = x;
  if (n == 0) {
    p = 1.0;
    dp = 0.0;
    return;
  }
  for (int k = 2; k <= n; ++k) {
    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  p = p1;
  // (1 - x^2) P_n' = n (P_{n-1} - x P_n)
  dp = n * (p0 - x * p1) / (1.0 - x * x);
}
}  // namespace

GaussLegendre gauss_legendre(int n) {
  if (n < 1) throw InputError("gauss_legendre: number of points must be >= 1, got " + std::to_string(n));
  GaussLegendre g;
  g.nodes.assign(n, 0.0);
  g.weights.assign(n, 0.0);
  const int half = (n + 1) / 2;
  const double pi = std::numbers::pi;
  for (int i = 0; i < half; ++i) {
    // Tricomi's initial guess for the i-th largest root (Abramowitz & Stegun 22.16.6).
    const double theta = pi * (4.0 * i + 3.0) / (4.0 * n + 2.0);
    double x = (1.0 - (n - 1.0) / (8.0 * n * n * n)) * std::cos(theta);
    double p = 0.0, dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      legendre_and_derivative(n, x, p, dp);
      const double dx = p / dp;
      x -= dx;
      if (std::abs(dx) <= 1e-16 * std::max(1.0, std::abs(x))) break;
    }
    legendre_and_derivative(n, x, p, dp);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    // largest roots first -> store symmetric, ascending order
    g.nodes[n - 1 - i] = x;
    g.nodes[i] = -x;
    g.weights[n - 1 - i] = w;
    g.weights[i] = w;
  }
  if (n % 2 == 1) g.nodes[n / 2] = 0.0;
  return g;
}

std::vector<double> fejer1_weights(int n) {
  if (n < 1) throw InputError("fejer1_weights: n must be >= 1, got " + std::to_string(n));
  std::vector<double> w(n);
  for (int j = 0; j < (n + 1) / 2; ++j) {
    const double t = std::numbers::pi * (j + 0.5) / n;
    double s = 0.0;
    for (int k = n / 2; k >= 1; --k) s += std::cos(2.0 * k * t) / (4.0 * k * k - 1.0);
    w[j] = w[n - 1 - j] = 2.0 / n * (1.0 - 2.0 * s);
  }
  return w;
}

std::vector<double> clenshaw_curtis_weights(int n) {
  if (n < 2) throw InputError("clenshaw_curtis_weights: n must be >= 2, got " + std::to_string(n));
  const int N = n - 1;
  std::vector<double> w(n);
  for (int j = 0; j <= N / 2; ++j) {
    const double t = std::numbers::pi * j / N;
    double s = 0.0;
    for (int k = N / 2; k >= 1; --k) s += (2 * k == N ? 1.0 : 2.0) * std::cos(2.0 * k * t) / (4.0 * k * k - 1.0);
    const double c = (j == 0 || j == N) ? 1.0 : 2.0;
    w[j] = w[N - j] = c / N * (1.0 - s);
  }
  return w;
}

}  // namespace atmosh::sh
