// Gauss–Legendre grid analysis/synthesis: FFT in longitude, scaled Legendre
// recurrences in latitude, vectorised over blocks of ring pairs.
#include "atmosh/sh/transform.hpp"

// Internal vector helpers never cross a library boundary, so GCC's note on the ABI of wide
// vector arguments is silenced. Within this file it still matters: a helper that takes or
// returns a vector wider than 16 bytes must be inlined into (always_inline, as
// fold_extended) or defined inside the dispatched function that uses it. Called out of
// line across a target boundary (a default-target helper from an AVX2 clone) the two
// sides pass such a vector in different places, and the values arrive as garbage.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <algorithm>
#include <bit>
#include <memory>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>
#include <type_traits>
#include <atomic>
#include <map>
#include <mutex>
#include <stdexcept>

#include <fftw3.h>

#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "legendre_impl.hpp"
#include "transform_impl.hpp"

namespace atmosh::sh {

namespace detail {


namespace {
// body(local, i) for i in [0, count) (columns m or blocks of them) on the toolkit's
// parallel loop, one index at a time from a shared counter: column cost ~ bands - m, so
// the dearest columns go first. make_local() builds each worker's scratch once; every
// column overwrites the scratch it reads, so results do not depend on the thread count.
template <class MakeLocal, class F>
void parallel_for_m(int count, int threads, MakeLocal&& make_local, F&& body) {
  atmosh::parallel_for_ranges_local(
      static_cast<std::size_t>(count), 1, count < 8 ? 1 : threads, make_local,
      [&](auto& local, std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) body(local, static_cast<int>(i));
      });
}
struct NoScratch {};

// Work arrays kept by the calling thread from one transform to the next: fresh pages from
// the system cost a page fault and a clear each, which was a quarter of an analysis at
// L = 1024 when the ~30 MB of work arrays were allocated per call. They only grow (to the
// largest transform the thread has run); contents are never assumed.
template <class T>
struct Reused {
  std::unique_ptr<T[]> p;
  std::size_t n = 0;
  T* get(std::size_t need) {
    if (need > n) {
      p.reset();
      p.reset(new T[need]);
      n = need;
    }
    return p.get();
  }
};
struct ThreadWork {
  Reused<double> fm, col, four;
};
ThreadWork& thread_work() {
  thread_local ThreadWork w;
  return w;
}

constexpr int B = 8;  // lanes (ring pairs) per block

struct Pairs {
  std::vector<int> north, south;  // south = -1: no partner
  std::vector<double> x, u;       // of the north ring
};

Pairs make_pairs(int nrings, const double* cos_t, const double* sin_t, bool symmetric) {
  Pairs p;
  if (symmetric) {
    for (int r = 0; r < (nrings + 1) / 2; ++r) {
      const int s = nrings - 1 - r;
      p.north.push_back(r);
      p.south.push_back(s == r ? -1 : s);
    }
  } else {
    for (int r = 0; r < nrings; ++r) {
      p.north.push_back(r);
      p.south.push_back(-1);
    }
  }
  const int np = static_cast<int>(p.north.size());
  const int padded = (np + B - 1) / B * B;
  p.x.assign(padded, 0.0);
  p.u.assign(padded, 1.0);
  for (int k = 0; k < np; ++k) {
    p.x[k] = cos_t[p.north[k]];
    p.u[k] = sin_t[p.north[k]];
  }
  return p;
}

// Sectoral extended-range values for every m and lane: mant[m * padded + k], exp[...].
void sectorals(int bands, const Pairs& p, const LegendreTable& t, double* mant, int* ex) {
  const std::size_t padded = p.x.size();
  // m outer: each row follows from the previous one (rows stream; lanes independent)
  for (std::size_t k = 0; k < padded; ++k) {
    mant[k] = 1.0 / std::sqrt(4.0 * std::numbers::pi);
    ex[k] = 0;
  }
  for (int m = 1; m < bands; ++m) {
    const double* pm = mant + (m - 1) * padded;
    const int* pe = ex + (m - 1) * padded;
    double* cm = mant + m * padded;
    int* ce = ex + m * padded;
    for (std::size_t k = 0; k < padded; ++k) {
      const XNum v = next_sectoral(XNum{pm[k], pe[k]}, t.sectoral()[m], p.u[k]);
      cm[k] = v.mant;
      ce[k] = v.exp;
    }
  }
}
}  // namespace

// Lanes join the sums once their recurrence value exceeds 2^-kJoinExp (polar
// optimisation): a lane starts in the extended range when its sectoral value is below
// that, and folds back to the plain range (exponent 0) when its mantissa passes
// kJoinFold = 2^(kScaleExp - kJoinExp), i.e. its value 2^-kJoinExp. The terms left out
// are below 2^-80 |f| each (lam >= |Pbar_lm| / alpha >= |Pbar_lm|), so they cannot change
// a double result at the 1e-13 level of the round trips; below that threshold lanes
// only cost work: at L = 1024 they are a large share of the triangle near the poles.
// Between checks values grow by less than 2^(60 kFoldEvery / 2) = 2^240, so they stay
// below 2^760.
constexpr int kJoinExp = 80;
inline const double kJoin = std::ldexp(1.0, -kJoinExp);
inline const double kJoinFold = std::ldexp(1.0, kScaleExp - kJoinExp);
// Sectoral value of a lane (mant * 2^ex) in the representation of the kernels: values
// below kJoin go to the extended range (exponent -kScaleExp) until they join.
inline void lane_start(double mant, int ex, double& m, double& e) {
  if (ex == 0 && std::abs(mant) < kJoin) {
    m = mant * kScaleUp;
    e = -kScaleExp;
  } else {
    m = mant;
    e = ex;
  }
}
// Set-up of the Legendre stage that depends on the rings alone: ring pairs, sectoral start
// values of every order and lane, and (filled by the first transform that needs them) the
// polar starts of every column.
//
// Polar starts of column m, for its blocks of W lanes (ring pairs): a block with a lane
// below 2^-kJoinExp at the sectoral degree steps the recurrence alone (its terms are
// dropped) until it joins the plain kernels; where and with which values it joins depends
// on the rings and m alone, so it is found once (polar_starts) and both directions start
// such blocks there. join[b]: the step k at which block b joins (0: plain from the start;
// kPolarNever: not by kmax, it adds nothing; kPolarMasked: it has plain and extended
// lanes at once and adds its plain lanes' terms while it steps, so it is stepped per
// transform); lam[slot[b] 2W ...]: lam_k-1 (W values) then lam_k (W values) at its join.
constexpr int kPolarNever = 1 << 30, kPolarMasked = -1;
struct PolarStarts {
  std::vector<int> join, slot;
  std::vector<double> lam;
};
struct RingPlan {
  int bands = 0;
  Pairs pr;
  // Every lane's start in the kernels' representation (lane_start of the sectoral value):
  // lam0, e0 [m * padded + q]; x^2 [q]; whether block b of W lanes of column m has no
  // extended lane: plain[m * (padded / W) + b]. The kernels copy them per column.
  std::vector<double> lam0, e0, csq;
  std::vector<unsigned char> plain;
  int W = 0;  // lanes per block the polar starts are for
  // per column, once found (null before); owned here
  struct Polar {
    std::unique_ptr<std::atomic<const PolarStarts*>[]> p;
    int n = 0;
    explicit Polar(int count) : p(new std::atomic<const PolarStarts*>[count]), n(count) {
      for (int i = 0; i < n; ++i) p[i].store(nullptr, std::memory_order_relaxed);
    }
    ~Polar() {
      for (int i = 0; i < n; ++i) delete p[i].load(std::memory_order_acquire);
    }
  } polar;
  RingPlan(int bands_, int nrings, const double* cos_t, const double* sin_t, bool symmetric, int lanes)
      : bands(bands_), pr(make_pairs(nrings, cos_t, sin_t, symmetric)), W(lanes), polar(bands_) {
    const std::size_t padded = pr.x.size(), nsect = static_cast<std::size_t>(bands) * padded;
    lam0.resize(nsect);
    e0.resize(nsect);
    {
      std::vector<double> smant(nsect);
      std::vector<int> sexp(nsect);
      sectorals(bands, pr, *legendre_table(bands), smant.data(), sexp.data());
      for (std::size_t i = 0; i < nsect; ++i) lane_start(smant[i], sexp[i], lam0[i], e0[i]);
    }
    csq.resize(padded);
    for (std::size_t q = 0; q < padded; ++q) csq[q] = pr.x[q] * pr.x[q];
    const std::size_t nb = padded / static_cast<std::size_t>(W);
    plain.assign(static_cast<std::size_t>(bands) * nb, 1);
    for (std::size_t i = 0; i < nsect; ++i)
      if (e0[i] != 0.0) plain[(i / padded) * nb + (i % padded) / static_cast<std::size_t>(W)] = 0;
  }
};
namespace {
int analysis_lanes();
}

// The plan kept with a GaussGrid: its ring plan and the fields it was made from.
struct GridPlan {
  int bands, nlat, nphi;
  LatitudeRule rule;
  std::vector<double> cos_t, sin_t, weights;
  RingPlan rings;
  explicit GridPlan(const GaussGrid& g)
      : bands(g.bands), nlat(g.nlat), nphi(g.nphi), rule(g.rule), cos_t(g.cos_t), sin_t(g.sin_t), weights(g.weights),
        rings(g.bands, g.nlat, g.cos_t.data(), g.sin_t.data(), true, analysis_lanes()) {}
  bool matches(const GaussGrid& g) const {
    return g.bands == bands && g.nlat == nlat && g.nphi == nphi && g.rule == rule && g.cos_t == cos_t &&
           g.sin_t == sin_t && g.weights == weights && rings.W == analysis_lanes();
  }
};
// The grid's plan where it matches the grid, else one made for this call.
std::shared_ptr<const GridPlan> plan_for(const GaussGrid& g) {
  if (g.plan && g.plan->matches(g)) return g.plan;
  return std::make_shared<const GridPlan>(g);
}


// ---- analysis: even-degree recurrence in x^2 ------------------------------------
// For one m write P_l = Pbar_lm and eps_l = sqrt((l^2 - m^2) / (4 l^2 - 1)), so that
// x P_l = eps_l+1 P_l+1 + eps_l P_l-1. Two steps of it give a recurrence over the
// degrees l = m + 2k of the parity of m alone:
//   eps_l+1 eps_l+2 P_l+2 = (x^2 - eps_l+1^2 - eps_l^2) P_l - eps_l eps_l-1 P_l-2.
// With P_m+2k = alpha_k lam_k (alpha_0 = alpha_1 = 1, alpha_k+1 = -C_k alpha_k-1, C_k
// the ratio multiplying P_l-2) it becomes lam_k+1 = (a'_k x^2 + b'_k) lam_k + lam_k-1:
// two fused multiply-adds per ring for two degrees. The alpha_k stay within
// [~1/m, 1] (the products of eps ratios telescope), so lam has the range of P.
// The degrees of the other parity are not recurred at all: for l = m + 2k
//   B_l = sum_r x_r O_r P_l(x_r) = eps_l+1 A_l+1 + eps_l A_l-1,  A_j = sum_r O_r P_j(x_r),
// exactly, ring by ring, so A_l+1 = (B_l - eps_l A_l-1) / eps_l+1 (forward substitution
// from A_m-1 = 0; the factor eps_l / eps_l+1 < 1 damps rounding errors). Per ring pair
// and two degrees: 2 FMAs of recurrence and 4 of accumulation (cos and sin parts of
// the even sum E and of x times the odd sum O). Round trips agree with the direct
// three-term recurrence to the same ~1e-13 (tests; docs/sh.md).
namespace {
typedef double V4 __attribute__((vector_size(4 * sizeof(double))));
typedef long long I4 __attribute__((vector_size(4 * sizeof(long long))));

// W lanes (ring pairs) of doubles and of 64-bit lane masks. W = 4: one AVX register
// per vector in the AVX2/FMA clone; W = 8: one AVX-512 register (x86-64-v4 kernels).
template <int W>
struct Lanes {
  typedef double D __attribute__((vector_size(W * sizeof(double))));
  typedef long long I __attribute__((vector_size(W * sizeof(long long))));
};

// One block of W ring pairs for one m (aligned to its vector size: GCC gives wide
// generic vectors only 16-byte alignment outside functions compiled for AVX).
template <int W>
struct alignas(W * sizeof(double)) AnaGroup {
  using D = typename Lanes<W>::D;
  D ec, es, oc, os;  // even sums E (cos, sin parts) and x * odd sums O
  D csq;             // x^2
  D lam1, lam2;      // lam_k-1, lam_k at the block's current step k
  D e;               // extended-range exponent per lane (0: plain range)
};
static_assert(alignof(AnaGroup<8>) == 64 && sizeof(AnaGroup<8>) == 8 * 64);

struct AnaCoef {
  // a'_k, b'_k, alpha_k (k <= kmax + 2); for the odd degrees l = m + 2k + 1:
  // A_l = rb_k B_l-1 - qa_k A_l-2 with rb_k = alpha_k / eps_l, qa_k = eps_l-1 / eps_l
  std::vector<double> ap, bp, alpha, eps, rb, qa, cc, aa, bb;
};

// Coefficients of column m for degrees below `bands` (steps k = 0..kmax+2 defined).
// Only the alpha products are sequential; the rest vectorises (sqrt without errno).
ATMOSH_DISPATCH_NO_ERRNO
static void ana_coefficients(int bands, int m, AnaCoef& c) {
  const int kmax = (bands - 1 - m) / 2;
  const int nk = kmax + 3, nl = 2 * nk + 4;
  c.eps.resize(nl);
  c.ap.resize(nk);
  c.bp.resize(nk);
  c.cc.resize(nk);
  c.aa.resize(nk);
  c.bb.resize(nk);
  c.rb.resize(nk);
  c.qa.resize(nk);
  c.alpha.resize(nk + 1);
  double* eps = c.eps.data();
  const double mm = m;
  eps[0] = 0.0;
  for (int i = 1; i < nl; ++i) {
    const double l = mm + i;
    eps[i] = std::sqrt((l - mm) * (l + mm) / ((2.0 * l - 1.0) * (2.0 * l + 1.0)));
  }
  for (int k = 0; k < nk; ++k) {
    const double e0 = eps[2 * k], e1 = eps[2 * k + 1], e2 = eps[2 * k + 2], em = k > 0 ? eps[2 * k - 1] : 1.0;
    const double A = 1.0 / (e1 * e2);
    c.aa[k] = A;
    c.bb[k] = -(e1 * e1 + e0 * e0) * A;
    c.cc[k] = -(e0 * em) * A;  // alpha_k+1 = cc_k alpha_k-1
    c.qa[k] = e0 / e1;
  }
  c.alpha[0] = c.alpha[1] = 1.0;
  for (int k = 1; k < nk; ++k) {
    c.alpha[k + 1] = c.cc[k] * c.alpha[k - 1];
  }
  for (int k = 0; k < nk; ++k) {
    const double r = c.alpha[k] / c.alpha[k + 1];
    c.ap[k] = c.aa[k] * r;
    c.bp[k] = c.bb[k] * r;
    c.rb[k] = c.alpha[k] / eps[2 * k + 1];
  }
}

// The coefficients of one column, read from a table or from AnaCoef (they depend on m and
// the step k only, not on the band limit: a table for B bands serves every bands <= B).
struct ColCoef {
  const double *ap, *bp, *alpha, *rb, *qa;
};
ColCoef view(const AnaCoef& c) { return {c.ap.data(), c.bp.data(), c.alpha.data(), c.rb.data(), c.qa.data()}; }

// Process-wide table of every column's coefficients (the largest band limit asked for so
// far, up to kCoefTableBands: ~10 MB at 1024 bands); computing them per call was 5-10% of
// a transform. Larger band limits compute them per column and call.
constexpr int kCoefTableBands = 1024;
class CoefTable {
 public:
  explicit CoefTable(int bands) : bands_(bands), off_(bands + 1) {
    std::size_t n = 0;
    for (int m = 0; m < bands; ++m) {
      off_[m] = n;
      n += 5 * static_cast<std::size_t>(steps(m)) + 1;
    }
    off_[bands] = n;
    store_.resize(n);
    AnaCoef c;
    for (int m = 0; m < bands; ++m) {
      ana_coefficients(bands, m, c);
      const int nk = steps(m);
      double* p = store_.data() + off_[m];
      std::copy(c.ap.begin(), c.ap.begin() + nk, p);
      std::copy(c.bp.begin(), c.bp.begin() + nk, p + nk);
      std::copy(c.rb.begin(), c.rb.begin() + nk, p + 2 * nk);
      std::copy(c.qa.begin(), c.qa.begin() + nk, p + 3 * nk);
      std::copy(c.alpha.begin(), c.alpha.begin() + nk + 1, p + 4 * nk);
    }
  }
  int bands() const { return bands_; }
  ColCoef col(int m) const {
    const int nk = steps(m);
    const double* p = store_.data() + off_[m];
    return {p, p + nk, p + 4 * nk, p + 2 * nk, p + 3 * nk};
  }

 private:
  int steps(int m) const { return (bands_ - 1 - m) / 2 + 3; }
  int bands_;
  std::vector<std::size_t> off_;
  std::vector<double> store_;
};
std::shared_ptr<const CoefTable> coef_table(int bands) {
  if (bands > kCoefTableBands) return nullptr;
  static std::mutex mu;
  static std::shared_ptr<const CoefTable> cached;
  std::lock_guard<std::mutex> lock(mu);
  if (!cached || cached->bands() < bands) cached = std::make_shared<const CoefTable>(std::max(bands, 64));
  return cached;
}

// {sum of the lanes of a0, ..., of a3}; 8-lane vectors are first folded to 4 lanes.
__attribute__((always_inline)) inline V4 hsum4(V4 a0, V4 a1, V4 a2, V4 a3) {
  const V4 u0 = __builtin_shufflevector(a0, a1, 0, 4, 2, 6) + __builtin_shufflevector(a0, a1, 1, 5, 3, 7);
  const V4 u1 = __builtin_shufflevector(a2, a3, 0, 4, 2, 6) + __builtin_shufflevector(a2, a3, 1, 5, 3, 7);
  return __builtin_shufflevector(u0, u1, 0, 1, 4, 5) + __builtin_shufflevector(u0, u1, 2, 3, 6, 7);
}
template <class D>
__attribute__((always_inline)) inline V4 fold4(D a) {
  if constexpr (sizeof(D) == sizeof(V4))
    return a;
  else
    return __builtin_shufflevector(a, a, 0, 1, 2, 3) + __builtin_shufflevector(a, a, 4, 5, 6, 7);
}
template <class D>
__attribute__((always_inline)) inline V4 hsum(D a0, D a1, D a2, D a3) {
  return hsum4(fold4(a0), fold4(a1), fold4(a2), fold4(a3));
}

// Whether any lane of a mask is set.
template <class I>
__attribute__((always_inline)) inline bool any(I m) {
  if constexpr (sizeof(I) == sizeof(I4)) {
    const I4 t = (I4)m | (I4)__builtin_shufflevector(m, m, 2, 3, 0, 1);
    return (t[0] | t[1]) != 0;
  } else {
    return any((I4)__builtin_shufflevector(m, m, 0, 1, 2, 3) | (I4)__builtin_shufflevector(m, m, 4, 5, 6, 7));
  }
}

// Lane masks from the bits alone (no vector comparisons: those would be lowered before
// this code is inlined into the wide-vector functions): e is 0 or a negative multiple of
// kScaleExp, so its sign bit marks the extended lanes; for non-negative doubles the bit
// patterns order like the values. Folds the extended lanes of a block (lam1, lam2, e:
// AnaGroup or SynState) whose |lam| passed kJoinFold by 2^-kScaleExp and returns the mask
// of the lanes still extended.
template <int W, class S>
__attribute__((always_inline)) inline typename Lanes<W>::I fold_extended(S& g) {
  using D = typename Lanes<W>::D;
  using I = typename Lanes<W>::I;
  const D down = D{} + kScaleDown, step = D{} + static_cast<double>(kScaleExp);
  const I fold = I{} + std::bit_cast<long long>(kJoinFold), magnitude = I{} + 0x7fffffffffffffffLL;
  I ext = (I)g.e >> 63;
  const I big = (((fold - ((I)g.lam2 & magnitude)) | (fold - ((I)g.lam1 & magnitude))) >> 63) & ext;
  if (any(big)) {
    g.lam1 = (D)(((I)(g.lam1 * down) & big) | ((I)g.lam1 & ~big));
    g.lam2 = (D)(((I)(g.lam2 * down) & big) | ((I)g.lam2 & ~big));
    g.e = (D)(((I)(g.e + step) & big) | ((I)g.e & ~big));
    ext = (I)g.e >> 63;
  }
  return ext;
}

// A block with a plain lane and extended ones (ext: their mask, after fold_extended) goes
// to the plain range as a whole when every extended lane is one scale step down (e =
// -kScaleExp) with both values at least 2^-kGraduateExp once scaled (normal doubles, far
// from the subnormals, so the lane's recurrence keeps its relative accuracy; or lam1 = 0,
// the start at step 0): its
// extended lanes are scaled to their plain values (exact: a power of two), and from then
// on they add their terms, which are below 2^-kJoinExp |f| until the lane would have
// joined. Returns whether it did; otherwise the block is left as it was.
constexpr int kGraduateExp = 1000;
template <int W, class S>
__attribute__((always_inline)) inline bool graduate(S& g, typename Lanes<W>::I ext) {
  using D = typename Lanes<W>::D;
  using I = typename Lanes<W>::I;
  const I magnitude = I{} + 0x7fffffffffffffffLL;
  const I floor = I{} + std::bit_cast<long long>(std::ldexp(1.0, kScaleExp - kGraduateExp));
  const I once = I{} + std::bit_cast<long long>(-static_cast<double>(kScaleExp));
  // (lam1 = 0 exactly, the start value lam_-1 at step 0, needs no accuracy)
  const I a1 = (I)g.lam1 & magnitude, a2 = (I)g.lam2 & magnitude, one = I{} + 1;
  const I low = (((a1 - floor) & ~(a1 - one)) | (a2 - floor)) >> 63;
  const I other = (I)g.e ^ once;  // nonzero where e != -kScaleExp
  if (any(ext & (low | ((other | -other) >> 63)))) return false;
  const D down = D{} + kScaleDown;
  g.lam1 = (D)(((I)(g.lam1 * down) & ext) | ((I)g.lam1 & ~ext));
  g.lam2 = (D)(((I)(g.lam2 * down) & ext) | ((I)g.lam2 & ~ext));
  g.e = D{};
  return true;
}

// Blocks whose sectoral values need the extended range (mant * 2^e, e < 0 a multiple
// of kScaleExp; an extended lane's terms are dropped: with the fold below its values
// are under 2^-250, far below any term that can change a double result). They add no
// terms, so they are stepped apart from the kernel: kExtBlocks at a time, their state in
// registers (one block alone would wait on its chain of two dependent FMAs per step).
// Every kFoldEvery steps each extended lane whose |lam| passed kJoinFold is scaled by
// 2^-kScaleExp (see kJoinExp below); a block leaves at the first check at which all its
// lanes are plain or at which it has a plain lane and can graduate (join[i] = that step,
// kmax + 1 if never; its state is stored then, and its registers run on unused). A block
// with a plain lane that cannot graduate yet adds the terms of its plain lanes to sums[k]
// itself (masked, one reduction per step: rare, see graduate), and is marked in masked[i].
constexpr int kFoldEvery = 8;
constexpr int kExtBlocks = 4;
template <int W>
__attribute__((always_inline)) inline void ana_extended(int kmax, const double* ap, const double* bp,
                                                        AnaGroup<W>* grp, const int* ids, int nx, int* join,
                                                        V4* sums, unsigned char* masked) {
  using D = typename Lanes<W>::D;
  using I = typename Lanes<W>::I;
  constexpr int NB = kExtBlocks;
  struct State {
    D lam1, lam2, e;
  };
  for (int j0 = 0; j0 < nx; j0 += NB) {
    const int nb = std::min(NB, nx - j0);
    State s[NB];
    D csq[NB];
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) {
      const AnaGroup<W>& g = grp[ids[j0 + (b < nb ? b : 0)]];
      s[b] = State{g.lam1, g.lam2, g.e};
      csq[b] = g.csq;
    }
    unsigned alive = (1u << nb) - 1;
    for (int k = 0; k <= kmax;) {
      unsigned mixed = 0;
#pragma GCC unroll 8
      for (int b = 0; b < NB; ++b) {
        if (!(alive >> b & 1)) continue;
        const I ext = fold_extended<W>(s[b]);
        if (!any(ext) || (any(~ext) && graduate<W>(s[b], ext))) {
          AnaGroup<W>& g = grp[ids[j0 + b]];
          g.lam1 = s[b].lam1;
          g.lam2 = s[b].lam2;
          g.e = s[b].e;
          join[ids[j0 + b]] = k;
          alive &= ~(1u << b);
        } else if (any(~ext)) {
          mixed |= 1u << b;
          masked[ids[j0 + b]] = 1;
        }
      }
      if (!alive) break;
      const int kend = std::min(k + kFoldEvery - 2, kmax);  // the steps up to the next check
      if (!mixed) {
        for (; k <= kend; k += 2) {
#pragma GCC unroll 8
          for (int b = 0; b < NB; ++b) {
            const D t1 = (ap[k] * csq[b] + bp[k]) * s[b].lam2 + s[b].lam1;
            s[b].lam1 = t1;
            s[b].lam2 = (ap[k + 1] * csq[b] + bp[k + 1]) * t1 + s[b].lam2;
          }
        }
      } else {
        for (; k <= kend; k += 2) {
#pragma GCC unroll 8
          for (int b = 0; b < NB; ++b) {
            const D t1 = (ap[k] * csq[b] + bp[k]) * s[b].lam2 + s[b].lam1;
            if (mixed >> b & 1) {
              const AnaGroup<W>& g = grp[ids[j0 + b]];
              const I plain = ~((I)s[b].e >> 63);
              const D v = (D)((I)s[b].lam2 & plain), w = (D)((I)t1 & plain);
              sums[k] += hsum(v * g.ec, v * g.es, v * g.oc, v * g.os);
              sums[k + 1] += hsum(w * g.ec, w * g.es, w * g.oc, w * g.os);
            }
            s[b].lam1 = t1;
            s[b].lam2 = (ap[k + 1] * csq[b] + bp[k + 1]) * t1 + s[b].lam2;
          }
        }
      }
    }
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b)
      if (alive >> b & 1) join[ids[j0 + b]] = kmax + 1;
  }
}

// The plain kernel: steps K0, K0+2, ... <= kmax; at step K the blocks grp[0..n) are
// active: the nplain plain blocks and those of the others (sorted by the step they join
// at, jsorted[0..nj) ascending) that have joined by K. Adds the lane sums of lam_K and
// lam_K+1 times (E cos, E sin, xO cos, xO sin) to sums[K] and sums[K+1].
template <int W>
__attribute__((always_inline)) inline void ana_kernel(int K0, int kmax, int nplain, const int* jsorted, int nj,
                                                      const double* ap, const double* bp, AnaGroup<W>* grp,
                                                      V4* sums) {
  using D = typename Lanes<W>::D;
  int p = 0;
  for (int K = K0; K <= kmax; K += 2) {
    while (p < nj && jsorted[p] <= K) ++p;
    const int n = nplain + p;
    const double a1 = ap[K], b1 = bp[K], a2 = ap[K + 1], b2 = bp[K + 1];
    D c0{}, c1{}, c2{}, c3{}, d0{}, d1{}, d2{}, d3{};
    for (int i = 0; i < n; ++i) {
      AnaGroup<W>& g = grp[i];
      // (the block's values are loaded once: GCC otherwise folds each of them into both of
      // its FMAs as a memory operand, 11 loads per block instead of 7, and at W = 8 the
      // loads rather than the FMAs then set the pace; 32 registers hold them. With 16 at
      // W = 4 the folded form is kept, as in builds without the AVX-512 clone, where the
      // 8-lane vectors are not registers.)
      D csq = g.csq, ec = g.ec, es = g.es, oc = g.oc, os = g.os;
      if constexpr (W == 8 && ATMOSH_HAS_DISPATCH) asm("" : "+v"(csq), "+v"(ec), "+v"(es), "+v"(oc), "+v"(os));
      D l2 = g.lam2, l1 = g.lam1;
      c0 += l2 * ec;
      c1 += l2 * es;
      c2 += l2 * oc;
      c3 += l2 * os;
      l1 = (a1 * csq + b1) * l2 + l1;
      d0 += l1 * ec;
      d1 += l1 * es;
      d2 += l1 * oc;
      d3 += l1 * os;
      l2 = (a2 * csq + b2) * l1 + l2;
      g.lam1 = l1;
      g.lam2 = l2;
    }
    sums[K] += hsum(c0, c1, c2, c3);
    sums[K + 1] += hsum(d0, d1, d2, d3);
  }
}

// Compiled kernels: 4 lanes in the AVX2/FMA clone (and the baseline), 8 lanes with
// AVX-512 where the CPU has it (one 512-bit register per vector halves the
// instructions per ring pair; the sums are the same up to rounding order).
ATMOSH_DISPATCH
static void ana_extended4(int kmax, const double* ap, const double* bp, AnaGroup<4>* grp, const int* ids, int nx,
                          int* join, V4* sums, unsigned char* masked) {
  ana_extended<4>(kmax, ap, bp, grp, ids, nx, join, sums, masked);
}
ATMOSH_DISPATCH
static void ana_kernel4(int K0, int kmax, int nplain, const int* jsorted, int nj, const double* ap, const double* bp,
                        AnaGroup<4>* grp, V4* sums) {
  ana_kernel<4>(K0, kmax, nplain, jsorted, nj, ap, bp, grp, sums);
}
#if ATMOSH_HAS_DISPATCH
#define ATMOSH_V4_KERNEL ATMOSH_TARGET_AVX512
bool has_avx512() { return cpu_has_avx512(); }
#else
#define ATMOSH_V4_KERNEL
bool has_avx512() { return false; }
#endif
ATMOSH_V4_KERNEL
static void ana_extended8(int kmax, const double* ap, const double* bp, AnaGroup<8>* grp, const int* ids, int nx,
                          int* join, V4* sums, unsigned char* masked) {
  ana_extended<8>(kmax, ap, bp, grp, ids, nx, join, sums, masked);
}
ATMOSH_V4_KERNEL
static void ana_kernel8(int K0, int kmax, int nplain, const int* jsorted, int nj, const double* ap, const double* bp,
                        AnaGroup<8>* grp, V4* sums) {
  ana_kernel<8>(K0, kmax, nplain, jsorted, nj, ap, bp, grp, sums);
}
#undef ATMOSH_V4_KERNEL

// Number of leading extended blocks (ids[0..nx), ring order, pole first) none of whose
// lanes reaches 2^-kJoinExp by step kmax, i.e. that contribute nothing. Near the pole
// |Pbar_lm| decreases towards the pole at every degree (beyond its last maximum), so these
// blocks are the poleward part of the extended ones: found by bisection, each probe a
// replay of ana_extended's stepping and checks for one block (stopping where a lane joins).
template <int W>
__attribute__((always_inline)) inline int ana_skip(int kmax, const double* ap, const double* bp,
                                                   const AnaGroup<W>* grp, const int* ids, int nx) {
  using D = typename Lanes<W>::D;
  auto reaches = [&](const AnaGroup<W>& g) {
    D l1 = g.lam1, l2 = g.lam2, e = g.e;
    const D csq = g.csq;
    for (int k = 0; k <= kmax; k += 2) {
      if (k % kFoldEvery == 0) {
        for (int j = 0; j < W; ++j) {
          if (e[j] < 0.0 && (std::abs(l1[j]) > kJoinFold || std::abs(l2[j]) > kJoinFold)) {
            l1[j] *= kScaleDown;
            l2[j] *= kScaleDown;
            e[j] += kScaleExp;
          }
          if (e[j] == 0.0) return true;
        }
      }
      const D t1 = (ap[k] * csq + bp[k]) * l2 + l1;
      l1 = t1;
      l2 = (ap[k + 1] * csq + bp[k + 1]) * t1 + l2;
    }
    return false;
  };
  int lo = 0, hi = nx;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (reaches(grp[ids[mid]]))
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

// The polar starts of a column (see PolarStarts): its extended blocks are made from their
// sectoral starts, those that never reach 2^-kJoinExp are left out (ana_skip), and the
// others are stepped as by the analysis (ana_extended, the terms of masked blocks to a
// scratch array) to the step at which they join, where their values are kept.
template <int W>
__attribute__((always_inline)) inline PolarStarts* make_polar_starts(int kmax, int ngroups, const double* csq,
                                                                     const double* lam0, const double* e0,
                                                                     const unsigned char* plain, const ColCoef& cf) {
  using D = typename Lanes<W>::D;
  // the calling thread's work arrays, kept from one column to the next (a plan made per
  // call finds every column's starts on every call)
  thread_local struct Work {
    std::vector<int> ids, join;
    std::vector<unsigned char> masked;
    std::unique_ptr<AnaGroup<W>[]> grp;
    std::unique_ptr<V4[]> sums;
    int ngrp = 0, nsums = 0;
  } w;
  auto ps = std::make_unique<PolarStarts>();
  ps->join.assign(ngroups, 0);
  ps->slot.assign(ngroups, -1);
  w.ids.clear();
  for (int gi = 0; gi < ngroups; ++gi)
    if (!plain[gi]) w.ids.push_back(gi);
  const int nx = static_cast<int>(w.ids.size());
  if (nx == 0) return ps.release();
  if (w.ngrp < ngroups) {
    w.grp.reset(new AnaGroup<W>[ngroups]);
    w.ngrp = ngroups;
  }
  if (w.nsums < kmax + 4) {
    w.sums.reset(new V4[kmax + 4]);
    w.nsums = kmax + 4;
  }
  w.join.assign(ngroups, 0);
  w.masked.assign(ngroups, 0);
  const int* const ids = w.ids.data();
  AnaGroup<W>* const grp = w.grp.get();
  for (int i = 0; i < nx; ++i) {
    const int gi = ids[i];
    AnaGroup<W>& g = grp[gi];
    g.ec = g.es = g.oc = g.os = D{};
    std::memcpy(&g.csq, csq + W * gi, W * sizeof(double));
    g.lam1 = D{};
    std::memcpy(&g.lam2, lam0 + W * gi, W * sizeof(double));
    std::memcpy(&g.e, e0 + W * gi, W * sizeof(double));
  }
  const int skip = nx > 1 ? ana_skip<W>(kmax, cf.ap, cf.bp, grp, ids, nx) : 0;
  for (int i = 0; i < skip; ++i) ps->join[ids[i]] = kPolarNever;
  ana_extended<W>(kmax, cf.ap, cf.bp, grp, ids + skip, nx - skip, w.join.data(), w.sums.get(), w.masked.data());
  int kept = 0;
  for (int i = skip; i < nx; ++i) kept += !w.masked[ids[i]] && w.join[ids[i]] <= kmax;
  ps->lam.resize(static_cast<std::size_t>(kept) * 2 * W);
  kept = 0;
  for (int i = skip; i < nx; ++i) {
    const int gi = ids[i];
    if (w.masked[gi]) {
      ps->join[gi] = kPolarMasked;
    } else if (w.join[gi] > kmax) {
      ps->join[gi] = kPolarNever;
    } else {
      ps->join[gi] = w.join[gi];
      ps->slot[gi] = kept;
      double* const lam = ps->lam.data() + static_cast<std::size_t>(kept++) * 2 * W;
      std::memcpy(lam, &grp[gi].lam1, W * sizeof(double));
      std::memcpy(lam + W, &grp[gi].lam2, W * sizeof(double));
    }
  }
  return ps.release();
}
ATMOSH_DISPATCH
static PolarStarts* make_polar_starts4(int kmax, int ngroups, const double* csq, const double* lam0, const double* e0,
                                       const unsigned char* plain, const ColCoef& cf) {
  return make_polar_starts<4>(kmax, ngroups, csq, lam0, e0, plain, cf);
}
#if ATMOSH_HAS_DISPATCH
ATMOSH_TARGET_AVX512
#endif
static PolarStarts* make_polar_starts8(int kmax, int ngroups, const double* csq, const double* lam0, const double* e0,
                                       const unsigned char* plain, const ColCoef& cf) {
  return make_polar_starts<8>(kmax, ngroups, csq, lam0, e0, plain, cf);
}
// Column m's polar starts, found by the first call that needs them (threads that find them
// at the same time keep the first one published; the others are the same values).
const PolarStarts& polar_starts(const RingPlan& rp, int m, const ColCoef& cf) {
  std::atomic<const PolarStarts*>& slot = rp.polar.p[m];
  if (const PolarStarts* ps = slot.load(std::memory_order_acquire)) return *ps;
  const int kmax = (rp.bands - 1 - m) / 2;
  const int ngroups = static_cast<int>(rp.pr.x.size()) / rp.W;
  const std::size_t off = static_cast<std::size_t>(m) * rp.pr.x.size();
  const unsigned char* plain = rp.plain.data() + static_cast<std::size_t>(m) * ngroups;
  std::unique_ptr<const PolarStarts> made(
      rp.W == 8 ? make_polar_starts8(kmax, ngroups, rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, plain, cf)
                : make_polar_starts4(kmax, ngroups, rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, plain, cf));
  const PolarStarts* expected = nullptr;
  if (slot.compare_exchange_strong(expected, made.get(), std::memory_order_acq_rel, std::memory_order_acquire))
    return *made.release();
  return *expected;
}

// Per-thread work space of the column sums for blocks of W ring pairs.
template <int W>
struct AnaWork {
  static constexpr int lanes = W;
  int ngroups;
  // (not std::vector: GCC drops the vector attribute, and thus the alignment, in template arguments)
  std::unique_ptr<AnaGroup<W>[]> nat, act;
  std::vector<int> join, ids, jsorted;
  std::vector<unsigned char> masked;  // ana_extended's marks (read by the polar starts only)
  explicit AnaWork(int padded)
      : ngroups(padded / W), nat(new AnaGroup<W>[ngroups]), act(new AnaGroup<W>[ngroups]), join(ngroups),
        ids(ngroups), jsorted(ngroups), masked(ngroups) {}
};

// One worker's scratch of the analysis columns (parallel_for_m).
template <int W>
struct AnaScratch {
  AnaWork<W> work;
  std::unique_ptr<V4[]> sums;
  AnaCoef cf;
  AnaScratch(int padded, int bands) : work(padded), sums(new V4[bands + 4]) {}
};

// sums[k] (k <= kmax + 1) of column m: f = the ring sums of m in blocks of W lanes
// (E cos, E sin, xO cos, xO sin: 4 W values per block); csq, lam0, e0 the lanes' x^2 and
// starts, plain the blocks without an extended lane (RingPlan), ps the column's polar starts.
template <int W>
__attribute__((always_inline)) inline void ana_column(int kmax, const double* csq, const double* lam0,
                                                      const double* e0, const unsigned char* plain,
                                                      const double* f, const ColCoef& cf, AnaWork<W>& w, V4* sums,
                                                      const PolarStarts& ps) {
  using D = typename Lanes<W>::D;
  const int ngroups = w.ngroups;
  auto build = [&](AnaGroup<W>& g, int gi) {
    std::memcpy(&g.ec, f + 4 * W * gi, 4 * W * sizeof(double));  // ec, es, oc, os
    std::memcpy(&g.csq, csq + W * gi, W * sizeof(double));
    g.lam1 = D{};
    std::memcpy(&g.lam2, lam0 + W * gi, W * sizeof(double));
    std::memcpy(&g.e, e0 + W * gi, W * sizeof(double));
  };
  // plain blocks are made in place in act (ring order); the others go to nat[gi]: those
  // with a polar start with its values, the masked ones to run their extended phase there
  int nx = 0, nm = 0, nplain = 0;
  int* const masked_ids = w.jsorted.data();  // (free until the sort below)
  for (int gi = 0; gi < ngroups; ++gi) {
    if (plain[gi]) {
      build(w.act[nplain++], gi);
      continue;
    }
    const int j = ps.join[gi];
    if (j == kPolarNever) continue;
    AnaGroup<W>& g = w.nat[gi];
    build(g, gi);
    if (j == kPolarMasked) {
      masked_ids[nm++] = gi;
    } else {
      const double* lam = ps.lam.data() + static_cast<std::size_t>(ps.slot[gi]) * 2 * W;
      std::memcpy(&g.lam1, lam, W * sizeof(double));
      std::memcpy(&g.lam2, lam + W, W * sizeof(double));
      g.e = D{};
      w.join[gi] = j;
      w.ids[nx++] = gi;
    }
  }
  if (nm > 0) {
    unsigned char* const scratch = w.masked.data();
    if constexpr (W == 8)
      ana_extended8(kmax, cf.ap, cf.bp, w.nat.get(), masked_ids, nm, w.join.data(), sums, scratch);
    else
      ana_extended4(kmax, cf.ap, cf.bp, w.nat.get(), masked_ids, nm, w.join.data(), sums, scratch);
    for (int i = 0; i < nm; ++i) w.ids[nx++] = masked_ids[i];
  }
  // the plain blocks in ring order (already in act), then the others by the step they join at
  const int* join = w.join.data();
  std::sort(w.ids.begin(), w.ids.begin() + nx, [&](int p, int q) { return join[p] < join[q] || (join[p] == join[q] && p < q); });
  int nj = 0;
  for (; nj < nx && join[w.ids[nj]] <= kmax; ++nj) {
    w.act[nplain + nj] = w.nat[w.ids[nj]];
    w.jsorted[nj] = join[w.ids[nj]];
  }
  if (nplain + nj == 0) return;
  const int K0 = nplain > 0 ? 0 : w.jsorted[0];
  if constexpr (W == 8)
    ana_kernel8(K0, kmax, nplain, w.jsorted.data(), nj, cf.ap, cf.bp, w.act.get(), sums);
  else
    ana_kernel4(K0, kmax, nplain, w.jsorted.data(), nj, cf.ap, cf.bp, w.act.get(), sums);
}
// Compiled as the kernels (the block copies in vector registers).
ATMOSH_DISPATCH
static void ana_column4(int kmax, const double* csq, const double* lam0, const double* e0, const unsigned char* plain,
                        const double* f, const ColCoef& cf, AnaWork<4>& w, V4* sums, const PolarStarts& ps) {
  ana_column<4>(kmax, csq, lam0, e0, plain, f, cf, w, sums, ps);
}
#if ATMOSH_HAS_DISPATCH
ATMOSH_TARGET_AVX512
#endif
static void ana_column8(int kmax, const double* csq, const double* lam0, const double* e0, const unsigned char* plain,
                        const double* f, const ColCoef& cf, AnaWork<8>& w, V4* sums, const PolarStarts& ps) {
  ana_column<8>(kmax, csq, lam0, e0, plain, f, cf, w, sums, ps);
}
}  // namespace

// ---- synthesis: the same recurrence in x^2, transposed ------------------------
// For one m, the even degrees l = m + 2k contribute E(x) = sum_k e_k lam_k(x) with
// e_k = alpha_k c_m+2k. The odd degrees follow from the analysis identity above: with
// L the unit lower bidiagonal matrix (L_k,k-1 = qa_k) and D = diag(rb_k),
// Pbar_m+2k+1(x) = x sum_j (L^-1 D)_kj lam_j(x) for every x, so
// O(x) = sum_k c_m+2k+1 Pbar_m+2k+1(x) = x sum_j d_j lam_j(x) with d = D L^-T c_odd (a
// backward substitution y_k = c_k - qa_k+1 y_k+1, d_k = rb_k y_k). Per ring pair and two
// degrees: 2 FMAs of recurrence (the same lam as the analysis) and 4 of accumulation
// (cos and sin parts of E and of O / x). Blocks of W ring pairs are run one group after
// the other (kSynBlocks at a time, to overlap the recurrences), k inner, with their state
// and sums in registers; lanes in the extended range are stepped as in ana_extended and
// contribute from the step at which they reach the plain range (their terms before are
// < 2^-250).
namespace {
template <int W>
struct SynState {
  using D = typename Lanes<W>::D;
  D csq, lam1, lam2, e, ec, es, dc, ds;
};

// NB blocks stepped together from step 0 to kmax. While any lane of them is in the
// extended range (ext), the steps are masked: an extended lane adds nothing, and every
// kFoldEvery steps its values are folded as in ana_extended; from the first check at which
// every lane is plain, the steps are plain. A plain lane gets the same operations in the
// same order in both kinds of step, so its sums do not depend on where the masked steps
// end. (cf: 4 values per step, zero past the column's last degree; defined to kmax + 1.)
// With join (and ext false), the blocks start from zero values (adding nothing) and
// block b takes its values from pend[b] (lam1, lam2) at step join[b] (from its polar start:
// the same values and steps as the masked stepping gives it), from k0, the first of them.
template <int W, int NB>
__attribute__((always_inline)) inline void syn_blocks(int kmax, const double* ap, const double* bp, const double* cf,
                                                      SynState<W>* s, bool ext, int k0 = 0,
                                                      const int* join = nullptr, const SynState<W>* pend = nullptr) {
  using D = typename Lanes<W>::D;
  using I = typename Lanes<W>::I;
  // the sums of one degree's values v (E cos, E sin, D cos, D sin by c[0..3])
  auto add = [](SynState<W>& t, D v, const double* c) __attribute__((always_inline)) {
    t.ec += v * c[0];
    t.es += v * c[1];
    t.dc += v * c[2];
    t.ds += v * c[3];
  };
  // one step of two degrees; keep[b]: the plain lanes of block b (all ones in plain steps)
  auto step = [&](int k, const I* keep) __attribute__((always_inline)) {
    const double* c = cf + 4 * k;
    const double a1 = ap[k], b1 = bp[k], a2 = ap[k + 1], b2 = bp[k + 1];
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) add(s[b], (D)((I)s[b].lam2 & keep[b]), c);
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) s[b].lam1 = (a1 * s[b].csq + b1) * s[b].lam2 + s[b].lam1;
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) add(s[b], (D)((I)s[b].lam1 & keep[b]), c + 4);
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) s[b].lam2 = (a2 * s[b].csq + b2) * s[b].lam1 + s[b].lam2;
  };
  int k = k0;
  I keep[NB];
#pragma GCC unroll 8
  for (int b = 0; b < NB; ++b) keep[b] = ~I{};
  if (join) {
    int klast = k0;
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b)
      if (join[b] <= kmax) klast = std::max(klast, join[b]);
    for (; k <= klast; k += 2) {
#pragma GCC unroll 8
      for (int b = 0; b < NB; ++b)
        if (join[b] == k) {
          s[b].lam1 = pend[b].lam1;
          s[b].lam2 = pend[b].lam2;
        }
      step(k, keep);
    }
  }
  if (ext) {
    for (; k <= kmax; k += 2) {
      if (k % kFoldEvery == 0) {
        I anyx{};
#pragma GCC unroll 8
        for (int b = 0; b < NB; ++b) {
          I x = fold_extended<W>(s[b]);
          if (any(x) && any(~x) && graduate<W>(s[b], x)) x = I{};
          keep[b] = ~x;
          anyx |= x;
        }
        if (!any(anyx)) break;
      }
      step(k, keep);
    }
  }
#pragma GCC unroll 8
  for (int b = 0; b < NB; ++b) keep[b] = ~I{};
  for (; k <= kmax; k += 2) step(k, keep);
}

// The sums of one block of W ring pairs (x: the lanes' cosines) to o[4 j + f] for lane j:
// E cos, E sin, x D cos, x D sin (a 4 x W transpose in registers).
template <int W>
__attribute__((always_inline)) inline void syn_store(const SynState<W>& s, const double* x, double* o) {
  using D = typename Lanes<W>::D;
  D xv;
  std::memcpy(&xv, x, sizeof xv);
  const D oc = xv * s.dc, os = xv * s.ds;
  if constexpr (W == 8) {
    const D plo = __builtin_shufflevector(s.ec, s.es, 0, 8, 1, 9, 2, 10, 3, 11);
    const D phi = __builtin_shufflevector(s.ec, s.es, 4, 12, 5, 13, 6, 14, 7, 15);
    const D qlo = __builtin_shufflevector(oc, os, 0, 8, 1, 9, 2, 10, 3, 11);
    const D qhi = __builtin_shufflevector(oc, os, 4, 12, 5, 13, 6, 14, 7, 15);
    const D r[4] = {__builtin_shufflevector(plo, qlo, 0, 1, 8, 9, 2, 3, 10, 11),
                    __builtin_shufflevector(plo, qlo, 4, 5, 12, 13, 6, 7, 14, 15),
                    __builtin_shufflevector(phi, qhi, 0, 1, 8, 9, 2, 3, 10, 11),
                    __builtin_shufflevector(phi, qhi, 4, 5, 12, 13, 6, 7, 14, 15)};
    std::memcpy(o, r, sizeof r);
  } else {
    static_assert(W == 4);
    const D plo = __builtin_shufflevector(s.ec, s.es, 0, 4, 1, 5);
    const D phi = __builtin_shufflevector(s.ec, s.es, 2, 6, 3, 7);
    const D qlo = __builtin_shufflevector(oc, os, 0, 4, 1, 5);
    const D qhi = __builtin_shufflevector(oc, os, 2, 6, 3, 7);
    const D r[4] = {__builtin_shufflevector(plo, qlo, 0, 1, 4, 5), __builtin_shufflevector(plo, qlo, 2, 3, 6, 7),
                    __builtin_shufflevector(phi, qhi, 0, 1, 4, 5), __builtin_shufflevector(phi, qhi, 2, 3, 6, 7)};
    std::memcpy(o, r, sizeof r);
  }
}

// Blocks of W ring pairs stepped together by the synthesis; what is left at the end goes
// two and one at a time. On Zen 5 (AVX-512) 4 blocks took 4-5 % less time than 2 at
// L = 256 and 1024 (3: about halfway), with a few read-only spills of x^2 at W = 8.
constexpr int kSynBlocks = 4;
// Ring pairs per block of the synthesis's sums (a multiple of every W).
constexpr int kSynQB = 16;
// Column m for all blocks: x, mant, ex per lane (padded), cf the step coefficients;
// writes the per-lane sums E cos, E sin, O cos, O sin (O = x * D) of ring pair q to
// out[(q / kSynQB) * bstride + 4 (q % kSynQB) + f].
template <int W>
__attribute__((always_inline)) inline void syn_column(int kmax, int ngroups, const double* x, const double* csq,
                                                      const double* lam0, const double* e0, const double* ap,
                                                      const double* bp,
                                                      const double* cf, double* out, std::size_t bstride,
                                                      const PolarStarts& ps) {
  auto at = [&](int q) { return out + static_cast<std::size_t>(q / kSynQB) * bstride + 4 * (q % kSynQB); };
  // Leading blocks that never join (polar starts) add nothing to their rings: their sums
  // are zero.
  int g0 = 0;
  while (g0 < ngroups && ps.join[g0] == kPolarNever) ++g0;
  for (int q = 0; q < W * g0; ++q)
    for (int f = 0; f < 4; ++f) at(q)[f] = 0.0;
  using D = typename Lanes<W>::D;
  auto load = [&](SynState<W>& s, int q0) __attribute__((always_inline)) {
    std::memcpy(&s.csq, csq + q0, sizeof(D));
    s.lam1 = D{};
    std::memcpy(&s.lam2, lam0 + q0, sizeof(D));
    std::memcpy(&s.e, e0 + q0, sizeof(D));
    s.ec = s.es = s.dc = s.ds = D{};
    return any(s.e != D{});  // whether a lane is extended
  };
  // kSynBlocks blocks at a time (their recurrences overlap), then what is left; each from
  // its polar start, or all stepped masked from their sectoral starts where one of them
  // has plain and extended lanes at once (kPolarMasked)
  auto run = [&](auto nb, int gi) __attribute__((always_inline)) {
    constexpr int NB = decltype(nb)::value;
    SynState<W> st[NB];
    bool masked = false;
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) masked |= ps.join[gi + b] == kPolarMasked;
    if (masked) {
      bool ext = false;
#pragma GCC unroll 8
      for (int b = 0; b < NB; ++b) ext |= load(st[b], W * (gi + b));
      syn_blocks<W, NB>(kmax, ap, bp, cf, st, ext);
    } else {
      SynState<W> pend[NB];
      int join[NB], k0 = kmax + 1;
#pragma GCC unroll 8
      for (int b = 0; b < NB; ++b) {
        const int g = gi + b, j = ps.join[g];
        std::memcpy(&st[b].csq, csq + W * g, sizeof(D));
        st[b].lam1 = st[b].lam2 = st[b].e = st[b].ec = st[b].es = st[b].dc = st[b].ds = D{};
        join[b] = j;
        pend[b].lam1 = pend[b].lam2 = D{};
        if (ps.slot[g] < 0 && j == 0) {  // a plain block
          pend[b].lam1 = D{};
          std::memcpy(&pend[b].lam2, lam0 + W * g, sizeof(D));
        } else if (j <= kmax) {
          const double* lam = ps.lam.data() + static_cast<std::size_t>(ps.slot[g]) * 2 * W;
          std::memcpy(&pend[b].lam1, lam, sizeof(D));
          std::memcpy(&pend[b].lam2, lam + W, sizeof(D));
        }
        if (j <= kmax) k0 = std::min(k0, j);
      }
      if (k0 <= kmax) syn_blocks<W, NB>(kmax, ap, bp, cf, st, false, k0, join, pend);
    }
#pragma GCC unroll 8
    for (int b = 0; b < NB; ++b) syn_store<W>(st[b], x + W * (gi + b), at(W * (gi + b)));
  };
  int gi = g0;
  for (; gi + kSynBlocks <= ngroups; gi += kSynBlocks) run(std::integral_constant<int, kSynBlocks>{}, gi);
  if constexpr (kSynBlocks > 2)
    if (gi + 2 <= ngroups) {
      run(std::integral_constant<int, 2>{}, gi);
      gi += 2;
    }
  if (gi < ngroups) run(std::integral_constant<int, 1>{}, gi);
}

// The step coefficients of synthesis column m from its coefficients c_l,m and c_l,-m (cos,
// sin; read from the degree rows of `coeffs` at l (l + 1) +- m): sc[4 k + {0, 1}] = e_k = alpha_k c_m+2k, sc[4 k + {2, 3}] = d_k =
// rb_k y_k with y_k = c_m+2k+1 - qa_k+1 y_k+1 for the odd degrees m + 2k + 1 < bands
// (k <= kodd; kodd = -1: none), zero past the last degree, to k = kmax + 1. The backward
// substitution is a chain of dependent operations: it runs two steps per link,
// y_k = (c_k - qa_k+1 c_k+1) + qa_k+1 qa_k+2 y_k+2 (y_k+1 from y_k+2 beside it).
ATMOSH_DISPATCH
static void syn_step_coefficients(int kmax, int kodd, const double* __restrict alpha, const double* __restrict qa,
                                  const double* __restrict rb, const double* __restrict coeffs, int m,
                                  bool prefetch, double* __restrict sc) {
  typedef double V2 __attribute__((vector_size(16)));
  // (c_l,m, c_l,-m) of degree l = m + i; c_l,-0 = 0
  auto ldc = [coeffs, m](int i) {
    const int l = m + i;
    const double* const row = coeffs + static_cast<std::size_t>(l) * (l + 1);
    return V2{row[m], m > 0 ? row[-m] : 0.0};
  };
  auto st = [](double* p, V2 v) { std::memcpy(p, &v, sizeof v); };
  if (prefetch) {
    // the values of these degrees 8 orders on (a cache line on from each of these), where
    // the degree has them
    for (int k = 0; k <= kmax; ++k) {
      st(sc + 4 * k, alpha[k] * ldc(2 * k));
      for (int i = 0; i < 2; ++i) {
        const int l = m + 2 * k + i;
        if (m + 8 > l) continue;
        const double* const row = coeffs + static_cast<std::size_t>(l) * (l + 1);
        __builtin_prefetch(row + m + 8);
        __builtin_prefetch(row - m - 8);
      }
    }
  } else {
    for (int k = 0; k <= kmax; ++k) st(sc + 4 * k, alpha[k] * ldc(2 * k));
  }
  for (int k = kodd + 1; k <= kmax + 1; ++k) st(sc + 4 * k + 2, V2{});
  st(sc + 4 * (kmax + 1), V2{});
  if (kodd < 0) return;
  int j = kodd;
  V2 y = ldc(2 * j + 1);  // y_kodd
  st(sc + 4 * j + 2, rb[j] * y);
  for (; j >= 2; j -= 2) {
    const V2 c1 = ldc(2 * (j - 1) + 1), c2 = ldc(2 * (j - 2) + 1);
    const V2 y1 = c1 - qa[j] * y;
    y = (c2 - qa[j - 1] * c1) + (qa[j - 1] * qa[j]) * y;
    st(sc + 4 * (j - 1) + 2, rb[j - 1] * y1);
    st(sc + 4 * (j - 2) + 2, rb[j - 2] * y);
  }
  if (j == 1) st(sc + 2, rb[0] * (ldc(1) - qa[1] * y));
}

ATMOSH_DISPATCH
static void syn_column4(int kmax, int ngroups, const double* x, const double* csq, const double* lam0,
                        const double* e0, const double* ap, const double* bp, const double* cf, double* out,
                        std::size_t bstride, const PolarStarts& ps) {
  syn_column<4>(kmax, ngroups, x, csq, lam0, e0, ap, bp, cf, out, bstride, ps);
}
#if ATMOSH_HAS_DISPATCH
ATMOSH_TARGET_AVX512
#endif
static void syn_column8(int kmax, int ngroups, const double* x, const double* csq, const double* lam0,
                        const double* e0, const double* ap, const double* bp, const double* cf, double* out,
                        std::size_t bstride, const PolarStarts& ps) {
  syn_column<8>(kmax, ngroups, x, csq, lam0, e0, ap, bp, cf, out, bstride, ps);
}
}  // namespace

namespace {
// Ring pairs per lane block of the analysis kernels (B is a multiple of both).
int analysis_lanes() { return has_avx512() ? 8 : 4; }

// Offset of the ring sums of column m, block of W ring pairs containing pair q, field f
// (0..3: E cos, E sin, xO cos, xO sin), lane of q: the sums are stored m-major.
// Planes of consecutive m lie ring_sum_stride(padded) values apart: 4 padded values and 16
// more, so that they are not a multiple of 4 kB apart (with padded a power of two they were,
// and the writes of one block's 4 W values per m, m after m, all fell in the same L1 sets).
inline std::size_t ring_sum_stride(int padded) { return static_cast<std::size_t>(padded) * 4 + 16; }
inline std::size_t ring_sum_index(int padded, int W, int m, int q, int f) {
  return static_cast<std::size_t>(m) * ring_sum_stride(padded) + static_cast<std::size_t>(q & -W) * 4 + W * f + (q & (W - 1));
}

void analysis_from_ring_sums(const RingPlan& rp, const double* fm, double* coeffs, int threads, bool assign);
// The synthesis's Legendre sums of every ring pair, handed over a block of kSynQB pairs at a
// time: block_done(q0, q1, sums) is called by the worker that has just finished the sums of
// pairs q0..q1-1, so that it can use them while they are in cache; pair q's sums of order m
// are sums[(m kSynQB + q - q0) 4 + f]: E cos, E sin, O cos, O sin (O = x D; see syn_store).
void synthesis_from_plan(const RingPlan& rp, const double* coeffs, int threads,
                         const std::function<void(int, int, const double*)>& block_done);
// Ring rows fourier[(r bands + m) 2 + {0, 1}] (as legendre_synthesis) of pairs q0..q1-1 from
// their block of sums.
void sums_to_rows(const Pairs& pr, int bands, int q0, int q1, const double* sums, double* fourier);
}  // namespace

void legendre_analysis(int bands, int nrings, const double* cos_t, const double* sin_t,
                       const double* fourier, bool symmetric, double* coeffs, int threads) {
  threads = atmosh::resolve_threads(threads);
  const RingPlan rp(bands, nrings, cos_t, sin_t, symmetric, analysis_lanes());
  const Pairs& pr = rp.pr;
  const int padded = static_cast<int>(pr.x.size());
  const int np = static_cast<int>(pr.north.size());
  const int W = rp.W;

  // Ring sums regrouped m-major, in blocks of m so that both the ring rows and the m
  // planes stream.
  constexpr int MB = 8;
  double* const fm = thread_work().fm.get(static_cast<std::size_t>(bands) * ring_sum_stride(padded));
  parallel_for_m((bands + MB - 1) / MB, threads, [] { return NoScratch{}; }, [&](NoScratch&, int block) {
    {
      const int mb = block * MB;
      const int m1 = std::min(bands, mb + MB);
      for (int q = np; q < padded; ++q)
        for (int m = mb; m < m1; ++m)
          for (int f = 0; f < 4; ++f) fm[ring_sum_index(padded, W, m, q, f)] = 0.0;
      for (int q = 0; q < np; ++q) {
        const double* fn = fourier + static_cast<std::size_t>(pr.north[q]) * bands * 2;
        const double* fs = pr.south[q] >= 0 ? fourier + static_cast<std::size_t>(pr.south[q]) * bands * 2 : nullptr;
        const double x = pr.x[q];
        for (int m = mb; m < m1; ++m) {
          const double nc = fn[2 * m], ns = fn[2 * m + 1];
          const double sc = fs ? fs[2 * m] : 0.0, ss = fs ? fs[2 * m + 1] : 0.0;
          double* o = fm + ring_sum_index(padded, W, m, q, 0);
          o[0] = nc + sc;
          o[W] = ns + ss;
          o[2 * W] = x * (nc - sc);
          o[3 * W] = x * (ns - ss);
        }
      }
    }
  });
  analysis_from_ring_sums(rp, fm, coeffs, threads, false);
}

namespace {
// The coefficients of analysis column m from its step sums (E cos, E sin, xO cos, xO sin
// per step k): out[4 k + {0, 1}] = alpha_k E (degree m + 2k); for the odd degrees
// m + 2k + 1 < bands (k <= kodd; kodd = -1: none) out[4 k + {2, 3}] = P_k by the forward
// substitution P_k = rb_k (xO)_k - qa_k P_k-1 (P_-1 = 0). That is a chain of dependent
// operations: it runs two steps per link, P_k+1 = (R_k+1 - qa_k+1 R_k) + qa_k+1 qa_k P_k-1
// with R_k = rb_k (xO)_k (P_k from P_k-1 beside it). Nothing is written past the column.
ATMOSH_DISPATCH
static void ana_outputs(int kmax, int kodd, const double* __restrict alpha, const double* __restrict rb,
                        const double* __restrict qa, const V4* __restrict sums, double* __restrict out) {
  typedef double V2 __attribute__((vector_size(16)));
  auto lo = [](const V4& v) { return V2{v[0], v[1]}; };
  auto hi = [](const V4& v) { return V2{v[2], v[3]}; };
  auto st = [](double* p, V2 v) { std::memcpy(p, &v, sizeof v); };
  for (int k = 0; k <= kmax; ++k) st(out + 4 * k, alpha[k] * lo(sums[k]));
  if (kodd < 0) return;
  V2 p = rb[0] * hi(sums[0]);
  st(out + 2, p);
  int k = 1;
  for (; k + 1 <= kodd; k += 2) {
    const V2 r1 = rb[k] * hi(sums[k]), r2 = rb[k + 1] * hi(sums[k + 1]);
    const V2 p1 = r1 - qa[k] * p;
    p = (r2 - qa[k + 1] * r1) + (qa[k + 1] * qa[k]) * p;
    st(out + 4 * k + 2, p1);
    st(out + 4 * k + 6, p);
  }
  if (k == kodd) st(out + 4 * k + 2, rb[k] * hi(sums[k]) - qa[k] * p);
}
}  // namespace

namespace {
// Legendre sums of the analysis from the ring sums fm (see ring_sum_index); adds the
// coefficients to coeffs, or (assign) writes them (coeffs need not be initialised).
void analysis_from_ring_sums(const RingPlan& rp, const double* fm, double* coeffs, int threads, bool assign) {
  const int bands = rp.bands;
  const Pairs& pr = rp.pr;
  const auto coefs = coef_table(bands);
  const int padded = static_cast<int>(pr.x.size());
  const bool wide = rp.W == 8;
  ThreadWork& tw = thread_work();

  // per-m results: column m at col_offset(m), 2 (bands - m) values
  auto col_offset = [bands](int m) { return 2 * (static_cast<std::size_t>(m) * bands - static_cast<std::size_t>(m) * (m - 1) / 2); };
  double* const col = tw.col.get(col_offset(bands));
  auto columns = [&](auto& scratch, int m) {
    auto& work = scratch.work;
    V4* const sums = scratch.sums.get();
    const int kmax = (bands - 1 - m) / 2;
    if (!coefs) ana_coefficients(bands, m, scratch.cf);
    const ColCoef cf = coefs ? coefs->col(m) : view(scratch.cf);
    for (int k = 0; k <= kmax + 1; ++k) sums[k] = V4{};
    const std::size_t off = static_cast<std::size_t>(m) * padded;
    const double* const fcol = fm + static_cast<std::size_t>(m) * ring_sum_stride(padded);
    const unsigned char* const plain = rp.plain.data() + static_cast<std::size_t>(m) * work.ngroups;
    if constexpr (std::remove_reference_t<decltype(work)>::lanes == 8)
      ana_column8(kmax, rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, plain, fcol, cf, work, sums,
                  polar_starts(rp, m, cf));
    else
      ana_column4(kmax, rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, plain, fcol, cf, work, sums,
                  polar_starts(rp, m, cf));
    // A_l (l - m even) directly; A_l+1 from B_l by forward substitution (cos and sin
    // parts side by side); column m goes to col[2 (l - m) + {0, 1}]
    ana_outputs(kmax, bands - 2 - m >= 0 ? (bands - 2 - m) / 2 : -1, cf.alpha, cf.rb, cf.qa, sums,
                col + col_offset(m));
  };
  if (wide)
    parallel_for_m(bands, threads, [&] { return AnaScratch<8>(padded, bands); }, columns);
  else
    parallel_for_m(bands, threads, [&] { return AnaScratch<4>(padded, bands); }, columns);
  // columns into the coefficient vector in tiles of 8 degrees x 8 orders (a tile reads 8
  // column runs and writes 16 row runs of 8 values; degree rows one after the other, with
  // one line per column in flight, were latency bound: a tenth of an analysis at L = 256)
  // (rows of tiles split between the threads: each writes its own degree rows)
  constexpr int T = 8;
  parallel_for_m((bands + T - 1) / T, bands >= 512 ? threads : 1, [] { return NoScratch{}; }, [&](NoScratch&, int lt) {
    const int l0 = lt * T;
    const int l1 = std::min(bands, l0 + T);
    for (int m0 = 0; m0 < l1; m0 += T) {
      const int m1 = std::min(l1, m0 + T);
      for (int m = m0; m < m1; ++m) {
        const double* c = col + col_offset(m);
        for (int l = std::max(l0, m); l < l1; ++l) {
          double* row = coeffs + static_cast<std::size_t>(l) * (l + 1);
          if (assign) {
            row[m] = c[2 * (l - m)];
            if (m > 0) row[-m] = c[2 * (l - m) + 1];
          } else {
            row[m] += c[2 * (l - m)];
            if (m > 0) row[-m] += c[2 * (l - m) + 1];
          }
        }
      }
    }
  });
}
}  // namespace

void legendre_synthesis(int bands, int nrings, const double* cos_t, const double* sin_t,
                        const double* coeffs, bool symmetric, double* fourier, int threads) {
  const RingPlan rp(bands, nrings, cos_t, sin_t, symmetric, analysis_lanes());
  synthesis_from_plan(rp, coeffs, atmosh::resolve_threads(threads), [&](int q0, int q1, const double* sums) {
    sums_to_rows(rp.pr, bands, q0, q1, sums, fourier);
  });
}

namespace {
void synthesis_from_plan(const RingPlan& rp, const double* coeffs, int threads,
                         const std::function<void(int, int, const double*)>& block_done) {
  const int bands = rp.bands;
  const auto coefs = coef_table(bands);
  const Pairs& pr = rp.pr;
  const int padded = static_cast<int>(pr.x.size());
  const int np = static_cast<int>(pr.north.size());
  ThreadWork& tw = thread_work();
  const int W = rp.W;
  // The per-column sums are kept in blocks of 16 ring pairs (sm, 4 values per pair, m after
  // m within a block) and handed to block_done at the end. (Strided reads and writes of
  // single values per (ring, m) cost a fifth of a synthesis at L = 1024.) The coefficients are
  // read from their degree rows by the column set-up: a regroup into m-major columns before
  // it was a separate pass over all of them (~6 % of a synthesis at L = 256 and 1024).
  constexpr int QB = kSynQB;  // ring pairs per block of the sums
  const int nqb = (padded + QB - 1) / QB;
  double* const sm = tw.fm.get(static_cast<std::size_t>(bands) * nqb * QB * 4);

  struct Scratch {
    AnaCoef cf;
    std::vector<double> sc;
  };
  auto column = [&](Scratch& scratch, int m) {
    std::vector<double>& sc = scratch.sc;
    const int kmax = (bands - 1 - m) / 2;
    if (!coefs) ana_coefficients(bands, m, scratch.cf);
    const ColCoef cf = coefs ? coefs->col(m) : view(scratch.cf);
    syn_step_coefficients(kmax, bands - 2 - m >= 0 ? (bands - 2 - m) / 2 : -1, cf.alpha, cf.qa, cf.rb, coeffs, m,
                          bands >= 512, sc.data());
    const std::size_t off = static_cast<std::size_t>(m) * padded;
    // block b of the sums: sm[((b * bands + m) * QB + j) * 4 + f] for pair b QB + j
    double* const out = sm + static_cast<std::size_t>(m) * QB * 4;
    const std::size_t bstride = static_cast<std::size_t>(bands) * QB * 4;
    if (W == 8)
      syn_column8(kmax, padded / 8, pr.x.data(), rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, cf.ap, cf.bp,
                  sc.data(), out, bstride, polar_starts(rp, m, cf));
    else
      syn_column4(kmax, padded / 4, pr.x.data(), rp.csq.data(), rp.lam0.data() + off, rp.e0.data() + off, cf.ap, cf.bp,
                  sc.data(), out, bstride, polar_starts(rp, m, cf));
  };
  parallel_for_m(
      bands, threads,
      [&] { return Scratch{{}, std::vector<double>(4 * (static_cast<std::size_t>(bands) + 4))}; }, column);
  parallel_for_m((np + QB - 1) / QB, threads, [] { return NoScratch{}; }, [&](NoScratch&, int block) {
    const int q0 = block * QB, q1 = std::min(np, q0 + QB);
    block_done(q0, q1, sm + static_cast<std::size_t>(block) * bands * QB * 4);
  });
}

// Orders m0..m1-1 of one pair's ring rows fn (north) and fs (south; null: none) from its
// sums v[m kSynQB 4 + f].
void sums_to_ring_rows(const double* v, int m0, int m1, double* fn, double* fs) {
  int mb = m0;
  if (mb == 0 && m1 > 0) {  // m = 0: no sine part, no sqrt2
    fn[0] = v[0] + v[2];
    fn[1] = 0.0;
    if (fs) {
      fs[0] = v[0] - v[2];
      fs[1] = 0.0;
    }
    mb = 1;
  }
  // (E cos, E sin) +- (O cos, O sin), times sqrt2: two values per order at once
  typedef double V2 __attribute__((vector_size(16)));
  const V2 s2 = V2{} + std::numbers::sqrt2;
  for (int m = mb; m < m1; ++m) {
    const double* const vm = v + static_cast<std::size_t>(m) * kSynQB * 4;
    V2 e, o;
    std::memcpy(&e, vm, sizeof e);
    std::memcpy(&o, vm + 2, sizeof o);
    const V2 pn = s2 * (e + o);
    std::memcpy(fn + 2 * m, &pn, sizeof pn);
    if (fs) {
      const V2 ps = s2 * (e - o);
      std::memcpy(fs + 2 * m, &ps, sizeof ps);
    }
  }
}

void sums_to_rows(const Pairs& pr, int bands, int q0, int q1, const double* sums, double* fourier) {
  // runs of 16 orders per ring (ring rows lie a multiple of 4 kB apart when bands is a
  // power of two: writing 32 of them in step, one value each, thrashed L1's sets)
  constexpr int MC = 16;
  for (int m0 = 0; m0 < bands; m0 += MC)
    for (int q = q0; q < q1; ++q)
      sums_to_ring_rows(sums + 4 * static_cast<std::size_t>(q - q0), m0, std::min(bands, m0 + MC),
                        fourier + static_cast<std::size_t>(pr.north[q]) * bands * 2,
                        pr.south[q] >= 0 ? fourier + static_cast<std::size_t>(pr.south[q]) * bands * 2 : nullptr);
}

// The split spectrum (RealFft::inverse_split) whose real and imaginary parts are the north
// and south rings of one pair, from the pair's sums v[m stride + f] (E cos, E sin, O cos,
// O sin), of orders m0 <= m < m1; where m1 = count (the pair's last orders), also the zeros
// for count <= k <= n - count. With P = E + O and Q = E - O, the rings' spectra are
// N = sqrt2 P and S = sqrt2 Q (P and Q at m = 0), and as in inverse2
// Re Z_m = g (P cos + Q sin), Im Z_m = g (Q cos - P sin), Re Z_-m = g (P cos - Q sin),
// Im Z_-m = g (Q cos + P sin), g = sqrt2 / 2. Four orders at a time through a 4 x 4
// transpose; no fused multiply-add, so every clone gives the same bits.
ATMOSH_DISPATCH_NO_FMA
void sums_to_split(const double* __restrict v, int stride, int m0, int m1, int count, int n, double* __restrict zr,
                   double* __restrict zi) {
  if (m0 == 0 && m1 > 0) {
    zr[0] = v[0] + v[2];
    zi[0] = v[0] - v[2];
  }
  const double g = std::numbers::sqrt2 / 2;
  double* const rm = zr + n;  // Z_-m at n - m
  double* const im = zi + n;
  int m = std::max(m0, 1);
  for (; m + 4 <= m1; m += 4) {
    // (one load per order, no array: a copy loop through the stack defeated store forwarding)
    const double* const vm = v + static_cast<std::size_t>(m) * stride;
    V4 a0, a1, a2, a3;
    std::memcpy(&a0, vm, sizeof a0);
    std::memcpy(&a1, vm + stride, sizeof a1);
    std::memcpy(&a2, vm + 2 * static_cast<std::size_t>(stride), sizeof a2);
    std::memcpy(&a3, vm + 3 * static_cast<std::size_t>(stride), sizeof a3);
    const V4 t0 = __builtin_shufflevector(a0, a1, 0, 4, 2, 6);  // ec, ec', oc, oc'
    const V4 t1 = __builtin_shufflevector(a0, a1, 1, 5, 3, 7);  // es, es', os, os'
    const V4 t2 = __builtin_shufflevector(a2, a3, 0, 4, 2, 6);
    const V4 t3 = __builtin_shufflevector(a2, a3, 1, 5, 3, 7);
    const V4 ec = __builtin_shufflevector(t0, t2, 0, 1, 4, 5), oc = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
    const V4 es = __builtin_shufflevector(t1, t3, 0, 1, 4, 5), os = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
    const V4 pc = ec + oc, ps = es + os, qc = ec - oc, qs = es - os;
    const V4 r0 = g * (pc + qs), i0 = g * (qc - ps), r1 = g * (pc - qs), i1 = g * (qc + ps);
    std::memcpy(zr + m, &r0, sizeof r0);
    std::memcpy(zi + m, &i0, sizeof i0);
    const V4 r1r = __builtin_shufflevector(r1, r1, 3, 2, 1, 0), i1r = __builtin_shufflevector(i1, i1, 3, 2, 1, 0);
    std::memcpy(rm - m - 3, &r1r, sizeof r1r);
    std::memcpy(im - m - 3, &i1r, sizeof i1r);
  }
  for (; m < m1; ++m) {
    const double* const vm = v + static_cast<std::size_t>(m) * stride;
    const double pc = vm[0] + vm[2], ps = vm[1] + vm[3], qc = vm[0] - vm[2], qs = vm[1] - vm[3];
    zr[m] = g * (pc + qs);
    zi[m] = g * (qc - ps);
    rm[-m] = g * (pc - qs);
    im[-m] = g * (qc + ps);
  }
  if (m1 == count) {
    std::fill(zr + count, rm - count + 1, 0.0);
    std::fill(zi + count, im - count + 1, 0.0);
  }
}
}  // namespace

// Radix-2 butterflies of one stage (half = len / 2 >= 4) with the stage's twiddles
// contiguous (wr, wi: e^{-2 pi i k / len}, k < half), so that the k loop vectorises.
ATMOSH_DISPATCH
static void fft_stage(double* __restrict re, double* __restrict im, int n, int half, const double* __restrict wr,
                      const double* __restrict wi0, double sign) {
  for (int i = 0; i < n; i += 2 * half) {
    double* __restrict r0 = re + i;
    double* __restrict i0 = im + i;
    double* __restrict r1 = re + i + half;
    double* __restrict i1 = im + i + half;
    for (int k = 0; k < half; ++k) {
      const double w_r = wr[k], w_i = -sign * wi0[k];
      const double xr = r1[k] * w_r - i1[k] * w_i;
      const double xi = r1[k] * w_i + i1[k] * w_r;
      r1[k] = r0[k] - xr;
      i1[k] = i0[k] - xi;
      r0[k] += xr;
      i0[k] += xi;
    }
  }
}

void fft(double* re, double* im, int n, int sign) {
  // bit reversal
  for (int i = 1, j = 0; i < n; ++i) {
    int bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) {
      std::swap(re[i], re[j]);
      std::swap(im[i], im[j]);
    }
  }
  // twiddles per stage: tw[half + k] = e^{-2 pi i k / (2 half)}, k < half
  thread_local std::vector<double> tw_re, tw_im;
  if (static_cast<int>(tw_re.size()) != n) {
    tw_re.assign(n, 0.0);
    tw_im.assign(n, 0.0);
    for (int half = 1; half < n; half <<= 1)
      for (int k = 0; k < half; ++k) {
        // same angles as k * (n / len) / n of the full table
        tw_re[half + k] = std::cos(std::numbers::pi * k / half);
        tw_im[half + k] = -std::sin(std::numbers::pi * k / half);
      }
  }
  // len = 2 and 4 (twiddles 1 and -+i) in one radix-2^2 pass
  if (n >= 4) {
    for (int i = 0; i < n; i += 4) {
      const double a0r = re[i] + re[i + 1], a0i = im[i] + im[i + 1];
      const double a1r = re[i] - re[i + 1], a1i = im[i] - im[i + 1];
      const double b0r = re[i + 2] + re[i + 3], b0i = im[i + 2] + im[i + 3];
      const double b1r = re[i + 2] - re[i + 3], b1i = im[i + 2] - im[i + 3];
      // second butterfly: w = 1 for k = 0, w = -sign i for k = 1: (x r, x i) -> (sign x i, -sign x r)
      const double cr = sign * b1i, ci = -sign * b1r;
      re[i] = a0r + b0r;
      im[i] = a0i + b0i;
      re[i + 2] = a0r - b0r;
      im[i + 2] = a0i - b0i;
      re[i + 1] = a1r - cr;
      im[i + 1] = a1i - ci;
      re[i + 3] = a1r + cr;
      im[i + 3] = a1i + ci;
    }
  } else if (n == 2) {
    const double r = re[1], m = im[1];
    re[1] = re[0] - r;
    im[1] = im[0] - m;
    re[0] += r;
    im[0] += m;
  }
  for (int half = 4; half < n; half <<= 1)
    fft_stage(re, im, n, half, tw_re.data() + half, tw_im.data() + half, static_cast<double>(sign));
}

namespace {
// How a size is transformed (chosen from the factors of n alone, so that the same input
// gives the same bits from run to run; the costs were measured with FFTW 3.3 on AVX2, one
// thread, docs/sh.md):
//   split: n a power of two >= 16 — two rings as the real and imaginary parts of one
//         complex FFT in FFTW's split format, so that the rings' own rows are its input
//         (forward) or output (inverse): 25-45 % less time per ring than one c2r per ring at
//         n = 128 ... 2048 (Zen 5, FFTW 3.3.10, docs/sh.md); sizes with a factor 3 or 5 were
//         slower in this form than as real FFTs;
//   real: other n = 2^a 3^b 5^c — one real FFT (r2c / c2r) per ring;
//   pair: other factors all <= 13 — two rings as the real and imaginary parts of one
//         complex FFT of size n (FFTW's real transforms of such sizes cost 3-4x the complex
//         ones per ring);
//   chirp: a prime factor > 13 (511 = 7 x 73, 2047 = 23 x 89: FFTW then takes 10-20x the
//         power-of-two time) — two rings at once through Bluestein's chirp convolution
//         with complex FFTs of the power of two M >= 2n.
enum class FftMode { real, split, pair, chirp };
struct FftPlans {
  FftMode mode = FftMode::real;
  int m = 0;                                   // complex FFT size: n (split, pair) or M (chirp)
  fftw_plan r2c = nullptr, c2r = nullptr;      // size n, real
  fftw_plan r2c_rows[2] = {nullptr, nullptr};  // 4 / 8 consecutive rings at once (real mode, even n)
  fftw_plan fwd = nullptr;                     // size m, complex, in place (chirp: its kernels, at set-up)
  fftw_plan sfwd = nullptr, sbwd = nullptr;    // size n, complex, split format, out of place (split)
  fftw_plan fwd_oop = nullptr, bwd_oop = nullptr;  // size m, complex, out of place (pair, chirp)
  // chirp analysis with m >= 4096: the convolution's FFTs as m = n1 x n2 (four steps: n1
  // columns of n2 values, twiddles, n2 rows of n1 values), spectra in transposed order
  int n1 = 0;
  fftw_plan col_f = nullptr, row_f = nullptr, row_b = nullptr, col_b = nullptr;
  std::vector<double> tw, twb, kfp, kbp;  // w_m^(j1 k2), its conjugate, kf and kb transposed
  std::vector<double> chirp;                   // w_t = e^{i pi t^2 / n}, t < n (re, im)
  std::vector<double> kf, kb;                  // FFT of the forward / inverse kernels, / M
};
std::mutex& fftw_planner_mutex() {
  static std::mutex mu;
  return mu;
}
// Plans of size n, made once and kept until the process exits; then libsh destroys its own
// plans and nothing else: FFTW's global state (wisdom, planner) belongs to the process, and
// fftw_cleanup() would invalidate the plans that other code in it holds.
struct PlanCache {
  std::map<std::pair<int, bool>, FftPlans> plans;  // (n, measured)
  ~PlanCache() {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    for (auto& [n, p] : plans)
      for (fftw_plan q : {p.r2c, p.c2r, p.fwd, p.sfwd, p.sbwd, p.fwd_oop, p.bwd_oop, p.r2c_rows[0],
                          p.r2c_rows[1], p.col_f, p.row_f, p.row_b, p.col_b})
        if (q) fftw_destroy_plan(q);
    plans.clear();
  }
};

FftMode fft_mode(int n) {
  int r = n, largest = 1;
  for (int p = 2; p * p <= r; ++p)
    while (r % p == 0) {
      largest = std::max(largest, p);
      r /= p;
    }
  if (r > 1) largest = std::max(largest, r);
  if (r == 1 && largest == 2 && n >= 16) return FftMode::split;
  if (largest <= 5) return FftMode::real;
  return largest <= 13 ? FftMode::pair : FftMode::chirp;
}

// e^{i pi t^2 / n} with t^2 reduced mod 2n (exact in integers, so large t lose nothing).
void chirp_value(long long t, int n, double& re, double& im) {
  const long long q = (t % (2LL * n)) * (t % (2LL * n)) % (2LL * n);
  const double a = std::numbers::pi * static_cast<double>(q) / n;
  re = std::cos(a);
  im = std::sin(a);
}

PlanCache& plan_cache() {  // (first used after the mutex is made, so destroyed before it)
  static PlanCache cache;
  return cache;
}

const FftPlans* fft_plans(int n, bool measured) {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  auto& plans = plan_cache().plans;
  auto it = plans.find({n, measured});
  if (it != plans.end()) return &it->second;
  // every plan below: FFTW_ESTIMATE, or FFTW_MEASURE where asked for (the method, p.mode,
  // stays the one of n; the planner overwrites the arrays it is given, all scratch here)
  const unsigned plan_flag = measured ? FFTW_MEASURE : FFTW_ESTIMATE;
  // FFTW's plans follow the process's wisdom, FFTW_ESTIMATE ones included, and FFTW_MEASURE
  // records more. So that the default plans depend on n alone, they are made with no wisdom
  // (it is set aside first); so that measured plans leave nothing that later plans (libsh's
  // default ones, other code's) would follow, the process's wisdom is put back as it was
  // once these plans are made. (If FFTW cannot export it, it is left alone.)
  struct WisdomKept {
    char* saved;
    explicit WisdomKept(bool set_aside) : saved(fftw_export_wisdom_to_string()) {
      if (saved && set_aside) fftw_forget_wisdom();
    }
    ~WisdomKept() {
      if (!saved) return;
      fftw_forget_wisdom();  // (importing adds to the wisdom there is)
      fftw_import_wisdom_from_string(saved);
      std::free(saved);  // FFTW allocates it with malloc
    }
  } wisdom_kept(!measured);
  FftPlans p;
  p.mode = fft_mode(n);
  double* r = fftw_alloc_real(static_cast<std::size_t>(n));
  fftw_complex* c = fftw_alloc_complex(static_cast<std::size_t>(n) / 2 + 1);
  p.r2c = fftw_plan_dft_r2c_1d(n, r, c, plan_flag);
  p.c2r = fftw_plan_dft_c2r_1d(n, c, r, plan_flag);
  fftw_free(r);
  fftw_free(c);
  bool ok = p.r2c && p.c2r;
  if (ok && p.mode == FftMode::real && n % 2 == 0) {
    // several rings per FFTW call (FFTW then vectorises across them): ~20 % less time per
    // ring than one call per ring at n = 512 (AVX2, FFTW 3.3.10); FFTW_ESTIMATE (unless
    // measured), so the plan, and the bits of the results, do not depend on timing
    const int nc = n / 2 + 1;
    for (int i = 0; i < 2; ++i) {
      const int rows = i == 0 ? 4 : 8;
      double* rr = fftw_alloc_real(static_cast<std::size_t>(n) * rows);
      fftw_complex* cc = fftw_alloc_complex(static_cast<std::size_t>(nc) * rows);
      p.r2c_rows[i] = fftw_plan_many_dft_r2c(1, &n, rows, rr, nullptr, 1, n, cc, nullptr, 1, nc,
                                             plan_flag | FFTW_PRESERVE_INPUT);
      fftw_free(rr);
      fftw_free(cc);
    }
  }
  if (ok && p.mode == FftMode::split) {
    // FFTW's split DFT is the forward one (sign -1); with the real and imaginary parts of
    // input and output exchanged it is the backward one: i conj(DFT(i conj z)) = IDFT(z)
    p.m = n;
    double* a = fftw_alloc_real(4 * static_cast<std::size_t>(n));
    fftw_iodim dim{n, 1, 1};
    p.sfwd = fftw_plan_guru_split_dft(1, &dim, 0, nullptr, a, a + n, a + 2 * n, a + 3 * n,
                                      plan_flag | FFTW_PRESERVE_INPUT);
    p.sbwd = fftw_plan_guru_split_dft(1, &dim, 0, nullptr, a + n, a, a + 3 * n, a + 2 * n, plan_flag);
    fftw_free(a);
    ok = p.sfwd && p.sbwd;
  }
  if (p.mode == FftMode::pair || p.mode == FftMode::chirp) {
    int m = n;
    if (p.mode == FftMode::chirp) {
      m = 1;
      while (m < 2 * n) m <<= 1;
    }
    p.m = m;
    fftw_complex* z = fftw_alloc_complex(static_cast<std::size_t>(m));
    if (p.mode == FftMode::chirp) {  // the kernels' transforms (below)
      p.fwd = fftw_plan_dft_1d(m, z, z, FFTW_FORWARD, plan_flag);
      ok = ok && p.fwd;
    }
    if (ok) {
      // out of place: FFTW's in-place plans of these sizes buffer their columns (a third of
      // the FFT time at M = 1024, a sixth at n = 525); the chirp's forward input keeps its
      // zero tail from call to call (an out-of-place c2c preserves its input)
      fftw_complex* y = fftw_alloc_complex(static_cast<std::size_t>(m));
      p.fwd_oop = fftw_plan_dft_1d(m, z, y, FFTW_FORWARD, plan_flag | FFTW_PRESERVE_INPUT);
      p.bwd_oop = fftw_plan_dft_1d(m, y, z, FFTW_BACKWARD, plan_flag | FFTW_PRESERVE_INPUT);
      fftw_free(y);
      ok = p.fwd_oop && p.bwd_oop;
    }
    if (ok && p.mode == FftMode::chirp) {
      // Forward: X_k = conj(w_k) sum_j (x_j conj(w_j)) w_{k-j}, k in (-cf, cf) with
      // cf = n/2 + 1, so the kernel w_t is needed for t in [-(n + cf - 2), cf - 1].
      // Inverse: z_j = w_j sum_k (Z_k w_k) conj(w_{j-k}), |k| < ci = (n + 1) / 2, j < n:
      // the kernel conj(w_t) for t in [-(ci - 1), n + ci - 2]. Both ranges are shorter
      // than M, so the cyclic convolutions of size M are the linear ones.
      p.chirp.resize(2 * static_cast<std::size_t>(n));
      for (int t = 0; t < n; ++t) chirp_value(t, n, p.chirp[2 * t], p.chirp[2 * t + 1]);
      const int cf = n / 2 + 1, ci = (n + 1) / 2;
      auto kernel = [&](int t0, int t1, double conj_sign, std::vector<double>& out) {
        for (int i = 0; i < 2 * m; ++i) reinterpret_cast<double*>(z)[i] = 0.0;
        for (int t = t0; t <= t1; ++t) {
          const int pos = ((t % m) + m) % m;
          chirp_value(t < 0 ? -static_cast<long long>(t) : t, n, z[pos][0], z[pos][1]);
          z[pos][1] *= conj_sign;
        }
        fftw_execute_dft(p.fwd, z, z);
        out.resize(2 * static_cast<std::size_t>(m));
        for (int i = 0; i < m; ++i) {
          out[2 * i] = z[i][0] / m;
          out[2 * i + 1] = z[i][1] / m;
        }
      };
      kernel(-(n + cf - 2), cf - 1, 1.0, p.kf);
      kernel(-(ci - 1), n + ci - 2, -1.0, p.kb);
    }
    if (ok && p.mode == FftMode::chirp && m >= 4096) {
      // FFTW_ESTIMATE's plans for these sizes are ~1.4x slower than what FFTW_MEASURE finds;
      // four steps over square-ish factors are deterministic and faster (docs/sh.md).
      // j = j1 + n1 j2, k = k2 + n2 k1: columns j1 (stride n1) transform j2 -> k2, the
      // twiddle w_m^(j1 k2), rows k2 (contiguous) transform j1 -> k1, so the spectrum U_k
      // lands at k1 + n1 k2; the kernel's transform is stored in that order, and the
      // inverse runs the steps backwards into natural order.
      int n1 = 1;
      while (n1 * n1 < m) n1 <<= 1;
      const int n2 = m / n1;
      p.n1 = n1;
      fftw_complex* y = fftw_alloc_complex(static_cast<std::size_t>(m));
      p.col_f = fftw_plan_many_dft(1, &n2, n1, z, nullptr, n1, 1, y, nullptr, n1, 1, FFTW_FORWARD,
                                   plan_flag | FFTW_PRESERVE_INPUT);
      p.row_f = fftw_plan_many_dft(1, &n1, n2, y, nullptr, 1, n1, y, nullptr, 1, n1, FFTW_FORWARD, plan_flag);
      p.row_b = fftw_plan_many_dft(1, &n1, n2, y, nullptr, 1, n1, y, nullptr, 1, n1, FFTW_BACKWARD, plan_flag);
      p.col_b = fftw_plan_many_dft(1, &n2, n1, y, nullptr, n1, 1, z, nullptr, n1, 1, FFTW_BACKWARD,
                                   plan_flag | FFTW_PRESERVE_INPUT);
      fftw_free(y);
      ok = p.col_f && p.row_f && p.row_b && p.col_b;
      const std::size_t mm = static_cast<std::size_t>(m);
      p.tw.resize(2 * mm);
      p.twb.resize(2 * mm);
      p.kfp.resize(2 * mm);
      p.kbp.resize(2 * mm);
      for (int k2 = 0; k2 < n2; ++k2)
        for (int j1 = 0; j1 < n1; ++j1) {
          const std::size_t i = static_cast<std::size_t>(j1) + static_cast<std::size_t>(n1) * k2;
          const double a = -2.0 * std::numbers::pi * static_cast<double>(static_cast<long long>(j1) * k2 % m) / m;
          p.tw[2 * i] = p.twb[2 * i] = std::cos(a);
          p.tw[2 * i + 1] = std::sin(a);
          p.twb[2 * i + 1] = -p.tw[2 * i + 1];
        }
      for (int k1 = 0; k1 < n1; ++k1)
        for (int k2 = 0; k2 < n2; ++k2) {
          const std::size_t i = static_cast<std::size_t>(k1) + static_cast<std::size_t>(n1) * k2;
          const std::size_t k = static_cast<std::size_t>(k2) + static_cast<std::size_t>(n2) * k1;
          p.kfp[2 * i] = p.kf[2 * k];
          p.kfp[2 * i + 1] = p.kf[2 * k + 1];
          p.kbp[2 * i] = p.kb[2 * k];
          p.kbp[2 * i + 1] = p.kb[2 * k + 1];
        }
    }
    fftw_free(z);
  }
  if (!ok) {
    for (fftw_plan q : {p.r2c, p.c2r, p.fwd, p.sfwd, p.sbwd, p.fwd_oop, p.bwd_oop, p.r2c_rows[0], p.r2c_rows[1],
                        p.col_f, p.row_f, p.row_b, p.col_b})
      if (q) fftw_destroy_plan(q);
    throw std::runtime_error("FFTW could not plan a real FFT of size " + std::to_string(n));
  }
  return &plans.emplace(std::make_pair(n, measured), std::move(p)).first->second;
}

// z *= k elementwise (m complex values, interleaved).
ATMOSH_DISPATCH
void complex_multiply(double* __restrict z, const double* __restrict k, int m) {
  for (int i = 0; i < m; ++i) {
    const double a = z[2 * i], b = z[2 * i + 1], c = k[2 * i], d = k[2 * i + 1];
    z[2 * i] = a * c - b * d;
    z[2 * i + 1] = a * d + b * c;
  }
}

// The chirp's cyclic convolution of `in` (m complex values) with the forward (kf) or
// inverse (kb) kernel into `out`, through the work array v: four steps with the kernel in
// transposed order where the plans have them (m >= 4096), else two out-of-place FFTs
// (FFTW's in-place plans of these sizes buffer their columns). `out` may be `in`.
void chirp_convolve(const FftPlans& p, bool forward, fftw_complex* in, double* v, fftw_complex* out) {
  const int m = p.m;
  auto* const vc = reinterpret_cast<fftw_complex*>(v);
  if (p.n1 > 0) {
    fftw_execute_dft(p.col_f, in, vc);
    complex_multiply(v, p.tw.data(), m);
    fftw_execute_dft(p.row_f, vc, vc);
    complex_multiply(v, (forward ? p.kfp : p.kbp).data(), m);
    fftw_execute_dft(p.row_b, vc, vc);
    complex_multiply(v, p.twb.data(), m);
    fftw_execute_dft(p.col_b, vc, out);
  } else {
    fftw_execute_dft(p.fwd_oop, in, vc);
    complex_multiply(v, (forward ? p.kf : p.kb).data(), m);
    fftw_execute_dft(p.bwd_oop, vc, out);
  }
}

// u_j = (f1_j + i f2_j) conj(w_j), j < n (the chirp's input; the rest of u stays zero).
// Rounded as the scalar expressions read (no fused multiply-add).
ATMOSH_DISPATCH_NO_FMA
void chirp_premultiply(const double* __restrict f1, const double* __restrict f2, const double* __restrict w, int n,
                       double* __restrict u) {
  for (int j = 0; j < n; ++j) {
    const double a = f1[j], b = f2[j], c = w[2 * j], d = w[2 * j + 1];
    u[2 * j] = a * c + b * d;
    u[2 * j + 1] = b * c - a * d;
  }
}

// From the chirp's cyclic convolution y (size m): X_k = conj(w_k) y_k, X_-k = conj(w_k) y_(m-k)
// (w_-k = w_k), then the two rings' spectra F1_k = (X_k + conj X_-k) / 2,
// F2_k = (X_k - conj X_-k) / (2 i), k < cm, re/im interleaved. The same operations, rounded the
// same way, as the pass over all k in (-cm, cm) followed by the split (no fused multiply-add).
ATMOSH_DISPATCH_NO_FMA
void chirp_split(const double* __restrict y, const double* __restrict w, int m, int cm, double* __restrict s1,
                 double* __restrict s2) {
  if (cm < 1) return;
  {
    const double c = w[0], d = w[1], x = y[0], v = y[1];
    const double p0 = x * c + v * d, p1 = v * c - x * d;
    s1[0] = 0.5 * (p0 + p0);
    s1[1] = 0.5 * (p1 - p1);
    s2[0] = 0.5 * (p1 + p1);
    s2[1] = -0.5 * (p0 - p0);
  }
  const double* ym = y + 2 * static_cast<std::size_t>(m);  // y_(m-k) at ym - 2k
  for (int k = 1; k < cm; ++k) {
    const double c = w[2 * k], d = w[2 * k + 1];
    const double xa = y[2 * k], va = y[2 * k + 1], xb = ym[-2 * k], vb = ym[-2 * k + 1];
    const double p0 = xa * c + va * d, p1 = va * c - xa * d;
    const double q0 = xb * c + vb * d, q1 = vb * c - xb * d;
    s1[2 * k] = 0.5 * (p0 + q0);
    s1[2 * k + 1] = 0.5 * (p1 - q1);
    s2[2 * k] = 0.5 * (p1 + q1);
    s2[2 * k + 1] = -0.5 * (p0 - q0);
  }
}

// The chirp inverse's input (z cleared by the caller): y_k = Z_k w_k at k and m - k for
// |k| < count, Z_k = V1_k + i V2_k from the two rings' (C, S) coefficients. The same
// operations as a loop over k in (-count, count), rounded the same way (no fused multiply-add).
ATMOSH_DISPATCH_NO_FMA
void chirp_inverse_fill(const double* __restrict cs1, const double* __restrict cs2, int count,
                        const double* __restrict w, int m, double* __restrict z) {
  if (count < 1) return;
  {
    const double re = cs1[0], im = cs2[0], c = w[0], d = w[1];
    z[0] = re * c - im * d;
    z[1] = re * d + im * c;
  }
  double* const zm = z + 2 * static_cast<std::size_t>(m);  // y_(m-k) at zm - 2k
  for (int k = 1; k < count; ++k) {
    const double c1 = 0.5 * cs1[2 * k], s1 = 0.5 * cs1[2 * k + 1], c2 = 0.5 * cs2[2 * k], s2 = 0.5 * cs2[2 * k + 1];
    // V1_k = c1 - i s1, V2_k = c2 - i s2: Z_k = (c1 + s2) + i (c2 - s1); Z_-k = (c1 - s2) + i (c2 + s1)
    const double c = w[2 * k], d = w[2 * k + 1];
    const double pr = c1 + s2, pi = c2 - s1, qr = c1 - s2, qi = c2 + s1;
    z[2 * k] = pr * c - pi * d;
    z[2 * k + 1] = pr * d + pi * c;
    zm[-2 * k] = qr * c - qi * d;
    zm[-2 * k + 1] = qr * d + qi * c;
  }
}

// The spectra of two rings, X1_k = (Z_k + conj(Z_-k)) / 2 and X2_k = (Z_k - conj(Z_-k)) / (2 i)
// for k < cm (re, im interleaved), from the split forward FFT Z of z = f1 + i f2 (zr, zi).
ATMOSH_DISPATCH_NO_FMA
void split_separate(const double* __restrict zr, const double* __restrict zi, int n, int cm, double* __restrict s1,
                    double* __restrict s2) {
  if (cm < 1) return;
  s1[0] = zr[0];
  s1[1] = 0.0;
  s2[0] = zi[0];
  s2[1] = 0.0;
  const double* const rm = zr + n;
  const double* const im = zi + n;
  for (int k = 1; k < cm; ++k) {
    s1[2 * k] = 0.5 * (zr[k] + rm[-k]);
    s1[2 * k + 1] = 0.5 * (zi[k] - im[-k]);
    s2[2 * k] = 0.5 * (zi[k] + im[-k]);
    s2[2 * k + 1] = -0.5 * (zr[k] - rm[-k]);
  }
}

// The split inverse's spectrum of two rings (see RealFft::inverse2): Z_k = V1_k + i V2_k
// for 0 < k < count and its mirror Z_-k at n - k, real parts in zr, imaginary parts in zi;
// k = 0 and the zeros between are the caller's. (Two loops, so that each vectorises.)
ATMOSH_DISPATCH_NO_FMA
void split_inverse_fill(const double* __restrict cs1, const double* __restrict cs2, int count, int n,
                        double* __restrict zr, double* __restrict zi) {
  // V1_k = c1 - i s1, V2_k = c2 - i s2: Z_k = (c1 + s2) + i (c2 - s1); Z_-k = (c1 - s2) + i (c2 + s1)
  for (int k = 1; k < count; ++k) {
    zr[k] = 0.5 * cs1[2 * k] + 0.5 * cs2[2 * k + 1];
    zi[k] = 0.5 * cs2[2 * k] - 0.5 * cs1[2 * k + 1];
  }
  double* const rm = zr + n;
  double* const im = zi + n;
  for (int k = 1; k < count; ++k) {
    rm[-k] = 0.5 * cs1[2 * k] - 0.5 * cs2[2 * k + 1];
    im[-k] = 0.5 * cs2[2 * k] + 0.5 * cs1[2 * k + 1];
  }
}

// v1_j + i v2_j = w_j z_j, j < n (the chirp inverse's last step; no fused multiply-add).
ATMOSH_DISPATCH_NO_FMA
void chirp_inverse_out(const double* __restrict z, const double* __restrict w, int n, double* __restrict v1,
                       double* __restrict v2) {
  for (int j = 0; j < n; ++j) {
    const double x = z[2 * j], y = z[2 * j + 1], c = w[2 * j], d = w[2 * j + 1];
    v1[j] = x * c - y * d;
    v2[j] = x * d + y * c;
  }
}
}  // namespace

bool fft_plans_made(int n, bool measured) {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  return plan_cache().plans.count({n, measured}) > 0;
}

std::string fft_plan_text(int n, bool measured) {
  const FftPlans* p = fft_plans(n, measured);
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  char* t = fftw_sprint_plan(p->r2c);
  std::string text = t ? t : "";
  std::free(t);
  return text;
}

RealFft::RealFft(int n, bool measured) : n_(n), measured_(measured) {
  if (n < 1) throw InputError("RealFft: size must be >= 1, got " + std::to_string(n));
  plans_ = fft_plans(n, measured);
  const int m = static_cast<const FftPlans*>(plans_)->m;
  real_ = fftw_alloc_real(static_cast<std::size_t>(n));
  spec_ = reinterpret_cast<double*>(fftw_alloc_complex(static_cast<std::size_t>(n) / 2 + 1));
  // chirp: three arrays of m complex values (in-place work / out-of-place output, the
  // forward input with its zero tail, the forward spectrum); split: four arrays of n values
  // (the spectrum's real and imaginary parts, two rings where the caller's rows are not
  // aligned as the plan's); pair: two arrays of n complex values (input, output)
  const FftMode mode = static_cast<const FftPlans*>(plans_)->mode;
  const bool chirp = mode == FftMode::chirp;
  work_ = m > 0 ? reinterpret_cast<double*>(fftw_alloc_complex(static_cast<std::size_t>(m) * (chirp ? 3 : 2)))
                : nullptr;
  if (chirp && work_) std::fill(work_ + 2 * static_cast<std::size_t>(m), work_ + 4 * static_cast<std::size_t>(m), 0.0);
  spec2_ = reinterpret_cast<double*>(fftw_alloc_complex(static_cast<std::size_t>(n) / 2 + 1));
  if (!real_ || !spec_ || !spec2_ || (m > 0 && !work_)) {
    fftw_free(real_);
    fftw_free(spec_);
    fftw_free(spec2_);
    fftw_free(work_);
    throw std::bad_alloc();
  }
}

bool RealFft::pairs_rings(int n) { return n >= 1 && fft_mode(n) != FftMode::real; }
bool RealFft::splits_rings(int n) { return n >= 1 && fft_mode(n) == FftMode::split; }

void RealFft::inverse_split(double* zr, double* zi, double* v1, double* v2) {
  // the backward FFT's real and imaginary parts straight into v1, v2 where they are aligned
  // as the plan's arrays
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  if (fftw_alignment_of(zr) != fftw_alignment_of(work_) || fftw_alignment_of(zi) != fftw_alignment_of(work_))
    throw std::logic_error("RealFft::inverse_split: spectrum arrays not aligned as FFTW's");
  const bool direct = fftw_alignment_of(v1) == fftw_alignment_of(zr) && fftw_alignment_of(v2) == fftw_alignment_of(zr);
  double* const o1 = direct ? v1 : work_ + 2 * static_cast<std::size_t>(n_);
  double* const o2 = direct ? v2 : work_ + 3 * static_cast<std::size_t>(n_);
  fftw_execute_split_dft(p.sbwd, zi, zr, o2, o1);
  if (!direct) {
    std::memcpy(v1, o1, sizeof(double) * n_);
    std::memcpy(v2, o2, sizeof(double) * n_);
  }
}

RealFft::~RealFft() {
  fftw_free(real_);
  fftw_free(spec_);
  fftw_free(spec2_);
  fftw_free(work_);
}

RealFft::RealFft(RealFft&& o) noexcept
    : n_(o.n_), measured_(o.measured_), plans_(o.plans_), real_(o.real_), spec_(o.spec_), spec2_(o.spec2_),
      work_(o.work_) {
  o.real_ = o.spec_ = o.spec2_ = o.work_ = nullptr;
}

namespace {
// a_m, b_m (m < count) from the spectrum X_k = a_k - i b_k, k <= n/2 (filled for
// k < min(count, n/2 + 1)); orders above n/2 are the aliases.
void emit_orders(const double* spec, int n, int count, double* out) {
  const int half = n / 2;
  if (count <= half + 1) {  // no aliases (the usual case): no index arithmetic
    for (int m = 0; m < count; ++m) {
      out[2 * m] = spec[2 * m];
      out[2 * m + 1] = -spec[2 * m + 1];
    }
    return;
  }
  for (int m = 0; m < count; ++m) {
    int k = m % n;
    double sg = -1.0;
    if (k > half) {
      k = n - k;
      sg = 1.0;
    }
    out[2 * m] = spec[2 * k];
    out[2 * m + 1] = sg * spec[2 * k + 1];
  }
}
}  // namespace

template <class T>
void RealFft::forward(const T* f, int count, double* out) {
  const double* in = real_;
  if constexpr (std::is_same_v<T, double>) {
    // an out-of-place r2c leaves its input alone (FFTW_PRESERVE_INPUT is its default): rows
    // with the alignment of the plan's array are read in place, others copied
    if (fftw_alignment_of(const_cast<double*>(f)) == fftw_alignment_of(real_))
      in = f;
    else
      std::memcpy(real_, f, sizeof(double) * n_);
  } else {
    for (int j = 0; j < n_; ++j) real_[j] = static_cast<double>(f[j]);
  }
  fftw_execute_dft_r2c(static_cast<const FftPlans*>(plans_)->r2c, const_cast<double*>(in),
                       reinterpret_cast<fftw_complex*>(spec_));
  // X_k = sum_j f_j e^{-2 pi i j k / n} = a_k - i b_k
  emit_orders(spec_, n_, count, out);
}
template void RealFft::forward<double>(const double*, int, double*);

bool RealFft::forward_rows(const double* f, int rows, double* spectra) {
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  const fftw_plan plan = rows == 4 ? p.r2c_rows[0] : rows == 8 ? p.r2c_rows[1] : nullptr;
  if (!plan || fftw_alignment_of(const_cast<double*>(f)) != 0 || fftw_alignment_of(spectra) != 0) return false;
  fftw_execute_dft_r2c(plan, const_cast<double*>(f), reinterpret_cast<fftw_complex*>(spectra));
  return true;
}
template void RealFft::forward<float>(const float*, int, double*);

void RealFft::forward2_spectra(const double* f1, const double* f2, int count, double* s1, double* s2) {
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  const int cm = std::min(count, n_ / 2 + 1);
  if (p.mode == FftMode::real) {
    for (int i = 0; i < 2; ++i) {
      const double* f = i == 0 ? f1 : f2;
      const double* in = real_;
      if (fftw_alignment_of(const_cast<double*>(f)) == fftw_alignment_of(real_))
        in = f;
      else
        std::memcpy(real_, f, sizeof(double) * n_);
      fftw_execute_dft_r2c(p.r2c, const_cast<double*>(in), reinterpret_cast<fftw_complex*>(spec_));
      std::memcpy(i == 0 ? s1 : s2, spec_, sizeof(double) * 2 * cm);
    }
    return;
  }
  if (p.mode == FftMode::chirp) {
    chirp_spectra(f1, f2, cm, s1, s2);
    return;
  }
  if (p.mode == FftMode::split) {
    split_spectra(f1, f2, cm, s1, s2);
    return;
  }
  pair_spectra(f1, f2, cm, s1, s2);
}

void RealFft::pair_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2) {
  // z_j = f1_j + i f2_j, its FFT X out of place; F1_k = (X_k + conj(X_-k)) / 2,
  // F2_k = (X_k - conj(X_-k)) / (2 i) for k < cm
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  const int n = n_;
  double* const z = work_;
  double* const x = work_ + 2 * static_cast<std::size_t>(n);
  for (int j = 0; j < n; ++j) {
    z[2 * j] = f1[j];
    z[2 * j + 1] = f2[j];
  }
  fftw_execute_dft(p.fwd_oop, reinterpret_cast<fftw_complex*>(z), reinterpret_cast<fftw_complex*>(x));
  for (int k = 0; k < cm; ++k) {
    const double* xp = x + 2 * static_cast<std::size_t>(k);
    const double* xm = x + 2 * static_cast<std::size_t>(k == 0 ? 0 : n - k);
    s1[2 * k] = 0.5 * (xp[0] + xm[0]);
    s1[2 * k + 1] = 0.5 * (xp[1] - xm[1]);
    s2[2 * k] = 0.5 * (xp[1] + xm[1]);
    s2[2 * k + 1] = -0.5 * (xp[0] - xm[0]);
  }
}

void RealFft::split_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2) {
  // z_j = f1_j + i f2_j from the rows themselves (copied where they are not aligned as the
  // plan's arrays); F1_k = (Z_k + conj(Z_-k)) / 2, F2_k = (Z_k - conj(Z_-k)) / (2 i)
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  const int n = n_;
  double* const zr = work_;
  double* const zi = work_ + n;
  const double* a = f1;
  const double* b = f2;
  if (fftw_alignment_of(const_cast<double*>(f1)) != fftw_alignment_of(zr) ||
      fftw_alignment_of(const_cast<double*>(f2)) != fftw_alignment_of(zr)) {
    double* const t = work_ + 2 * static_cast<std::size_t>(n);
    std::memcpy(t, f1, sizeof(double) * n);
    std::memcpy(t + n, f2, sizeof(double) * n);
    a = t;
    b = t + n;
  }
  fftw_execute_split_dft(p.sfwd, const_cast<double*>(a), const_cast<double*>(b), zr, zi);
  split_separate(zr, zi, n, cm, s1, s2);
}

void RealFft::chirp_spectra(const double* f1, const double* f2, int cm, double* s1, double* s2) {
  // Bluestein: X_k = conj(w_k) sum_j (z_j conj(w_j)) w_(k-j), the convolution cyclic of size
  // m >= n + 2 cm - 2 through two out-of-place FFTs and the kernel's transform kf
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  const int m = p.m;
  double* const y = work_;
  double* const u = work_ + 2 * static_cast<std::size_t>(m);
  double* const v = work_ + 4 * static_cast<std::size_t>(m);
  chirp_premultiply(f1, f2, p.chirp.data(), n_, u);
  chirp_convolve(p, true, reinterpret_cast<fftw_complex*>(u), v, reinterpret_cast<fftw_complex*>(y));
  chirp_split(y, p.chirp.data(), m, cm, s1, s2);
}

void RealFft::forward2(const double* f1, const double* f2, int count, double* out1, double* out2) {
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  if (p.mode == FftMode::real) {
    forward(f1, count, out1);
    forward(f2, count, out2);
    return;
  }
  const int n = n_, cm = std::min(count, n / 2 + 1);
  if (p.mode == FftMode::chirp)
    chirp_spectra(f1, f2, cm, spec_, spec2_);
  else if (p.mode == FftMode::split)
    split_spectra(f1, f2, cm, spec_, spec2_);
  else
    pair_spectra(f1, f2, cm, spec_, spec2_);
  emit_orders(spec_, n, count, out1);
  emit_orders(spec2_, n, count, out2);
}

void RealFft::inverse(const double* cs, int count, double* v) {
  if (2 * count - 1 > n_)
    throw InputError("RealFft::inverse: " + std::to_string(count) + " orders need at least " +
                     std::to_string(2 * count - 1) + " points, have " + std::to_string(n_));
  const int nspec = n_ / 2 + 1;
  // c2r: v_j = X_0 + 2 Re sum_{0 < k < n/2} X_k e^{2 pi i j k / n} (+ X_{n/2} (-1)^j):
  // X_0 = C_0, X_m = (C_m - i S_m) / 2
  spec_[0] = count > 0 ? cs[0] : 0.0;
  spec_[1] = 0.0;
  for (int m = 1; m < nspec; ++m) {
    spec_[2 * m] = m < count ? 0.5 * cs[2 * m] : 0.0;
    spec_[2 * m + 1] = m < count ? -0.5 * cs[2 * m + 1] : 0.0;
  }
  // straight into v where it has the alignment of the plan's array (c2r destroys only its
  // input, spec_)
  if (fftw_alignment_of(v) == fftw_alignment_of(real_)) {
    fftw_execute_dft_c2r(static_cast<const FftPlans*>(plans_)->c2r, reinterpret_cast<fftw_complex*>(spec_), v);
    return;
  }
  fftw_execute_dft_c2r(static_cast<const FftPlans*>(plans_)->c2r, reinterpret_cast<fftw_complex*>(spec_), real_);
  std::copy(real_, real_ + n_, v);
}

void RealFft::inverse2(const double* cs1, const double* cs2, int count, double* v1, double* v2) {
  const FftPlans& p = *static_cast<const FftPlans*>(plans_);
  if (p.mode == FftMode::real) {
    inverse(cs1, count, v1);
    inverse(cs2, count, v2);
    return;
  }
  if (2 * count - 1 > n_)
    throw InputError("RealFft::inverse2: " + std::to_string(count) + " orders need at least " +
                     std::to_string(2 * count - 1) + " points, have " + std::to_string(n_));
  const int n = n_, m = p.m;
  if (p.mode == FftMode::split) {
    // Z_k = V1_k + i V2_k (as below) in split format; the backward FFT's real and imaginary
    // parts are the two rings, written to v1, v2 themselves where they are aligned as the
    // plan's arrays
    double* const zr = work_;
    double* const zi = work_ + n;
    zr[0] = count > 0 ? cs1[0] : 0.0;
    zi[0] = count > 0 ? cs2[0] : 0.0;
    split_inverse_fill(cs1, cs2, count, n, zr, zi);
    const int k0 = std::max(count, 1);
    std::fill(zr + k0, zr + n - k0 + 1, 0.0);
    std::fill(zi + k0, zi + n - k0 + 1, 0.0);
    inverse_split(zr, zi, v1, v2);
    return;
  }
  double* z = work_;
  if (p.mode == FftMode::chirp) {
    std::fill(z, z + 2 * m, 0.0);
    const double* w = p.chirp.data();
    chirp_inverse_fill(cs1, cs2, count, w, m, z);
    double* const v = work_ + 4 * static_cast<std::size_t>(m);
    auto* const zc = reinterpret_cast<fftw_complex*>(z);
    chirp_convolve(p, false, zc, v, zc);
    chirp_inverse_out(z, w, n, v1, v2);
    return;
  }
  // pair: Z_k = V1_k + i V2_k, V_0 = C_0, V_k = (C_k - i S_k) / 2, V_-k = conj(V_k), zero
  // for count <= |k|; its backward FFT out of place, whose real and imaginary parts are the
  // rings
  std::fill(z, z + 2 * static_cast<std::size_t>(n), 0.0);
  auto put = [&](int k, double re, double im) {
    double* v = z + 2 * static_cast<std::size_t>(k < 0 ? k + n : k);
    v[0] = re;
    v[1] = im;
  };
  if (count > 0) put(0, cs1[0], cs2[0]);
  for (int k = 1; k < count; ++k) {
    const double c1 = 0.5 * cs1[2 * k], s1 = 0.5 * cs1[2 * k + 1], c2 = 0.5 * cs2[2 * k], s2 = 0.5 * cs2[2 * k + 1];
    // V1_k = c1 - i s1, V2_k = c2 - i s2: Z_k = (c1 + s2) + i (c2 - s1); Z_-k = (c1 - s2) + i (c2 + s1)
    put(k, c1 + s2, c2 - s1);
    put(-k, c1 - s2, c2 + s1);
  }
  double* const y = work_ + 2 * static_cast<std::size_t>(n);
  fftw_execute_dft(p.bwd_oop, reinterpret_cast<fftw_complex*>(z), reinterpret_cast<fftw_complex*>(y));
  for (int j = 0; j < n; ++j) {
    v1[j] = y[2 * j];
    v2[j] = y[2 * j + 1];
  }
}

}  // namespace detail

namespace {
// Weighted ring sums of one ring pair for the Legendre stage: from the ring sums fn
// (north) and fs (south, null: none) at [2 m + {0, 1}] and the rings' quadrature
// weights, E cos, E sin, xO cos, xO sin at out[f * bands + m]. Rounded as written (no
// fused multiply-add), as the sums regrouped by legendre_analysis.
ATMOSH_DISPATCH_NO_FMA
void pair_sums(int bands, const double* fn, const double* fs, double wn, double ws, double x, double* out,
               std::size_t stride) {
  double* ec = out;
  double* es = out + stride;
  double* oc = out + 2 * stride;
  double* os = out + 3 * stride;
  for (int m = 0; m < bands; ++m) {
    const double sq = m > 0 ? std::numbers::sqrt2 : 1.0;
    const double wnm = wn * sq, wsm = ws * sq;
    const double nc = fn[2 * m] * wnm, ns = fn[2 * m + 1] * (m > 0 ? wnm : 0.0);
    const double sc = fs ? fs[2 * m] * wsm : 0.0, ss = fs ? fs[2 * m + 1] * (m > 0 ? wsm : 0.0) : 0.0;
    ec[m] = nc + sc;
    es[m] = ns + ss;
    oc[m] = x * (nc - sc);
    os[m] = x * (ns - ss);
  }
}
}  // namespace

namespace {
// The weighted ring sums of a block of W ring pairs straight from the rings' raw spectra
// (X_k = a_k - i b_k, re/im interleaved, rows sstride values apart; lane k's north ring
// at north + k sstride, its south ring at south + (W - 1 - k) sstride) into the m-major
// layout: o[m * mstride + W f + k] (f: E cos, E sin, xO cos, xO sin). The same operations,
// rounded the same way, as emit_orders + pair_sums + the regrouping (no fused multiply-add).
ATMOSH_DISPATCH_NO_FMA
void spectra_to_ring_sums(int L, int W, const double* north, const double* south, std::size_t sstride,
                          const double* wn, const double* ws, const double* x, double* o, std::size_t mstride) {
  int m0 = 0;
  if (W == 4 || W == 8) {
    // two orders at a time, four lanes at a time: the four lanes' (re, im) of orders m,
    // m + 1 transposed in registers, then the same products and sums elementwise over
    // the lanes
    typedef double V __attribute__((vector_size(32)));
    auto load = [](const double* p) {
      V v;
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    auto store = [](double* p, V v) { std::memcpy(p, &v, sizeof v); };
    // r0..r3: (re_m, im_m, re_m+1, im_m+1) of lanes 0..3 -> re_m, im_m, re_m+1, im_m+1 over lanes
    auto transpose = [](V r0, V r1, V r2, V r3, V& a, V& b, V& c, V& d) {
      const V t0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6), t1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);
      const V t2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6), t3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
      a = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
      b = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
      c = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
      d = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
    };
    const V zero = V{};
    struct Quad {
      V wn, ws, x;
      const double* n[4];
      const double* s[4];
    };
    // lanes 4h .. 4h + 3 (the lanes' south rows are in reverse order)
    Quad qd[2];
    const int nq = W / 4;
    for (int h = 0; h < nq; ++h) {
      Quad& q = qd[h];
      q.wn = V{wn[4 * h], wn[4 * h + 1], wn[4 * h + 2], wn[4 * h + 3]};
      q.ws = V{ws[4 * h], ws[4 * h + 1], ws[4 * h + 2], ws[4 * h + 3]};
      q.x = V{x[4 * h], x[4 * h + 1], x[4 * h + 2], x[4 * h + 3]};
      for (int k = 0; k < 4; ++k) {
        q.n[k] = north + static_cast<std::size_t>(4 * h + k) * sstride;
        q.s[k] = south + static_cast<std::size_t>(W - 1 - 4 * h - k) * sstride;
      }
    }
    auto emit = [&](const Quad& q, double* om, V nre, V nim, V sre, V sim, double sq, bool sin_on) {
      const V wnm = q.wn * sq, wsm = q.ws * sq;
      const V nc = nre * wnm, ns = -nim * (sin_on ? wnm : zero);
      const V sc = sre * wsm, ss = -sim * (sin_on ? wsm : zero);
      store(om, nc + sc);
      store(om + W, ns + ss);
      store(om + 2 * W, q.x * (nc - sc));
      store(om + 3 * W, q.x * (ns - ss));
    };
    for (; m0 + 2 <= L; m0 += 2) {
      const std::size_t j = 2 * static_cast<std::size_t>(m0);
      double* om = o + static_cast<std::size_t>(m0) * mstride;
      for (int h = 0; h < nq; ++h) {
        const Quad& q = qd[h];
        V nre0, nim0, nre1, nim1, sre0, sim0, sre1, sim1;
        transpose(load(q.n[0] + j), load(q.n[1] + j), load(q.n[2] + j), load(q.n[3] + j), nre0, nim0, nre1, nim1);
        transpose(load(q.s[0] + j), load(q.s[1] + j), load(q.s[2] + j), load(q.s[3] + j), sre0, sim0, sre1, sim1);
        emit(q, om + 4 * h, nre0, nim0, sre0, sim0, m0 > 0 ? std::numbers::sqrt2 : 1.0, m0 > 0);
        emit(q, om + mstride + 4 * h, nre1, nim1, sre1, sim1, std::numbers::sqrt2, true);
      }
    }
  }
  for (int m = m0; m < L; ++m) {
    const double sq = m > 0 ? std::numbers::sqrt2 : 1.0;
    double* om = o + static_cast<std::size_t>(m) * mstride;
    for (int k = 0; k < W; ++k) {
      const double* N = north + k * sstride + 2 * static_cast<std::size_t>(m);
      const double* S = south + (W - 1 - k) * sstride + 2 * static_cast<std::size_t>(m);
      const double wnm = wn[k] * sq, wsm = ws[k] * sq;
      const double nc = N[0] * wnm, ns = -N[1] * (m > 0 ? wnm : 0.0);
      const double sc = S[0] * wsm, ss = -S[1] * (m > 0 ? wsm : 0.0);
      om[k] = nc + sc;
      om[W + k] = ns + ss;
      om[2 * W + k] = x[k] * (nc - sc);
      om[3 * W + k] = x[k] * (ns - ss);
    }
  }
}

// The ring sums of a block of 4 ring pairs from lane rows to the m-major layout:
// out[m * mstride + 4 f + k] = lanes[(4 k + f) * ls + m], four orders at a time by 4x4
// transposes in registers (the scalar gather read 16 rows at once, a tenth of an analysis
// at L = 256).
ATMOSH_DISPATCH
void lanes_to_ring_sums4(int L, const double* __restrict lanes, std::size_t ls, double* __restrict out,
                         std::size_t mstride) {
  typedef double V __attribute__((vector_size(32)));
  auto load = [](const double* p) {
    V v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  int m = 0;
  for (; m + 4 <= L; m += 4)
    for (int f = 0; f < 4; ++f) {
      const V r0 = load(lanes + (0 + f) * ls + m), r1 = load(lanes + (4 + f) * ls + m);
      const V r2 = load(lanes + (8 + f) * ls + m), r3 = load(lanes + (12 + f) * ls + m);
      const V t0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6), t1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);
      const V t2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6), t3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
      const V c[4] = {__builtin_shufflevector(t0, t2, 0, 1, 4, 5), __builtin_shufflevector(t1, t3, 0, 1, 4, 5),
                      __builtin_shufflevector(t0, t2, 2, 3, 6, 7), __builtin_shufflevector(t1, t3, 2, 3, 6, 7)};
      for (int i = 0; i < 4; ++i) std::memcpy(out + (m + i) * mstride + 4 * f, &c[i], sizeof(V));
    }
  for (; m < L; ++m)
    for (int f = 0; f < 4; ++f)
      for (int k = 0; k < 4; ++k) out[m * mstride + 4 * f + k] = lanes[(4 * k + f) * ls + m];
}
}  // namespace

double GaussGrid::phi(int j) const { return 2.0 * std::numbers::pi * j / nphi; }

GaussGrid gauss_grid(int bands, int nlat, int nphi) {
  check_bands(bands, "gauss_grid");
  if (nlat == 0) nlat = bands;
  if (nphi == 0) {
    nphi = 1;
    while (nphi < 2 * bands - 1) nphi <<= 1;
  }
  if (nlat < bands) throw InputError("gauss_grid: nlat must be >= bands, got " + std::to_string(nlat));
  if (nphi < 2 * bands - 1) throw InputError("gauss_grid: nphi must be >= 2*bands-1, got " + std::to_string(nphi));
  GaussGrid g;
  g.bands = bands;
  g.nlat = nlat;
  g.nphi = nphi;
  const GaussLegendre gl = gauss_legendre(nlat);
  g.cos_t.resize(nlat);
  g.sin_t.resize(nlat);
  g.weights.resize(nlat);
  for (int i = 0; i < nlat; ++i) {
    const double x = gl.nodes[nlat - 1 - i];
    g.cos_t[i] = x;
    g.sin_t[i] = std::sqrt((1.0 - x) * (1.0 + x));
    g.weights[i] = gl.weights[nlat - 1 - i];
  }
  g.plan = std::make_shared<const detail::GridPlan>(g);
  return g;
}

GaussGrid regular_grid(int bands, LatitudeRule rule, int nlat, int nphi) {
  check_bands(bands, "regular_grid");
  if (rule == LatitudeRule::gauss) throw InputError("regular_grid: rule must be fejer or clenshaw_curtis (gauss: use gauss_grid)");
  if (nlat == 0) nlat = 2 * bands;
  if (nphi == 0) {
    nphi = 1;
    while (nphi < 2 * bands - 1) nphi <<= 1;
  }
  if (nlat < 2 * bands - 1 || nlat < 2)
    throw InputError("regular_grid: nlat must be >= 2*bands-1 (and >= 2), got " + std::to_string(nlat));
  if (nphi < 2 * bands - 1) throw InputError("regular_grid: nphi must be >= 2*bands-1, got " + std::to_string(nphi));
  GaussGrid g;
  g.bands = bands;
  g.rule = rule;
  g.nlat = nlat;
  g.nphi = nphi;
  g.weights = rule == LatitudeRule::fejer ? fejer1_weights(nlat) : clenshaw_curtis_weights(nlat);
  g.cos_t.resize(nlat);
  g.sin_t.resize(nlat);
  for (int i = 0; i < (nlat + 1) / 2; ++i) {
    const double t = rule == LatitudeRule::fejer ? std::numbers::pi * (i + 0.5) / nlat
                                                 : std::numbers::pi * i / (nlat - 1);
    // exact mirror symmetry (the Legendre stage pairs ring i with ring nlat-1-i)
    const bool equator = 2 * i + 1 == nlat;
    g.cos_t[i] = equator ? 0.0 : std::cos(t);
    g.sin_t[i] = equator ? 1.0 : std::sin(t);
    g.cos_t[nlat - 1 - i] = -g.cos_t[i];
    g.sin_t[nlat - 1 - i] = g.sin_t[i];
  }
  g.plan = std::make_shared<const detail::GridPlan>(g);
  return g;
}

std::vector<double> analyse(const GaussGrid& g, const double* values, int threads) {
  if (g.bands < 1 || g.nlat < 1 || g.nphi < 1 || static_cast<int>(g.cos_t.size()) != g.nlat)
    throw InputError("analyse: grid is not initialised (use gauss_grid)");
  std::vector<double> c(sh_count(g.bands));
  analyse(g, values, c.data(), threads);
  return c;
}

void analyse(const GaussGrid& g, const double* values, double* coeffs, int threads) {
  if (g.bands < 1 || g.nlat < 1 || g.nphi < 1 || static_cast<int>(g.cos_t.size()) != g.nlat)
    throw InputError("analyse: grid is not initialised (use gauss_grid)");
  threads = atmosh::resolve_threads(threads);
  const int L = g.bands, n = g.nphi;
  // Ring sums straight into the m-major layout of the Legendre stage: one block of
  // ring pairs at a time (its planes stay in cache while its lanes are filled).
  const auto plan = detail::plan_for(g);
  const detail::Pairs& pr = plan->rings.pr;
  const int padded = static_cast<int>(pr.x.size()), np = static_cast<int>(pr.north.size());
  const int W = plan->rings.W;
  double* const fm = detail::thread_work().fm.get(static_cast<std::size_t>(L) * detail::ring_sum_stride(padded));
  const double dphi = 2.0 * std::numbers::pi / n;
  // row stride of the lane buffers: off a multiple of 4 kB (the 4 W rows are read in step)
  const std::size_t LS = static_cast<std::size_t>(L) + 8;
  // One block of W ring pairs at a time from the shared counter; each worker keeps its
  // FFT plan and lane buffers.
  struct FftwFree {
    void operator()(double* p) const { fftw_free(p); }
  };
  struct Scratch {
    detail::RealFft fft;
    std::vector<double> fn, fs, lanes;  // lanes: [lane][field][m]
    std::unique_ptr<double, FftwFree> spectra;  // 2 W rings' spectra (forward_rows)
  };
  const std::size_t sstride = 2 * (static_cast<std::size_t>(n) / 2 + 1);
  auto block = [&](Scratch& scratch, int blk) {
    detail::RealFft& fft = scratch.fft;
    // whole blocks of distinct north and south rings: W north rows and W south rows, each
    // consecutive, through one FFTW call each and straight into the ring sums
    const int q0 = blk * W, qe = q0 + W - 1;
    if (qe < np && pr.south[qe] > pr.north[qe] && pr.north[q0] == q0 && 2 * L <= n + 2) {
      double* const sn = scratch.spectra.get();
      double* const ss = sn + W * sstride;
      const int s_first = pr.south[qe];  // rows s_first .. s_first + W - 1: lanes W - 1 .. 0
      bool done = fft.forward_rows(values + static_cast<std::size_t>(q0) * n, W, sn) &&
                  fft.forward_rows(values + static_cast<std::size_t>(s_first) * n, W, ss);
      if (!done) {  // other sizes: ring pair by ring pair (paired or chirp FFTs)
        for (int k = 0; k < W; ++k)
          fft.forward2_spectra(values + static_cast<std::size_t>(pr.north[q0 + k]) * n,
                               values + static_cast<std::size_t>(pr.south[q0 + k]) * n, L, sn + k * sstride,
                               ss + (W - 1 - k) * sstride);
        done = true;
      }
      if (done) {
        double wn[8], ws[8];
        for (int k = 0; k < W; ++k) {
          wn[k] = g.weights[pr.north[q0 + k]] * dphi;
          ws[k] = g.weights[pr.south[q0 + k]] * dphi;
        }
        spectra_to_ring_sums(L, W, sn, ss, sstride, wn, ws, pr.x.data() + q0,
                             fm + detail::ring_sum_index(padded, W, 0, q0, 0), detail::ring_sum_stride(padded));
        return;
      }
    }
    std::vector<double>& fn = scratch.fn;
    std::vector<double>& fs = scratch.fs;
    std::vector<double>& lanes = scratch.lanes;
    for (int k = 0; k < W; ++k) {
      const int q = blk * W + k;
      double* out = lanes.data() + static_cast<std::size_t>(k) * 4 * LS;
      if (q >= np) {
        std::fill(out, out + 4 * LS, 0.0);
        continue;
      }
      const int r = pr.north[q], s = pr.south[q];
      if (s >= 0)
        fft.forward2(values + static_cast<std::size_t>(r) * n, values + static_cast<std::size_t>(s) * n, L, fn.data(),
                     fs.data());
      else
        fft.forward(values + static_cast<std::size_t>(r) * n, L, fn.data());
      // weights of the Gauss rule in latitude and of the uniform rule in longitude
      pair_sums(L, fn.data(), s >= 0 ? fs.data() : nullptr, g.weights[r] * dphi, s >= 0 ? g.weights[s] * dphi : 0.0,
                pr.x[q], out, LS);
    }
    // one contiguous run of 4 W values per m
    double* const o = fm + detail::ring_sum_index(padded, W, 0, blk * W, 0);
    if (W == 4) {
      lanes_to_ring_sums4(L, lanes.data(), LS, o, detail::ring_sum_stride(padded));
    } else {
      for (int m = 0; m < L; ++m)
        for (int f = 0; f < 4; ++f)
          for (int k = 0; k < W; ++k)
            o[static_cast<std::size_t>(m) * detail::ring_sum_stride(padded) + f * W + k] = lanes[(static_cast<std::size_t>(k) * 4 + f) * LS + m];
    }
  };
  atmosh::parallel_for_ranges_local(
      static_cast<std::size_t>(padded / W), 1, threads,
      [&] {
        Scratch s{detail::RealFft(n, g.fft == FftPlanning::measure), std::vector<double>(2 * static_cast<std::size_t>(L)),
                  std::vector<double>(2 * static_cast<std::size_t>(L)),
                  std::vector<double>(static_cast<std::size_t>(W) * 4 * LS),
                  std::unique_ptr<double, FftwFree>(reinterpret_cast<double*>(fftw_alloc_complex(W * sstride)))};
        if (!s.spectra) throw std::bad_alloc();
        return s;
      },
      [&](Scratch& scratch, std::size_t b, std::size_t e) {
        for (std::size_t blk = b; blk < e; ++blk) block(scratch, static_cast<int>(blk));
      });
  detail::analysis_from_ring_sums(plan->rings, fm, coeffs, threads, true);
}

std::vector<double> synthesise(const GaussGrid& g, const double* coeffs, int threads) {
  if (g.bands < 1 || g.nlat < 1 || g.nphi < 1 || static_cast<int>(g.cos_t.size()) != g.nlat)
    throw InputError("synthesise: grid is not initialised (use gauss_grid)");
  std::vector<double> out(static_cast<std::size_t>(g.nlat) * g.nphi);
  synthesise(g, coeffs, out.data(), threads);
  return out;
}

void synthesise(const GaussGrid& g, const double* coeffs, double* values, int threads) {
  if (g.bands < 1 || g.nlat < 1 || g.nphi < 1 || static_cast<int>(g.cos_t.size()) != g.nlat)
    throw InputError("synthesise: grid is not initialised (use gauss_grid)");
  threads = atmosh::resolve_threads(threads);
  const int L = g.bands, n = g.nphi;
  const bool measured = g.fft == FftPlanning::measure;
  const auto plan = detail::plan_for(g);
  const detail::Pairs& pr = plan->rings.pr;
  const int np = static_cast<int>(pr.north.size());
  constexpr int QB = detail::kSynQB;
  auto row = [](double* base, int r, std::size_t len) { return base + static_cast<std::size_t>(r) * len; };
  if (detail::RealFft::splits_rings(n) && 2 * L - 1 <= n && n <= 1024) {
    // Powers of two to 1024: each pair's north and south rings as the real and imaginary
    // parts of one split-format complex FFT, its spectrum made from the pair's sums and
    // transformed into the two rows of `values` by the worker that made the sums, while they
    // are in cache. (With n = 2048 the block's 16 spectra fill half of L2, and FFTs from there
    // were slower than the ring rows below with their FFTs in L1: 23.3 against 22.5 ms at
    // L = 1024, where at L = 256 the spectra gave 0.431 against 0.453 ms.)
    // The spectra of a block's pairs are made 16 orders at a time over all its pairs, so
    // that the block's sums are read once (one pair after another, they were read from L2
    // 16 times: 10 % slower at L = 256).
    struct FftwFree {
      void operator()(double* p) const { fftw_free(p); }
    };
    detail::synthesis_from_plan(plan->rings, coeffs, threads, [&](int q0, int q1, const double* sums) {
      thread_local std::unique_ptr<detail::RealFft> fft;
      thread_local std::unique_ptr<double, FftwFree> zbuf;
      thread_local int zn = 0;
      thread_local std::vector<double> cs;
      if (!fft || fft->size() != n || fft->measured() != measured) fft = std::make_unique<detail::RealFft>(n, measured);
      if (zn != n) {
        zbuf.reset(fftw_alloc_real(2 * static_cast<std::size_t>(n) * QB));
        if (!zbuf) throw std::bad_alloc();
        zn = n;
      }
      auto z = [&](int q) { return zbuf.get() + 2 * static_cast<std::size_t>(n) * (q - q0); };
      constexpr int MC = 16;
      for (int m0 = 0; m0 < L; m0 += MC)
        for (int q = q0; q < q1; ++q)
          if (pr.south[q] >= 0)
            detail::sums_to_split(sums + 4 * static_cast<std::size_t>(q - q0), 4 * QB, m0, std::min(L, m0 + MC), L, n,
                                  z(q), z(q) + n);
      for (int q = q0; q < q1; ++q) {
        if (pr.south[q] >= 0) {
          fft->inverse_split(z(q), z(q) + n, row(values, pr.north[q], n), row(values, pr.south[q], n));
        } else {  // a ring without a mirror image (the equator of an odd nlat)
          cs.resize(2 * static_cast<std::size_t>(L));
          detail::sums_to_ring_rows(sums + 4 * static_cast<std::size_t>(q - q0), 0, L, cs.data(), nullptr);
          fft->inverse(cs.data(), L, row(values, pr.north[q], n));
        }
      }
    });
    return;
  }
  // every ring and order of the work array is written by sums_to_rows
  double* const four = detail::thread_work().four.get(static_cast<std::size_t>(g.nlat) * L * 2);
  // Each block of ring pairs is transformed in longitude by the worker that made its rows,
  // while they are in cache, where the FFTs need no ring of another block: always for one
  // real FFT per ring; for sizes that pair rings 2p and 2p + 1 (inverse2) when every block
  // holds both rings of each such pair (nlat even). The same operations, and bits, as the
  // loop below.
  auto block_rings = [&](int q0, int q1, int* rings) {  // sorted, at most 2 QB
    int k = 0;
    for (int q = q0; q < q1; ++q) {
      rings[k++] = pr.north[q];
      if (pr.south[q] >= 0) rings[k++] = pr.south[q];
    }
    std::sort(rings, rings + k);
    return k;
  };
  const bool paired = detail::RealFft::pairs_rings(n);
  bool fuse = true;
  if (paired) {  // every even ring r < nlat - 1 of a block with r + 1 in the same block
    int rings[2 * QB];
    for (int q0 = 0; q0 < np && fuse; q0 += QB) {
      const int k = block_rings(q0, std::min(np, q0 + QB), rings);
      for (int i = 0; i < k && fuse; ++i)
        if (rings[i] % 2 == 0 ? rings[i] + 1 < g.nlat && (i + 1 == k || rings[i + 1] != rings[i] + 1)
                              : i == 0 || rings[i - 1] != rings[i] - 1)
          fuse = false;
    }
  }
  const std::size_t len = 2 * static_cast<std::size_t>(L);
  if (fuse) {
    detail::synthesis_from_plan(plan->rings, coeffs, threads, [&](int q0, int q1, const double* sums) {
      detail::sums_to_rows(pr, L, q0, q1, sums, four);
      thread_local std::unique_ptr<detail::RealFft> fft;
      if (!fft || fft->size() != n || fft->measured() != measured) fft = std::make_unique<detail::RealFft>(n, measured);
      int rings[2 * QB];
      const int k = block_rings(q0, q1, rings);
      for (int i = 0; i < k; ++i) {
        const int r = rings[i];
        if (!paired) {
          fft->inverse(row(four, r, len), L, row(values, r, n));
        } else if (r % 2 == 0) {
          if (r + 1 < g.nlat)
            fft->inverse2(row(four, r, len), row(four, r + 1, len), L, row(values, r, n), row(values, r + 1, n));
          else
            fft->inverse(row(four, r, len), L, row(values, r, n));
        }
      }
    });
    return;
  }
  detail::synthesis_from_plan(plan->rings, coeffs, threads, [&](int q0, int q1, const double* sums) {
    detail::sums_to_rows(pr, L, q0, q1, sums, four);
  });
  // Two rings at a time from the shared counter; each worker keeps its FFT plan.
  const int npairs = (g.nlat + 1) / 2;
  atmosh::parallel_for_ranges_local(
      static_cast<std::size_t>(npairs), 1, threads, [&] { return detail::RealFft(n, measured); },
      [&](detail::RealFft& fft, std::size_t b, std::size_t e) {
        for (std::size_t q = b; q < e; ++q) {
          const std::size_t r = 2 * q;
          if (static_cast<int>(r) + 1 < g.nlat)
            fft.inverse2(four + r * L * 2, four + (r + 1) * L * 2, L, values + r * n, values + (r + 1) * n);
          else
            fft.inverse(four + r * L * 2, L, values + r * n);
        }
      });
}

}  // namespace atmosh::sh
