// fast_exp.hpp (private to libatmo) — exp(-x) without a libm call, for loops that
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

namespace detail {
// The constants of exp_neg for one floating-point type: the largest argument (above it
// the result is exactly 0), the round-to-nearest shift 1.5 * 2^(mantissa bits), log2(e),
// ln 2 split into a high part with trailing zero bits and the rest (Cody-Waite), the
// exponent bias, the mantissa bits and the degree of the Taylor polynomial.
template <class F>
struct ExpNegConstants;
template <>
struct ExpNegConstants<double> {
  using Bits = std::uint64_t;
  static constexpr double kMax = 700.0, kShift = 6755399441055744.0, kLog2e = 1.4426950408889634,
                          kLn2Hi = 0.6931471803691238, kLn2Lo = 1.9082149292705877e-10;
  static constexpr int kBias = 1023, kMantissa = 52, kDegree = 12;  // truncation < 2e-17
};
template <>
struct ExpNegConstants<float> {
  using Bits = std::uint32_t;
  static constexpr float kMax = 87.0f, kShift = 12582912.0f, kLog2e = 1.44269504f, kLn2Hi = 0.693359375f,
                         kLn2Lo = -2.12194440e-4f;
  static constexpr int kBias = 127, kMantissa = 23, kDegree = 7;  // truncation < 6e-9
};

constexpr double factorial(int k) { return k <= 1 ? 1.0 : k * factorial(k - 1); }

// sum_{j=k..K} r^(j-k) k!/j! ... by Horner: 1/k! + r (1/(k+1)! + r (...)), from the top.
template <class F, int K, int k = 0>
[[gnu::always_inline]] inline F exp_taylor(F r) {
  if constexpr (k == K)
    return F(1) / F(factorial(K));
  else
    return exp_taylor<F, K, k + 1>(r) * r + F(1) / F(factorial(k));
}

// exp(-x), branch-free so that loops over wavelengths vectorise: Cody-Waite reduction
// x = n ln2 + r, |r| <= ln2/2, Taylor polynomial, 2^-n assembled in the exponent bits.
template <class F>
[[gnu::always_inline]] inline F exp_neg(F x) {
  using C = ExpNegConstants<F>;
  // std::min(x, kMax), spelt out: the helpers' calls are not inlined into the
  // target_clones copies of the callers (atmosh/dispatch.hpp), this is.
  const F xc = C::kMax < x ? C::kMax : x;  // also maps +inf; NaN is not expected (finite sums)
  // Round to nearest by the shift (no libm call, vectorises).
  const F n = (xc * C::kLog2e + C::kShift) - C::kShift;
  const F r = (n * C::kLn2Hi - xc) + n * C::kLn2Lo;  // -(x - n ln2)
  const F p = exp_taylor<F, C::kDegree>(r);
  // 2^-n: the integer bias - n sits in the low mantissa bits of k (it is at most
  // 2 bias - 1 over the domain, so it fits the exponent field); shifting it there is
  // an integer op.
  const F k = (F(C::kBias) - n) + C::kShift;
  typename C::Bits bits;
  std::memcpy(&bits, &k, sizeof bits);
  bits <<= C::kMantissa;
  F scale;
  std::memcpy(&scale, &bits, sizeof scale);
  return x < C::kMax ? p * scale : F(0);
}
}  // namespace detail

// exp(-x) for x in [-700, 700] in double precision (x = +inf or huge gives exactly 0).
[[gnu::always_inline]] inline double exp_neg(double x) { return detail::exp_neg(x); }

// exp(-x) for x >= 0 in single precision (x = +inf or >= 87 gives exactly 0).
[[gnu::always_inline]] inline float exp_neg_f(float x) { return detail::exp_neg(x); }

}  // namespace atmosh::atmo
