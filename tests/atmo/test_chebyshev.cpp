// ChebyshevFit (atmosh/atmo/chebyshev.hpp) against closed forms: the interpolant of a
// polynomial of degree < n is the polynomial; analytic functions converge
// geometrically (Trefethen, ATAP, thm. 8.2: error <= 4 M rho^-n / (rho - 1) for f
// analytic and |f| <= M in the Bernstein ellipse of parameter rho); a kink defeats the
// check, and so does anything that is not finite.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "atmosh/atmo/chebyshev.hpp"

using atmosh::atmo::ChebyshevFit;

namespace {

// Largest |fit - f| on a fine grid over [a, b] (not the fit's own check points).
template <class F>
double max_error(const ChebyshevFit& fit, F&& f, double a, double b) {
  double e = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double x = a + (b - a) * i / 1000.0;
    e = std::max(e, std::fabs(fit(x) - f(x)));
  }
  return e;
}

}  // namespace

TEST(Chebyshev, ReproducesPolynomialsBelowItsDegree) {
  const auto p = [](double x) { return 3.0 - 2.0 * x + 0.5 * x * x * x - 0.25 * std::pow(x, 7); };
  const ChebyshevFit fit = ChebyshevFit::checked(p, -0.4, 1.3, 8, 1, 1e-13);
  ASSERT_TRUE(fit.valid());
  EXPECT_EQ(fit.points(), 8);
  EXPECT_LE(max_error(fit, p, -0.4, 1.3), 1e-13);
  // The same with a piece for every fifth of the interval.
  const ChebyshevFit five = ChebyshevFit::checked(p, -0.4, 1.3, 8, 5, 1e-13);
  ASSERT_TRUE(five.valid());
  EXPECT_EQ(five.pieces(), 5);
  EXPECT_LE(max_error(five, p, -0.4, 1.3), 1e-13);
}

TEST(Chebyshev, AnalyticFunctionsConvergeGeometrically) {
  // exp on [0, 1]: entire; 16 points reach rounding.
  const auto e = [](double x) { return std::exp(x); };
  const ChebyshevFit fe = ChebyshevFit::checked(e, 0.0, 1.0, 16, 1, 1e-14);
  ASSERT_TRUE(fe.valid());
  EXPECT_LE(max_error(fe, e, 0.0, 1.0), 1e-14 * std::exp(1.0));
  // 1 / (x + 0.5) on [0, 1]: a pole one half-width beyond the end (rho = 2 + sqrt 3:
  // ~2e-5 with 8 points), so one part of 8 points fails a 1e-10 check; 32 parts
  // (rho >= 65 for each) pass it, and the error between the check points stays
  // within it.
  const auto g = [](double x) { return 1.0 / (x + 0.5); };
  EXPECT_FALSE(ChebyshevFit::checked(g, 0.0, 1.0, 8, 1, 1e-10).valid());
  const ChebyshevFit fg = ChebyshevFit::checked(g, 0.0, 1.0, 8, 32, 1e-10);
  ASSERT_TRUE(fg.valid());
  EXPECT_LE(fg.check_error(), 1e-10 * 2.0);
  EXPECT_LE(max_error(fg, g, 0.0, 1.0), 1e-10 * 2.0);
}

TEST(Chebyshev, KinksAndBadInputFail) {
  // |x - 0.3| has a kink inside: the check fails at every split of a few parts.
  const auto k = [](double x) { return std::fabs(x - 0.3); };
  for (int pieces : {1, 2, 4, 8}) EXPECT_FALSE(ChebyshevFit::checked(k, 0.0, 1.0, 8, pieces, 1e-10).valid()) << pieces;
  // A function that is not finite somewhere it is sampled.
  const auto inf = [](double x) { return x > 0.5 ? std::numeric_limits<double>::infinity() : x; };
  EXPECT_FALSE(ChebyshevFit::checked(inf, 0.0, 1.0, 8, 1, 1e-10).valid());
  // Bad intervals and counts give an invalid fit without sampling.
  int calls = 0;
  const auto count = [&](double x) {
    ++calls;
    return x;
  };
  EXPECT_FALSE(ChebyshevFit::checked(count, 1.0, 1.0, 8, 1, 1e-10).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, 1.0, 0.0, 8, 1, 1e-10).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, 0.0, std::nan(""), 8, 1, 1e-10).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, 0.0, 1.0, 0, 1, 1e-10).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, 0.0, 1.0, ChebyshevFit::kMaxPoints + 1, 1, 1e-10).valid());
  EXPECT_FALSE(ChebyshevFit::checked(count, 0.0, 1.0, 8, 0, 1e-10).valid());
  EXPECT_EQ(calls, 0);
  // An all-zero function fits exactly; an empty fit covers nothing.
  const ChebyshevFit zero = ChebyshevFit::checked([](double) { return 0.0; }, -1.0, 1.0, 8, 1, 1e-10);
  ASSERT_TRUE(zero.valid());
  EXPECT_EQ(zero(0.37), 0.0);
  EXPECT_TRUE(zero.covers(-1.0));
  EXPECT_FALSE(zero.covers(1.0 + 1e-12));
  EXPECT_FALSE(ChebyshevFit{}.covers(0.0));
}
