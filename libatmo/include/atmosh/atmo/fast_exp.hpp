// atmosh/atmo/fast_exp.hpp — exp(-x) without a libm call, for loops that
// the compiler should vectorise (the sky integral's loop over wavelengths). For a
// single scalar call libm's exp is faster (its table-driven kernel has a shorter
// dependency chain than this degree-12 polynomial).
//
// Accuracy: relative error <= 4e-16 for x in [-700, 700] (tests/atmo: against
// std::exp over 1e6 points and at the ends; negative x, i.e. exp(|x|), is what the
// optical-depth tables use to decode their logarithms); x >= 700, +inf: exactly 0
// (exp(-700) ~ 1e-304). x < -700 is outside the domain.
// NaN input is not expected (finite sums).
// exp_neg_f, the single-precision version (8 lanes per AVX2 vector; the sky's
// spectral loop): relative error <= 2e-7 (about 2 float ulp) for x in [0, 87];
// x >= 87, +inf: exactly 0 (exp(-87) ~ 1.6e-38, the smallest normal floats).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace atmosh::atmo {

// exp(-x) for x in [-700, 700] (x = +inf or huge gives exactly 0), branch-free so that loops
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
  // 2^-n: the integer 1023 - n (in [13, 2033]) sits in the low mantissa bits of
  // k + 1.5 * 2^52; shifting it into the exponent field is a 64-bit integer op.
  const double k = (1023.0 - n) + kShift;
  std::uint64_t bits;
  std::memcpy(&bits, &k, sizeof bits);
  bits <<= 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return x < 700.0 ? p * scale : 0.0;
}

// exp(-x) in single precision for x >= 0: the same scheme as exp_neg with a
// degree-7 Taylor polynomial (truncation < 6e-9 relative on |r| <= ln2/2).
inline float exp_neg_f(float x) {
  const float xc = std::min(x, 87.0f);
  constexpr float kShift = 12582912.0f;  // 1.5 * 2^23
  const float n = (xc * 1.44269504f + kShift) - kShift;
  const float r = (n * 0.693359375f - xc) + n * -2.12194440e-4f;  // -(x - n ln2), ln2 split in two
  float p = 1.0f / 5040.0f;
  p = p * r + 1.0f / 720.0f;
  p = p * r + 1.0f / 120.0f;
  p = p * r + 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  // 2^-n from the integer 127 - n (in [1, 127]) in the low mantissa bits of k.
  const float k = (127.0f - n) + kShift;
  std::uint32_t bits;
  std::memcpy(&bits, &k, sizeof bits);
  bits <<= 23;
  float scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return x < 87.0f ? p * scale : 0.0f;
}

}  // namespace atmosh::atmo
