// Internal: extended-range sectoral values and the column recurrence shared by
// basis evaluation and grid analysis/synthesis.
#pragma once

#include <cmath>

#include "atmosh/sh/basis.hpp"

namespace atmosh::sh::detail {

constexpr int kScaleExp = 600;                   // rescale step, powers of two
inline const double kScaleUp = std::ldexp(1.0, kScaleExp);
inline const double kScaleDown = std::ldexp(1.0, -kScaleExp);
inline const double kSmall = std::ldexp(1.0, -800);  // below: rescale mantissa
inline const double kFold = std::ldexp(1.0, 100);    // above (exp < 0): fold into exp

/// Extended-range number mant * 2^exp (exp <= 0, multiple of kScaleExp).
struct XNum {
  double mant;
  int exp;
};

inline double xnum_value(double mant, int exp) { return exp == 0 ? mant : std::ldexp(mant, exp); }

/// Next sectoral value: Pbar_mm = -s_m * sin_t * Pbar_m-1,m-1.
inline XNum next_sectoral(XNum p, double s_m, double sin_t) {
  p.mant *= -s_m * sin_t;
  if (p.mant != 0.0 && std::abs(p.mant) < kSmall) {
    p.mant *= kScaleUp;
    p.exp -= kScaleExp;
  }
  return p;
}

/// Column m: calls out(l, value) for l = m..bands-1 given the sectoral value.
template <class Out>
inline void legendre_column(int bands, int m, double x, XNum pmm, const double* a, const double* b,
                            Out&& out) {
  if (pmm.exp == 0) {
    double p2 = pmm.mant;
    out(m, p2);
    if (m + 1 >= bands) return;
    double p1 = std::sqrt(2.0 * m + 3.0) * x * p2;
    out(m + 1, p1);
    std::size_t k = tri_index(m + 2, m);
    for (int l = m + 2; l < bands; ++l) {
      const double p = a[k] * x * p1 - b[k] * p2;
      out(l, p);
      p2 = p1;
      p1 = p;
      k += l + 1;
    }
    return;
  }
  // extended-range path: the column starts below the double range.
  double p2 = pmm.mant;
  int e = pmm.exp;
  out(m, xnum_value(p2, e));
  if (m + 1 >= bands) return;
  double p1 = std::sqrt(2.0 * m + 3.0) * x * p2;
  out(m + 1, xnum_value(p1, e));
  std::size_t k = tri_index(m + 2, m);
  int l = m + 2;
  for (; l < bands && e < 0; ++l) {
    double p = a[k] * x * p1 - b[k] * p2;
    p2 = p1;
    p1 = p;
    if (std::abs(p1) > kFold) {
      p1 *= kScaleDown;
      p2 *= kScaleDown;
      e += kScaleExp;
    }
    out(l, xnum_value(p1, e));
    k += l + 1;
  }
  for (; l < bands; ++l) {
    const double p = a[k] * x * p1 - b[k] * p2;
    out(l, p);
    p2 = p1;
    p1 = p;
    k += l + 1;
  }
}

}  // namespace atmosh::sh::detail
