// Compiled batch kernels of the straight-line low-band basis (fast.hpp): the generated
// code of fast_generated.hpp run on packs of directions (one SIMD lane per direction),
// so that every line of it is one vector operation whatever the output stride.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "atmosh/sh/fast.hpp"
#include "atmosh/dispatch.hpp"

namespace atmosh::sh::detail {

namespace {

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // packs are passed only between inlined internal functions
#endif

// W lanes of T with the arithmetic the generated code uses (T{}, T(constant), +, -, *).
template <class T, int W>
struct Pack {
  typedef T V __attribute__((vector_size(W * sizeof(T))));
  typedef T U __attribute__((vector_size(W * sizeof(T)), aligned(sizeof(T))));  // unaligned access
  V v;
  Pack() : v{} {}
  Pack(V x) : v(x) {}
  Pack(double c) : v(V{} + static_cast<T>(c)) {}
  __attribute__((always_inline)) friend Pack operator+(Pack a, Pack b) { return Pack(a.v + b.v); }
  __attribute__((always_inline)) friend Pack operator-(Pack a, Pack b) { return Pack(a.v - b.v); }
  __attribute__((always_inline)) friend Pack operator*(Pack a, Pack b) { return Pack(a.v * b.v); }
};

template <int B, class T, class P>
__attribute__((always_inline)) inline void eval_pack(P x, P y, P z, P* o) {
  if constexpr (B == 1) generated::eval_1(x, y, z, o);
  if constexpr (B == 2) generated::eval_2(x, y, z, o);
  if constexpr (B == 3) generated::eval_3(x, y, z, o);
  if constexpr (B == 4) generated::eval_4(x, y, z, o);
  if constexpr (B == 5) generated::eval_5(x, y, z, o);
  if constexpr (B == 6) generated::eval_6(x, y, z, o);
  if constexpr (B == 7) generated::eval_7(x, y, z, o);
  if constexpr (B == 8) generated::eval_8(x, y, z, o);
}

// Bytes of lanes per pack: 32 (one AVX register in the AVX2 clone, two SSE registers
// in the baseline one: 8 floats or 4 doubles) or 64 (one AVX-512 register: 16 floats
// or 8 doubles).
template <int B, int Bytes, class T>
__attribute__((always_inline)) inline void batch(std::size_t n, const T* xs, const T* ys, const T* zs, T* out,
                                                 std::size_t stride) {
  constexpr int W = Bytes / static_cast<int>(sizeof(T));
  using P = Pack<T, W>;
  using V = typename P::V;
  // Stores dominate: where every output row has the same alignment (stride a multiple of
  // the pack) but the rows do not start on a pack boundary, the first pack is stored
  // unaligned and the next starts at the first aligned direction `head` (directions
  // head..W-1 are computed twice, to the same values): every later store is aligned. A
  // store that straddles two cache lines costs about twice as much (1.2 vs 0.7 ns per
  // direction at L = 4, float, AVX-512).
  std::size_t head = 0;
  if (n >= 2 * W && (stride * sizeof(T)) % Bytes == 0) {
    const std::size_t mis = reinterpret_cast<std::uintptr_t>(out) % Bytes;
    if (mis != 0 && mis % sizeof(T) == 0) head = (Bytes - mis) / sizeof(T);
  }
  std::size_t k = 0;
  for (; k + W <= n; k = (k == 0 && head > 0) ? head : k + W) {
    using U = typename P::U;
    P o[B * B];
    eval_pack<B, T>(P(V(*reinterpret_cast<const U*>(xs + k))), P(V(*reinterpret_cast<const U*>(ys + k))),
                    P(V(*reinterpret_cast<const U*>(zs + k))), o);
    for (int i = 0; i < B * B; ++i) *reinterpret_cast<U*>(out + i * stride + k) = o[i].v;
  }
  for (; k < n; ++k) {
    T o[B * B];
    evaluate_fast(B, xs[k], ys[k], zs[k], o);
    for (int i = 0; i < B * B; ++i) out[i * stride + k] = o[i];
  }
}

template <int Bytes, class T>
__attribute__((always_inline)) inline void batch_any(int bands, std::size_t n, const T* xs, const T* ys,
                                                     const T* zs, T* out, std::size_t stride) {
  switch (bands) {
    case 1: batch<1, Bytes>(n, xs, ys, zs, out, stride); break;
    case 2: batch<2, Bytes>(n, xs, ys, zs, out, stride); break;
    case 3: batch<3, Bytes>(n, xs, ys, zs, out, stride); break;
    case 4: batch<4, Bytes>(n, xs, ys, zs, out, stride); break;
    case 5: batch<5, Bytes>(n, xs, ys, zs, out, stride); break;
    case 6: batch<6, Bytes>(n, xs, ys, zs, out, stride); break;
    case 7: batch<7, Bytes>(n, xs, ys, zs, out, stride); break;
    case 8: batch<8, Bytes>(n, xs, ys, zs, out, stride); break;
    default: break;
  }
}

ATMOSH_DISPATCH __attribute__((flatten))  // the generated code inlined into each clone
void batch_avx2(int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out,
                std::size_t stride) {
  batch_any<32>(bands, n, xs, ys, zs, out, stride);
}

ATMOSH_DISPATCH __attribute__((flatten))
void batch_avx2(int bands, std::size_t n, const double* xs, const double* ys, const double* zs, double* out,
                std::size_t stride) {
  batch_any<32>(bands, n, xs, ys, zs, out, stride);
}

#if ATMOSH_HAS_DISPATCH
// The kernels are bound by stores (L^2 values per direction): where the CPU has
// AVX-512 (x86-64-v4), one 64-byte pack per store halves their number.
ATMOSH_TARGET_AVX512 __attribute__((flatten)) void batch_avx512(
    int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out, std::size_t stride) {
  batch_any<64>(bands, n, xs, ys, zs, out, stride);
}

ATMOSH_TARGET_AVX512 __attribute__((flatten)) void batch_avx512(
    int bands, std::size_t n, const double* xs, const double* ys, const double* zs, double* out, std::size_t stride) {
  batch_any<64>(bands, n, xs, ys, zs, out, stride);
}

bool has_avx512() { return cpu_has_avx512(); }
#else
template <class T>
void batch_avx512(int bands, std::size_t n, const T* xs, const T* ys, const T* zs, T* out, std::size_t stride) {
  batch_avx2(bands, n, xs, ys, zs, out, stride);
}
bool has_avx512() { return false; }
#endif

// The AVX-512 kernel where the CPU has it, else the AVX2 / baseline clone.
template <class T>
void batch_on_this_cpu(int bands, std::size_t n, const T* xs, const T* ys, const T* zs, T* out, std::size_t stride) {
  if (has_avx512())
    batch_avx512(bands, n, xs, ys, zs, out, stride);
  else
    batch_avx2(bands, n, xs, ys, zs, out, stride);
}

}  // namespace

}  // namespace atmosh::sh::detail

namespace atmosh::sh {

bool evaluate_fast_batch(int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out,
                         std::size_t stride) {
  if (bands < 1 || bands > kFastMaxBands) return false;
  detail::batch_on_this_cpu(bands, n, xs, ys, zs, out, stride);
  return true;
}

bool evaluate_fast_batch(int bands, std::size_t n, const double* xs, const double* ys, const double* zs,
                         double* out, std::size_t stride) {
  if (bands < 1 || bands > kFastMaxBands) return false;
  detail::batch_on_this_cpu(bands, n, xs, ys, zs, out, stride);
  return true;
}

}  // namespace atmosh::sh
