// atmosh/sh/fast.hpp — straight-line SH evaluation for low bands (1..8), float or double.
//
// Same convention as basis.hpp (real, orthonormal, Condon–Shortley, index l(l+1)+m).
// The code is generated (scripts/gen_sh_fast.py, after Sloan 2013, JCGT 2(2)): per
// order m a polynomial in z times Re/Im (x + i y)^m, constants to 20 digits.
// The direction MUST be of unit length (no normalisation, no checks: this is the
// inner-loop path; use atmosh::sh::evaluate for checked input).
//
// Accuracy (tested against the general recurrence of basis.hpp): <= 1e-14 relative
// to the band's scale sqrt((2l+1)/(4 pi)) in double, <= 1e-6 in float.
// The batch form takes structure-of-arrays input and writes out[i * stride + k]
// (coefficient-major). For float and double it runs a compiled kernel: the same
// straight-line code on packs of 8 floats / 4 doubles (one SIMD lane per direction; an
// AVX2/FMA clone is picked at run time with GCC on x86-64), so the results equal
// evaluate_fast() to rounding (FMA contraction), not bit for bit. Choose a
// stride that is not a multiple of 4 KiB / sizeof(T): equal-offset output streams alias
// in the L1 cache and cost 10-20x (measured, docs/sh.md).
#pragma once

#include <cstddef>
#include <type_traits>

#include "atmosh/sh/fast_generated.hpp"

namespace atmosh::sh {

constexpr int kFastMaxBands = 8;

/// Y_0..Y_{bands^2-1} at a unit direction; 1 <= bands <= 8 (returns false otherwise).
template <class T>
inline bool evaluate_fast(int bands, T x, T y, T z, T* out) {
  switch (bands) {
    case 1: generated::eval_1(x, y, z, out); return true;
    case 2: generated::eval_2(x, y, z, out); return true;
    case 3: generated::eval_3(x, y, z, out); return true;
    case 4: generated::eval_4(x, y, z, out); return true;
    case 5: generated::eval_5(x, y, z, out); return true;
    case 6: generated::eval_6(x, y, z, out); return true;
    case 7: generated::eval_7(x, y, z, out); return true;
    case 8: generated::eval_8(x, y, z, out); return true;
    default: return false;
  }
}

/// n unit directions (xs, ys, zs); out[i * stride + k] for coefficient i of direction k
/// (stride >= n). 1 <= bands <= 8 (returns false otherwise).
/// float and double: the compiled SIMD kernels (src/fast_batch.cpp).
bool evaluate_fast_batch(int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out,
                         std::size_t stride);
bool evaluate_fast_batch(int bands, std::size_t n, const double* xs, const double* ys, const double* zs,
                         double* out, std::size_t stride);
/// Other types (e.g. long double): the generated straight-line code, one direction at a time.
template <class T>
inline bool evaluate_fast_batch(int bands, std::size_t n, const T* xs, const T* ys, const T* zs, T* out,
                                std::size_t stride) {
  if constexpr (std::is_same_v<T, float> || std::is_same_v<T, double>) {
    // Explicit evaluate_fast_batch<float>(...): the non-template overload above (it wins
    // overload resolution against this template).
    return evaluate_fast_batch(bands, n, xs, ys, zs, out, stride);
  }
  switch (bands) {
    case 1: generated::eval_batch_1(n, xs, ys, zs, out, stride); return true;
    case 2: generated::eval_batch_2(n, xs, ys, zs, out, stride); return true;
    case 3: generated::eval_batch_3(n, xs, ys, zs, out, stride); return true;
    case 4: generated::eval_batch_4(n, xs, ys, zs, out, stride); return true;
    case 5: generated::eval_batch_5(n, xs, ys, zs, out, stride); return true;
    case 6: generated::eval_batch_6(n, xs, ys, zs, out, stride); return true;
    case 7: generated::eval_batch_7(n, xs, ys, zs, out, stride); return true;
    case 8: generated::eval_batch_8(n, xs, ys, zs, out, stride); return true;
    default: return false;
  }
}

}  // namespace atmosh::sh
