// atmosh/sh/quadrature.hpp — Gauss–Legendre quadrature on [-1, 1].
//
// gauss_legendre(n) returns n nodes x_i (ascending, in (-1, 1)) and positive
// weights w_i with  sum_i w_i p(x_i) = integral_{-1}^{1} p(x) dx  exactly (up to
// rounding) for every polynomial p of degree <= 2n-1.
//
// Method: Newton iteration on the three-term Legendre recurrence in double,
// started from Tricomi's asymptotic approximation of the roots; weights from
// w_i = 2 / ((1 - x_i^2) P_n'(x_i)^2). Symmetry x_{n-1-i} = -x_i is imposed.
//
// Accuracy: nodes to ~1e-15 absolute (a few ulp), weights to ~1e-15 relative
// for n up to several thousand; sum of weights equals 2 to ~1e-14.
// Cost: O(n^2) (each Newton step evaluates the recurrence, O(n)).
//
// Units: dimensionless. Throws atmosh::InputError for n < 1.
#pragma once

#include <vector>

namespace atmosh::sh {

struct GaussLegendre {
  std::vector<double> nodes;    ///< ascending, in (-1, 1)
  std::vector<double> weights;  ///< positive, summing to 2
};

/// n-point Gauss–Legendre rule on [-1, 1]; exact for polynomials of degree <= 2n-1.
GaussLegendre gauss_legendre(int n);

/// Fejér's first rule on the n "pixel-centre" nodes x_j = cos t_j, t_j = (j + 1/2) pi / n
/// (j = 0..n-1, so x descending: node 0 nearest +1). Weights (Fejér 1933; closed form as
/// in Waldvogel 2006, BIT 46:195):
///   w_j = (2/n) [1 - 2 sum_{k=1}^{floor(n/2)} cos(2 k t_j) / (4k^2 - 1)],
/// positive, summing to 2. Exact for polynomials in x of degree <= n-1 (degree n too when n
/// is odd, by symmetry). Cost O(n^2). Throws InputError for n < 1.
std::vector<double> fejer1_weights(int n);

/// Clenshaw–Curtis rule on the n >= 2 nodes x_j = cos t_j, t_j = j pi / (n-1), j = 0..n-1
/// (both poles included; node 0 at x = +1). With N = n-1 (Waldvogel 2006):
///   w_j = (c_j / N) [1 - sum_{k=1}^{floor(N/2)} b_k cos(2 k t_j) / (4k^2 - 1)],
/// c_0 = c_N = 1, otherwise 2; b_k = 1 for k = N/2, otherwise 2. Positive, summing to 2.
/// Exact for degree <= N (N + 1 when N is even). Cost O(n^2). InputError for n < 2.
std::vector<double> clenshaw_curtis_weights(int n);

}  // namespace atmosh::sh
