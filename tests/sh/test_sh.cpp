// Tests of atmosh::sh against independent references (closed forms, exact quadrature,
// published constants). Each reference value cites its source.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <complex>
#include <limits>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/fast.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/sh/transform.hpp"
#include "atmosh/sh/zonal.hpp"

using namespace atmosh::sh;
constexpr double kPi = std::numbers::pi;

namespace {
std::vector<glm::dvec3> test_dirs(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  std::vector<glm::dvec3> d = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1e-9, 1}, {1e-300, 0, -1}};
  for (int i = 0; i < n; ++i) d.push_back(glm::normalize(glm::dvec3(nd(rng), nd(rng), nd(rng))));
  return d;
}
std::vector<double> random_coeffs(int bands, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  std::vector<double> c(bands * bands);
  for (auto& v : c) v = nd(rng);
  return c;
}
}  // namespace

// ---- quadrature ----------------------------------------------------------------------
TEST(GaussLegendre, ExactForPolynomialsUpToDegree2nMinus1) {
  // integral_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k (elementary).
  for (int n : {1, 2, 3, 7, 20, 64, 200}) {
    const GaussLegendre g = gauss_legendre(n);
    for (int k = 0; k <= std::min(2 * n - 1, 60); ++k) {
      double s = 0;
      for (int i = 0; i < n; ++i) s += g.weights[i] * std::pow(g.nodes[i], k);
      const double exact = (k % 2) ? 0.0 : 2.0 / (k + 1);
      EXPECT_NEAR(s, exact, 2e-15 * n) << "n=" << n << " k=" << k;
    }
  }
}

TEST(GaussLegendre, LargeRulesAreAccurate) {
  // Known values: 3-point rule nodes 0, +-sqrt(3/5), weights 8/9, 5/9 (Abramowitz & Stegun 25.4.29).
  const GaussLegendre g3 = gauss_legendre(3);
  EXPECT_NEAR(g3.nodes[2], std::sqrt(0.6), 1e-16);
  EXPECT_NEAR(g3.weights[1], 8.0 / 9.0, 1e-16);
  for (int n : {1000, 3000}) {
    const GaussLegendre g = gauss_legendre(n);
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      s += g.weights[i];
      s2 += g.weights[i] * g.nodes[i] * g.nodes[i];
      ASSERT_TRUE(std::isfinite(g.nodes[i]) && g.weights[i] > 0);
    }
    EXPECT_NEAR(s, 2.0, 1e-13);
    EXPECT_NEAR(s2, 2.0 / 3.0, 1e-13);
  }
  EXPECT_THROW(gauss_legendre(0), atmosh::InputError);
}

TEST(Zonal, LegendreAndZonalCoefficientsOfExponential) {
  // exp(k mu) = sum_l (2l+1) i_l(k) P_l(mu) (Abramowitz & Stegun 10.2.36), so
  // z_l = 2 pi * sqrt((2l+1)/(4 pi)) * 2 i_l(k) ; i_0 = sinh k / k, i_1 = (k cosh k - sinh k)/k^2.
  const double k = 1.7;
  const auto z = zonal_coefficients([k](double mu) { return std::exp(k * mu); }, 6);
  const double i0 = std::sinh(k) / k, i1 = (k * std::cosh(k) - std::sinh(k)) / (k * k);
  EXPECT_NEAR(z[0], 4 * kPi * std::sqrt(1 / (4 * kPi)) * i0, 1e-14);
  EXPECT_NEAR(z[1], 4 * kPi * std::sqrt(3 / (4 * kPi)) * i1, 1e-14);
  const auto p = legendre_polynomials(0.3, 4);
  EXPECT_NEAR(p[2], 0.5 * (3 * 0.09 - 1), 1e-16);        // P_2 = (3x^2-1)/2
  EXPECT_NEAR(p[3], 0.5 * (5 * 0.027 - 3 * 0.3), 1e-16);  // P_3 = (5x^3-3x)/2
}

// Composite quadrature over given pieces: the clamped cosine max(0, mu) is linear on
// [-1, 0] and [0, 1], so with a break at its kink the projection is exact; its
// moments in closed form (Abramowitz & Stegun 22.13.8 / the classic result for the
// clamped cosine): 2 pi int_0^1 mu P_l dmu = 2 pi * {1/2, 1/3, 1/8, 0, -1/48, 0, 1/128}
// for l = 0..6. Without the break (one piece) the same rule is not exact. And a
// Henyey-Greenstein lobe g = 0.999 (4 pi p = (1 - g^2)/(1 + g^2 - 2 g mu)^1.5,
// Legendre coefficients (2l+1) g^l) with pieces graded toward mu = 1.
TEST(Zonal, PiecewiseQuadratureResolvesKinksAndPeaks) {
  const double m[7] = {1.0 / 2, 1.0 / 3, 1.0 / 8, 0.0, -1.0 / 48, 0.0, 1.0 / 128};
  auto clamped = [](double mu) { return std::max(0.0, mu); };
  const auto z = zonal_coefficients(clamped, 7, std::vector<double>{-1.0, 0.0, 1.0}, 4);
  const auto z1 = zonal_coefficients(clamped, 7, std::vector<double>{-1.0, 1.0}, 4);
  double off1 = 0.0;
  for (int l = 0; l < 7; ++l) {
    const double y = std::sqrt((2 * l + 1) / (4 * kPi));
    EXPECT_NEAR(z[l], 2 * kPi * y * m[l], 1e-14) << l;
    off1 = std::max(off1, std::abs(z1[l] - 2 * kPi * y * m[l]));
  }
  EXPECT_GT(off1, 1e-6);
  const double g = 0.999;
  auto hg = [g](double mu) { return (1 - g * g) / std::pow((1 - g) * (1 - g) + 2 * g * (1 - mu), 1.5) / (4 * kPi); };
  std::vector<double> breaks{-1.0, 0.0};
  for (double s = 0.5; s > 1e-7; s *= 0.5) breaks.push_back(1.0 - s);
  breaks.push_back(1.0);
  const int L = 64;
  const auto zh = zonal_coefficients(hg, L, breaks, 20);
  for (int l = 0; l < L; ++l) EXPECT_NEAR(zh[l] / std::sqrt((2 * l + 1) / (4 * kPi)), std::pow(g, l), 1e-9) << l;
  EXPECT_THROW(zonal_coefficients(hg, L, std::vector<double>{0.5, 0.2}, 4), atmosh::InputError);
  EXPECT_THROW(zonal_coefficients(hg, L, std::vector<double>{-1.0, 1.5}, 4), atmosh::InputError);
  EXPECT_THROW(zonal_coefficients(hg, L, std::vector<double>{-1.0}, 4), atmosh::InputError);
  EXPECT_THROW(zonal_coefficients(hg, L, std::vector<double>{-1.0, 1.0}, 0), atmosh::InputError);
}

// ---- basis ------------------------------------------------------------------------------
TEST(Basis, ClosedFormsLowBands) {
  // Real SH with Condon–Shortley phase, e.g. Wikipedia "Table of spherical harmonics"
  // (real forms) / Sloan 2008 appendix A2 with the CS sign on odd m.
  const double k1 = std::sqrt(3 / (4 * kPi)), k2 = 0.5 * std::sqrt(15 / kPi), k20 = 0.25 * std::sqrt(5 / kPi);
  for (const auto& d : test_dirs(50, 1)) {
    const auto y = evaluate(3, d);
    const double x = d.x, yy = d.y, z = d.z;
    EXPECT_NEAR(y[0], 0.5 / std::sqrt(kPi), 1e-16);
    EXPECT_NEAR(y[1], -k1 * yy, 1e-15);
    EXPECT_NEAR(y[2], k1 * z, 1e-15);
    EXPECT_NEAR(y[3], -k1 * x, 1e-15);
    EXPECT_NEAR(y[4], k2 * x * yy, 1e-15);
    EXPECT_NEAR(y[5], -k2 * yy * z, 1e-15);
    EXPECT_NEAR(y[6], k20 * (3 * z * z - 1), 1e-15);
    EXPECT_NEAR(y[7], -k2 * x * z, 1e-15);
    EXPECT_NEAR(y[8], 0.5 * k2 * (x * x - yy * yy), 1e-15);
  }
}

TEST(Basis, FastPathAgreesWithGeneralPath) {
  // evaluate() itself runs the fast path for L <= 8: the reference is the general path at
  // kFastMaxBands + 1 bands (its first L^2 values).
  for (int L = 1; L <= kFastMaxBands; ++L)
    for (const auto& d : test_dirs(100, 2)) {
      const auto g = evaluate(kFastMaxBands + 1, d);
      double yd[64];
      float yf[64];
      evaluate_fast(L, d.x, d.y, d.z, yd);
      evaluate_fast(L, float(d.x), float(d.y), float(d.z), yf);
      for (int l = 0; l < L; ++l) {
        const double scale = std::sqrt((2 * l + 1) / (4 * kPi));
        for (int m = -l; m <= l; ++m) {
          const int i = sh_index(l, m);
          EXPECT_LE(std::abs(yd[i] - g[i]), 1e-14 * scale) << "L=" << L << " i=" << i;
          EXPECT_LE(std::abs(yf[i] - g[i]), 1e-6 * scale) << "L=" << L << " i=" << i;
        }
      }
    }
  // batch form (compiled kernel, packs of directions, tail directions) against the
  // general path: n = 37 is not a multiple of the pack width, stride > n
  const auto dirs = test_dirs(32, 3);
  const std::size_t n = dirs.size(), stride = n + 3;
  for (int L = 1; L <= kFastMaxBands; ++L) {
    std::vector<float> xs, ys, zs, outf(L * L * stride);
    std::vector<double> xd, yd, zd, outd(L * L * stride);
    for (const auto& d : dirs) {
      xs.push_back(float(d.x)), ys.push_back(float(d.y)), zs.push_back(float(d.z));
      xd.push_back(d.x), yd.push_back(d.y), zd.push_back(d.z);
    }
    ASSERT_TRUE(evaluate_fast_batch(L, n, xs.data(), ys.data(), zs.data(), outf.data(), stride));
    ASSERT_TRUE(evaluate_fast_batch(L, n, xd.data(), yd.data(), zd.data(), outd.data(), stride));
    for (std::size_t k = 0; k < n; ++k) {
      const auto g = evaluate(kFastMaxBands + 1, dirs[k]);
      for (int l = 0; l < L; ++l) {
        const double scale = std::sqrt((2 * l + 1) / (4 * kPi));
        for (int m = -l; m <= l; ++m) {
          const int i = sh_index(l, m);
          EXPECT_LE(std::abs(outd[i * stride + k] - g[i]), 1e-14 * scale) << "L=" << L << " k=" << k << " i=" << i;
          EXPECT_LE(std::abs(outf[i * stride + k] - g[i]), 1e-6 * scale) << "L=" << L << " k=" << k << " i=" << i;
        }
      }
    }
  }
  float dummy = 0;
  EXPECT_FALSE(evaluate_fast_batch(9, 1, &dummy, &dummy, &dummy, &dummy, 1));
}

TEST(Basis, BatchAgreesWithGeneralPath) {
  // evaluate_batch() runs the column recurrence on packs of directions; compare with
  // evaluate() (itself tested against closed forms, single columns and the sum rule)
  // at random directions, both poles exactly, directions 1e-9 and 1e-300 rad off a pole
  // (the latter takes the extended-range path), and a non-unit direction.
  auto dirs = test_dirs(40, 11);
  dirs.push_back({0, 0, 7.5});
  dirs.push_back({-3, 4, 0});
  dirs.push_back({1e-300, 1e-300, 1});
  const std::size_t n = dirs.size(), stride = n + 5;  // n = 48: several packs
  std::vector<double> xs, ys, zs;
  for (const auto& d : dirs) xs.push_back(d.x), ys.push_back(d.y), zs.push_back(d.z);
  for (int L : {1, 2, 3, 4, 9, 16, 17, 33, 64, 128}) {
    for (std::size_t cnt : {n, std::size_t{3}}) {  // also a pass with a partial pack only
      std::vector<double> out(sh_count(L) * stride, -7.0);
      evaluate_batch(L, cnt, xs.data(), ys.data(), zs.data(), out.data(), stride);
      for (std::size_t k = 0; k < cnt; ++k) {
        const auto g = evaluate(L, dirs[k]);
        for (int l = 0; l < L; ++l) {
          const double scale = std::sqrt((2 * l + 1) / (4 * kPi));
          for (int m = -l; m <= l; ++m) {
            const int i = sh_index(l, m);
            EXPECT_LE(std::abs(out[i * stride + k] - g[i]), 1e-13 * scale) << "L=" << L << " k=" << k << " i=" << i;
          }
        }
      }
      for (int i = 0; i < sh_count(L); ++i)
        for (std::size_t k = cnt; k < stride; ++k) ASSERT_EQ(out[i * stride + k], -7.0) << "wrote past n";
    }
  }
  std::vector<double> out(16 * 4);
  const double bad_x[2] = {0, NAN}, bad_y[2] = {0, 0}, bad_z[2] = {1, 1};
  EXPECT_THROW(evaluate_batch(4, 2, bad_x, bad_y, bad_z, out.data(), 4), atmosh::InputError);
  const double zero[1] = {0};
  EXPECT_THROW(evaluate_batch(4, 1, zero, zero, zero, out.data(), 4), atmosh::InputError);
  EXPECT_THROW(evaluate_batch(4, 2, bad_y, bad_y, bad_z, out.data(), 1), atmosh::InputError);  // stride < n
  EXPECT_THROW(evaluate_batch(129, 1, bad_y, bad_y, bad_z, out.data(), 1), atmosh::InputError);
}

TEST(Basis, FloatBatchAgreesWithGeneralPath) {
  // evaluate_batch() in float: the recurrence in single precision. Against evaluate() in
  // double at the same (float) directions: random ones, both poles, directions 1e-3 rad
  // and 1e-20 rad off a pole (the latter below the float sectoral threshold at every L
  // here: computed in double and rounded), and directions whose squares overflow or
  // underflow in float. Bound from the header: 2e-6 (l + 1) sqrt((2l+1)/4pi).
  std::vector<glm::vec3> dirs;
  for (const auto& d : test_dirs(60, 13)) dirs.push_back(glm::vec3(d));
  dirs.push_back({0, 0, 1});
  dirs.push_back({0, 0, -2});
  dirs.push_back({1e-3f, 0, 1});
  dirs.push_back({0, -1e-20f, -1});
  dirs.push_back({3e30f, -1e30f, 2e30f});
  dirs.push_back({1e-30f, 2e-30f, -1e-30f});
  dirs.push_back({1e-44f, 0, 0});  // a denormal float
  const std::size_t n = dirs.size(), stride = n + 3;
  std::vector<float> xs, ys, zs;
  for (const auto& d : dirs) xs.push_back(d.x), ys.push_back(d.y), zs.push_back(d.z);
  double worst = 0;
  for (int L : {1, 2, 3, 4, 9, 16, 17, 33, 64, 128}) {
    for (std::size_t cnt : {n, std::size_t{5}}) {
      std::vector<float> out(sh_count(L) * stride, -7.0f);
      evaluate_batch(L, cnt, xs.data(), ys.data(), zs.data(), out.data(), stride);
      for (std::size_t k = 0; k < cnt; ++k) {
        const auto g = evaluate(L, glm::dvec3(dirs[k]));
        for (int l = 0; l < L; ++l) {
          const double bound = 2e-6 * (l + 1) * std::sqrt((2 * l + 1) / (4 * kPi));
          for (int m = -l; m <= l; ++m) {
            const int i = sh_index(l, m);
            const double e = std::abs(out[i * stride + k] - g[i]);
            ASSERT_TRUE(std::isfinite(out[i * stride + k])) << "L=" << L << " k=" << k << " i=" << i;
            worst = std::max(worst, e / bound);
            EXPECT_LE(e, bound) << "L=" << L << " k=" << k << " i=" << i;
          }
        }
      }
      for (int i = 0; i < sh_count(L); ++i)
        for (std::size_t k = cnt; k < stride; ++k) ASSERT_EQ(out[i * stride + k], -7.0f) << "wrote past n";
    }
  }
  std::printf("float batch: worst error %.3g of the bound\n", worst);
  std::vector<float> out(16 * 4);
  const float bad_x[2] = {0, NAN}, bad_y[2] = {0, 0}, bad_z[2] = {1, 1};
  EXPECT_THROW(evaluate_batch(4, 2, bad_x, bad_y, bad_z, out.data(), 4), atmosh::InputError);
  const float zero[1] = {0}, inf[1] = {INFINITY};
  EXPECT_THROW(evaluate_batch(4, 1, zero, zero, zero, out.data(), 4), atmosh::InputError);
  EXPECT_THROW(evaluate_batch(4, 1, inf, zero, zero, out.data(), 4), atmosh::InputError);
  EXPECT_THROW(evaluate_batch(129, 1, bad_y, bad_y, bad_z, out.data(), 1), atmosh::InputError);
}

// The batch kernels align their stores: when every output row has the same alignment
// (stride a multiple of 16 floats / 8 doubles) but rows start off a 64-byte boundary,
// the first directions take a separate short pass. Every start offset, against the
// per-direction general path, and nothing written outside the n columns of each row.
TEST(Basis, BatchesAgreeAtEveryOutputAlignment) {
  const auto dirs = test_dirs(40, 5);  // n = 40: a short pass, full passes, a partial one
  const std::size_t n = dirs.size();
  std::vector<double> xd, yd, zd;
  std::vector<float> xf, yf, zf;
  for (const auto& d : dirs) {
    xd.push_back(d.x), yd.push_back(d.y), zd.push_back(d.z);
    xf.push_back(float(d.x)), yf.push_back(float(d.y)), zf.push_back(float(d.z));
  }
  for (std::size_t stride : {std::size_t{64}, n + 1}) {
    for (std::size_t off = 0; off < 16; ++off) {
      for (int L : {4, 16}) {
        std::vector<double> bufd(sh_count(L) * stride + 32, -7.0);
        double* outd = bufd.data();
        while (reinterpret_cast<std::uintptr_t>(outd) % 64) ++outd;
        outd += off % 8;
        evaluate_batch(L, n, xd.data(), yd.data(), zd.data(), outd, stride);
        std::vector<float> buff(sh_count(L) * stride + 32, -7.0f);
        float* outf = buff.data();
        while (reinterpret_cast<std::uintptr_t>(outf) % 64) ++outf;
        outf += off;
        if (L == 4) {
          ASSERT_TRUE(evaluate_fast_batch(4, n, xf.data(), yf.data(), zf.data(), outf, stride));
        }
        else evaluate_batch(L, n, xf.data(), yf.data(), zf.data(), outf, stride);
        for (std::size_t k = 0; k < n; ++k) {
          const auto g = evaluate(L, dirs[k]);
          const auto gf = evaluate(L, glm::dvec3(xf[k], yf[k], zf[k]));  // at the float direction
          for (int i = 0; i < sh_count(L); ++i) {
            const int l = static_cast<int>(std::sqrt(double(i)));
            const double scale = std::sqrt((2 * l + 1) / (4 * kPi));
            ASSERT_LE(std::abs(outd[i * stride + k] - g[i]), 1e-13 * scale) << "off " << off << " k " << k;
            const double tolf = L == 4 ? 1e-6 * scale : 2e-6 * (l + 1) * scale;  // headers' bounds
            ASSERT_LE(std::abs(outf[i * stride + k] - gf[i]), tolf) << "off " << off << " k " << k;
          }
        }
        for (int i = 0; i < sh_count(L); ++i)
          for (std::size_t k = n; k < stride; ++k) {
            ASSERT_EQ(outd[i * stride + k], -7.0) << "wrote past n";
            ASSERT_EQ(outf[i * stride + k], -7.0f) << "wrote past n";
          }
        for (double* p = bufd.data(); p < outd; ++p) ASSERT_EQ(*p, -7.0) << "wrote before the buffer";
        for (float* p = buff.data(); p < outf; ++p) ASSERT_EQ(*p, -7.0f) << "wrote before the buffer";
      }
    }
  }
}

TEST(Basis, RowPathAgreesWithSingleColumnsAndSumRule) {
  // evaluate() runs bands 10..128 row by row (all m of a band at once, cos/sin(m p) by
  // complex multiplication). Check it against legendre_column (one column at a time)
  // times sqrt2 cos/sin(m p) from std::cos/std::sin, and against Unsold's closed form
  // sum_m Y_lm^2 = (2l+1)/(4 pi) (Unsold 1927, Ann. Phys. 82:355).
  for (int L : {10, 15, 16, 17, 33, 64, 128}) {
    std::vector<double> y(sh_count(L)), col(L);
    for (const auto& d : test_dirs(20, 7)) {
      evaluate(L, d, y.data());
      const double rho = std::hypot(d.x, d.y);
      const double phi = std::atan2(d.y, d.x);
      for (int m = 0; m < L; ++m) {
        legendre_column(L, m, d.z, rho, col.data());
        for (int l = m; l < L; ++l) {
          const double scale = std::sqrt((2 * l + 1) / (4 * kPi));
          const double want_c = m == 0 ? col[l - m] : std::sqrt(2.0) * col[l - m] * std::cos(m * phi);
          EXPECT_LE(std::abs(y[sh_index(l, m)] - want_c), 1e-13 * scale) << "L=" << L << " l=" << l << " m=" << m;
          if (m > 0) {
            const double want_s = std::sqrt(2.0) * col[l - m] * std::sin(m * phi);
            EXPECT_LE(std::abs(y[sh_index(l, -m)] - want_s), 1e-13 * scale) << "L=" << L << " l=" << l << " m=" << -m;
          }
        }
      }
      for (int l = 0; l < L; ++l) {
        double sum = 0;
        for (int m = -l; m <= l; ++m) sum += y[sh_index(l, m)] * y[sh_index(l, m)];
        EXPECT_NEAR(sum / ((2 * l + 1) / (4 * kPi)), 1.0, 1e-13) << "L=" << L << " l=" << l;
      }
    }
  }
}

TEST(Basis, UnsoldSumRuleAtHighBands) {
  // Unsöld's theorem: sum_m Y_lm(w)^2 = (2l+1)/(4 pi) for every direction (also for the
  // real basis). Checked at l up to 2799, including the poles and 1e-12 rad from them.
  const int L = 2800;
  std::vector<double> y(sh_count(L));
  for (const glm::dvec3 d : {glm::dvec3(0, 0, 1), glm::dvec3(1e-12, 0, 1), glm::dvec3(0.3, -0.2, 0.9),
                             glm::dvec3(1, 1, 0), glm::dvec3(0.1, 0, -1)}) {
    evaluate(L, d, y.data());
    for (double v : y) ASSERT_TRUE(std::isfinite(v));
    for (int l : {0, 1, 10, 171, 500, 1500, 2799}) {
      double s = 0;
      for (int m = -l; m <= l; ++m) s += y[sh_index(l, m)] * y[sh_index(l, m)];
      EXPECT_NEAR(s / ((2 * l + 1) / (4 * kPi)), 1.0, 2e-10) << "l=" << l;
    }
  }
  // Y_l0 at the pole = sqrt((2l+1)/(4 pi)) (P_l(1) = 1).
  evaluate(L, {0, 0, 1}, y.data());
  EXPECT_NEAR(y[sh_index(2799, 0)] / std::sqrt(5599 / (4 * kPi)), 1.0, 1e-9);
  EXPECT_EQ(y[sh_index(2799, 5)], 0.0);
}

TEST(Basis, OrthonormalityByExactQuadratureUpTo2800) {
  // integral Y_lm Y_l'm dOmega = 2 pi integral Pbar_lm Pbar_l'm dmu (the phi integral of
  // cos^2 / sin^2 is pi, times the sqrt2^2 of the real basis), evaluated with an n-point
  // Gauss–Legendre rule, exact for the degree-(l + l') polynomial integrand when n >= L.
  const int L = 2800, n = 2800;
  const GaussLegendre g = gauss_legendre(n);
  for (int m : {0, 1, 171, 1000, 2000, 2790}) {
    std::vector<int> ls = {m, m + 1, m + 2, (m + L) / 2, L - 2, L - 1};
    std::vector<std::vector<double>> P(n, std::vector<double>(L - m));
    for (int i = 0; i < n; ++i) {
      const double x = g.nodes[i];
      legendre_column(L, m, x, std::sqrt((1 - x) * (1 + x)), P[i].data());
    }
    double worst = 0;
    for (int a : ls)
      for (int b : ls) {
        double s = 0;
        for (int i = 0; i < n; ++i) s += g.weights[i] * P[i][a - m] * P[i][b - m];
        s *= 2 * kPi;
        worst = std::max(worst, std::abs(s - (a == b ? 1.0 : 0.0)));
      }
    EXPECT_LT(worst, 1e-11) << "m=" << m;
  }
}

TEST(Basis, BadInput) {
  EXPECT_THROW(evaluate(4, {std::nan(""), 0, 1}), atmosh::InputError);
  EXPECT_THROW(evaluate(4, {0, 0, 0}), atmosh::InputError);
  EXPECT_THROW(evaluate(0, {0, 0, 1}), atmosh::InputError);
  EXPECT_THROW(evaluate(-3, {0, 0, 1}), atmosh::InputError);
}

// ---- transform / projection ------------------------------------------------------------
TEST(Transform, AnalysisInvertsSynthesisAndMatchesDirectSum) {
  for (int L : {1, 2, 7, 64, 200}) {
    const auto c = random_coeffs(L, 10 + L);
    const GaussGrid g = gauss_grid(L);
    const auto f = synthesise(g, c.data());
    const auto c2 = analyse(g, f.data(), 2);
    double e = 0, scale = 0;
    for (int i = 0; i < L * L; ++i) e = std::max(e, std::abs(c2[i] - c[i])), scale = std::max(scale, std::abs(c[i]));
    EXPECT_LT(e / scale, 1e-12) << "L=" << L;
    // synthesis agrees with the direct sum of basis functions
    for (int r : {0, g.nlat / 2, g.nlat - 1}) {
      const int j = g.nphi / 3;
      const glm::dvec3 d(g.sin_t[r] * std::cos(g.phi(j)), g.sin_t[r] * std::sin(g.phi(j)), g.cos_t[r]);
      EXPECT_NEAR(f[r * g.nphi + j], reconstruct(L, c.data(), d), 1e-11 * std::sqrt(double(L * L)));
    }
  }
}

// Single terms of high order, whose values at the rings nearer the poles start far below
// the double range and reach it at different degrees in neighbouring rings (the kernels'
// extended-range lanes, blocks whose lanes join at different steps, the last columns with
// no odd degree or a single one): synthesis against the direct sum of the basis
// (reconstruct, the three-term recurrence in cos theta) at every ring, and analysis giving
// back the one coefficient. Two grids: nphi = 402 (ring rows, chirp FFTs) and 512 (a power of
// two: spectra of north and south rings made from the sums, split FFTs; nlat = 201 odd, so
// the equator ring goes alone).
TEST(Transform, SingleHighOrderTermsMatchDirectSumsOnEveryRing) {
  const int L = 201;
  for (const GaussGrid& g : {gauss_grid(L), gauss_grid(L, L, 512)})
  for (const auto& [l, m] : std::vector<std::pair<int, int>>{{200, 200}, {200, -200}, {200, 199}, {199, -170}, {200, 120}, {150, 75}}) {
    std::vector<double> c(static_cast<std::size_t>(L) * L, 0.0);
    c[sh_index(l, m)] = 1.0;
    const auto f = synthesise(g, c.data());
    double peak = 0, err = 0;
    for (int r = 0; r < g.nlat; ++r)
      for (int j : {1, g.nphi / 3, g.nphi - 2}) {
        const glm::dvec3 d(g.sin_t[r] * std::cos(g.phi(j)), g.sin_t[r] * std::sin(g.phi(j)), g.cos_t[r]);
        const double ref = reconstruct(L, c.data(), d);
        peak = std::max(peak, std::abs(ref));
        err = std::max(err, std::abs(f[static_cast<std::size_t>(r) * g.nphi + j] - ref));
      }
    EXPECT_GT(peak, 0.1) << "l=" << l << " m=" << m << " nphi=" << g.nphi;
    EXPECT_LT(err, 1e-13 * peak) << "l=" << l << " m=" << m << " nphi=" << g.nphi;
    const auto a = analyse(g, f.data(), 2);
    double off = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (static_cast<int>(i) != sh_index(l, m)) off = std::max(off, std::abs(a[i]));
    EXPECT_NEAR(a[sh_index(l, m)], 1.0, 1e-13) << "l=" << l << " m=" << m;
    EXPECT_LT(off, 1e-13) << "l=" << l << " m=" << m;
  }
}

// A grid of 16 rings (8 symmetric pairs) whose lane blocks mix rings at 20-22 degrees
// from the poles with rings near the equator, at band limit 2048: for orders m ~ 700-800
// the polar rings start near 2^-1000 to 2^-1240 (beyond the double range: the kernels'
// extended range) while the equatorial ones are plain from the first degree, and the polar
// ones still climb to within 1e-9 of the peak (to O(1) for m <= 740: turning point
// l ~ m / sin t) before l = 2047. Such blocks first step their low lanes masked and move
// them to the plain range only once they are one scale step down and far from the
// subnormals; a lane moved too early (or scaled by the wrong power) is wrong by many orders
// of magnitude. Synthesis is checked on every ring against Pbar_lm(cos t) from
// legendre_column (the three-term recurrence in cos t) times the longitude factor, taken from
// the direct sum (reconstruct) at an equatorial ring; analysis by the adjoint identity
// analyse(f)[T2] = sum_ij w_i dphi f_ij Y_T2(ij) with f = synthesise(T1).
TEST(Transform, BlocksWhoseLanesSpanTheDoubleRangeMatchDirectSums) {
  const int L = 2048;
  GaussGrid g;
  g.bands = L;
  g.nphi = 4096;
  const double north[] = {20, 21, 22, 80, 82, 84, 86, 88};  // degrees from the pole
  for (int i = 0; i < 16; ++i) {
    const double t = (i < 8 ? north[i] : 180.0 - north[15 - i]) * kPi / 180.0;
    g.cos_t.push_back(std::cos(t));
    g.sin_t.push_back(std::sin(t));
    g.weights.push_back(0.125);
  }
  g.nlat = 16;
  const std::vector<std::pair<int, int>> terms{{2047, 700}, {2047, -700}, {2046, 700}, {2040, 720},
                                               {2047, 740}, {2047, 780}, {2047, 800}};
  std::vector<std::vector<double>> f;
  std::vector<double> c(static_cast<std::size_t>(L) * L, 0.0), col(L);
  for (const auto& term : terms) {
    const int l = term.first, m = term.second;  // (plain variables: lambdas capture them below)
    c[sh_index(l, m)] = 1.0;
    f.push_back(synthesise(g, c.data()));
    const int j = 3;  // cos(m phi_j), sin(m phi_j) away from 0
    auto pbar = [&](int r) {
      legendre_column(l + 1, std::abs(m), g.cos_t[r], g.sin_t[r], col.data());
      return col[l - std::abs(m)];
    };
    int r0 = 3;  // the equatorial ring with the largest |Pbar_lm|
    for (int r = 4; r < 13; ++r)
      if (std::abs(pbar(r)) > std::abs(pbar(r0))) r0 = r;
    const glm::dvec3 d0(g.sin_t[r0] * std::cos(g.phi(j)), g.sin_t[r0] * std::sin(g.phi(j)), g.cos_t[r0]);
    const double lon = reconstruct(l + 1, c.data(), d0) / pbar(r0);  // Y_lm = Pbar_lm(cos t) lon(phi)
    c[sh_index(l, m)] = 0.0;
    double peak = 0, err = 0, polar = 0;
    for (int r = 0; r < g.nlat; ++r) {
      const double ref = pbar(r) * lon;
      peak = std::max(peak, std::abs(ref));
      if (r == 1 || r == 14) polar = std::max(polar, std::abs(ref));
      err = std::max(err, std::abs(f.back()[static_cast<std::size_t>(r) * g.nphi + j] - ref));
    }
    EXPECT_GT(polar, 1e-9 * peak) << "the 21-degree rings come far above the tolerance: l=" << l << " m=" << m;
    EXPECT_LT(err, 3e-12 * peak) << "l=" << l << " m=" << m;
  }
  const double dphi = 2 * kPi / g.nphi;
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (int r = 0; r < g.nlat; ++r)
      for (int j = 0; j < g.nphi; ++j) {
        const std::size_t i = static_cast<std::size_t>(r) * g.nphi + j;
        s += g.weights[r] * dphi * a[i] * b[i];
      }
    return s;
  };
  for (std::size_t a = 0; a < terms.size(); ++a) {
    analyse(g, f[a].data(), c.data(), a == 0 ? 2 : 1);
    for (std::size_t b = 0; b < terms.size(); ++b) {
      const double expect = dot(f[a], f[b]), scale = std::sqrt(dot(f[a], f[a]) * dot(f[b], f[b]));
      EXPECT_NEAR(c[sh_index(terms[b].first, terms[b].second)], expect, 1e-12 * scale)
          << "T1 = " << terms[a].first << "," << terms[a].second << " T2 = " << terms[b].first << ","
          << terms[b].second;
    }
  }
}

TEST(Projection, PolynomialFunctionsHaveKnownCoefficients) {
  // f = 3 z^2 - 1 + x: exactly (4/k20) Y_20 - Y_11 / k1 (closed forms above), so
  // c_20 = 1/k20' with 3z^2-1 = Y_20 / (sqrt(5/pi)/4), c_11 = -1/sqrt(3/(4pi)).
  auto f = [](const glm::dvec3& d) { return 3 * d.z * d.z - 1 + d.x; };
  const auto c = project_function(f, 4);
  for (int i = 0; i < 16; ++i) {
    double expect = 0;
    if (i == sh_index(2, 0)) expect = 4 / std::sqrt(5 / kPi);
    if (i == sh_index(1, 1)) expect = -1 / std::sqrt(3 / (4 * kPi));
    EXPECT_NEAR(c[i], expect, 1e-14) << i;
  }
  // Monte Carlo: unbiased, seeded, converging; jittered beats uniform at equal count.
  ProjectOptions jo{Method::jittered, 45, 7, 1}, uo{Method::uniform, 2025, 7, 1};
  const auto cj = project_function(f, 4, jo), cj2 = project_function(f, 4, jo), cu = project_function(f, 4, uo);
  double ej = 0, eu = 0;
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(cj[i], cj2[i]);
    ej += (cj[i] - c[i]) * (cj[i] - c[i]);
    eu += (cu[i] - c[i]) * (cu[i] - c[i]);
  }
  EXPECT_LT(std::sqrt(ej), 0.1);
  EXPECT_LT(ej, eu);
}

TEST(Projection, ZonalLobeByFunkHecke) {
  // A zonal function k(s . w) about axis s has c_lm = sqrt(4 pi/(2l+1)) z_l Y_lm(s)
  // (Funk–Hecke / addition theorem), with z_l its zonal coefficients about +z.
  const double kap = 3.0;
  const glm::dvec3 s = glm::normalize(glm::dvec3(0.3, -0.4, 0.5));
  const int L = 20;
  const auto c = project_function([&](const glm::dvec3& d) { return std::exp(kap * glm::dot(d, s)); }, L,
                                  ProjectOptions{Method::quadrature, 40, 1, 1});
  const auto z = zonal_coefficients([&](double mu) { return std::exp(kap * mu); }, L);
  const auto ys = evaluate(L, s);
  for (int l = 0; l < L; ++l)
    for (int m = -l; m <= l; ++m)
      EXPECT_NEAR(c[sh_index(l, m)], std::sqrt(4 * kPi / (2 * l + 1)) * z[l] * ys[sh_index(l, m)], 1e-13);
}

TEST(Projection, SolidAnglesSumTo4Pi) {
  for (int N : {1, 2, 3, 8, 64, 257}) {
    double s = 0, approx = 0;
    for (int r = 0; r < N; ++r)
      for (int q = 0; q < N; ++q) {
        s += 6 * cube_texel_solid_angle(q, r, N);
        const double u = 2.0 * (q + 0.5) / N - 1, v = 2.0 * (r + 0.5) / N - 1;
        approx += 6 * 4.0 / (N * N) / std::pow(1 + u * u + v * v, 1.5);
      }
    EXPECT_NEAR(s, 4 * kPi, 1e-12) << N;
    if (N <= 2) {
      EXPECT_GT(std::abs(approx - 4 * kPi), 0.1) << "the centre-point weight is not exact";
    }
  }
  for (int H : {1, 2, 5, 90}) {
    double s = 0;
    for (int r = 0; r < H; ++r) s += 2 * H * equirect_pixel_solid_angle(2 * H, H, r);
    EXPECT_NEAR(s, 4 * kPi, 1e-12);
  }
}

TEST(Projection, ImagesOfConstantsAndCubeOrientation) {
  // constant 1 -> c_00 = sqrt(4 pi), everything else 0 (exact solid angles).
  const int N = 8;
  CubeMap cube;
  cube.size = N;
  cube.channels = 1;
  for (auto& f : cube.faces) f.assign(N * N, 1.0f);
  const auto cc = project_cube(cube, 3)[0];
  EXPECT_NEAR(cc[0], std::sqrt(4 * kPi), 1e-12);
  // face centres point along their axes
  EXPECT_NEAR(cube_texel_direction(0, N / 2, N / 2, 2 * (N / 2)).x, 1.0, 0.2);
  EXPECT_GT(cube_texel_direction(4, 3, 3, 7).z, 0.99);
  EXPECT_GT(cube_texel_direction(2, 3, 3, 7).y, 0.99);
  std::vector<float> img(2 * 16 * 8, 1.0f);
  const auto ce = project_equirect(ImageView{16, 8, 1, img.data()}, 3, 1, PixelRule::solid_angle)[0];
  EXPECT_NEAR(ce[0], std::sqrt(4 * kPi), 1e-12);
  // solid-angle rule: m != 0 and odd l vanish exactly (uniform rule in p, mirror-symmetric
  // rows); c_20 is the midpoint error of the pixel-centre basis value, O(1/H^2).
  for (int i = 1; i < 9; ++i)
    if (i != sh_index(2, 0)) {
      EXPECT_NEAR(ce[i], 0.0, 1e-12);
    }
  std::vector<float> img64(2 * 64 * 64, 1.0f);
  const auto ce64 = project_equirect(ImageView{128, 64, 1, img64.data()}, 3, 1, PixelRule::solid_angle)[0];
  EXPECT_LT(std::abs(ce64[6]), std::abs(ce[6]) / 40);
  // cross unpack: horizontal cross of face indices
  std::vector<float> cross(4 * N * 3 * N, -1.0f);
  const int cells[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < N; ++r)
      for (int q = 0; q < N; ++q) cross[(cells[f][1] * N + r) * 4 * N + cells[f][0] * N + q] = float(f);
  const CubeMap un = unpack_cross(ImageView{4 * N, 3 * N, 1, cross.data()});
  for (int f = 0; f < 6; ++f) EXPECT_EQ(un.faces[f][5], float(f));
  // nearest-texel lookup inverts the texel direction
  for (int f = 0; f < 6; ++f) {
    double v;
    sample_cube(un, cube_texel_direction(f, 2, 5, N), &v);
    EXPECT_EQ(v, double(f));
  }
}

// ---- rotation ---------------------------------------------------------------------------
TEST(Rotation, ConventionIsActive) {
  // Rotating the function z (c_10 = 1) by +90 deg about y sends the lobe from +z to +x:
  // f'(r) = f(R^-1 r) = (R e_z) . r = x = -Y_11 / k1 (closed forms above).
  Rotation R(2, EulerZYZ{0, kPi / 2, 0});
  std::vector<double> c(4, 0.0);
  c[2] = 1;
  const auto o = R.apply(c);
  EXPECT_NEAR(o[3], -1.0, 1e-15);
  EXPECT_NEAR(o[1], 0.0, 1e-15);
  EXPECT_NEAR(o[2], 0.0, 1e-15);
}

TEST(Rotation, CommutesWithProjection) {
  const int L = 12;
  const auto c = random_coeffs(L, 5);
  for (const EulerZYZ e : {EulerZYZ{0.7, 2.1, -1.3}, EulerZYZ{3.0, 3.1, 0.2}, EulerZYZ{-0.4, 0.0, 1.0}}) {
    const glm::dmat3 M = matrix_from_euler(e), Mi = glm::transpose(M);
    const auto cr = Rotation(L, e).apply(c);
    const auto cp = project_function([&](const glm::dvec3& d) { return reconstruct(L, c.data(), Mi * d); }, L);
    for (int i = 0; i < L * L; ++i) EXPECT_NEAR(cr[i], cp[i], 1e-12);
  }
}

TEST(Rotation, RepresentationsAgreeAndCompose) {
  const int L = 9;
  const auto c = random_coeffs(L, 6);
  const EulerZYZ e1{0.3, 1.2, -2.0}, e2{2.5, 0.4, 0.9};
  const glm::dmat3 M1 = matrix_from_euler(e1), M2 = matrix_from_euler(e2);
  const auto a = Rotation(L, e1).apply(Rotation(L, e2).apply(c));
  const auto b = Rotation(L, M1 * M2).apply(c);
  const auto q = Rotation(L, glm::quat_cast(M1 * M2)).apply(c);
  for (int i = 0; i < L * L; ++i) {
    EXPECT_NEAR(a[i], b[i], 1e-13);
    EXPECT_NEAR(q[i], b[i], 1e-13);
  }
  std::vector<double> z(L * L);
  rotate_z(L, 0.77, c.data(), z.data());
  const auto zr = Rotation(L, EulerZYZ{0.77, 0, 0}).apply(c);
  for (int i = 0; i < L * L; ++i) EXPECT_NEAR(z[i], zr[i], 1e-13);
  EXPECT_THROW(Rotation(L, glm::dmat3(2.0)), atmosh::InputError);
}

TEST(Rotation, OrthogonalAtHighBands) {
  const EulerZYZ e{0.3, 1.9, 2.5};
  {
    const Rotation R(64, e);
    const int l = 63, n = 2 * l + 1;
    const auto D = R.band_matrix(l);
    double worst = 0;
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < n; ++k) {
        double s = 0;
        for (int j = 0; j < n; ++j) s += D[i * n + j] * D[k * n + j];
        worst = std::max(worst, std::abs(s - (i == k)));
      }
    EXPECT_LT(worst, 1e-12);
  }
  {
    // band 299 of L = 300: sampled columns are orthonormal
    const int L = 300, l = 299, n = 2 * l + 1;
    const Rotation R(L, e);
    std::vector<std::vector<double>> cols;
    for (int j : {0, 100, l, n - 1}) {
      std::vector<double> in(L * L, 0.0), out(L * L);
      in[l * l + j] = 1;
      R.apply(in.data(), out.data());
      cols.emplace_back(out.begin() + l * l, out.begin() + l * l + n);
    }
    for (std::size_t a = 0; a < cols.size(); ++a)
      for (std::size_t b = 0; b < cols.size(); ++b) {
        double s = 0;
        for (int i = 0; i < n; ++i) s += cols[a][i] * cols[b][i];
        EXPECT_NEAR(s, a == b ? 1.0 : 0.0, 1e-10);
      }
  }
}

TEST(Rotation, BandEnergyIsInvariant) {
  const int L = 30;
  const auto c = random_coeffs(L, 8);
  const auto r = Rotation(L, EulerZYZ{1.0, 2.0, 3.0}).apply(c);
  const auto e0 = band_energy(c, L), e1 = band_energy(r, L);
  for (int l = 0; l < L; ++l) EXPECT_NEAR(e1[l], e0[l], 1e-12 * e0[l]);
  const auto f = cumulative_energy_fraction(e0);
  EXPECT_DOUBLE_EQ(f.back(), 1.0);
}

// ---- convolution --------------------------------------------------------------------
TEST(Irradiance, ClampedCosineFactors) {
  // Ramamoorthi & Hanrahan 2001, eq. 9: A_0 = pi, A_1 = 2pi/3, A_2 = pi/4, A_3 = 0,
  // A_4 = -pi/24, A_5 = 0, A_6 = pi/64.
  const auto A = irradiance_factors(7);
  const double ref[7] = {kPi, 2 * kPi / 3, kPi / 4, 0, -kPi / 24, 0, kPi / 64};
  for (int l = 0; l < 7; ++l) EXPECT_NEAR(A[l], ref[l], 1e-15) << l;
}

TEST(Irradiance, ConstantAndSingleDirection) {
  // constant radiance L0 -> E = pi L0 in every direction.
  std::vector<double> c(9, 0.0);
  c[0] = 2.0 * std::sqrt(4 * kPi);  // L = 2
  for (const auto& n : test_dirs(10, 9)) EXPECT_NEAR(irradiance_at(c, 3, n), 2 * kPi, 1e-13);
  // a single direction s (radiance = delta, coefficients Y(s)): E(n) -> max(0, n.s)
  const int L = 64;
  const glm::dvec3 s = glm::normalize(glm::dvec3(0.2, 0.5, 0.8));
  const auto ys = evaluate(L, s);
  const auto e = irradiance(ys, L);
  // addition theorem: E_L(n) = sum_l A_l (2l+1)/(4 pi) P_l(n . s) (an independent path)
  const auto A = irradiance_factors(L);
  double worst = 0, trunc = 0;
  for (const auto& n : test_dirs(200, 10)) {
    const auto P = legendre_polynomials(glm::dot(n, s), L);
    double ref = 0;
    for (int l = 0; l < L; ++l) ref += A[l] * (2 * l + 1) / (4 * kPi) * P[l];
    const double got = reconstruct(L, e.data(), n);
    worst = std::max(worst, std::abs(got - ref));
    trunc = std::max(trunc, std::abs(got - std::max(0.0, glm::dot(n, s))));
  }
  EXPECT_LT(worst, 1e-13);
  // truncation error of the clamped cosine at 64 bands (kink at the horizon): measured 4.1e-3
  EXPECT_LT(trunc, 1e-2);
}

TEST(Windows, NonNegativeRemovesNegativeLobes) {
  for (int L : {3, 8, 16}) {
    const auto w = window_weights(Window::nonnegative, L);
    EXPECT_GE(windowed_delta_min(w), -1e-8);
    EXPECT_LT(windowed_delta_min(window_weights(Window::none, L)), -0.01);
    const auto h = window_weights(Window::hanning, L);
    EXPECT_DOUBLE_EQ(h[0], 1.0);
    EXPECT_NEAR(h[L / 2], 0.5 * (1 + std::cos(kPi * (L / 2) / L)), 1e-15);
  }
}

TEST(Conversions, SchmidtFourPiNoCsAndComplex) {
  // f = z: orthonormal c_10 = sqrt(4pi/3); Schmidt Y_10 = P_1 = z so c = 1;
  // 4pi-normalised Y_10 = sqrt(3) z so c = 1/sqrt(3).
  std::vector<double> c(4, 0.0);
  c[2] = std::sqrt(4 * kPi / 3);
  EXPECT_NEAR(convert(c, 2, Normalization::orthonormal, true, Normalization::schmidt, true)[2], 1.0, 1e-15);
  EXPECT_NEAR(convert(c, 2, Normalization::orthonormal, true, Normalization::four_pi, true)[2], 1 / std::sqrt(3.0), 1e-15);
  // f = x = -sqrt(4pi/3) Y_11 (CS); without CS, x = +sqrt(4pi/3) Y_11.
  std::vector<double> cx(4, 0.0);
  cx[3] = -std::sqrt(4 * kPi / 3);
  EXPECT_NEAR(convert(cx, 2, Normalization::orthonormal, true, Normalization::orthonormal, false)[3], std::sqrt(4 * kPi / 3), 1e-15);
  // complex: x = sqrt(2pi/3) (Y_1^-1 - Y_1^1) (e.g. Jackson, Classical Electrodynamics, 3.53).
  const auto a = to_complex(cx, 2);
  EXPECT_NEAR(a[sh_index(1, 1)].real(), -std::sqrt(2 * kPi / 3), 1e-15);
  EXPECT_NEAR(a[sh_index(1, -1)].real(), std::sqrt(2 * kPi / 3), 1e-15);
  const auto back = from_complex(to_complex(random_coeffs(5, 4), 5), 5);
  const auto orig = random_coeffs(5, 4);
  for (int i = 0; i < 25; ++i) EXPECT_NEAR(back[i], orig[i], 1e-15);
}

TEST(Basis, ReconstructIsTheSumOfCoefficientsTimesBasis) {
  // reconstruct() (fast path to 8 bands, a per-thread buffer above) against sum c_i Y_i
  // with Y from the general path at one band more.
  for (int L : {1, 4, 8, 9, 20, 130}) {
    const auto c = random_coeffs(L, 40 + L);
    for (const auto& d : test_dirs(10, 5)) {
      const auto y = evaluate(L + 1, d);
      double s = 0;
      for (int i = 0; i < L * L; ++i) s += c[i] * y[i];
      EXPECT_NEAR(reconstruct(L, c.data(), d), s, 1e-13 * L) << L;
    }
  }
  // non-unit lengths (the small-band path normalises; tiny ones go through the checked path)
  const auto c4 = random_coeffs(4, 77);
  const glm::dvec3 u = glm::normalize(glm::dvec3(0.3, -0.4, 0.8));
  const double r0 = reconstruct(4, c4.data(), u);
  for (double len : {1e-300, 1e-200, 1e-3, 7.5, 1e100, 1e300}) {
    EXPECT_NEAR(reconstruct(4, c4.data(), u * len), r0, 1e-14) << len;
    const auto y = evaluate(4, u * len), y0 = evaluate(4, u);
    for (int i = 0; i < 16; ++i) EXPECT_NEAR(y[i], y0[i], 1e-15) << len;
  }
  const double c0 = 1.0;
  EXPECT_THROW(evaluate(4, glm::dvec3(0.0)), atmosh::InputError);
  EXPECT_THROW(evaluate(4, glm::dvec3(std::nan(""), 0, 1)), atmosh::InputError);
  EXPECT_THROW(reconstruct(4, &c0, glm::dvec3(0.0, std::numeric_limits<double>::infinity(), 0)), atmosh::InputError);
  EXPECT_THROW(reconstruct(1, &c0, glm::dvec3(0.0)), atmosh::InputError);
  EXPECT_THROW(reconstruct(0, &c0, glm::dvec3(0, 0, 1)), atmosh::InputError);
}
