// SH rotation: z-rotations in closed form and the real-basis Ry(90 deg) matrix from
// Wigner d^l(pi/2) by a stable recurrence.
#include "atmosh/sh/rotation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/dispatch.hpp"

namespace atmosh::sh {

namespace {

constexpr double kPi = std::numbers::pi;

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // V4 is passed only between inlined internal functions
#endif
// 4 doubles: one AVX register in the AVX2/FMA clone, two SSE2 registers otherwise. Its
// alignment differs between the two (16 / 32 bytes), so V4 is used for values only and
// memory is always plain doubles, read and written through memcpy.
typedef double V4 __attribute__((vector_size(4 * sizeof(double))));
typedef long long M4 __attribute__((vector_size(4 * sizeof(long long))));
// Lane permutation of two V4 (indices 0..3: a, 4..7: b).
#if defined(__clang__)
#define ATMOSH_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
#define ATMOSH_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, M4{i0, i1, i2, i3})
#endif

// Real-basis Ry(90) of band l in parity-split, tiled, half storage.
//
// Write the coefficients of band l as cosine parts c_m (m = 0..l) and sine parts s_m
// (m = 1..l), each split by the parity of m. In the real basis Ry(90) maps cosine parts
// to cosine parts and sine parts to sine parts; the cosine block C[m'][m] is non-zero only
// for m + m' + l even, the sine block S[m'][m] only for m + m' + l odd. The Wigner
// symmetry d_{m m'}(pi/2) = (-1)^(m'-m) d_{m' m}(pi/2) (the real-basis weights are
// symmetric in m, m') gives C^T = (-1)^l C and S^T = (-1)^(l+1) S. So each band consists of
//   * two symmetric blocks (even m -> even m, odd m -> odd m): C for even l, S for odd l;
//   * one rectangular block X (even rows m', odd columns m) together with its negative
//     transpose (odd rows, even columns): S for even l, C for odd l.
// Only the lower triangle of each symmetric block and X once are stored, half of the
// non-zero entries, in 4 x 4 tiles (4 columns of 4 rows, one V4 per column), padded with
// zeros. Every stored element is used twice per application (y_i += a_ij x_j and
// y_j += a_ij x_i), so the bytes streamed per application halve and the arithmetic stays.
// The even-m sine vector carries a zero slot for m = 0 (matrix row and column zero), so
// that s_m and c_m sit at the same index: the z-rotations become elementwise.
//
// Tile k of a block: doubles [16 k, 16 k + 16), column-major (4 columns of 4 rows).
struct BandY90 {
  int l = 0;
  int te = 0, to = 0;              // tiles per even-m / odd-m vector: ceil(ne / 4), ceil(no / 4)
  std::vector<double> store;       // the three blocks, each starting 64-byte aligned
  const double* rect = nullptr;    // X: te x to tiles, column groups outer, row groups inner
  const double* sym_e = nullptr;   // even -> even block: tiles (r, J), r >= J, J outer
  const double* sym_o = nullptr;   // odd -> odd block
};

// d^l_{m'm}(pi/2) for 0 <= m, m' <= l into d[m' * (l+1) + m] (column by column, extended
// range: any l).
void wigner_half_pi_columns(int l, std::vector<double>& d) {
  const int n = l + 1;
  d.assign(static_cast<std::size_t>(n) * n, 0.0);
  std::vector<double> q(n + 1, 0.0);  // q[k] = sqrt((l-k)(l+k+1))
  for (int k = 0; k <= l; ++k) q[k] = std::sqrt(static_cast<double>(l - k) * (l + k + 1));
  // starting values d_{l,m} = (-1)^(l-m) sqrt(C(2l,l+m)) 2^-l as mant * 2^exp
  double mant = 1.0;
  int ex = -l;
  for (int m = l; m >= 0; --m) {
    if (m < l) {
      mant *= -std::sqrt(static_cast<double>(l + m + 1) / (l - m));
      int e2 = 0;
      mant = std::frexp(mant, &e2);
      ex += e2;
    }
    // recurrence in m' from l down to m:
    // d_{m'-1} = (2 m d_{m'} - q[m'] d_{m'+1}) / q[m'-1]
    double p1 = mant, p2 = 0.0;  // p1 = d_{m'}, p2 = d_{m'+1}
    int e = ex;
    auto value = [&](double v) { return e == 0 ? v : std::ldexp(v, e); };
    d[static_cast<std::size_t>(l) * n + m] = value(p1);
    for (int mp = l; mp > m; --mp) {
      const double p0 = (2.0 * m * p1 - q[mp] * p2) / q[mp - 1];
      p2 = p1;
      p1 = p0;
      if (e < 0 && std::abs(p1) > 0x1p+200) {
        const int k = std::min(-e, 200);
        p1 = std::ldexp(p1, -k);
        p2 = std::ldexp(p2, -k);
        e += k;
      }
      d[static_cast<std::size_t>(mp - 1) * n + m] = value(p1);
    }
    // symmetry d_{m m'} = (-1)^(m'-m) d_{m' m}
    for (int mp = m + 1; mp <= l; ++mp)
      d[static_cast<std::size_t>(m) * n + mp] = ((mp - m) & 1 ? -1.0 : 1.0) * d[static_cast<std::size_t>(mp) * n + m];
  }
}

// The same, row by row: row m'-1 from rows m' and m'+1 for all m < m' at once (contiguous,
// vectorised; reciprocals instead of divisions), the starting row d_{l,m} scaled by 2^S
// so that its smallest value 2^(S-l) stays a normal double (S = 600 from l = 900 on; the
// values only grow from the starting row inwards), the upper triangle by symmetry.
// For l > 1600 the columns path (per-column exponents).
ATMOSH_DISPATCH_NO_ERRNO
void wigner_half_pi(int l, std::vector<double>& d, bool fill_upper) {
  if (l > 1600) {
    wigner_half_pi_columns(l, d);
    return;
  }
  const int n = l + 1;
  d.resize(static_cast<std::size_t>(n) * n);
  std::vector<double> q(n + 1, 0.0), iq(n + 1, 0.0), twom(n);
  for (int k = 0; k <= l; ++k) {
    q[k] = std::sqrt(static_cast<double>(l - k) * (l + k + 1));
    iq[k] = q[k] > 0.0 ? 1.0 / q[k] : 0.0;
    twom[k] = 2.0 * k;
  }
  const int S = l >= 900 ? 600 : 0;
  double* top = d.data() + static_cast<std::size_t>(l) * n;
  top[l] = std::ldexp(1.0, S - l);
  for (int m = l - 1; m >= 0; --m) top[m] = -top[m + 1] * std::sqrt(static_cast<double>(l + m + 1) / (l - m));
  std::vector<double> zero(n, 0.0);
  for (int mp = l; mp >= 1; --mp) {
    const double* r1 = d.data() + static_cast<std::size_t>(mp) * n;
    const double* r2 = mp < l ? d.data() + static_cast<std::size_t>(mp + 1) * n : zero.data();
    double* r0 = d.data() + static_cast<std::size_t>(mp - 1) * n;
    const double qm = q[mp], iqm = iq[mp - 1];
    for (int m = 0; m < mp; ++m) r0[m] = (twom[m] * r1[m] - qm * r2[m]) * iqm;
  }
  if (S != 0) {
    const double down = std::ldexp(1.0, -S);
    for (int mp = 0; mp <= l; ++mp) {
      double* r = d.data() + static_cast<std::size_t>(mp) * n;
      for (int m = 0; m <= mp; ++m) r[m] *= down;
    }
  }
  if (!fill_upper) return;
  // upper triangle: d_{m m'} = (-1)^(m'-m) d_{m' m}, in blocks (both matrices stay in cache)
  constexpr int kB = 32;
  for (int i0 = 0; i0 < n; i0 += kB)
    for (int j0 = i0; j0 < n; j0 += kB)
      for (int mp = j0; mp < std::min(n, j0 + kB); ++mp)
        for (int m = i0; m < std::min(mp, i0 + kB); ++m)
          d[static_cast<std::size_t>(m) * n + mp] = ((mp - m) & 1 ? -1.0 : 1.0) * d[static_cast<std::size_t>(mp) * n + m];
}

void build_band(int l, BandY90& out) {
  thread_local std::vector<double> d;  // reused from band to band (no zeroing)
  wigner_half_pi(l, d, false);         // lower triangle (m <= m'); the rest by symmetry
  const int n = l + 1;
  auto D = [&](int mp, int m) {
    return mp >= m ? d[static_cast<std::size_t>(mp) * n + m]
                   : ((m - mp) & 1 ? -1.0 : 1.0) * d[static_cast<std::size_t>(m) * n + mp];
  };
  const double r2 = std::numbers::sqrt2;
  // real-basis entries (zero outside the checkerboard and for the m = 0 sine slot)
  auto cval = [&](int mp, int m) {
    if (m > l || mp > l || ((l + mp + m) & 1)) return 0.0;
    if (mp == 0 && m == 0) return D(0, 0);
    if (mp == 0 || m == 0) return r2 * D(mp, m);
    return 2.0 * D(mp, m);
  };
  auto sval = [&](int mp, int m) {
    if (m > l || mp > l || m == 0 || mp == 0 || !((l + mp + m) & 1)) return 0.0;
    return 2.0 * D(mp, m);
  };
  const bool even = (l & 1) == 0;
  // block element (i, j): even index i <-> m = 2i, odd index i <-> m = 2i + 1
  auto sym_e = [&](int i, int j) { return even ? cval(2 * i, 2 * j) : sval(2 * i, 2 * j); };
  auto sym_o = [&](int i, int j) { return even ? cval(2 * i + 1, 2 * j + 1) : sval(2 * i + 1, 2 * j + 1); };
  auto rect = [&](int i, int j) { return even ? sval(2 * i, 2 * j + 1) : cval(2 * i, 2 * j + 1); };
  const int ne = l / 2 + 1, no = (l + 1) / 2;
  out.l = l;
  out.te = (ne + 3) / 4;
  out.to = (no + 3) / 4;
  const std::size_t nx = 16 * static_cast<std::size_t>(out.te) * out.to;
  const std::size_t nse = 8 * static_cast<std::size_t>(out.te) * (out.te + 1);
  const std::size_t nso = 8 * static_cast<std::size_t>(out.to) * (out.to + 1);
  out.store.assign(nx + nse + nso + 8, 0.0);
  double* p = out.store.data();
  while (reinterpret_cast<std::uintptr_t>(p) % 64 != 0) ++p;
  auto tile = [&p](int r, int J, const auto& f) {
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 4; ++i) *p++ = f(4 * r + i, 4 * J + k);
  };
  auto in_range = [](int nrow, int ncol, const auto& f) {
    return [=](int i, int j) { return i < nrow && j < ncol ? f(i, j) : 0.0; };
  };
  const auto fe = in_range(ne, ne, sym_e);
  const auto fo = in_range(no, no, sym_o);
  const auto fx = in_range(ne, no, rect);
  out.rect = p;
  for (int J = 0; J < out.to; ++J)
    for (int r = 0; r < out.te; ++r) tile(r, J, fx);
  out.sym_e = p;
  for (int J = 0; J < out.te; ++J)
    for (int r = J; r < out.te; ++r) tile(r, J, fe);
  out.sym_o = p;
  for (int J = 0; J < out.to; ++J)
    for (int r = J; r < out.to; ++r) tile(r, J, fo);
}

constexpr int kDefaultCacheBands = 256;  // ~22 MB of band matrices
constexpr int kMaxBands = 8192;

struct Y90Cache {
  std::mutex mu;
  std::atomic<int> ready{1};                  // bands [1, ready) built
  std::atomic<int> limit{kDefaultCacheBands};  // bands below this are cached
  std::unique_ptr<BandY90> band[kMaxBands];
};

Y90Cache& y90_cache() {
  static Y90Cache c;
  return c;
}

// Bands 1..min(n, limit)-1 built (once, in order; looked up without a lock afterwards).
const std::unique_ptr<BandY90>* cached_bands(int n) {
  Y90Cache& c = y90_cache();
  n = std::min(n, c.limit.load(std::memory_order_acquire));
  if (c.ready.load(std::memory_order_acquire) < n) {
    std::lock_guard<std::mutex> lock(c.mu);
    int l = c.ready.load(std::memory_order_relaxed);
    for (; l < n; ++l) {
      auto b = std::make_unique<BandY90>();
      build_band(l, *b);
      c.band[l] = std::move(b);
    }
    if (n > c.ready.load(std::memory_order_relaxed)) c.ready.store(n, std::memory_order_release);
  }
  return c.band;
}

#define ATMOSH_INLINE inline __attribute__((always_inline))

ATMOSH_INLINE V4 splat(double x) { return V4{x, x, x, x}; }
// Work vectors are plain doubles, read and written 4 at a time through memcpy.
ATMOSH_INLINE V4 load4(const double* p) {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
ATMOSH_INLINE void store4(double* p, V4 v) { std::memcpy(p, &v, sizeof v); }

// Lane k of the result: the sum of the lanes of t_k (fixed order).
ATMOSH_INLINE V4 hsum4(V4 t0, V4 t1, V4 t2, V4 t3) {
  const V4 a = ATMOSH_SHUFFLE(t0, t1, 0, 4, 2, 6) + ATMOSH_SHUFFLE(t0, t1, 1, 5, 3, 7);
  const V4 b = ATMOSH_SHUFFLE(t2, t3, 0, 4, 2, 6) + ATMOSH_SHUFFLE(t2, t3, 1, 5, 3, 7);
  return ATMOSH_SHUFFLE(a, b, 0, 1, 4, 5) + ATMOSH_SHUFFLE(a, b, 2, 3, 6, 7);
}

// One column group of off-diagonal tiles A_r (4 columns a0..a3 each), r = r0..r1-1:
// y_r += A_r b (b0..b3: x of the 4 columns, broadcast), t_k += a_k x_r (the transposed
// product, summed over lanes later). kFirst: y_r is not yet written (y_r = A_r b).
template <bool kFirst>
ATMOSH_INLINE void tile_column(const double*& T, int r0, int r1, V4 b0, V4 b1, V4 b2, V4 b3, const double* x,
                               double* y, V4& t0, V4& t1, V4& t2, V4& t3) {
  for (int r = r0; r < r1; ++r, T += 16) {
    const V4 a0 = load4(T), a1 = load4(T + 4), a2 = load4(T + 8), a3 = load4(T + 12);
    V4 acc;
    if constexpr (kFirst) acc = a0 * b0;
    else acc = load4(y + 4 * r) + a0 * b0;
    acc += a1 * b1;
    acc += a2 * b2;
    acc += a3 * b3;
    store4(y + 4 * r, acc);
    const V4 u = load4(x + 4 * r);
    t0 += a0 * u;
    t1 += a1 * u;
    t2 += a2 * u;
    t3 += a3 * u;
  }
}

// y = A x for a symmetric block stored as lower tiles (nt x nt tiles).
ATMOSH_INLINE void sym_mv(const double* T, int nt, const double* x, double* y) {
  for (int J = 0; J < nt; ++J) {
    const V4 xj = load4(x + 4 * J);
    const V4 b0 = splat(xj[0]), b1 = splat(xj[1]), b2 = splat(xj[2]), b3 = splat(xj[3]);
    V4 diag = load4(T) * b0;  // diagonal tile (symmetric, stored whole)
    diag += load4(T + 4) * b1;
    diag += load4(T + 8) * b2;
    diag += load4(T + 12) * b3;
    T += 16;
    V4 t0 = {0, 0, 0, 0}, t1 = t0, t2 = t0, t3 = t0;
    if (J == 0) {
      tile_column<true>(T, 1, nt, b0, b1, b2, b3, x, y, t0, t1, t2, t3);
      store4(y, diag + hsum4(t0, t1, t2, t3));
    } else {
      tile_column<false>(T, J + 1, nt, b0, b1, b2, b3, x, y, t0, t1, t2, t3);
      store4(y + 4 * J, load4(y + 4 * J) + diag + hsum4(t0, t1, t2, t3));
    }
  }
}

// y1 = X x2 (tr row tiles), y2 = -X^T x1 (tc column tiles).
ATMOSH_INLINE void rect_mv(const double* T, int tr, int tc, const double* x1, const double* x2, double* y1,
                           double* y2) {
  for (int J = 0; J < tc; ++J) {
    const V4 xj = load4(x2 + 4 * J);
    const V4 b0 = splat(xj[0]), b1 = splat(xj[1]), b2 = splat(xj[2]), b3 = splat(xj[3]);
    V4 t0 = {0, 0, 0, 0}, t1 = t0, t2 = t0, t3 = t0;
    if (J == 0) tile_column<true>(T, 0, tr, b0, b1, b2, b3, x1, y1, t0, t1, t2, t3);
    else tile_column<false>(T, 0, tr, b0, b1, b2, b3, x1, y1, t0, t1, t2, t3);
    store4(y2 + 4 * J, -hsum4(t0, t1, t2, t3));
  }
}

// Parity-split band: cos even, sin even (slot 0 for m = 0, zero), cos odd, sin odd.
struct Split {
  double *ce, *se, *co, *so;
};

// out = Ry(90) in.
ATMOSH_INLINE void apply_y90(const BandY90& B, const Split& in, const Split& out) {
  if ((B.l & 1) == 0) {
    sym_mv(B.sym_e, B.te, in.ce, out.ce);
    sym_mv(B.sym_o, B.to, in.co, out.co);
    rect_mv(B.rect, B.te, B.to, in.se, in.so, out.se, out.so);
  } else {
    rect_mv(B.rect, B.te, B.to, in.ce, in.co, out.ce, out.co);
    sym_mv(B.sym_e, B.te, in.se, out.se);
    sym_mv(B.sym_o, B.to, in.so, out.so);
  }
}

// (c, s) <- (c cos - s sin, c sin + s cos), elementwise over n vectors.
ATMOSH_INLINE void zrot_split(double* c, double* s, const double* cs, const double* sn, int n) {
  for (int i = 0; i < 4 * n; i += 4) {
    const V4 a = load4(c + i), b = load4(s + i), C = load4(cs + i), S = load4(sn + i);
    store4(c + i, a * C - b * S);
    store4(s + i, a * S + b * C);
  }
}

// cos/sin(m angle) split by parity: [cos, m = 0, 2, 4, .. | cos, m = 1, 3, ..] (nh each),
// the same for sin; padded with cos = 1, sin = 0.
struct ZTable {
  const double *ce, *se, *co, *so;
};

// (c, s) rotated by the angles of the table entries cs, sn (4 lanes).
ATMOSH_INLINE void rot(V4 c, V4 s, const double* cs, const double* sn, V4& c2, V4& s2) {
  const V4 C = load4(cs), S = load4(sn);
  c2 = c * C - s * S;
  s2 = c * S + s * C;
}
ATMOSH_INLINE void rot_store(V4 c, V4 s, const double* cs, const double* sn, double* pc, double* ps) {
  V4 c2, s2;
  rot(c, s, cs, sn, c2, s2);
  store4(pc, c2);
  store4(ps, s2);
}

// z-rotation of a split band (te / to vectors).
ATMOSH_INLINE void zrot_band(const Split& v, const ZTable& z, int te, int to) {
  zrot_split(v.ce, v.se, z.ce, z.se, te);
  zrot_split(v.co, v.so, z.co, z.so, to);
}

// ---- Ry(90) on the fly ---------------------------------------------------------------
// Bands from kStreamFrom to kStreamTo are not stored: each application runs the row
// recurrence of wigner_half_pi again (the same rows, bit for bit) and uses every row as
// it is made. In the real basis, with x~ = L x, L = diag(1/sqrt2 at m = 0, 1 elsewhere),
// the cosine block is C = 2 L d^c L and the sine block S = 2 d^s, where d^c (d^s) keeps
// the entries d_{m'm}(pi/2) with l + m' + m even (odd); the upper triangles follow from
// C^T = (-1)^l C and S^T = -(-1)^l S. So row m' (m <= m') of d gives, in one pass over
// its two parity halves, the row sums y~_{m'} += sum_m d_{m'm} x~_m and the transposed
// terms y~_m += sigma d_{m'm} x~_{m'} (m < m'), and makes row m' - 1. Per entry: three
// operations of recurrence and two multiply-adds; nothing is read from memory but three
// rows and the two vectors of the band (a few tens of kB). Rows are stored parity-split
// (even m | odd m), like the vectors, so that the halves are contiguous.
constexpr int kStreamFrom = 256;   // the default cache holds the bands below
constexpr int kStreamTo = 1600;    // wigner_half_pi's row path (one scale factor per band)

struct StreamWork {
  int stride = 0;                  // doubles per half row (multiple of 4)
  std::vector<double> rows;        // 3 rows of 2 halves, + 4 for alignment
  std::vector<double> q, iq;       // sqrt((l - k)(l + k + 1)) and its reciprocal
  std::vector<double> tw;          // 2m, parity-split: [even m | odd m], stride each
  explicit StreamWork(int bands) {
    stride = 4 * (((bands + 2) / 2 + 4) / 4 + 1);
    rows.assign(6 * static_cast<std::size_t>(stride) + 4, 0.0);
    q.assign(bands + 2, 0.0);
    iq.assign(bands + 2, 0.0);
    tw.assign(2 * static_cast<std::size_t>(stride), 0.0);
    for (int i = 0; i < stride; ++i) {
      tw[i] = 2.0 * (2 * i);
      tw[stride + i] = 2.0 * (2 * i + 1);
    }
  }
};

// out = Ry(90) in for band l (kStreamFrom <= l <= kStreamTo); in.ce[0] is scaled by
// 1/sqrt2 on the way (in is a work buffer). te / to: vectors of even / odd m.
ATMOSH_DISPATCH
void y90_stream(int l, int te, int to, StreamWork& sw, const Split& in, const Split& out) {
  const int stride = sw.stride;
  double* base = sw.rows.data();
  while (reinterpret_cast<std::uintptr_t>(base) % 32 != 0) ++base;
  double* r2 = base;               // row m' + 1
  double* r1 = base + 2 * stride;  // row m'
  double* r0 = base + 4 * stride;  // row m' - 1 (made now)
  std::fill(base, base + 6 * stride, 0.0);
  double* q = sw.q.data();
  double* iq = sw.iq.data();
  for (int k = 0; k <= l; ++k) {
    q[k] = std::sqrt(static_cast<double>(l - k) * (l + k + 1));
    iq[k] = q[k] > 0.0 ? 1.0 / q[k] : 0.0;
  }
  const int S = l >= 900 ? 600 : 0;
  // row l: d_{l,m} = (-1)^(l-m) sqrt(C(2l, l+m)) 2^-l, times 2^S
  {
    double t = std::ldexp(1.0, S - l);
    r1[(l & 1) * stride + (l >> 1)] = t;
    for (int m = l - 1; m >= 0; --m) {
      t = -t * std::sqrt(static_cast<double>(l + m + 1) / (l - m));
      r1[(m & 1) * stride + (m >> 1)] = t;
    }
  }
  in.ce[0] *= 1.0 / std::numbers::sqrt2;
  for (int i = 0; i < 4 * te; ++i) out.ce[i] = out.se[i] = 0.0;
  for (int i = 0; i < 4 * to; ++i) out.co[i] = out.so[i] = 0.0;
  const double sigma_c = (l & 1) ? -1.0 : 1.0;
  for (int mp = l; mp >= 0; --mp) {
    const V4 vq = splat(q[mp]), viq = splat(mp > 0 ? iq[mp - 1] : 0.0);
    for (int P = 0; P < 2; ++P) {
      const bool ctype = ((l + mp + P) & 1) == 0;
      const double* x = P ? (ctype ? in.co : in.so) : (ctype ? in.ce : in.se);
      double* y = P ? (ctype ? out.co : out.so) : (ctype ? out.ce : out.se);
      const double sigma = ctype ? sigma_c : -sigma_c;
      // the same type's vectors at m = m' (half m' & 1)
      const double* xd = (mp & 1) ? (ctype ? in.co : in.so) : (ctype ? in.ce : in.se);
      double* yd = (mp & 1) ? (ctype ? out.co : out.so) : (ctype ? out.ce : out.se);
      const double xmp = xd[mp >> 1];
      const int nv = std::min((mp + 2 - P) / 8 + 1, P ? to : te);
      const double* a = r1 + P * stride;
      const double* b = r2 + P * stride;
      double* c = r0 + P * stride;
      const double* tw = sw.tw.data() + P * stride;
      const V4 sx = splat(sigma * xmp);
      V4 d0 = splat(0.0), d1 = d0;
      int v = 0;
      for (; v + 1 < nv; v += 2) {
        const V4 a0 = load4(a + 4 * v), a1 = load4(a + 4 * v + 4);
        d0 += a0 * load4(x + 4 * v);
        d1 += a1 * load4(x + 4 * v + 4);
        store4(y + 4 * v, load4(y + 4 * v) + a0 * sx);
        store4(y + 4 * v + 4, load4(y + 4 * v + 4) + a1 * sx);
        store4(c + 4 * v, (load4(tw + 4 * v) * a0 - vq * load4(b + 4 * v)) * viq);
        store4(c + 4 * v + 4, (load4(tw + 4 * v + 4) * a1 - vq * load4(b + 4 * v + 4)) * viq);
      }
      for (; v < nv; ++v) {
        const V4 a0 = load4(a + 4 * v);
        d0 += a0 * load4(x + 4 * v);
        store4(y + 4 * v, load4(y + 4 * v) + a0 * sx);
        store4(c + 4 * v, (load4(tw + 4 * v) * a0 - vq * load4(b + 4 * v)) * viq);
      }
      const V4 d = d0 + d1;
      // the diagonal once: its transposed term comes off, the row sum goes on
      if (P == (mp & 1)) y[mp >> 1] -= a[mp >> 1] * sigma * xmp;
      yd[mp >> 1] += (d[0] + d[1]) + (d[2] + d[3]);
    }
    // row m' - 1 ends at m = m' - 1
    for (int m = mp; m <= mp + 2; ++m) r0[(m & 1) * stride + (m >> 1)] = 0.0;
    double* t = r2;
    r2 = r1;
    r1 = r0;
    r0 = t;
  }
  const double f = std::ldexp(2.0, -S);
  for (int i = 0; i < 4 * te; ++i) {
    out.ce[i] *= f;
    out.se[i] *= f;
  }
  for (int i = 0; i < 4 * to; ++i) {
    out.co[i] *= f;
    out.so[i] *= f;
  }
  out.ce[0] *= 1.0 / std::numbers::sqrt2;
  out.se[0] = 0.0;
}

ATMOSH_INLINE V4 reverse4(V4 a) { return ATMOSH_SHUFFLE(a, a, 3, 2, 1, 0); }

// Rotates band l: vout = Rz(alpha') Y90 Rz(beta') Y90 Rz(gamma') vin, with v[l + m].
// w, u: two Split buffers of whole tiles.
//
// Split layout from v: cosine parts c_m = v[l + m] (forward from v + l), sine parts
// s_m = v[l - m] (backward from v + l); 8 consecutive values of each direction give one
// vector of even m and one of odd m (the m = 0 sine slot is set to zero).
// Bp: the stored matrix of band l, or null: Ry(90) on the fly (y90_stream, work sw).
ATMOSH_DISPATCH
void rotate_band(int l, const BandY90* Bp, StreamWork* sw, const double* vin, double* vout, bool read_around,
                 const ZTable& za, const ZTable& zb, const ZTable& zg, const Split& w, const Split& u) {
  const int n = l + 1;           // n values in each direction, m = 0..l
  const struct {
    int te, to;
  } B{(l / 2 + 1 + 3) / 4, ((l + 1) / 2 + 3) / 4};
  const int nv = B.te;           // vectors of even m; odd m has B.to = nv or nv - 1
  const M4 iota = {0, 1, 2, 3};
  const V4 zero = {0, 0, 0, 0};
  for (int j = 0; j < nv; ++j) {
    const int k = 8 * j, left = n - k;  // values m = k .. k + 7 valid while < n
    V4 f0, f1, g0, g1;                  // f: c_{k..k+7}; g: s_{k..k+7}
    if (left >= 8 || read_around) {
      // whole vectors; past the band end they read the neighbouring bands (kept in
      // bounds by the caller), and those lanes are set to zero
      f0 = load4(vin + l + k);
      f1 = load4(vin + l + k + 4);
      g0 = reverse4(load4(vin + l - k - 3));
      g1 = reverse4(load4(vin + l - k - 7));
      if (left < 8) {
        const M4 lim = {left, left, left, left};
        f0 = iota < lim ? f0 : zero;
        g0 = iota < lim ? g0 : zero;
        f1 = iota + 4 < lim ? f1 : zero;
        g1 = iota + 4 < lim ? g1 : zero;
      }
    } else {
      double f[8] = {0, 0, 0, 0, 0, 0, 0, 0}, g[8] = {0, 0, 0, 0, 0, 0, 0, 0};
      for (int i = 0; i < left; ++i) {
        f[i] = vin[l + k + i];
        g[i] = vin[l - k - i];
      }
      f0 = load4(f);
      f1 = load4(f + 4);
      g0 = load4(g);
      g1 = load4(g + 4);
    }
    if (j == 0) g0 = ATMOSH_SHUFFLE(g0, zero, 4, 1, 2, 3);  // no sine part at m = 0
    // first z-rotation on the way
    const int i = 4 * j;
    rot_store(ATMOSH_SHUFFLE(f0, f1, 0, 2, 4, 6), ATMOSH_SHUFFLE(g0, g1, 0, 2, 4, 6), zg.ce + i, zg.se + i, w.ce + i,
              w.se + i);
    if (j < B.to)
      rot_store(ATMOSH_SHUFFLE(f0, f1, 1, 3, 5, 7), ATMOSH_SHUFFLE(g0, g1, 1, 3, 5, 7), zg.co + i, zg.so + i,
                w.co + i, w.so + i);
  }
  if (Bp) {
    apply_y90(*Bp, w, u);
    zrot_band(u, zb, B.te, B.to);
    apply_y90(*Bp, u, w);
  } else {
    y90_stream(l, B.te, B.to, *sw, w, u);
    zrot_band(u, zb, B.te, B.to);
    y90_stream(l, B.te, B.to, *sw, u, w);
  }
  // back to v[l + m]: sine parts first, so that the m = 0 slot ends as c_0
  for (int j = nv - 1; j >= 0; --j) {
    const int k = 8 * j, left = n - k;
    // last z-rotation on the way
    const int i = 4 * j;
    V4 ce, se, co = zero, so = zero;
    rot(load4(w.ce + i), load4(w.se + i), za.ce + i, za.se + i, ce, se);
    if (j < B.to) rot(load4(w.co + i), load4(w.so + i), za.co + i, za.so + i, co, so);
    const V4 f0 = ATMOSH_SHUFFLE(ce, co, 0, 4, 1, 5), f1 = ATMOSH_SHUFFLE(ce, co, 2, 6, 3, 7);
    const V4 g0 = ATMOSH_SHUFFLE(se, so, 0, 4, 1, 5), g1 = ATMOSH_SHUFFLE(se, so, 2, 6, 3, 7);
    if (left >= 8) {
      store4(vout + l - k - 3, reverse4(g0));
      store4(vout + l - k - 7, reverse4(g1));
      store4(vout + l + k, f0);
      store4(vout + l + k + 4, f1);
    } else {
      double f[8], g[8];
      store4(f, f0);
      store4(f + 4, f1);
      store4(g, g0);
      store4(g + 4, g1);
      for (int i = 0; i < left; ++i) {
        vout[l - k - i] = g[i];
        vout[l + k + i] = f[i];
      }
    }
  }
}

// Number of doubles per parity vector: whole tiles of the largest band.
int half_len(int bands) { return 4 * (((bands - 1) / 2 + 1 + 3) / 4); }

// cos/sin(m angle) in the ZTable layout (c = [even m | odd m], s likewise).
void trig_table(int bands, double angle, std::vector<double>& c, std::vector<double>& s) {
  const int nh = half_len(bands);
  c.assign(2 * static_cast<std::size_t>(nh), 1.0);
  s.assign(2 * static_cast<std::size_t>(nh), 0.0);
  for (int m = 0; m < bands; ++m) {
    // direct evaluation (no recurrence drift)
    const int i = (m & 1) * nh + m / 2;
    c[i] = std::cos(m * angle);
    s[i] = std::sin(m * angle);
  }
}

void check_rotation_matrix(const glm::dmat3& M) {
  double err = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(M[i][j])) throw InputError("rotation matrix has a NaN or infinite entry");
      double s = 0;
      for (int k = 0; k < 3; ++k) s += M[i][k] * M[j][k];
      err = std::max(err, std::abs(s - (i == j ? 1.0 : 0.0)));
    }
  const double det = glm::determinant(M);
  if (err > 1e-6 || det < 0)
    throw InputError("matrix is not a rotation: |M^T M - I| = " + std::to_string(err) + ", det = " + std::to_string(det));
}

}  // namespace

glm::dmat3 matrix_from_euler(const EulerZYZ& e) {
  auto rz = [](double a) {
    glm::dmat3 m(1.0);
    m[0][0] = std::cos(a);
    m[0][1] = std::sin(a);
    m[1][0] = -std::sin(a);
    m[1][1] = std::cos(a);
    return m;
  };
  glm::dmat3 ry(1.0);
  ry[0][0] = std::cos(e.beta);
  ry[0][2] = -std::sin(e.beta);
  ry[2][0] = std::sin(e.beta);
  ry[2][2] = std::cos(e.beta);
  return rz(e.alpha) * ry * rz(e.gamma);
}

EulerZYZ euler_from_matrix(const glm::dmat3& M) {
  check_rotation_matrix(M);
  auto R = [&](int i, int j) { return M[j][i]; };
  EulerZYZ e;
  const double sb = std::hypot(R(0, 2), R(1, 2));
  e.beta = std::atan2(sb, R(2, 2));
  if (sb < 1e-14) {
    e.gamma = 0.0;
    if (R(2, 2) > 0)
      e.alpha = std::atan2(R(1, 0), R(0, 0));
    else
      e.alpha = std::atan2(-R(1, 0), -R(0, 0));
  } else {
    e.alpha = std::atan2(R(1, 2), R(0, 2));
    e.gamma = std::atan2(R(2, 1), -R(2, 0));
  }
  return e;
}

glm::dmat3 matrix_from_quaternion(const glm::dquat& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!std::isfinite(n) || n == 0.0) throw InputError("quaternion has zero length or a NaN component");
  return glm::mat3_cast(glm::dquat(q.w / n, q.x / n, q.y / n, q.z / n));
}

Rotation::Rotation(int bands, const EulerZYZ& e) : bands_(bands), e_(e) {
  check_bands(bands, "Rotation", kMaxBands);
  if (!std::isfinite(e.alpha) || !std::isfinite(e.beta) || !std::isfinite(e.gamma))
    throw InputError("Rotation: Euler angle is not finite");
  trig_table(bands, e.alpha + kPi / 2, ca_, sa_);
  trig_table(bands, e.beta - kPi, cb_, sb_);
  trig_table(bands, e.gamma + kPi / 2, cg_, sg_);
}

Rotation::Rotation(int bands, const glm::dmat3& m) : Rotation(bands, euler_from_matrix(m)) {}
Rotation::Rotation(int bands, const glm::dquat& q) : Rotation(bands, euler_from_matrix(matrix_from_quaternion(q))) {}

void Rotation::apply(const double* in, double* out) const {
  const int nh = half_len(bands_);
  // two split buffers of 4 vectors of nh doubles, 32-byte aligned (on the stack when small)
  constexpr int kStack = 8 * 64 + 4;
  double stack_buf[kStack];
  std::vector<double> heap_buf;
  double* base = stack_buf;
  if (8 * nh + 4 > kStack) {
    heap_buf.resize(8 * static_cast<std::size_t>(nh) + 4);
    base = heap_buf.data();
  }
  while (reinterpret_cast<std::uintptr_t>(base) % 32 != 0) ++base;
  const Split w{base, base + nh, base + 2 * nh, base + 3 * nh};
  const Split u{base + 4 * nh, base + 5 * nh, base + 6 * nh, base + 7 * nh};
  auto ztable = [nh](const std::vector<double>& c, const std::vector<double>& s) {
    return ZTable{c.data(), s.data(), c.data() + nh, s.data() + nh};
  };
  const ZTable za = ztable(ca_, sa_), zb = ztable(cb_, sb_), zg = ztable(cg_, sg_);
  const std::unique_ptr<BandY90>* cache = cached_bands(bands_);
  const int ncached = std::min(bands_, y90_cache().ready.load(std::memory_order_acquire));
  BandY90 local;
  std::unique_ptr<StreamWork> sw;
  if (bands_ > kStreamFrom) sw = std::make_unique<StreamWork>(bands_);
  out[0] = in[0];
  for (int l = 1; l < bands_; ++l) {
    const BandY90* B = nullptr;
    if (l < ncached && l < kStreamFrom) {
      B = cache[l].get();
    } else if (l < kStreamFrom || l > kStreamTo) {
      build_band(l, local);
      B = &local;
    }
    rotate_band(l, B, sw.get(), in + l * l, out + l * l, l >= 3 && l + 1 < bands_, za, zb, zg, w, u);
  }
}

std::vector<double> Rotation::apply(const std::vector<double>& in) const {
  if (static_cast<int>(in.size()) < sh_count(bands_))
    throw InputError("Rotation::apply: coefficient vector has " + std::to_string(in.size()) + " entries, need " +
                     std::to_string(sh_count(bands_)));
  std::vector<double> out(sh_count(bands_));
  apply(in.data(), out.data());
  return out;
}

std::vector<double> Rotation::band_matrix(int l) const {
  if (l < 0 || l >= bands_) throw InputError("band_matrix: band " + std::to_string(l) + " out of range");
  const int n = 2 * l + 1;
  std::vector<double> M(static_cast<std::size_t>(n) * n);
  if (l == 0) {
    M[0] = 1.0;
    return M;
  }
  // band l alone, applied to its 2l+1 unit vectors: (2l+1) band products, O(l^3)
  const int nh = half_len(bands_);
  std::vector<double> buf(8 * static_cast<std::size_t>(nh) + 4);
  double* base = buf.data();
  while (reinterpret_cast<std::uintptr_t>(base) % 32 != 0) ++base;
  const Split w{base, base + nh, base + 2 * nh, base + 3 * nh};
  const Split u{base + 4 * nh, base + 5 * nh, base + 6 * nh, base + 7 * nh};
  auto ztable = [nh](const std::vector<double>& c, const std::vector<double>& s) {
    return ZTable{c.data(), s.data(), c.data() + nh, s.data() + nh};
  };
  const ZTable za = ztable(ca_, sa_), zb = ztable(cb_, sb_), zg = ztable(cg_, sg_);
  const std::unique_ptr<BandY90>* cache = cached_bands(std::min(l + 1, kStreamFrom));
  BandY90 local;
  std::unique_ptr<StreamWork> sw;
  const BandY90* B = nullptr;
  if (l < kStreamFrom && l < y90_cache().ready.load(std::memory_order_acquire)) {
    B = cache[l].get();
  } else if (l < kStreamFrom || l > kStreamTo) {
    build_band(l, local);
    B = &local;
  } else {
    sw = std::make_unique<StreamWork>(l + 1);
  }
  std::vector<double> in(n, 0.0), out(n);
  for (int j = 0; j < n; ++j) {
    in[j] = 1.0;
    rotate_band(l, B, sw.get(), in.data(), out.data(), false, za, zb, zg, w, u);
    in[j] = 0.0;
    for (int i = 0; i < n; ++i) M[static_cast<std::size_t>(i) * n + j] = out[i];
  }
  return M;
}

void reserve_rotation_cache(int bands) {
  check_bands(bands, "reserve_rotation_cache", kMaxBands);
  // bands from kStreamFrom to kStreamTo are applied on the fly (faster than streaming their
  // stored matrices from memory): only the bands below are ever kept
  cached_bands(std::min(bands, kStreamFrom));
}

int rotation_cache_bands() { return y90_cache().ready.load(std::memory_order_acquire); }

void rotate_z(int bands, double alpha, const double* in, double* out) {
  check_bands(bands, "rotate_z", 1 << 20);
  if (!std::isfinite(alpha)) throw InputError("rotate_z: angle is not finite");
  for (int l = 0; l < bands; ++l) {
    out[l * (l + 1)] = in[l * (l + 1)];
  }
  for (int m = 1; m < bands; ++m) {
    const double c = std::cos(m * alpha), s = std::sin(m * alpha);
    for (int l = m; l < bands; ++l) {
      const int i = l * (l + 1);
      const double a = in[i + m], b = in[i - m];
      out[i + m] = a * c - b * s;
      out[i - m] = a * s + b * c;
    }
  }
}

}  // namespace atmosh::sh
