// atmosh/sh/gaunt.hpp — products of spherical harmonics: Wigner 3j symbols, Gaunt
// coefficients of the real basis, the triple-product tensor, products of SH functions.
//
// Convention: the real orthonormal SH of basis.hpp (Condon–Shortley phase, index l(l+1)+m).
// Gaunt coefficient G(l1 m1, l2 m2, l3 m3) = integral Y_l1m1 Y_l2m2 Y_l3m3 dOmega (1/sr^(1/2)).
//
// Method: Wigner 3j symbols (l1 l2 l3; m1 m2 m3), all l1 at once for fixed l2, l3, m2, m3
// (m1 = -m2-m3), by the three-term recurrence in l1 of Schulten & Gordon (1975, J. Math.
// Phys. 16:1961), run forward from l1min while the solution grows and backward from l1max,
// matched by least squares over three points (as Luscombe & Luban 1998, Phys. Rev. E
// 57:7274), normalised by sum_l1 (2 l1 + 1) (3j)^2 = 1 with the sign of (l1max ...) equal
// to (-1)^(l2-l3-m1). No factorials: finite and accurate to l in the thousands
// (measured: Gaunt coefficients at l ~ 200 agree with quadrature to ~1e-15 absolute).
// The complex Gaunt integral is
//   integral Y_l1^m1 Y_l2^m2 Y_l3^m3 = sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi)) (l1 l2 l3; 0 0 0) (l1 l2 l3; m1 m2 m3),
// and the real one follows from Y_lm = (Y_l^m + (-1)^m Y_l^-m)/sqrt2 (m > 0),
// (Y_l^|m| - (-1)^m Y_l^-|m|)/(i sqrt2) (m < 0).
// Selection rules (the result is an exact 0 otherwise): |l2-l3| <= l1 <= l2+l3,
// l1+l2+l3 even, and |m1| = |m2|+|m3| or ||m2|-|m3|| with the number of negative m even
// (real SH: sin x sin x cos or cos x cos x cos only).
//
// Products: for f = sum a_i Y_i (La bands) and g = sum b_j Y_j (Lb bands), f g has
// La + Lb - 1 bands, with c_k = sum_ij a_i b_j G(i, j, k). product() computes it exactly
// (to rounding) by synthesis on a Gauss grid exact for La + Lb - 1 bands, pointwise
// multiplication and analysis (O(L^3)), truncated to `bands_out` bands. TripleProduct holds
// the sparse tensor for repeated small-band use (apply(), product_matrix()).
//
// Throws atmosh::InputError for negative l, |m| > l, bands < 1 or too short inputs.
#pragma once

#include <cstdint>
#include <vector>

namespace atmosh::sh {

/// (l1 l2 l3; m1 m2 m3) for l1 = l1min..l2+l3 with m1 = -m2-m3, into out (size l2+l3-l1min+1),
/// l1min = max(|l2-l3|, |m2+m3|). Returns l1min. Throws InputError for negative l or |m| > l.
int wigner3j_family(int l2, int l3, int m2, int m3, std::vector<double>& out);
/// One 3j symbol (0 where the selection rules say so).
double wigner3j(int l1, int l2, int l3, int m1, int m2, int m3);
/// Gaunt coefficient of the real orthonormal SH: integral Y_l1m1 Y_l2m2 Y_l3m3 dOmega.
double gaunt(int l1, int m1, int l2, int m2, int l3, int m3);

/// Non-zero Gaunt coefficients G(i, j, k) (linear indices) for i < bands_a^2, j < bands_b^2,
/// k < bands_out^2.
struct GauntEntry {
  std::int32_t i, j, k;
  double value;
};

class TripleProduct {
 public:
  /// bands_out = 0: bands_a + bands_b - 1 (the exact product).
  TripleProduct(int bands_a, int bands_b, int bands_out = 0);
  int bands_a() const { return la_; }
  int bands_b() const { return lb_; }
  int bands_out() const { return lo_; }
  const std::vector<GauntEntry>& entries() const { return e_; }
  /// c = projection of (sum a_i Y_i)(sum b_j Y_j) onto bands_out bands (a: bands_a^2,
  /// b: bands_b^2, c: bands_out^2 values).
  void apply(const double* a, const double* b, double* c) const;
  /// The matrix M (bands_out^2 x bands_b^2, row-major) with M b = apply(a, b): the
  /// product operator of the function a.
  std::vector<double> product_matrix(const double* a) const;

 private:
  int la_, lb_, lo_;
  std::vector<GauntEntry> e_;  // sorted by k, then i, then j
};

/// Coefficients (bands_out^2) of the product of two SH functions; bands_out = 0 gives
/// the exact product (bands_a + bands_b - 1 bands). Exact to rounding at any band.
std::vector<double> product(const std::vector<double>& a, int bands_a, const std::vector<double>& b, int bands_b,
                            int bands_out = 0, int threads = 1);

}  // namespace atmosh::sh
