// Rotation at high bands: the full band matrix of band 999 (L = 1000) is orthogonal and
// rotates the basis (f'(R d) = f(d), checked with the independently tested basis);
// band_matrix agrees with apply; the band cache changes no result.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/rotation.hpp"

using namespace atmosh::sh;

#if !defined(__SANITIZE_ADDRESS__) && !defined(__has_feature)
#define ATMOSH_FULL_SPEED 1
#elif defined(__has_feature)
#if !__has_feature(address_sanitizer)
#define ATMOSH_FULL_SPEED 1
#endif
#endif

namespace {
// max |(D D^T - I)_ik| over sampled rows i and all k, and the same for D^T D.
double orthogonality_error(const std::vector<double>& D, int n, int row_step) {
  std::vector<double> T(D.size());
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) T[static_cast<std::size_t>(j) * n + i] = D[static_cast<std::size_t>(i) * n + j];
  double worst = 0;
  for (const std::vector<double>* A : {&D, static_cast<const std::vector<double>*>(&T)})
    for (int i = 0; i < n; i += row_step) {
      const double* ri = A->data() + static_cast<std::size_t>(i) * n;
      for (int k = 0; k < n; ++k) {
        const double* rk = A->data() + static_cast<std::size_t>(k) * n;
        double s = 0;
        for (int j = 0; j < n; ++j) s += ri[j] * rk[j];
        worst = std::max(worst, std::abs(s - (i == k)));
      }
    }
  return worst;
}
}  // namespace

TEST(Rotation, FullBandAtHighBandIsOrthogonalAndRotatesTheBasis) {
#ifdef ATMOSH_FULL_SPEED
  const int L = 1000;
#else
  const int L = 300;  // sanitizer builds: the same checks at a lower band
#endif
  const int l = L - 1, n = 2 * l + 1;
  const EulerZYZ e{0.3, 1.9, 2.5};
  const Rotation R(L, e);
  const auto D = R.band_matrix(l);
  for (double v : D) ASSERT_TRUE(std::isfinite(v));
  EXPECT_LE(orthogonality_error(D, n, 37), 1e-14);
  // sum_i D_im Y_li(R d) = Y_lm(d)
  const glm::dmat3 M = matrix_from_euler(e);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> nd;
  const double scale = std::sqrt((2.0 * l + 1) / (4 * std::numbers::pi));
  for (int t = 0; t < 2; ++t) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(nd(rng), nd(rng), nd(rng)));
    const auto y = evaluate(L, d), yr = evaluate(L, M * d);
    for (int m : {-l, -l / 2, -1, 0, 7, l / 3, l}) {
      double s = 0;
      for (int i = 0; i < n; ++i) s += D[static_cast<std::size_t>(i) * n + (m + l)] * yr[l * l + i];
      EXPECT_NEAR(s, y[l * l + m + l], 1e-11 * scale) << "m=" << m;
    }
  }
}

TEST(Rotation, BandMatrixAgreesWithApplyAndCacheChangesNothing) {
  const EulerZYZ e{1.1, 0.7, -2.0};
  const int L = 40, l = 39, n = 2 * l + 1;
  const Rotation R(L, e);
  const auto D = R.band_matrix(l);
  std::vector<double> in(L * L, 0.0), out(L * L);
  for (int j = 0; j < n; ++j) {
    in[l * l + j] = 1.0;
    R.apply(in.data(), out.data());
    in[l * l + j] = 0.0;
    for (int i = 0; i < n; ++i) EXPECT_EQ(D[static_cast<std::size_t>(i) * n + j], out[l * l + i]);
  }
  EXPECT_EQ(R.band_matrix(0), std::vector<double>{1.0});
  // bands 256..299 made on the fly in every application: reserving the cache keeps only
  // the bands below 256 and changes no bit
  const int Lh = 300;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> nd;
  std::vector<double> c(Lh * Lh), a(Lh * Lh), b(Lh * Lh);
  for (auto& v : c) v = nd(rng);
  const Rotation Rh(Lh, e);
  Rh.apply(c.data(), a.data());
  reserve_rotation_cache(Lh);
  EXPECT_EQ(rotation_cache_bands(), 256);
  Rh.apply(c.data(), b.data());
  EXPECT_EQ(a, b);
  EXPECT_THROW(reserve_rotation_cache(0), atmosh::InputError);
  EXPECT_THROW(R.band_matrix(L), atmosh::InputError);
}

TEST(Rotation, BandsMadeOnTheFlyRotateBandLimitedFunctions) {
  // Bands 256..599 apply Ry(90) on the fly (rotation.cpp). Reference: the definition of an
  // active rotation, f'(R d) = f(d), evaluated pointwise with evaluate() (basis.cpp, an
  // independent recurrence) for a random function of 600 bands at a few directions; the
  // bands below 256 (cached matrices) are zero here, so only the on-the-fly path acts.
  const int L = 600;
  const EulerZYZ e{0.4, 2.2, -1.3};
  const Rotation R(L, e);
  const glm::dmat3 M = matrix_from_euler(e);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> nd;
  std::vector<double> c(L * L, 0.0);
  for (int i = 256 * 256; i < L * L; ++i) c[i] = nd(rng);
  const auto cr = R.apply(c);
  for (int i = 0; i < 256 * 256; ++i) ASSERT_EQ(cr[i], 0.0);
  double scale = 0;  // |f| is of the order of sqrt(sum c^2 / (4 pi))
  for (double v : c) scale += v * v;
  scale = std::sqrt(scale / (4 * std::numbers::pi));
  for (int t = 0; t < 4; ++t) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(nd(rng), nd(rng), nd(rng)));
    const auto y = evaluate(L, d), yr = evaluate(L, M * d);
    double f = 0, fr = 0;
    for (int i = 0; i < L * L; ++i) {
      f += c[i] * y[i];
      fr += cr[i] * yr[i];
    }
    EXPECT_NEAR(fr, f, 1e-11 * scale) << t;
  }
}
