// Downstream use of the installed atmosh::sh: Gauss–Legendre weights sum to 2
// (the length of [-1, 1]); exit 0 on success.
#include <atmosh/error.hpp>
#include <atmosh/sh/quadrature.hpp>

#include <cmath>
#include <cstdio>

int main() {
  const auto gl = atmosh::sh::gauss_legendre(16);
  double sum = 0.0;
  for (double w : gl.weights) sum += w;
  std::printf("sum of 16 Gauss-Legendre weights = %.17g\n", sum);
  return std::fabs(sum - 2.0) < 1e-13 ? 0 : 1;
}
