// Wigner 3j symbols, Gaunt coefficients of the real SH and SH products, against
// independent references: Racah's closed formula for 3j symbols (exact factorials at small
// l; Edmonds 1957, eq. 3.7.3), closed forms derived below, and quadrature of the triple
// product (Gauss–Legendre in cos t times the uniform rule in p, exact for these degrees).
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <cstdint>
#include <numbers>
#include <random>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/gaunt.hpp"
#include "atmosh/sh/quadrature.hpp"
#include "atmosh/sh/transform.hpp"

using namespace atmosh::sh;

namespace {
constexpr double kPi = std::numbers::pi;

long double fact(int n) {
  long double f = 1;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

// Racah's formula (Edmonds 1957, eq. 3.7.3), in long double; for small l only.
double racah3j(int j1, int j2, int j3, int m1, int m2, int m3) {
  if (m1 + m2 + m3 != 0 || j3 < std::abs(j1 - j2) || j3 > j1 + j2 || std::abs(m1) > j1 || std::abs(m2) > j2 ||
      std::abs(m3) > j3)
    return 0.0;
  const long double delta = fact(j1 + j2 - j3) * fact(j1 - j2 + j3) * fact(-j1 + j2 + j3) / fact(j1 + j2 + j3 + 1);
  const long double pre = std::sqrt(delta * fact(j1 + m1) * fact(j1 - m1) * fact(j2 + m2) * fact(j2 - m2) *
                                    fact(j3 + m3) * fact(j3 - m3));
  long double s = 0;
  for (int k = 0; k <= j1 + j2 + j3; ++k) {
    const int a[6] = {k, j3 - j2 + k + m1, j3 - j1 + k - m2, j1 + j2 - j3 - k, j1 - k - m1, j2 - k + m2};
    bool ok = true;
    for (int v : a) ok &= v >= 0;
    if (!ok) continue;
    long double d = 1;
    for (int v : a) d *= fact(v);
    s += (k % 2 ? -1.0L : 1.0L) / d;
  }
  const int e = j1 - j2 - m3;
  return static_cast<double>(((e % 2 + 2) % 2 ? -1.0L : 1.0L) * pre * s);
}

// integral Y_l1m1 Y_l2m2 Y_l3m3 dOmega by quadrature: Y_lm = Pbar_l|m|(x) Phi_m(p) with
// Phi_0 = 1, Phi_m = sqrt2 cos(m p) (m > 0), sqrt2 sin(|m| p) (m < 0): the x integral by an
// n-point Gauss rule (n > (l1+l2+l3)/2), the p integral by the uniform rule with more than
// |m1|+|m2|+|m3| points (both exact).
double gaunt_by_quadrature(int l1, int m1, int l2, int m2, int l3, int m3) {
  const int n = (l1 + l2 + l3) / 2 + 2;
  const GaussLegendre g = gauss_legendre(n);
  const int lmax = std::max({l1, l2, l3});
  std::vector<double> c1(lmax + 1), c2(lmax + 1), c3(lmax + 1);
  double sx = 0;
  for (int k = 0; k < n; ++k) {
    const double x = g.nodes[k], s = std::sqrt((1 - x) * (1 + x));
    legendre_column(lmax + 1, std::abs(m1), x, s, c1.data());
    legendre_column(lmax + 1, std::abs(m2), x, s, c2.data());
    legendre_column(lmax + 1, std::abs(m3), x, s, c3.data());
    sx += g.weights[k] * c1[l1 - std::abs(m1)] * c2[l2 - std::abs(m2)] * c3[l3 - std::abs(m3)];
  }
  auto Phi = [](int m, double p) {
    return m == 0 ? 1.0 : (m > 0 ? std::numbers::sqrt2 * std::cos(m * p) : std::numbers::sqrt2 * std::sin(-m * p));
  };
  const int np = std::abs(m1) + std::abs(m2) + std::abs(m3) + 3;
  double sp = 0;
  for (int j = 0; j < np; ++j) {
    const double p = 2 * kPi * (j + 0.25) / np;
    sp += Phi(m1, p) * Phi(m2, p) * Phi(m3, p);
  }
  return sx * sp * 2 * kPi / np;
}

std::vector<double> random_coeffs(int bands, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd;
  std::vector<double> c(static_cast<std::size_t>(bands) * bands);
  for (auto& v : c) v = nd(rng);
  return c;
}
}  // namespace

TEST(Wigner3j, MatchesRacahFormulaAtSmallL) {
  double worst = 0;
  for (int l1 = 0; l1 <= 8; ++l1)
    for (int l2 = 0; l2 <= 8; ++l2)
      for (int l3 = std::abs(l1 - l2); l3 <= l1 + l2 && l3 <= 10; ++l3)
        for (int m2 = -l2; m2 <= l2; ++m2)
          for (int m3 = -l3; m3 <= l3; ++m3) {
            const int m1 = -m2 - m3;
            if (std::abs(m1) > l1) continue;
            const double ref = racah3j(l1, l2, l3, m1, m2, m3);
            const double v = wigner3j(l1, l2, l3, m1, m2, m3);
            worst = std::max(worst, std::abs(v - ref));
            ASSERT_NEAR(v, ref, 1e-14) << l1 << " " << l2 << " " << l3 << " " << m1 << " " << m2 << " " << m3;
          }
  EXPECT_LT(worst, 1e-14);
  // (l l 0; m -m 0) = (-1)^(l-m) / sqrt(2l+1) (Edmonds 1957, eq. 3.7.9), up to high l
  for (int l : {1, 10, 100, 1000, 3000})
    for (int m : {-l, -l / 3, 0, 1, l}) {
      const double ref = ((l - m) % 2 ? -1.0 : 1.0) / std::sqrt(2.0 * l + 1);
      EXPECT_NEAR(wigner3j(l, l, 0, m, -m, 0), ref, 1e-15) << l << " " << m;
      // the same symbol from the family over l1 = 0..2l (cyclic permutation)
      EXPECT_NEAR(wigner3j(0, l, l, 0, m, -m), ref, 1e-14) << l << " " << m;
    }
  EXPECT_EQ(wigner3j(2, 2, 2, 1, 1, 1), 0.0);   // m sum != 0
  EXPECT_EQ(wigner3j(5, 1, 1, 0, 0, 0), 0.0);   // triangle
  EXPECT_THROW(wigner3j(1, 1, 1, 2, -1, -1), atmosh::InputError);
}

TEST(Wigner3j, OrthogonalityAtHighL) {
  // sum_{m2} (l1 l2 l3; m1 m2 m3)(l1 l2 l3'; m1 m2 m3) ... use the l1-sum form
  // sum_{l1} (2 l1 + 1) (l1 l2 l3; m1 m2 m3)(l1 l2 l3; m1 m2' m3') = delta_{m2 m2'} with
  // m2 + m3 = m2' + m3' (Edmonds 1957, eq. 3.7.7): different families, so a real check.
  for (auto [l2, l3, m2, m3, m2b] : {std::array<int, 5>{200, 150, 17, -40, 20}, std::array<int, 5>{300, 300, 0, 5, 3},
                                     std::array<int, 5>{120, 400, -100, 110, -99}}) {
    const int m3b = m2 + m3 - m2b;
    std::vector<double> a, b;
    const int la = wigner3j_family(l2, l3, m2, m3, a), lb = wigner3j_family(l2, l3, m2b, m3b, b);
    ASSERT_EQ(la, lb);
    double s = 0, n = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      s += (2.0 * (la + k) + 1) * a[k] * b[k];
      n += (2.0 * (la + k) + 1) * a[k] * a[k];
      ASSERT_TRUE(std::isfinite(a[k]));
    }
    EXPECT_NEAR(s, 0.0, 1e-13);
    EXPECT_NEAR(n, 1.0, 1e-13);
  }
}

TEST(Gaunt, ClosedFormsAtSmallL) {
  // Y_00 = 1/sqrt(4 pi): G(00, lm, lm) = 1/sqrt(4 pi) by orthonormality.
  for (int l = 0; l <= 30; l += 3)
    for (int m = -l; m <= l; m += std::max(1, l / 4)) EXPECT_NEAR(gaunt(0, 0, l, m, l, m), 1 / std::sqrt(4 * kPi), 1e-15);
  // Y_10 = sqrt(3/4pi) z, Y_20 = sqrt(5/4pi) (3z^2-1)/2: int z^2 (3z^2-1)/2 dOmega = 8 pi/15,
  // so G(10, 10, 20) = (3/4pi) sqrt(5/4pi) 8pi/15 = (2/5) sqrt(5/4pi).
  EXPECT_NEAR(gaunt(1, 0, 1, 0, 2, 0), 0.4 * std::sqrt(5 / (4 * kPi)), 1e-15);
  // Y_11 = -sqrt(3/4pi) x, Y_1-1 = -sqrt(3/4pi) y, Y_22 = sqrt(15/16pi)(x^2-y^2),
  // Y_2-2 = sqrt(15/16pi) 2xy: int x^2 (x^2-y^2) = 4pi/5 - 4pi/15 = 8pi/15,
  // int xy 2xy = 8pi/15, so both are (2/5) sqrt(15/16pi); the m = 0 partner:
  // int x^2 (3z^2-1)/2 = (3 * 4pi/15 - 4pi/3)/2 = -4pi/15 -> G(11,11,20) = -(1/5) sqrt(5/4pi).
  EXPECT_NEAR(gaunt(1, 1, 1, 1, 2, 2), 0.4 * std::sqrt(15 / (16 * kPi)), 1e-15);
  EXPECT_NEAR(gaunt(1, -1, 1, 1, 2, -2), 0.4 * std::sqrt(15 / (16 * kPi)), 1e-15);
  EXPECT_NEAR(gaunt(1, -1, 1, -1, 2, 2), -0.4 * std::sqrt(15 / (16 * kPi)), 1e-15);
  EXPECT_NEAR(gaunt(1, 1, 1, 1, 2, 0), -0.2 * std::sqrt(5 / (4 * kPi)), 1e-15);
  EXPECT_EQ(gaunt(1, 1, 1, -1, 2, 0), 0.0);  // int x y (3z^2-1) = 0: odd number of sines
}

TEST(Gaunt, AllTriplesAgreeWithQuadratureAndSelectionRules) {
  // Every triple of l <= 5 (46656 of them): against quadrature on a grid exact for them,
  // and an exact zero wherever a selection rule says so.
  const int L = 6, n = L * L;
  const GaussGrid g = gauss_grid(L, 9, 16);  // x degree <= 15 < 2*9, p frequency <= 15 < 16
  std::vector<double> Y(static_cast<std::size_t>(g.nlat) * g.nphi * n);
  for (int i = 0; i < g.nlat; ++i)
    for (int j = 0; j < g.nphi; ++j)
      evaluate_angles(L, std::atan2(g.sin_t[i], g.cos_t[i]), g.phi(j), Y.data() + (static_cast<std::size_t>(i) * g.nphi + j) * n);
  int zeros = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < n; ++c) {
        const int la = static_cast<int>(std::sqrt(a)), lb = static_cast<int>(std::sqrt(b)), lc = static_cast<int>(std::sqrt(c));
        const int ma = a - la * (la + 1), mb = b - lb * (lb + 1), mc = c - lc * (lc + 1);
        double q = 0;
        for (int i = 0; i < g.nlat; ++i)
          for (int j = 0; j < g.nphi; ++j) {
            const double* y = Y.data() + (static_cast<std::size_t>(i) * g.nphi + j) * n;
            q += g.weights[i] * y[a] * y[b] * y[c];
          }
        q *= 2 * kPi / g.nphi;
        const double v = gaunt(la, ma, lb, mb, lc, mc);
        ASSERT_NEAR(v, q, 1e-14) << la << "," << ma << " " << lb << "," << mb << " " << lc << "," << mc;
        const int nneg = (ma < 0) + (mb < 0) + (mc < 0);
        const int A = std::abs(ma), B = std::abs(mb), C = std::abs(mc);
        const bool rules = (la + lb + lc) % 2 == 0 && la >= std::abs(lb - lc) && la <= lb + lc && nneg % 2 == 0 &&
                           (A == B + C || B == A + C || C == A + B);
        if (!rules) {
          EXPECT_EQ(v, 0.0);
          ++zeros;
        }
        // symmetric in its three arguments
        if (a < b && b < c) {
          EXPECT_NEAR(gaunt(lc, mc, la, ma, lb, mb), v, 1e-15);
        }
      }
  EXPECT_GT(zeros, 40000);
}

TEST(Gaunt, StableAtHighL) {
  // l ~ 200..400 against the quadrature reference (column recurrences of basis.hpp).
  const int cases[][6] = {{200, 5, 150, -3, 250, -8},    {200, 0, 200, 0, 200, 0},  {201, 100, 200, -60, 199, -40},
                          {300, 150, 150, 100, 200, 50}, {10, 10, 200, -195, 210, -205}, {256, -128, 256, -128, 2, 0},
                          {400, 0, 399, 1, 3, 1}};
  for (const auto& c : cases) {
    const double v = gaunt(c[0], c[1], c[2], c[3], c[4], c[5]);
    const double q = gaunt_by_quadrature(c[0], c[1], c[2], c[3], c[4], c[5]);
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_NEAR(v, q, 1e-14 + 1e-11 * std::abs(q)) << c[0] << " " << c[2] << " " << c[4];
    EXPECT_GT(std::abs(q), 1e-6) << c[0] << " " << c[2] << " " << c[4];  // not trivially zero
  }
  EXPECT_EQ(gaunt(256, -128, 256, 128, 2, 0), 0.0);  // sin x cos x 1: odd in p
  EXPECT_NEAR(gaunt_by_quadrature(256, -128, 256, 128, 2, 0), 0.0, 1e-14);
}

TEST(Gaunt, ProductsAgreeWithPointwiseProducts) {
  // f g at random directions: the exact product (La + Lb - 1 bands) reproduces f(d) g(d);
  // the tensor (TripleProduct) and the grid path (product) agree; the product matrix of f
  // applied to g is the same product; truncation keeps the lower bands.
  const int La = 5, Lb = 4, Lp = La + Lb - 1;
  const auto a = random_coeffs(La, 1), b = random_coeffs(Lb, 2);
  const auto c = product(a, La, b, Lb);
  ASSERT_EQ(static_cast<int>(c.size()), Lp * Lp);
  const TripleProduct tp(La, Lb);
  std::vector<double> ct(Lp * Lp);
  tp.apply(a.data(), b.data(), ct.data());
  for (int k = 0; k < Lp * Lp; ++k) EXPECT_NEAR(c[k], ct[k], 1e-13) << k;
  const auto M = tp.product_matrix(a.data());
  for (int k = 0; k < Lp * Lp; ++k) {
    double s = 0;
    for (int j = 0; j < Lb * Lb; ++j) s += M[static_cast<std::size_t>(k) * Lb * Lb + j] * b[j];
    EXPECT_NEAR(s, c[k], 1e-13);
  }
  std::mt19937_64 rng(4);
  std::normal_distribution<double> nd;
  for (int t = 0; t < 20; ++t) {
    const glm::dvec3 d(nd(rng), nd(rng), nd(rng));
    const double f = reconstruct(La, a.data(), d), gg = reconstruct(Lb, b.data(), d), p = reconstruct(Lp, c.data(), d);
    EXPECT_NEAR(p, f * gg, 1e-12 * (1 + std::abs(f * gg)));
  }
  const auto c3 = product(a, La, b, Lb, 3);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(c3[k], c[k], 1e-13);
  // at a higher band through the grid path
  const int Lh = 96;
  const auto ah = random_coeffs(Lh, 5), bh = random_coeffs(Lh, 6);
  const auto ch = product(ah, Lh, bh, Lh);
  for (int t = 0; t < 5; ++t) {
    const glm::dvec3 d(nd(rng), nd(rng), nd(rng));
    const double f = reconstruct(Lh, ah.data(), d), gg = reconstruct(Lh, bh.data(), d);
    EXPECT_NEAR(reconstruct(2 * Lh - 1, ch.data(), d), f * gg, 1e-10 * (1 + std::abs(f * gg)));
  }
  EXPECT_THROW(product(a, La, b, 7), atmosh::InputError);
}
