// atmosh/atmo/fast_exp.hpp — exp(-x) for x >= 0 without a libm call, for loops that
// the compiler should vectorise (the sky integral's loop over wavelengths). For a
// single scalar call libm's exp is faster (its table-driven kernel has a shorter
// dependency chain than this degree-12 polynomial).
//
// Accuracy: relative error <= 4e-16 for x in [0, 700] (tests/atmo: against std::exp
// over 1e6 points and at the ends); x >= 700, +inf: exactly 0 (exp(-700) ~ 1e-304).
// NaN input is not expected (finite sums).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace atmosh::atmo {

// exp(-x) for x >= 0 (x = +inf or huge gives exactly 0), branch-free so that loops
// over wavelengths vectorise: Cody-Waite reduction x = n ln2 + r, |r| <= ln2/2,
// degree-12 Taylor polynomial (truncation < 2e-17 relative), 2^-n assembled in the
// exponent bits.
inline double exp_neg(double x) {
  const double xc = std::min(x, 700.0);  // also maps +inf; NaN is not expected (finite sums)
  // Round to nearest by the 1.5 * 2^52 shift (no libm call, vectorises).
  constexpr double kShift = 6755399441055744.0;
  const double n = (xc * 1.4426950408889634 + kShift) - kShift;
  const double r = (n * 0.6931471803691238 - xc) + n * 1.9082149292705877e-10;  // -(x - n ln2)
  double p = 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  // 2^-n: the integer 1023 - n (in [13, 1023]) sits in the low mantissa bits of
  // k + 1.5 * 2^52; shifting it into the exponent field is a 64-bit integer op.
  const double k = (1023.0 - n) + kShift;
  std::uint64_t bits;
  std::memcpy(&bits, &k, sizeof bits);
  bits <<= 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return x < 700.0 ? p * scale : 0.0;
}

}  // namespace atmosh::atmo
