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

}  // namespace atmosh::sh
