// The FFTs behind the transforms: the paired and chirp (Bluestein) methods against direct
// sums in long double, and libsh's teardown leaving the process's other FFTW plans and
// wisdom alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fftw3.h>

#include "atmosh/error.hpp"
#include "atmosh/sh/transform.hpp"
#include "transform_impl.hpp"  // private (libsh/src): detail::RealFft

using namespace atmosh::sh;

namespace {
long double angle(long long m, long long j, long long n) {
  return 2.0L * std::numbers::pi_v<long double> * ((m * j) % n) / n;
}
// v_j = sum_{m < count} (C_m cos(2 pi j m / n) + S_m sin(2 pi j m / n)) in long double from
// cs[2m] = C_m, cs[2m + 1] = S_m (S_0 not used): the direct sum behind inverse and inverse2.
long double inverse_sum(const std::vector<double>& cs, int count, int j, int n) {
  long double v = 0;
  for (int m = 0; m < count; ++m) {
    const long double p = angle(m, j, n);
    v += cs[2 * m] * std::cos(p) + (m > 0 ? cs[2 * m + 1] * std::sin(p) : 0.0L);
  }
  return v;
}
// bands^2 coefficients uniform in [-1, 1) from the seed
std::vector<double> uniform_coeffs(int bands, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<double> c(static_cast<std::size_t>(bands) * bands);
  for (auto& v : c) v = U(rng);
  return c;
}
}  // namespace

TEST(Transform, PairedRealFftsMatchDirectSums) {
  // Sizes of each method: powers of two from 16 (two rings per split-format complex FFT:
  // 16, 64, 512), other 2^a 3^b 5^c (real FFTs: 1, 2, 8, 96), other factors <= 13 (two rings
  // per complex FFT: 7, 21, 77, 525), a factor > 13 (Bluestein: 17, 34, 89, 511);
  // forward with aliased orders (count > n/2), inverse at the largest count. Plans of
  // FFTW_ESTIMATE and of FFTW_MEASURE (measured: its planner overwrites the arrays it plans
  // on, the chirp's kernels among them were they made first).
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<std::pair<int, bool>> cases;
  for (int n : {1, 2, 8, 16, 64, 512, 96, 7, 21, 77, 525, 17, 34, 89, 511})
    for (bool measured : {false, true}) cases.emplace_back(n, measured);
  for (const auto& [n, measured] : cases) {
    SCOPED_TRACE(measured ? "FFTW_MEASURE" : "FFTW_ESTIMATE");
    detail::RealFft fft(n, measured);
    ASSERT_EQ(fft.measured(), measured);
    std::vector<double> f1(n), f2(n);
    for (auto& v : f1) v = U(rng);
    for (auto& v : f2) v = U(rng);
    const std::vector<int> counts = n > 100 ? std::vector<int>{(n + 1) / 2} : std::vector<int>{1, (n + 1) / 2, n / 2 + 1, n + 3};
    for (int count : counts) {
      std::vector<double> o1(2 * count), o2(2 * count);
      fft.forward2(f1.data(), f2.data(), count, o1.data(), o2.data());
      for (int m = 0; m < count; ++m) {
        long double a1 = 0, b1 = 0, a2 = 0, b2 = 0;
        for (int j = 0; j < n; ++j) {
          const long double p = angle(m, j, n);
          a1 += f1[j] * std::cos(p);
          b1 += f1[j] * std::sin(p);
          a2 += f2[j] * std::cos(p);
          b2 += f2[j] * std::sin(p);
        }
        const double tol = 1e-14 * n + 1e-14;
        ASSERT_NEAR(o1[2 * m], static_cast<double>(a1), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o1[2 * m + 1], static_cast<double>(b1), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o2[2 * m], static_cast<double>(a2), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o2[2 * m + 1], static_cast<double>(b2), tol) << n << " " << count << " " << m;
      }
    }
    for (int count : {1, (n + 1) / 2}) {
      std::vector<double> c1(2 * count), c2(2 * count), v1(n), v2(n);
      for (auto& x : c1) x = U(rng);
      for (auto& x : c2) x = U(rng);
      fft.inverse2(c1.data(), c2.data(), count, v1.data(), v2.data());
      for (int j = 0; j < n; ++j) {
        const double tol = 1e-14 * n + 1e-14;
        ASSERT_NEAR(v1[j], static_cast<double>(inverse_sum(c1, count, j, n)), tol) << n << " " << count << " " << j;
        ASSERT_NEAR(v2[j], static_cast<double>(inverse_sum(c2, count, j, n)), tol) << n << " " << count << " " << j;
      }
      if (n > 1) {
        std::vector<double> big(2 * ((n + 1) / 2 + 1), 0.0);
        EXPECT_THROW(fft.inverse2(big.data(), big.data(), (n + 1) / 2 + 1, v1.data(), v2.data()), atmosh::InputError);
      }
    }
  }
}

TEST(Transform, ChirpOfFourStepsMatchesDirectSums) {
  // Bluestein sizes whose convolution size M = 2^k is 4096 or more run their FFTs in four
  // steps (n1 x n2, twiddles, spectrum in transposed order): 2047 = 23 x 89 (M = 4096, the
  // transforms at L = 1024) and 2053 (prime, M = 8192, n1 != n2), against long-double
  // direct sums at every 23rd order (and the largest) of a count with aliased orders
  // (count > n/2); the inverse at every 23rd point.
  // Plans of FFTW_ESTIMATE and (2047, the size of the benchmarks) of FFTW_MEASURE.
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> U(-1, 1);
  for (const auto& [n, measured] : {std::pair{2047, false}, std::pair{2053, false}, std::pair{2047, true}}) {
    SCOPED_TRACE(measured ? "FFTW_MEASURE" : "FFTW_ESTIMATE");
    detail::RealFft fft(n, measured);
    std::vector<double> f1(n), f2(n);
    for (auto& v : f1) v = U(rng);
    for (auto& v : f2) v = U(rng);
    {
      const int count = n + 5;  // orders below n/2 (the analysis's) and their aliases above
      std::vector<double> o1(2 * count), o2(2 * count);
      fft.forward2(f1.data(), f2.data(), count, o1.data(), o2.data());
      for (int m = 0; m < count; m = m + 23 < count || m == count - 1 ? m + 23 : count - 1) {
        long double a1 = 0, b1 = 0, a2 = 0, b2 = 0;
        for (int j = 0; j < n; ++j) {
          const long double p = angle(m, j, n), c = std::cos(p), s = std::sin(p);
          a1 += f1[j] * c;
          b1 += f1[j] * s;
          a2 += f2[j] * c;
          b2 += f2[j] * s;
        }
        const double tol = 1e-14 * n;
        ASSERT_NEAR(o1[2 * m], static_cast<double>(a1), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o1[2 * m + 1], static_cast<double>(b1), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o2[2 * m], static_cast<double>(a2), tol) << n << " " << count << " " << m;
        ASSERT_NEAR(o2[2 * m + 1], static_cast<double>(b2), tol) << n << " " << count << " " << m;
      }
    }
    // inverse (synthesis) at the largest count, every 13th point
    const int count = (n + 1) / 2;
    std::vector<double> c1(2 * count), c2(2 * count), v1(n), v2(n);
    for (auto& x : c1) x = U(rng);
    for (auto& x : c2) x = U(rng);
    fft.inverse2(c1.data(), c2.data(), count, v1.data(), v2.data());
    for (int j = 0; j < n; j += 23) {
      ASSERT_NEAR(v1[j], static_cast<double>(inverse_sum(c1, count, j, n)), 1e-14 * n) << n << " " << j;
      ASSERT_NEAR(v2[j], static_cast<double>(inverse_sum(c2, count, j, n)), 1e-14 * n) << n << " " << j;
    }
  }
}

TEST(Transform, SplitFftsOfTwoRingsReadAndWriteRowsInPlaceOrCopied) {
  // Powers of two transform two rings as one complex FFT in FFTW's split format, reading the
  // rows themselves (forward2_spectra) or writing into them (inverse2) where they have the
  // alignment of the plan's arrays, through copies otherwise. Both ways against direct sums
  // in long double, the same bits either way, and the input rows left as they were.
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int n : {16, 128, 1024}) {
    detail::RealFft fft(n);
    ASSERT_TRUE(detail::RealFft::pairs_rings(n)) << n;
    const int cm = n / 2 + 1;
    double* buf = fftw_alloc_real(2 * static_cast<std::size_t>(n) + 1);
    std::vector<double> f1(n), f2(n);
    for (auto& v : f1) v = U(rng);
    for (auto& v : f2) v = U(rng);
    std::vector<std::vector<double>> spectra;  // s1, s2 of the aligned rows, then of the shifted
    for (int shift : {0, 1}) {
      double* r1 = buf + shift;
      double* r2 = r1 + n;
      std::memcpy(r1, f1.data(), sizeof(double) * n);
      std::memcpy(r2, f2.data(), sizeof(double) * n);
      std::vector<double> s1(2 * cm), s2(2 * cm);
      fft.forward2_spectra(r1, r2, cm, s1.data(), s2.data());
      for (int j = 0; j < n; ++j) ASSERT_TRUE(r1[j] == f1[j] && r2[j] == f2[j]) << "input changed, n = " << n;
      spectra.push_back(s1);
      spectra.push_back(s2);
    }
    for (int k = 0; k < cm; ++k) {
      // X_k = sum_j f_j e^{-2 pi i j k / n}
      long double a1 = 0, b1 = 0, a2 = 0, b2 = 0;
      for (int j = 0; j < n; ++j) {
        const long double p = angle(k, j, n);
        a1 += f1[j] * std::cos(p);
        b1 -= f1[j] * std::sin(p);
        a2 += f2[j] * std::cos(p);
        b2 -= f2[j] * std::sin(p);
      }
      const double tol = 1e-14 * n;
      ASSERT_NEAR(spectra[0][2 * k], static_cast<double>(a1), tol) << n << " " << k;
      ASSERT_NEAR(spectra[0][2 * k + 1], static_cast<double>(b1), tol) << n << " " << k;
      ASSERT_NEAR(spectra[1][2 * k], static_cast<double>(a2), tol) << n << " " << k;
      ASSERT_NEAR(spectra[1][2 * k + 1], static_cast<double>(b2), tol) << n << " " << k;
      for (int i = 0; i < 2; ++i) {
        ASSERT_EQ(spectra[i][2 * k], spectra[2 + i][2 * k]) << n << " " << k;
        ASSERT_EQ(spectra[i][2 * k + 1], spectra[2 + i][2 * k + 1]) << n << " " << k;
      }
    }
    const int count = n / 2;
    std::vector<double> c1(2 * count), c2(2 * count);
    for (auto& v : c1) v = U(rng);
    for (auto& v : c2) v = U(rng);
    std::vector<double> va;
    for (int shift : {0, 1}) {
      double* r1 = buf + shift;
      double* r2 = r1 + n;
      fft.inverse2(c1.data(), c2.data(), count, r1, r2);
      if (shift == 0) {
        va.assign(r1, r1 + 2 * static_cast<std::size_t>(n));
        continue;
      }
      for (int j = 0; j < 2 * n; ++j) ASSERT_EQ(va[j], r1[j]) << n << " " << j;
    }
    for (int j = 0; j < n; ++j) {
      ASSERT_NEAR(va[j], static_cast<double>(inverse_sum(c1, count, j, n)), 1e-14 * n) << n << " " << j;
      ASSERT_NEAR(va[n + j], static_cast<double>(inverse_sum(c2, count, j, n)), 1e-14 * n) << n << " " << j;
    }
    fftw_free(buf);
  }
}

TEST(Transform, RealFftRowsReadAndWrittenInPlaceOrCopied) {
  // forward() reads a row in place when it has the alignment of the plan's array and copies
  // it otherwise; inverse() writes straight into such a row and through a copy otherwise.
  // Both ways against direct sums in long double, and the same bits either way.
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int n : {16, 96, 512}) {
    detail::RealFft fft(n);
    const int count = n / 2;
    // a 16-byte aligned row (fftw_malloc) and one 8 bytes off it
    double* buf = fftw_alloc_real(static_cast<std::size_t>(n) + 1);
    double* aligned = buf;
    double* shifted = buf + 1;
    std::vector<double> f(n);
    for (auto& v : f) v = U(rng);
    std::vector<double> oa(2 * count), os(2 * count);
    std::memcpy(aligned, f.data(), sizeof(double) * n);
    fft.forward(aligned, count, oa.data());
    for (int j = 0; j < n; ++j) ASSERT_EQ(aligned[j], f[j]) << "input changed, n = " << n;
    std::memcpy(shifted, f.data(), sizeof(double) * n);
    fft.forward(shifted, count, os.data());
    for (int m = 0; m < count; ++m) {
      long double a = 0, b = 0;
      for (int j = 0; j < n; ++j) {
        a += f[j] * std::cos(angle(m, j, n));
        b += f[j] * std::sin(angle(m, j, n));
      }
      ASSERT_NEAR(oa[2 * m], static_cast<double>(a), 1e-14 * n) << n << " " << m;
      ASSERT_NEAR(oa[2 * m + 1], static_cast<double>(b), 1e-14 * n) << n << " " << m;
      ASSERT_EQ(oa[2 * m], os[2 * m]) << n << " " << m;
      ASSERT_EQ(oa[2 * m + 1], os[2 * m + 1]) << n << " " << m;
    }
    std::vector<double> cs(2 * count);
    for (auto& v : cs) v = U(rng);
    fft.inverse(cs.data(), count, aligned);
    std::vector<double> va(aligned, aligned + n);
    fft.inverse(cs.data(), count, shifted);
    for (int j = 0; j < n; ++j) {
      long double v = 0;
      for (int m = 0; m < count; ++m) v += cs[2 * m] * std::cos(angle(m, j, n)) + (m > 0 ? cs[2 * m + 1] * std::sin(angle(m, j, n)) : 0.0L);
      ASSERT_NEAR(va[j], static_cast<double>(v), 1e-14 * n) << n << " " << j;
      ASSERT_EQ(va[j], shifted[j]) << n << " " << j;
    }
    fftw_free(buf);
  }
}

namespace {
// A user's FFTW state, checked after libsh's static teardown (atexit runs the handlers in
// reverse order of registration, and libsh's plan cache is created after this one is
// registered, so its destructor runs first).
struct UserFftw {
  int n = 96;
  double* in = nullptr;
  fftw_complex* out = nullptr;
  fftw_plan plan = nullptr;
};
UserFftw user;

void check_user_fftw_at_exit() {
  // the plan still transforms (against the direct sums) and the wisdom is still there
  for (int j = 0; j < user.n; ++j) user.in[j] = std::cos(0.37 * j * j) + 0.25 * j / user.n;
  fftw_execute(user.plan);
  for (int k = 0; k <= user.n / 2; ++k) {
    std::complex<long double> s = 0;
    for (int j = 0; j < user.n; ++j) s += std::polar<long double>(user.in[j], -angle(k, j, user.n));
    if (std::abs(user.out[k][0] - static_cast<double>(s.real())) > 1e-12 ||
        std::abs(user.out[k][1] - static_cast<double>(s.imag())) > 1e-12)
      std::_Exit(3);
  }
  // the wisdom of the user's FFTW_MEASURE plan is still known: FFTW_WISDOM_ONLY plans
  // from it (it returns no plan where the wisdom was dropped)
  fftw_plan again = fftw_plan_dft_r2c_1d(user.n, user.in, user.out, FFTW_MEASURE | FFTW_WISDOM_ONLY);
  const bool same = again != nullptr;
  if (again) fftw_destroy_plan(again);
  fftw_destroy_plan(user.plan);
  fftw_free(user.in);
  fftw_free(user.out);
  std::_Exit(same ? 0 : 4);
}
}  // namespace

TEST(Transform, UserFftwPlansAndWisdomSurviveLibshTeardown) {
  // In a fresh process (threadsafe death test: the binary re-runs only this test), a user
  // plans an FFT with FFTW_MEASURE (which records wisdom), then libsh transforms on grids
  // of each FFT method and the process exits. libsh's teardown must destroy only its own
  // plans: fftw_cleanup() there would drop the user's wisdom (and, by FFTW's manual, make
  // the user's plan undefined). Exit codes: 3 plan wrong, 4 wisdom lost.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        user.in = fftw_alloc_real(user.n);
        user.out = fftw_alloc_complex(user.n / 2 + 1);
        user.plan = fftw_plan_dft_r2c_1d(user.n, user.in, user.out, FFTW_MEASURE);
        std::atexit(check_user_fftw_at_exit);
        for (int nphi : {16, 21, 17}) {
          const GaussGrid g = gauss_grid(8, 8, nphi);
          std::vector<double> c(64, 0.5);
          const auto f = synthesise(g, c.data());
          const auto c2 = analyse(g, f.data());
          if (std::abs(c2[5] - 0.5) > 1e-12) std::_Exit(5);
        }
        std::exit(0);
      },
      ::testing::ExitedWithCode(0), "");
}

TEST(Transform, RingBlockFftsMatchDirectSums) {
  // forward_rows (4 or 8 consecutive rings per FFTW call, the path of the analysis for even
  // 2^a 3^b 5^c sizes other than powers of two) against direct sums in long double; rows off
  // FFTW's alignment and sizes without such plans are refused.
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int n : {24, 96}) {
    detail::RealFft fft(n);
    const int nc = n / 2 + 1;
    for (int rows : {4, 8}) {
      double* f = fftw_alloc_real(static_cast<std::size_t>(n) * rows + 1);
      double* spec = fftw_alloc_real(2 * static_cast<std::size_t>(nc) * rows);
      for (int i = 0; i < n * rows; ++i) f[i] = U(rng);
      const std::vector<double> f0(f, f + n * rows);
      ASSERT_TRUE(fft.forward_rows(f, rows, spec));
      for (int r = 0; r < rows; ++r)
        for (int k = 0; k < nc; ++k) {
          std::complex<long double> s = 0;
          for (int j = 0; j < n; ++j) s += std::polar<long double>(f0[r * n + j], -angle(k, j, n));
          ASSERT_NEAR(spec[2 * (r * nc + k)], static_cast<double>(s.real()), 1e-14 * n) << n << " " << r << " " << k;
          ASSERT_NEAR(spec[2 * (r * nc + k) + 1], static_cast<double>(s.imag()), 1e-14 * n) << n << " " << r << " " << k;
        }
      for (int i = 0; i < n * rows; ++i) ASSERT_EQ(f[i], f0[i]) << "input changed";
      EXPECT_FALSE(fft.forward_rows(f + 1, rows, spec)) << "a row 8 bytes off FFTW's alignment";
      EXPECT_FALSE(fft.forward_rows(f, 3, spec)) << "3 rows: no plan";
      fftw_free(f);
      fftw_free(spec);
    }
  }
  // odd; 2 x 7 (paired complex FFTs); 2 x 23 (chirp); powers of two (split FFTs of two rings)
  for (int n : {15, 14, 46, 16, 512}) {
    detail::RealFft fft(n);
    double* f = fftw_alloc_real(static_cast<std::size_t>(n) * 4);
    double* spec = fftw_alloc_real(2 * (static_cast<std::size_t>(n) / 2 + 1) * 4);
    for (int i = 0; i < 4 * n; ++i) f[i] = 0.0;
    EXPECT_FALSE(fft.forward_rows(f, 4, spec)) << n;
    fftw_free(f);
    fftw_free(spec);
  }
}

TEST(Transform, CallerArraysAndTheGridsPlanGiveTheSameBits) {
  // analyse / synthesise into caller-provided arrays give the bits of the returning forms;
  // a grid whose rings were changed after gauss_grid no longer uses the plan made with it
  // (results as from a grid without a plan), and a copy shares its plan.
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int nphi : {66, 65}) {
    const GaussGrid g = gauss_grid(33, 0, nphi);
    ASSERT_TRUE(g.plan);
    std::vector<double> c(33 * 33);
    for (auto& v : c) v = U(rng);
    const auto f = synthesise(g, c.data());
    std::vector<double> f2(f.size(), std::nan("")), c2(c.size(), std::nan(""));
    synthesise(g, c.data(), f2.data());
    analyse(g, f.data(), c2.data());
    const auto a = analyse(g, f.data());
    for (std::size_t i = 0; i < f.size(); ++i) ASSERT_EQ(f[i], f2[i]) << i;
    for (std::size_t i = 0; i < c.size(); ++i) {
      ASSERT_EQ(a[i], c2[i]) << i;
      ASSERT_NEAR(a[i], c[i], 1e-13) << i;
    }
    GaussGrid moved = g;  // shares the plan; then its rings move
    EXPECT_EQ(moved.plan, g.plan);
    for (int i = 0; i < moved.nlat; ++i) {
      const double t = std::acos(moved.cos_t[i]) * 0.999;
      moved.cos_t[i] = std::cos(t);
      moved.sin_t[i] = std::sin(t);
    }
    GaussGrid bare = moved;
    bare.plan.reset();
    const auto am = analyse(moved, f.data()), ab = analyse(bare, f.data());
    const auto fm = synthesise(moved, c.data()), fb = synthesise(bare, c.data());
    double diff = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      ASSERT_EQ(am[i], ab[i]) << i;
      diff = std::max(diff, std::abs(am[i] - a[i]));
    }
    for (std::size_t i = 0; i < f.size(); ++i) ASSERT_EQ(fm[i], fb[i]) << i;
    EXPECT_GT(diff, 1e-6) << "the moved rings gave the original grid's coefficients";
  }
}

TEST(Transform, PolarStartsFoundByConcurrentCallsGiveTheBitsOfFreshPlans) {
  // The polar starts of every column (where the blocks of polar rings join the plain
  // kernels, and their values there) are found by the first transform on a grid's plan and
  // kept in it. Two threads running their first transforms on one grid at once (each also
  // with two worker threads), and later calls, give the bits of a grid without a plan
  // (whose calls each find them afresh).
  const int L = 300;
  const GaussGrid g = gauss_grid(L, 0, 600);
  GaussGrid bare = g;
  bare.plan.reset();
  const auto c = uniform_coeffs(L, 61);
  const auto f_ref = synthesise(bare, c.data());
  const auto a_ref = analyse(bare, f_ref.data());
  std::vector<double> f1(f_ref.size()), f2(f_ref.size()), a1(c.size()), a2(c.size());
  std::thread t1([&] { synthesise(g, c.data(), f1.data(), 2); analyse(g, f_ref.data(), a1.data(), 1); });
  std::thread t2([&] { analyse(g, f_ref.data(), a2.data(), 2); synthesise(g, c.data(), f2.data(), 1); });
  t1.join();
  t2.join();
  const auto f3 = synthesise(g, c.data());
  const auto a3 = analyse(g, f_ref.data(), 2);
  for (std::size_t i = 0; i < f_ref.size(); ++i) {
    ASSERT_EQ(f1[i], f_ref[i]) << i;
    ASSERT_EQ(f2[i], f_ref[i]) << i;
    ASSERT_EQ(f3[i], f_ref[i]) << i;
  }
  double err = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(a1[i], a_ref[i]) << i;
    ASSERT_EQ(a2[i], a_ref[i]) << i;
    ASSERT_EQ(a3[i], a_ref[i]) << i;
    err = std::max(err, std::abs(a_ref[i] - c[i]));
  }
  EXPECT_LT(err, 1e-12);
}

TEST(Transform, MeasuredFftPlansGiveTheTransformsToRounding) {
  // GaussGrid::fft = FftPlanning::measure: FFTW_MEASURE plans, chosen by timing, of every
  // method (512: split, 768: real rows, 525: paired, 511: chirp). Synthesis and analysis
  // agree with those of the default plans to rounding, round trips stay exact, and repeated
  // calls in the process give the same bits (the plans are made once per size and kept).
  const int L = 96;
  const auto c = uniform_coeffs(L, 83);
  for (int nphi : {512, 768, 525, 511}) {
    SCOPED_TRACE(nphi);
    const GaussGrid g = gauss_grid(L, 0, nphi);
    GaussGrid gm = g;
    gm.fft = FftPlanning::measure;
    const auto f = synthesise(g, c.data()), fm = synthesise(gm, c.data(), 2);
    double fmax = 0, fdiff = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      fmax = std::max(fmax, std::abs(f[i]));
      fdiff = std::max(fdiff, std::abs(f[i] - fm[i]));
    }
    EXPECT_LT(fdiff, 1e-14 * fmax);
    const auto a = analyse(g, f.data()), am = analyse(gm, f.data());
    for (std::size_t i = 0; i < c.size(); ++i) {
      ASSERT_NEAR(am[i], a[i], 1e-14) << i;
      ASSERT_NEAR(am[i], c[i], 1e-13) << i;
    }
    const auto fm2 = synthesise(gm, c.data());
    const auto am2 = analyse(gm, f.data(), 2);
    for (std::size_t i = 0; i < f.size(); ++i) ASSERT_EQ(fm2[i], fm[i]) << i;
    for (std::size_t i = 0; i < c.size(); ++i) ASSERT_EQ(am2[i], am[i]) << i;
  }
  // FFTW_MEASURE records wisdom, which later FFTW_ESTIMATE plans (the default ones, other
  // code's) would follow: libsh leaves none behind and keeps what was there. The test's own
  // measured r2c of 1000 (its wisdom) before measured transforms at 1536 (sizes no other
  // test plans, real FFTs); then FFTW_WISDOM_ONLY finds the r2c of 1000 and not that of 1536.
  const int n = 1536, n_own = 1000;
  double* r = fftw_alloc_real(n);
  fftw_complex* z = fftw_alloc_complex(n / 2 + 1);
  const fftw_plan own = fftw_plan_dft_r2c_1d(n_own, r, z, FFTW_MEASURE);
  GaussGrid gm = gauss_grid(L, 0, n);
  gm.fft = FftPlanning::measure;
  const auto fm = synthesise(gm, c.data());
  EXPECT_EQ(analyse(gm, fm.data()).size(), c.size());
  const fftw_plan leaked = fftw_plan_dft_r2c_1d(n, r, z, FFTW_MEASURE | FFTW_WISDOM_ONLY);
  EXPECT_EQ(leaked, nullptr) << "libsh's measured plans left wisdom behind";
  const fftw_plan kept = fftw_plan_dft_r2c_1d(n_own, r, z, FFTW_MEASURE | FFTW_WISDOM_ONLY);
  EXPECT_NE(kept, nullptr) << "the process's own wisdom was lost";
  for (fftw_plan q : {own, leaked, kept})
    if (q) fftw_destroy_plan(q);
  fftw_free(r);
  fftw_free(z);
}

TEST(Transform, FftPlanningOfTheGridIsHonouredAndDefaultPlansIgnoreWisdom) {
  // analyse / synthesise make the plans the grid asks for (sizes no other test uses: 1296,
  // real FFTs; 1320, paired); and the default plans depend on n alone: made after the
  // process has wisdom for the very problem (an FFTW_MEASURE r2c of 1200 of the test's own,
  // which FFTW_ESTIMATE plans would then follow), libsh's is the plan FFTW_ESTIMATE makes
  // with no wisdom (fftw_sprint_plan).
  const int L = 40;
  const auto c = uniform_coeffs(L, 89);
  std::mt19937_64 rng(90);
  std::uniform_real_distribution<double> U(-1, 1);
  for (const auto& [n, synthesis_first] : {std::pair{1296, false}, std::pair{1320, true}}) {
    ASSERT_FALSE(detail::fft_plans_made(n, true)) << n;
    ASSERT_FALSE(detail::fft_plans_made(n, false)) << n;
    GaussGrid gm = gauss_grid(L, 0, n);
    gm.fft = FftPlanning::measure;
    if (synthesis_first) {
      const auto f = synthesise(gm, c.data());
      EXPECT_TRUE(detail::fft_plans_made(n, true)) << n;
      EXPECT_FALSE(detail::fft_plans_made(n, false)) << n;
      const auto a = analyse(gm, f.data());
      for (std::size_t i = 0; i < c.size(); ++i) ASSERT_NEAR(a[i], c[i], 1e-13) << i;
    } else {
      std::vector<double> f(static_cast<std::size_t>(gm.nlat) * n);
      for (auto& v : f) v = U(rng);
      const auto a = analyse(gm, f.data());
      EXPECT_TRUE(detail::fft_plans_made(n, true)) << n;
      EXPECT_FALSE(detail::fft_plans_made(n, false)) << n;
      EXPECT_EQ(a.size(), c.size());
    }
  }
  const int n = 1200;
  ASSERT_FALSE(detail::fft_plans_made(n, false));
  double* r = fftw_alloc_real(n);
  fftw_complex* z = fftw_alloc_complex(n / 2 + 1);
  auto text = [](fftw_plan q) {
    char* t = fftw_sprint_plan(q);
    std::string s = t ? t : "";
    std::free(t);
    fftw_destroy_plan(q);
    return s;
  };
  // FFTW_ESTIMATE's plan with no wisdom (the process's wisdom set aside and put back)
  char* saved = fftw_export_wisdom_to_string();
  ASSERT_NE(saved, nullptr);
  fftw_forget_wisdom();
  const std::string clean = text(fftw_plan_dft_r2c_1d(n, r, z, FFTW_ESTIMATE));
  fftw_import_wisdom_from_string(saved);
  std::free(saved);
  const fftw_plan own = fftw_plan_dft_r2c_1d(n, r, z, FFTW_MEASURE);  // wisdom for the problem
  const std::string followed = text(fftw_plan_dft_r2c_1d(n, r, z, FFTW_ESTIMATE));
  const std::string libsh = detail::fft_plan_text(n, false);
  EXPECT_FALSE(clean.empty());
  EXPECT_EQ(libsh, clean) << "FFTW_ESTIMATE with wisdom would give " << followed;
  if (followed == clean)
    std::printf("(FFTW_MEASURE chose FFTW_ESTIMATE's plan of %d here: the wisdom check is vacuous)\n", n);
  fftw_destroy_plan(own);
  fftw_free(r);
  fftw_free(z);
}
