// ChebyshevFit (atmosh/atmo/chebyshev.hpp) against closed forms: the interpolant of a
// polynomial of degree < n is the polynomial; analytic functions converge
// geometrically (Trefethen, ATAP, thm. 8.2: error <= 4 M rho^-n / (rho - 1) for f
// analytic and |f| <= M in the Bernstein ellipse of parameter rho), so a part that
// fails its check is halved until it passes; a kink is fitted when it is a given
// breakpoint and defeats the check otherwise; anything not finite fails.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "atmosh/atmo/chebyshev.hpp"

using atmosh::atmo::ChebyshevFit;

namespace {

// A scalar function as a one-channel f(x, out).
template <class G>
auto channel(G g) {
  return [g](double x, double* out) { out[0] = g(x); };
}

// Largest |fit - g| on a fine grid over [a, b] (not the fit's own check points).
template <class G>
double max_error(const ChebyshevFit& fit, G&& g, double a, double b) {
  double e = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double x = a + (b - a) * i / 1000.0;
    double v;
    fit(x, &v);
    e = std::max(e, std::fabs(v - g(x)));
  }
  return e;
}

}  // namespace

TEST(Chebyshev, ReproducesPolynomialsBelowItsDegree) {
  const auto p = [](double x) { return 3.0 - 2.0 * x + 0.5 * x * x * x - 0.25 * std::pow(x, 7); };
  const ChebyshevFit fit = ChebyshevFit::checked(channel(p), {-0.4, 1.3}, 8, 1, 1e-13, 17);
  ASSERT_TRUE(fit.valid());
  EXPECT_EQ(fit.points(), 8);
  EXPECT_EQ(fit.pieces(), 1);
  EXPECT_EQ(fit.samples(), 17);
  EXPECT_LE(max_error(fit, p, -0.4, 1.3), 1e-13);
  // Given breakpoints: a part between each, and every part exact.
  const ChebyshevFit five = ChebyshevFit::checked(channel(p), {-0.4, -0.1, 0.0, 0.5, 1.0, 1.3}, 8, 1, 1e-13, 1000);
  ASSERT_TRUE(five.valid());
  EXPECT_EQ(five.pieces(), 5);
  EXPECT_LE(max_error(five, p, -0.4, 1.3), 1e-13);
  // Two channels at once.
  const ChebyshevFit two = ChebyshevFit::checked(
      [&](double x, double* out) {
        out[0] = p(x);
        out[1] = -7.0 * x * x;
      },
      {0.0, 2.0}, 8, 2, 1e-13, 17);
  ASSERT_TRUE(two.valid());
  double v[2];
  two(1.7, v);
  EXPECT_NEAR(v[0], p(1.7), 1e-13 * std::fabs(p(1.7)));
  EXPECT_NEAR(v[1], -7.0 * 1.7 * 1.7, 1e-13 * 7.0 * 4.0);
}

TEST(Chebyshev, AnalyticFunctionsConvergeGeometrically) {
  // exp on [0, 1]: entire; 16 points reach rounding.
  const auto e = [](double x) { return std::exp(x); };
  const ChebyshevFit fe = ChebyshevFit::checked(channel(e), {0.0, 1.0}, 16, 1, 1e-14, 33);
  ASSERT_TRUE(fe.valid());
  EXPECT_LE(max_error(fe, e, 0.0, 1.0), 1e-14 * std::exp(1.0));
  // 1 / (x + 0.5) on [0, 1]: a pole one half-width beyond the end (rho = 2 + sqrt 3:
  // ~2e-5 with 8 points), so one part of 8 points fails a 1e-10 check; halving
  // passes it (rho >= 65 for parts of 1/32), the error between the check points
  // stays within it, and the parts are finest next to the pole.
  const auto g = [](double x) { return 1.0 / (x + 0.5); };
  EXPECT_FALSE(ChebyshevFit::checked(channel(g), {0.0, 1.0}, 8, 1, 1e-10, 17).valid());
  const ChebyshevFit fg = ChebyshevFit::checked(channel(g), {0.0, 1.0}, 8, 1, 1e-10, 10000);
  ASSERT_TRUE(fg.valid());
  EXPECT_GT(fg.pieces(), 2);
  EXPECT_LE(fg.check_error(), 1e-10);
  EXPECT_LE(max_error(fg, g, 0.0, 1.0), 2e-10 * 2.0);
  // A budget too small for the parts it needs: no fit.
  EXPECT_FALSE(ChebyshevFit::checked(channel(g), {0.0, 1.0}, 8, 1, 1e-10, fg.samples() - 1).valid());
}

TEST(Chebyshev, KinksAndBadInputFail) {
  // |x - 0.3| has a kink at 0.3: as a breakpoint it is fitted exactly; off the
  // breakpoints the part that holds it fails until it is ~1e-9 wide (the
  // interpolant's error there is ~ its width), beyond a budget of 300 samples.
  const auto k = [](double x) { return std::fabs(x - 0.3); };
  const ChebyshevFit at = ChebyshevFit::checked(channel(k), {0.0, 0.3, 1.0}, 8, 1, 1e-12, 34);
  ASSERT_TRUE(at.valid());
  EXPECT_LE(max_error(at, k, 0.0, 1.0), 1e-12);
  EXPECT_FALSE(ChebyshevFit::checked(channel(k), {0.0, 1.0}, 8, 1, 1e-10, 300).valid());
  // A function that is not finite somewhere it is sampled.
  const auto inf = [](double x) { return x > 0.5 ? std::numeric_limits<double>::infinity() : x; };
  EXPECT_FALSE(ChebyshevFit::checked(channel(inf), {0.0, 1.0}, 8, 1, 1e-10, 1000).valid());
  // Bad breakpoints, counts and channels give an invalid fit without sampling.
  int calls = 0;
  const auto count = [&](double x, double* out) {
    ++calls;
    out[0] = x;
  };
  for (const std::vector<double>& b : {std::vector<double>{1.0}, {1.0, 1.0}, {1.0, 0.0}, {0.0, std::nan("")},
                                       {0.0, 0.5, 0.5, 1.0}}) {
    EXPECT_FALSE(ChebyshevFit::checked(count, b, 8, 1, 1e-10, 1000).valid());
  }
  EXPECT_FALSE(ChebyshevFit::checked(count, {0.0, 1.0}, 0, 1, 1e-10, 1000).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, {0.0, 1.0}, ChebyshevFit::kMaxPoints + 1, 1, 1e-10, 1000).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, {0.0, 1.0}, 8, 0, 1e-10, 1000).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, {0.0, 1.0}, 8, ChebyshevFit::kMaxChannels + 1, 1e-10, 1000).valid());
  EXPECT_EQ(calls, 0);
  // An all-zero function fits exactly; an empty fit covers nothing.
  const ChebyshevFit zero = ChebyshevFit::checked(channel([](double) { return 0.0; }), {-1.0, 1.0}, 8, 1, 1e-10, 17);
  ASSERT_TRUE(zero.valid());
  double v = 1.0;
  zero(0.37, &v);
  EXPECT_EQ(v, 0.0);
  EXPECT_TRUE(zero.covers(-1.0));
  EXPECT_FALSE(zero.covers(1.0 + 1e-12));
  EXPECT_FALSE(ChebyshevFit{}.covers(0.0));
}
