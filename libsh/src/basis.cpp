// Real SH basis of any band: scaled column recurrences of Pbar_lm.
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/fast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/dispatch.hpp"
#include "legendre_impl.hpp"

namespace atmosh::sh {

void check_bands(int bands, const char* where, int max_bands) {
  if (bands < 1 || bands > max_bands)
    throw InputError(std::string(where) + ": bands must be in [1, " + std::to_string(max_bands) +
                     "], got " + std::to_string(bands));
}

glm::dvec3 checked_direction(const glm::dvec3& d, const char* where) {
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
    throw InputError(std::string(where) + ": direction has a NaN or infinite component");
  const double n2 = d.x * d.x + d.y * d.y + d.z * d.z;
  if (std::isfinite(n2) && n2 > 1e-280) return d / std::sqrt(n2);
  // Squares near the largest double (1e308) overflow and those below ~1e-154 underflow,
  // which turned valid directions into "(0,0,0)" or NaN: scale by the largest component
  // first. (Ordinary directions keep the plain form above, bit for bit.)
  const double m = std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
  if (!(m > 0.0)) throw InputError(std::string(where) + ": direction (0,0,0) has no length");
  const glm::dvec3 s = d / m;
  return s / std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
}

LegendreTable::LegendreTable(int bands) : bands_(bands) {
  const std::size_t n = tri_index(bands, 0);
  a_.assign(n, 0.0);
  b_.assign(n, 0.0);
  s_.assign(bands + 1, 0.0);
  for (int m = 1; m <= bands; ++m) s_[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
  for (int l = 2; l < bands; ++l) {
    for (int m = 0; m <= l - 2; ++m) {
      const double ll = l, mm = m;
      const double den = ll * ll - mm * mm;
      a_[tri_index(l, m)] = std::sqrt((4.0 * ll * ll - 1.0) / den);
      b_[tri_index(l, m)] =
          std::sqrt((2.0 * ll + 1.0) * ((ll - 1.0) * (ll - 1.0) - mm * mm) / ((2.0 * ll - 3.0) * den));
    }
  }
}

std::shared_ptr<const LegendreTable> legendre_table(int bands) {
  static std::mutex mu;
  static std::shared_ptr<const LegendreTable> cached;
  std::lock_guard<std::mutex> lock(mu);
  if (!cached || cached->bands() < bands) cached = std::make_shared<const LegendreTable>(std::max(bands, 32));
  return cached;
}

void legendre_normalized(int bands, double cos_t, double sin_t, double* out) {
  check_bands(bands, "legendre_normalized");
  if (!std::isfinite(cos_t) || !std::isfinite(sin_t))
    throw InputError("legendre_normalized: cos/sin of the polar angle is not finite");
  const auto table = legendre_table(bands);
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  for (int m = 0; m < bands; ++m) {
    if (m > 0) pmm = detail::next_sectoral(pmm, table->sectoral()[m], sin_t);
    detail::legendre_column(bands, m, cos_t, pmm, table->a(), table->b(),
                            [&](int l, double v) { out[tri_index(l, m)] = v; });
  }
}

void legendre_column(int bands, int m, double cos_t, double sin_t, double* out) {
  check_bands(bands, "legendre_column");
  if (m < 0 || m >= bands) throw InputError("legendre_column: m = " + std::to_string(m) + " out of range");
  if (!std::isfinite(cos_t) || !std::isfinite(sin_t))
    throw InputError("legendre_column: cos/sin of the polar angle is not finite");
  const auto table = legendre_table(bands);
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  for (int k = 1; k <= m; ++k) pmm = detail::next_sectoral(pmm, table->sectoral()[k], sin_t);
  detail::legendre_column(bands, m, cos_t, pmm, table->a(), table->b(), [&](int l, double v) { out[l - m] = v; });
}

namespace {
// Column-by-column evaluation (any band; handles the extended-range sectoral terms).
void evaluate_unit_columns(int bands, const glm::dvec3& d, double* out, const LegendreTable& table) {
  const double rho = std::sqrt(d.x * d.x + d.y * d.y);
  const double ct = d.z, st = rho;
  double c1 = 1.0, s1 = 0.0;  // cos p, sin p
  if (rho > 0.0) {
    c1 = d.x / rho;
    s1 = d.y / rho;
  }
  const double* a = table.a();
  const double* b = table.b();
  detail::XNum pmm{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
  detail::legendre_column(bands, 0, ct, pmm, a, b, [&](int l, double v) { out[sh_index(l, 0)] = v; });
  double cm = 1.0, sm = 0.0;
  const double r2 = std::numbers::sqrt2;
  for (int m = 1; m < bands; ++m) {
    pmm = detail::next_sectoral(pmm, table.sectoral()[m], st);
    const double cn = cm * c1 - sm * s1;
    sm = sm * c1 + cm * s1;
    cm = cn;
    const double fc = r2 * cm, fs = r2 * sm;
    detail::legendre_column(bands, m, ct, pmm, a, b, [&](int l, double v) {
      const int i = l * (l + 1);
      out[i + m] = v * fc;
      out[i - m] = v * fs;
    });
  }
}

// Row-by-row evaluation for bands <= kRowBands: one pass of the same column recurrence,
// run over all orders m of band l at once (independent lanes, no serial dependency
// inside a band, vectorised), cos/sin(m p) by complex multiplication (no trig per m).
// Rows need a_lm, b_lm for m <= l-1 (a_{l,l-1} = sqrt(2l+1), b_{l,l-1} = 0 by the same
// formula), stored row-contiguous at tri_index(l, m).
constexpr int kRowBands = 128;
constexpr int kRowMinBands = 10;
constexpr int kRowStride = kRowBands + 4;  // row l at l * kRowStride, zero-padded past m = l-1

struct RowTable {
  std::vector<double> a, b;
  double s[kRowBands];
  RowTable() : a(static_cast<std::size_t>(kRowBands) * kRowStride, 0.0), b(a) {
    s[0] = 0.0;
    for (int m = 1; m < kRowBands; ++m) s[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int l = 1; l < kRowBands; ++l)
      for (int m = 0; m <= l - 1; ++m) {
        const double ll = l, mm = m;
        const double den = ll * ll - mm * mm;
        a[l * kRowStride + m] = std::sqrt((4.0 * ll * ll - 1.0) / den);
        b[l * kRowStride + m] = l < 2 ? 0.0
                                      : std::sqrt((2.0 * ll + 1.0) * ((ll - 1.0) * (ll - 1.0) - mm * mm) /
                                                  ((2.0 * ll - 3.0) * den));
      }
  }
};

const RowTable& row_table() {
  static const RowTable* t = new RowTable();  // built once, never freed (no exit-time order issues)
  return *t;
}

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // V4 passed only between inlined internal functions
#endif
// 4 doubles; GCC/clang lower it to one AVX register or two SSE2 registers.
typedef double V4 __attribute__((vector_size(4 * sizeof(double))));
inline V4 load4(const double* p) {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(double* p, V4 v) { std::memcpy(p, &v, sizeof v); }
alignas(32) constexpr double kUnit[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

#if defined(__GNUC__) && !defined(__clang__)
#define ATMOSH_SH_UNROLL _Pragma("GCC unroll 16")
#else
#define ATMOSH_SH_UNROLL
#endif

// NB > 0: the band count is a compile-time constant (loops unrolled, lane selects fixed).
template <int NB>
__attribute__((always_inline)) inline void rows_kernel(int bands_rt, double ct, double c1, double s1,
                                                       const double* pmm, const double* ta, const double* tb,
                                                       double* __restrict out) {
  const int bands = NB > 0 ? NB : bands_rt;
  // Row buffers: lanes past m = l hold finite values that meet zero coefficients only.
  // five work rows of w lanes (lanes read: m <= bands + 2), zeroed in one go
  alignas(32) double ws[5 * (kRowBands + 8)];
  const int w = (bands + 7) & ~3;
  std::memset(ws, 0, sizeof(double) * 5 * w);
  double* buf[3] = {ws, ws + w, ws + 2 * w};
  double* C = ws + 3 * w;
  double* S = ws + 4 * w;
  const double r2 = std::numbers::sqrt2;
  double cm = 1.0, sm = 0.0;
  C[0] = 1.0;
  for (int m = 1; m < bands; ++m) {
    const double cn = cm * c1 - sm * s1;
    sm = sm * c1 + cm * s1;
    cm = cn;
    C[m] = r2 * cm;
    S[m] = r2 * sm;
  }
  double* p2 = buf[0];
  double* p1 = buf[1];
  double* p = buf[2];
  p1[0] = pmm[0];
  out[0] = pmm[0];
  const V4 vct = {ct, ct, ct, ct};
  ATMOSH_SH_UNROLL
  for (int l = 1; l < bands; ++l) {
    const double* a = ta + l * kRowStride;
    const double* b = tb + l * kRowStride;
    double* o = out + l * (l + 1);  // o[m] = Y_lm, m = -l..l
    const int last = l / 4;         // block holding m = l
    const bool spill_ok = l + 1 < bands;  // the next band's slots may be written early
    ATMOSH_SH_UNROLL
    for (int j = 0; j <= last; ++j) {
      const int m = 4 * j;
      V4 v = load4(a + m) * vct * load4(p1 + m) - load4(b + m) * load4(p2 + m);
      if (j == last) {  // put P_ll in lane l - m without a store/reload round trip
        const V4 e = load4(kUnit[l - m]), pl = {pmm[l], pmm[l], pmm[l], pmm[l]};
        v = v * (V4{1.0, 1.0, 1.0, 1.0} - e) + pl * e;
      }
      store4(p + m, v);  // whole-vector store: the next rows reload it whole
      const V4 w = v * load4(S + m);
      const V4 u = v * load4(C + m);
      if (j < last) {
        store4(o - m - 3, V4{w[3], w[2], w[1], w[0]});  // m..m+3 -> o[-m-3 .. -m]
        store4(o + m, u);
      } else {
        for (int k = (j == 0 ? 1 : 0); k < 4 && m + k <= l; ++k) o[-(m + k)] = w[k];
        if (spill_ok) {
          store4(o + m, u);  // lanes past l land in band l+1, rewritten later
        } else {
          for (int k = 0; k < 4 && m + k <= l; ++k) o[m + k] = u[k];
        }
      }
    }
    double* t = p2;
    p2 = p1;
    p1 = p;
    p = t;
  }
}

ATMOSH_DISPATCH
void evaluate_rows_kernel(int bands, double ct, double c1, double s1, const double* pmm, const double* ta,
                          const double* tb, double* __restrict out) {
  if (bands == 16) {
    rows_kernel<16>(bands, ct, c1, s1, pmm, ta, tb, out);
  } else {
    rows_kernel<0>(bands, ct, c1, s1, pmm, ta, tb, out);
  }
}

// ---- batches: the column recurrence vectorised across directions ----------------------
// One lane per direction (kLanes directions per pass), structure-of-arrays input,
// coefficient-major output. Per order m the column l = m..bands-1 is run in registers,
// P_lm = a_lm cos t P_l-1,m - b_lm P_l-2,m: every step is one vector operation on a pack
// of directions. Doubles: 4 per pack (one AVX register in the AVX2/FMA clone, two SSE2
// registers otherwise; 8-double generic vectors were lowered by GCC 12 through integer
// registers in those clones: 5x slower), 8 (one zmm register) where the CPU has AVX-512
// (atmosh/dispatch.hpp). Floats: twice as many lanes in the same registers.
template <class T, int Lanes>
struct Lane {
  typedef T V __attribute__((vector_size(Lanes * sizeof(T))));
};

template <bool Full, class T, class VB>
__attribute__((always_inline)) inline void put(T* p, VB v, int count) {
  if constexpr (Full) {
    typedef T Vu __attribute__((vector_size(sizeof(VB)), aligned(sizeof(T))));
    *reinterpret_cast<Vu*>(p) = v;
  } else {
    for (int k = 0; k < count; ++k) p[k] = v[k];
  }
}

// Smallest sectoral term the plain-range pass accepts: below it a lane takes the
// extended-range path. Double: the single-direction row path's threshold (2^-800, 2^222
// above the smallest normal double); float: 2^-100, 2^26 above the smallest normal float.
template <class T>
inline T small_sectoral() {
  if constexpr (sizeof(T) == sizeof(double)) return detail::kSmall;
  else return std::ldexp(1.0f, -100);
}

// a_lm, b_lm column-major (column m at m * kRowStride, entry l), for bands <= kRowBands,
// in double and rounded to float.
struct ColTable {
  std::vector<double> a, b;
  std::vector<float> af, bf;
  double s[kRowBands];
  float sf[kRowBands];
  ColTable() : a(static_cast<std::size_t>(kRowBands) * kRowStride, 0.0), b(a) {
    s[0] = 0.0;
    for (int m = 1; m < kRowBands; ++m) s[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int m = 0; m < kRowBands; ++m)
      for (int l = m + 2; l < kRowBands; ++l) {
        const double ll = l, mm = m;
        const double den = ll * ll - mm * mm;
        a[m * kRowStride + l] = std::sqrt((4.0 * ll * ll - 1.0) / den);
        b[m * kRowStride + l] =
            std::sqrt((2.0 * ll + 1.0) * ((ll - 1.0) * (ll - 1.0) - mm * mm) / ((2.0 * ll - 3.0) * den));
      }
    af.assign(a.begin(), a.end());
    bf.assign(b.begin(), b.end());
    for (int m = 0; m < kRowBands; ++m) sf[m] = static_cast<float>(s[m]);
  }
  template <class T>
  const T* ta() const {
    if constexpr (sizeof(T) == sizeof(double)) return a.data();
    else return af.data();
  }
  template <class T>
  const T* tb() const {
    if constexpr (sizeof(T) == sizeof(double)) return b.data();
    else return bf.data();
  }
  template <class T>
  const T* ts() const {
    if constexpr (sizeof(T) == sizeof(double)) return s;
    else return sf;
  }
};

const ColTable& col_table() {
  static const ColTable* t = new ColTable();  // built once, never freed
  return *t;
}

// One pass over `count` <= kLanes directions given by cos t, sin t (>= 0), cos p, sin p.
// Returns a bit mask of the lanes whose last sectoral term leaves the plain range
// (small_sectoral): their values are written too (finite, but not accurate) and must be
// replaced by the caller.
template <int NB, bool Full, class T, class VB>
__attribute__((always_inline)) inline unsigned batch_pass(int bands_rt, VB ct, VB st, VB c1, VB s1, const T* ta,
                                                      const T* tb, const T* ts, T* out, std::size_t stride,
                                                      int count) {
  const int bands = NB > 0 ? NB : bands_rt;
  const T y00 = static_cast<T>(1.0 / std::sqrt(4.0 * std::numbers::pi));
  VB p = VB{} + y00;
  for (int m = 1; m < bands; ++m) p = p * (-ts[m] * st);
  // |P_mm| is unimodal in m (the factors s_m sin t decrease), so the last one is the smallest
  const T small = small_sectoral<T>();
  unsigned bad = 0;
  for (int k = 0; k < count; ++k)
    if (st[k] > 0 && std::abs(p[k]) < small) {
      bad |= 1u << k;
      st[k] = 0;  // the lane's m > 0 terms become exact zeros, not subnormals (which are slow)
    }
  const T r2 = static_cast<T>(std::numbers::sqrt2);
  const std::size_t step = 2 * stride;  // row l(l+1) -> (l+1)(l+2): + 2(l+1) rows
  VB pmm = VB{} + y00, cm = VB{} + T(1), sm = VB{};
  {  // m = 0
    T* o = out;  // row l(l+1)
    std::size_t inc = step;
    VB p2 = pmm;
    put<Full>(o, p2, count);
    if (bands < 2) return bad;
    VB p1 = (static_cast<T>(std::sqrt(3.0)) * ct) * p2;
    o += inc;
    inc += step;
    put<Full>(o, p1, count);
    const T* a = ta;
    const T* b = tb;
    for (int l = 2; l < bands; ++l) {
      const VB q = a[l] * ct * p1 - b[l] * p2;
      o += inc;
      inc += step;
      put<Full>(o, q, count);
      p2 = p1;
      p1 = q;
    }
  }
  for (int m = 1; m < bands; ++m) {
    pmm = pmm * (-ts[m] * st);
    const VB cn = cm * c1 - sm * s1;
    sm = sm * c1 + cm * s1;
    cm = cn;
    const VB C = r2 * cm, S = r2 * sm;
    const std::size_t mo = static_cast<std::size_t>(m) * stride;
    T* o = out + static_cast<std::size_t>(m) * (m + 1) * stride;  // row m(m+1), centre of band m
    std::size_t inc = static_cast<std::size_t>(m + 1) * step;
    VB p2 = pmm;
    put<Full>(o + mo, p2 * C, count);
    put<Full>(o - mo, p2 * S, count);
    if (m + 1 >= bands) break;
    VB p1 = (static_cast<T>(std::sqrt(2.0 * m + 3.0)) * ct) * p2;
    o += inc;
    inc += step;
    put<Full>(o + mo, p1 * C, count);
    put<Full>(o - mo, p1 * S, count);
    const T* a = ta + m * kRowStride;  // column m of the column-major table
    const T* b = tb + m * kRowStride;
    for (int l = m + 2; l < bands; ++l) {
      const VB q = a[l] * ct * p1 - b[l] * p2;
      o += inc;
      inc += step;
      put<Full>(o + mo, q * C, count);
      put<Full>(o - mo, q * S, count);
      p2 = p1;
      p1 = q;
    }
  }
  return bad;
}

void evaluate_unit(int bands, const glm::dvec3& d, double* out);

// Set-up of a pass: lanes k < count from (xs, ys, zs), the rest (0, 0, 1).
// cos t = z/|d|, sin t = h/|d|, cos p = x/h, sin p = y/h with h = sqrt(x^2 + y^2)
// (cos p = 1, sin p = 0 at h = 0), as vector operations. A float direction whose squares
// would leave the normal float range is first scaled by a power of two (exact).
template <class T, class VB>
__attribute__((always_inline)) inline void batch_setup(const T* xs, const T* ys, const T* zs, int count, VB& ct,
                                                       VB& st, VB& c1, VB& s1) {
  constexpr int kLanes = sizeof(VB) / sizeof(T);
  alignas(64) T X[kLanes] = {}, Y[kLanes] = {}, Z[kLanes];
  for (int k = 0; k < kLanes; ++k) Z[k] = 1;
  for (int k = 0; k < count; ++k) {
    X[k] = xs[k];
    Y[k] = ys[k];
    Z[k] = zs[k];
    if constexpr (sizeof(T) == sizeof(float)) {
      const float big = std::max({std::abs(X[k]), std::abs(Y[k]), std::abs(Z[k])});
      if (big > 0x1p60f || big < 0x1p-60f) {
        const int e = std::ilogb(big);
        X[k] = std::ldexp(X[k], -e);
        Y[k] = std::ldexp(Y[k], -e);
        Z[k] = std::ldexp(Z[k], -e);
      }
    }
  }
  alignas(64) T H[kLanes], N[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    const T h2 = X[k] * X[k] + Y[k] * Y[k];
    H[k] = std::sqrt(h2);
    N[k] = std::sqrt(h2 + Z[k] * Z[k]);
  }
  VB x, y, z, h, n;
  std::memcpy(&x, X, sizeof x);
  std::memcpy(&y, Y, sizeof y);
  std::memcpy(&z, Z, sizeof z);
  std::memcpy(&h, H, sizeof h);
  std::memcpy(&n, N, sizeof n);
  const VB one = VB{} + T(1);
  const VB in = one / n, ih = one / h;
  ct = z * in;
  st = h * in;
  c1 = h > 0 ? x * ih : one;
  s1 = h > 0 ? y * ih : VB{};
}

template <int NB, int kLanes, class T>
__attribute__((always_inline)) inline void batch_all(int bands, std::size_t n, const T* xs, const T* ys,
                                                     const T* zs, T* out, std::size_t stride) {
  using VB = typename Lane<T, kLanes>::V;
  const ColTable& t = col_table();
  const T* ta = t.ta<T>();
  const T* tb = t.tb<T>();
  const T* ts = t.ts<T>();
  // Where every output row has the same alignment but not on a vector boundary, the
  // first pass stores unaligned and the next starts at the first aligned direction
  // `head` (directions head..kLanes-1 are computed twice; the second pass's values
  // stand): every later store is aligned (a store that straddles two cache lines costs
  // about twice as much). (A loop, not a lambda: a lambda would not inherit the target
  // of the clone.)
  std::size_t head = 0;
  constexpr std::size_t kBytes = kLanes * sizeof(T);
  if (n >= 4 * kLanes && (stride * sizeof(T)) % kBytes == 0) {
    const std::size_t mis = reinterpret_cast<std::uintptr_t>(out) % kBytes;
    if (mis != 0 && mis % sizeof(T) == 0) head = (kBytes - mis) / sizeof(T);
  }
  for (std::size_t k0 = 0; k0 < n; k0 = (k0 == 0 && head > 0) ? head : k0 + kLanes) {
    const int count = static_cast<int>(std::min<std::size_t>(kLanes, n - k0));
    VB ct, st, c1, s1;
    batch_setup(xs + k0, ys + k0, zs + k0, count, ct, st, c1, s1);
    T* o = out + k0;
    const unsigned bad = count == kLanes
                             ? batch_pass<NB, true>(bands, ct, st, c1, s1, ta, tb, ts, o, stride, count)
                             : batch_pass<NB, false>(bands, ct, st, c1, s1, ta, tb, ts, o, stride, count);
    if (bad != 0) {  // lanes near a pole (small_sectoral): extended range in double, one by one
      std::vector<double> y(sh_count(bands));
      for (int k = 0; k < count; ++k) {
        if (!(bad >> k & 1u)) continue;
        evaluate_unit(bands, checked_direction({xs[k0 + k], ys[k0 + k], zs[k0 + k]}, "evaluate_batch"),
                      y.data());
        for (int i = 0; i < sh_count(bands); ++i) o[i * stride + k] = static_cast<T>(y[i]);
      }
    }
  }
}

ATMOSH_DISPATCH_NO_ERRNO
void evaluate_batch_kernel(int bands, std::size_t n, const double* xs, const double* ys, const double* zs,
                           double* out, std::size_t stride) {
  batch_all<0, 4>(bands, n, xs, ys, zs, out, stride);
}

ATMOSH_DISPATCH_NO_ERRNO
void evaluate_batch_kernel(int bands, std::size_t n, const float* xs, const float* ys, const float* zs,
                             float* out, std::size_t stride) {
  batch_all<0, 8>(bands, n, xs, ys, zs, out, stride);
}

#if ATMOSH_HAS_DISPATCH
ATMOSH_TARGET_AVX512 __attribute__((optimize("no-math-errno"))) void evaluate_batch_kernel_avx512(
    int bands, std::size_t n, const double* xs, const double* ys, const double* zs, double* out, std::size_t stride) {
  batch_all<0, 8>(bands, n, xs, ys, zs, out, stride);
}

ATMOSH_TARGET_AVX512 __attribute__((optimize("no-math-errno"))) void evaluate_batch_kernel_avx512(
    int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out, std::size_t stride) {
  batch_all<0, 16>(bands, n, xs, ys, zs, out, stride);
}
#endif

void evaluate_unit(int bands, const glm::dvec3& d, double* out) {
  if (bands <= kFastMaxBands) {  // straight-line code (fast.hpp); d is of unit length here
    evaluate_fast(bands, d.x, d.y, d.z, out);
    return;
  }
  if (bands < kRowMinBands) {  // few bands: the column path has less set-up
    static const LegendreTable* small = new LegendreTable(kRowBands);
    evaluate_unit_columns(bands, d, out, *small);
    return;
  }
  if (bands <= kRowBands) {
    const RowTable& t = row_table();
    const double rho = std::sqrt(d.x * d.x + d.y * d.y);
    double c1 = 1.0, s1 = 0.0;  // cos p, sin p
    if (rho > 0.0) {
      c1 = d.x / rho;
      s1 = d.y / rho;
    }
    // sectoral terms; if one leaves the plain double range (sin^m t below ~1e-240:
    // within 1e-16 rad of a pole at L = 16, 0.013 rad at L = 128), fall back to the
    // extended-range column path.
    double pmm[kRowBands];
    detail::XNum x{1.0 / std::sqrt(4.0 * std::numbers::pi), 0};
    pmm[0] = x.mant;
    bool plain = true;
    for (int m = 1; m < bands; ++m) {
      x = detail::next_sectoral(x, t.s[m], rho);
      pmm[m] = x.mant;
      plain = plain && x.exp == 0;
    }
    if (plain) {
      evaluate_rows_kernel(bands, d.z, c1, s1, pmm, t.a.data(), t.b.data(), out);
      return;
    }
  }
  evaluate_unit_columns(bands, d, out, *legendre_table(bands));
}
}  // namespace

void evaluate(int bands, const glm::dvec3& dir, double* out) {
  if (bands >= 1 && bands <= kFastMaxBands) {
    // the common small-band case: one reciprocal square root, then the straight-line code;
    // zero, NaN, infinite or over/underflowing lengths go through the checked path
    const double r2 = dir.x * dir.x + dir.y * dir.y + dir.z * dir.z;
    if (r2 > 0x1p-900 && r2 < 0x1p+900) {
      const double inv = 1.0 / std::sqrt(r2);
      evaluate_fast(bands, dir.x * inv, dir.y * inv, dir.z * inv, out);
      return;
    }
  }
  check_bands(bands, "evaluate");
  const glm::dvec3 d = checked_direction(dir, "evaluate");
  evaluate_unit(bands, d, out);
}

namespace {
template <class T>
void check_batch(int bands, std::size_t n, const T* xs, const T* ys, const T* zs, std::size_t stride) {
  check_bands(bands, "evaluate_batch", kRowBands);
  if (stride < n)
    throw InputError("evaluate_batch: stride " + std::to_string(stride) + " is less than n = " + std::to_string(n));
  for (std::size_t k = 0; k < n; ++k) {
    const double x = xs[k], y = ys[k], z = zs[k];  // squares in double: no float overflow
    const double r2 = x * x + y * y + z * z;
    if (!(r2 > 0.0 && r2 < std::numeric_limits<double>::infinity()))
      throw InputError("evaluate_batch: direction " + std::to_string(k) + " (" + std::to_string(x) + ", " +
                       std::to_string(y) + ", " + std::to_string(z) + ") is zero, not finite or too long");
  }
}

// Checks, then the AVX-512 kernel where the CPU has it, else the AVX2/baseline clones.
template <class T>
void run_batch(int bands, std::size_t n, const T* xs, const T* ys, const T* zs, T* out, std::size_t stride) {
  check_batch(bands, n, xs, ys, zs, stride);
#if ATMOSH_HAS_DISPATCH
  if (cpu_has_avx512()) {
    evaluate_batch_kernel_avx512(bands, n, xs, ys, zs, out, stride);
    return;
  }
#endif
  evaluate_batch_kernel(bands, n, xs, ys, zs, out, stride);
}
}  // namespace

void evaluate_batch(int bands, std::size_t n, const double* xs, const double* ys, const double* zs, double* out,
                    std::size_t stride) {
  run_batch(bands, n, xs, ys, zs, out, stride);
}

void evaluate_batch(int bands, std::size_t n, const float* xs, const float* ys, const float* zs, float* out,
                    std::size_t stride) {
  run_batch(bands, n, xs, ys, zs, out, stride);
}

std::vector<double> evaluate(int bands, const glm::dvec3& dir) {
  check_bands(bands, "evaluate");
  std::vector<double> y(sh_count(bands));
  evaluate(bands, dir, y.data());
  return y;
}

glm::dvec3 direction_from_angles(double theta, double phi) {
  const double st = std::sin(theta);
  return {st * std::cos(phi), st * std::sin(phi), std::cos(theta)};
}

void evaluate_angles(int bands, double theta, double phi, double* out) {
  if (!std::isfinite(theta) || !std::isfinite(phi))
    throw InputError("evaluate_angles: angle is not finite");
  check_bands(bands, "evaluate_angles");
  // use |sin t| and sign-adjusted phi so that theta outside [0, pi] still works
  glm::dvec3 d = direction_from_angles(theta, phi);
  evaluate_unit(bands, d, out);
}

double reconstruct(int bands, const double* coeffs, const glm::dvec3& dir) {
  const int n = sh_count(bands);
  double s = 0.0;
  if (bands >= 1 && bands <= kFastMaxBands) {  // on the stack (checks as in evaluate)
    const double r2 = dir.x * dir.x + dir.y * dir.y + dir.z * dir.z;
    glm::dvec3 d;
    if (r2 > 0x1p-900 && r2 < 0x1p+900)
      d = dir * (1.0 / std::sqrt(r2));
    else
      d = checked_direction(dir, "reconstruct");
    double y[kFastMaxBands * kFastMaxBands];
    evaluate_fast(bands, d.x, d.y, d.z, y);
    for (int i = 0; i < n; ++i) s += coeffs[i] * y[i];
    return s;
  }
  check_bands(bands, "reconstruct");
  const glm::dvec3 d = checked_direction(dir, "reconstruct");
  // a per-thread buffer, grown to the largest band count seen: no allocation per call
  thread_local std::vector<double> y;
  if (y.size() < static_cast<std::size_t>(n)) y.resize(n);
  evaluate_unit(bands, d, y.data());
  for (int i = 0; i < n; ++i) s += coeffs[i] * y[i];
  return s;
}

}  // namespace atmosh::sh
