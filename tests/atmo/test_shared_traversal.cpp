// The shared CPU/GPU control flow (shared/*.glsl.hpp): the cut points of a view
// ray, the window choice and shell search of the table lookup, and the walk of
// a piecewise-linear column, each against an independent construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <random>
#include <vector>

#include "fast_exp.hpp"  // private (libatmo/src)
#include "integrate.hpp"  // private (libatmo/src)
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/atmo/shared/scatter.glsl.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/atmo/sorted_index.hpp"

namespace sg = atmosh::atmo::shared;

namespace {
constexpr double kR = 6371e3, kT = kR + 100e3;

// The cut set by definition: every root s in (0, s_end) of |origin + s v| = k for
// each sphere k (solved here as a quadratic in s), the tangent point, the
// shadow edges, and both ends; sorted.
std::vector<double> cuts_by_definition(double r, double mu, double mu_s, double nu, double s_end,
                                       const std::vector<double>& radii) {
  std::vector<double> c = {0.0, s_end};
  for (double k : radii) {
    // s^2 + 2 r mu s + (r^2 - k^2) = 0
    const double b = r * mu, cc = (r - k) * (r + k), disc = b * b - cc;
    if (disc < 0) continue;
    for (double s : {-b - std::sqrt(disc), -b + std::sqrt(disc)})
      if (s > 0 && s < s_end) c.push_back(s);
  }
  if (-r * mu > 0 && -r * mu < s_end) c.push_back(-r * mu);
  for (int i = 0; i < 2; ++i) {
    const double s = sg::shadow_edge_distance(r, mu, mu_s, nu, kR, i);
    if (s > 0 && s < s_end) c.push_back(s);
  }
  std::sort(c.begin(), c.end());
  return c;
}
}  // namespace

TEST(SharedViewRayCuts, AreTheSortedCutSetOfTheRay) {
  std::vector<double> radii;
  for (int i = 1; i < 16; ++i) radii.push_back(kR + 100e3 * std::pow(i / 16.0, 2.0));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), h(0.0, 100e3);
  int with_shadow = 0;
  for (int t = 0; t < 2000; ++t) {
    const double r = kR + (t % 5 == 0 ? 0.0 : h(rng)), mu = u(rng), mu_s = 0.3 * u(rng);
    const double sin_mu = std::sqrt(1 - mu * mu), phi = 3.14159 * u(rng);
    const double nu = std::clamp(mu * mu_s + sin_mu * std::sqrt(1 - mu_s * mu_s) * std::cos(phi), -1.0, 1.0);
    const double s_end = sg::ray_hits_ground(r, mu, kR) ? sg::distance_to_ground(r, mu, kR) : sg::distance_to_top(r, mu, kT);
    if (!(s_end > 0)) continue;
    const sg::ViewRayCuts c =
        sg::view_ray_cuts(r, mu, mu_s, nu, kR, s_end, sg::tangent_radius_sq(r, mu), radii.data(), int(radii.size()));
    const auto ref = cuts_by_definition(r, mu, mu_s, nu, s_end, radii);
    ASSERT_EQ(c.n, int(ref.size())) << "r " << r << " mu " << mu;
    for (int i = 0; i < c.n; ++i) {
      EXPECT_NEAR(c.s[i], ref[i], 1e-9 * kT) << i;  // two ways of solving the same quadratic
      if (i > 0) {
        EXPECT_LE(c.s[i - 1], c.s[i]);  // ascending, no sort needed by the caller
      }
    }
    EXPECT_EQ(c.s[0], 0.0);
    EXPECT_EQ(c.s[c.n - 1], s_end);
    for (int i = 0; i < 2; ++i) {
      const double se = sg::shadow_edge_distance(r, mu, mu_s, nu, kR, i);
      with_shadow += se > 0 && se < s_end;
    }
  }
  EXPECT_GT(with_shadow, 20);  // the shadow edges are exercised
}

TEST(SharedViewRayCuts, FitTheLargestSphereCount) {
  std::vector<double> radii;
  for (int i = 1; i <= sg::kMaxCutSpheres; ++i) radii.push_back(kR + 100e3 * i / (sg::kMaxCutSpheres + 1.0));
  // A ray from the top grazing just above the ground crosses every sphere twice,
  // and meets both shadow edges with the sun behind the planet.
  const double r = kT, mu = sg::mu_horizon(kT, kR) + 1e-6;
  const double s_end = sg::distance_to_top(r, mu, kT);
  const sg::ViewRayCuts c = sg::view_ray_cuts(r, mu, -0.2, -0.5, kR, s_end, sg::tangent_radius_sq(r, mu),
                                              radii.data(), sg::kMaxCutSpheres);
  EXPECT_LE(c.n, sg::kMaxViewCuts);
  EXPECT_GE(c.n, 2 * sg::kMaxCutSpheres + 3);
  for (int i = 1; i < c.n; ++i) EXPECT_LE(c.s[i - 1], c.s[i]);
}

TEST(SharedLutLookup, ShellSearchIsUpperBound) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1000.0);
  for (int n : {1, 2, 4, 5, 32, 33, 100}) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (double& x : v) x = u(rng);
    std::sort(v.begin(), v.end());
    auto at = [&](int i) { return v[static_cast<std::size_t>(i)]; };
    std::vector<double> probes = {-1.0, 1001.0};
    for (int i = 0; i < 50; ++i) probes.push_back(u(rng));
    for (double x : v) probes.push_back(x);
    for (double x : probes) {
      int k;
      ATMOSH_LUT_SHELL_INDEX(k, n, x, at);
      EXPECT_EQ(k, int(std::upper_bound(v.begin(), v.end(), x) - v.begin()) - 1) << n << " " << x;
    }
  }
}

// SortedIndex (the CPU's O(1) shell and profile search) gives the index of
// std::upper_bound - 1 for every probe, on uniform, clustered (geometric, as shells
// near the ground) and tiny tables, at and next to every value, below, above, NaN.
TEST(SortedIndex, IsUpperBoundMinusOne) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1000.0);
  std::vector<std::vector<double>> tables;
  for (int n : {1, 2, 3, 32, 200, 1000}) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (double& x : v) x = u(rng);
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    tables.push_back(v);
  }
  std::vector<double> geo;  // 1e-3 .. 1e3, ratio 1.2: many values in the first bucket
  for (double x = 1e-3; x < 1e3; x *= 1.2) geo.push_back(x);
  tables.push_back(geo);
  tables.push_back({0.0, 1e-12, 1.0});  // two values closer than a bucket's rounding
  for (const auto& v : tables) {
    const atmosh::atmo::SortedIndex idx(v);
    std::vector<double> probes = {-1.0, 1e9, -0.0, std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity()};
    for (int i = 0; i < 2000; ++i) probes.push_back(u(rng));
    for (double x : v)
      for (double p : {x, std::nextafter(x, -1e300), std::nextafter(x, 1e300)}) probes.push_back(p);
    for (double x : probes)
      EXPECT_EQ(idx.find(x), int(std::upper_bound(v.begin(), v.end(), x) - v.begin()) - 1) << v.size() << " " << x;
    EXPECT_EQ(idx.find(std::numeric_limits<double>::quiet_NaN()), -1);
  }
  EXPECT_EQ(atmosh::atmo::SortedIndex().find(1.0), -1);
}

TEST(SharedLutLookup, WindowsContainTheSampleAndWeightsReproduceCubics) {
  for (int n : {4, 5, 16, 64}) {
    for (int t = 0; t <= 1000; ++t) {
      const double x = t / 1000.0;
      const int jw = sg::lut_direction_window(x, n);
      const double p = sg::lut_direction_offset(x, n, jw);
      EXPECT_GE(jw, 0);
      EXPECT_LE(jw + 3, n - 1);
      EXPECT_GE(p, -1e-12);  // x inside the window [x_jw, x_jw+3]
      EXPECT_LE(p, 3.0 + 1e-12);
      EXPECT_NEAR(jw + p, x * (n - 1), 1e-12);
    }
  }
  // Shell windows: inside the table, and the Lagrange weights (with the inverse
  // denominators formed as OpticalDepthLut does) reproduce any cubic exactly.
  const std::vector<double> rho = {0.0, 30e3, 95e3, 180e3, 320e3, 500e3, 1130e3};
  const int S = int(rho.size());
  auto cubic = [](double x) { return 2.0 - 3e-6 * x + 4e-12 * x * x - 1e-18 * x * x * x; };
  for (int k = -1; k < S; ++k) {
    const int w = sg::lut_window_start(k, S);
    EXPECT_GE(w, 0);
    EXPECT_LE(w + 3, S - 1);
    if (k >= 0 && k < S - 1) {
      EXPECT_TRUE(w <= k && k + 1 <= w + 3) << k;  // the interval lies in the window
    }
    const double lo = rho[std::clamp(k, 0, S - 1)], hi = rho[std::clamp(k + 1, 0, S - 1)];
    for (double f : {0.0, 0.3, 0.77, 1.0}) {
      const double x = lo + f * (hi - lo);
      double sum = 0.0, interp = 0.0;
      for (int i = 0; i < 4; ++i) {
        double den = 1.0;
        for (int j = 0; j < 4; ++j)
          if (j != i) den *= rho[w + i] - rho[w + j];
        const double l = sg::lut_shell_weight(x, 1.0 / den, rho[w], rho[w + 1], rho[w + 2], rho[w + 3], i);
        sum += l;
        interp += l * cubic(rho[w + i]);
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      EXPECT_NEAR(interp, cubic(x), 1e-11 * std::abs(cubic(x)) + 1e-12);
    }
  }
}

// The table entry's ray (lut_table_distance, lut_table_mu) against the geometry it
// stands for: the ray of length d from radius r with zenith cosine mu ends on the top
// sphere (toward the top) or the ground sphere (toward the ground), i.e. the shared
// distance functions, solved independently as roots of the sphere quadratic, give d
// back; and lut_x inverts the direction sample.
TEST(SharedLutLookup, TableRaysEndOnTheirSphere) {
  const double R = 6360e3, T = R + 100e3, Hh = std::sqrt((T - R) * (T + R));
  for (double h : {10.0, 1e3, 25e3, 80e3}) {
    const double r = R + h, rho = std::sqrt((r - R) * (r + R));
    for (double x : {0.05, 0.3, 0.5, 0.77, 0.98}) {
      for (bool ground : {false, true}) {
        const double d = sg::lut_table_distance(r, rho, x, R, T, Hh, ground);
        ASSERT_GT(d, 0.0);
        const double mu = sg::lut_table_mu(r, rho, d, T, ground);
        // |P + d v|^2 = r^2 + 2 r mu d + d^2 must be the sphere's radius squared.
        const double k = ground ? R : T;
        EXPECT_NEAR(r * r + 2 * r * mu * d + d * d, k * k, 1e-12 * k * k) << h << " " << x << " " << ground;
        const double dmin = ground ? r - R : T - r, dmax = ground ? rho : rho + Hh;
        EXPECT_NEAR(sg::lut_x(d, dmin, dmax), x, 1e-12);
        if (ground) {
          EXPECT_TRUE(sg::ray_hits_ground(r, mu, R));
          EXPECT_NEAR(sg::distance_to_ground(r, mu, R), d, 1e-6 * d);
        } else if (!sg::ray_hits_ground(r, mu, R)) {
          EXPECT_NEAR(sg::distance_to_top(r, mu, T), d, 1e-6 * d);
        }
      }
    }
  }
}

// The closed-form walk with more nodes than the GLSL build holds (and than the
// CPU's stack scratch) against adaptive quadrature of the same profile.
TEST(SharedLinearColumn, ManyNodesMatchQuadrature) {
  const int n = 40;
  std::vector<double> radius(n), value(n), slope(n, 0.0);
  for (int i = 0; i < n; ++i) {
    radius[i] = kR + 2e3 + 1.5e3 * i + 200.0 * std::sin(i);
    value[i] = (i == 0 || i == n - 1) ? 0.0 : 0.5 + 0.4 * std::cos(0.7 * i);
  }
  for (int i = 0; i + 1 < n; ++i) slope[i] = (value[i + 1] - value[i]) / (radius[i + 1] - radius[i]);
  auto density = [&](double rr) {
    if (rr <= radius[0] || rr >= radius[n - 1]) return 0.0;
    const int i = int(std::upper_bound(radius.begin(), radius.end(), rr) - radius.begin()) - 1;
    return value[i] + (value[i + 1] - value[i]) * (rr - radius[i]) / (radius[i + 1] - radius[i]);
  };
  std::vector<double> q(n);
  for (double h : {0.0, 10e3, 30e3, 80e3})
    for (double mu : {-1.0, -0.3, -0.05, -0.01, 0.0, 0.02, 0.4, 1.0}) {
      const double r = kR + h;
      const double len = sg::ray_hits_ground(r, mu, kR) ? sg::distance_to_ground(r, mu, kR) : sg::distance_to_top(r, mu, kT);
      const double closed = sg::piecewise_linear_column(r, mu, len, radius.data(), value.data(), slope.data(), n, q.data());
      // Breakpoints: every node-sphere crossing and the tangent point.
      std::vector<double> pts;
      const double t = -r * mu, rt2 = sg::tangent_radius_sq(r, mu);
      if (t > 0 && t < len) pts.push_back(t);
      for (double k : radius)
        if (k * k >= rt2)
          for (double s : {t - std::sqrt(k * k - rt2), t + std::sqrt(k * k - rt2)})
            if (s > 0 && s < len) pts.push_back(s);
      auto f = [&](double s) { return density(sg::radius_along(r, mu, s)); };
      const auto ref = atmosh::atmo::integrate_adaptive<double>(f, 0.0, len, pts, 1e-9, 1e-12, 20000);
      EXPECT_NEAR(closed, ref.value, 1e-9 * std::max(1.0, std::abs(ref.value))) << "h " << h << " mu " << mu;
    }
}

namespace {
// The table build's traversal (ATMOSH_LUT_RAY_PIECES): the pieces tile [0, L] in
// order, and their inner ends are exactly the crossings of the radii and the tangent
// point inside (0, L), solved here as a quadratic per sphere and sorted.
TEST(SharedTraversal, TableRayPiecesTileTheRayAtEveryCrossing) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> radii;
  for (int i = 0; i <= 40; ++i) radii.push_back(kR + 100e3 * std::pow(i / 40.0, 2));
  for (int trial = 0; trial < 2000; ++trial) {
    const double r = kR + 100e3 * U(rng);
    const double mu = trial % 10 == 0 ? -std::sqrt(1 - std::pow(kR / r, 2)) * (1 + 1e-12) : 2 * U(rng) - 1;
    const double L = 2e6 * U(rng);
    std::vector<double> expect;
    for (double k : radii) {
      const double b = r * mu, cc = (r - k) * (r + k), disc = b * b - cc;
      if (disc < 0) continue;
      for (double s : {-b - std::sqrt(disc), -b + std::sqrt(disc)})
        if (s > 0 && s < L) expect.push_back(s);
    }
    if (-r * mu > 0 && -r * mu < L) expect.push_back(-r * mu);
    std::sort(expect.begin(), expect.end());
    expect.erase(std::unique(expect.begin(), expect.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }),
                 expect.end());
    std::vector<std::pair<double, double>> pieces;
    auto radius_at = [&](int i) { return radii[static_cast<std::size_t>(i)]; };
    auto piece = [&](double a, double b) { pieces.emplace_back(a, b); };
    const int N = static_cast<int>(radii.size());
    ATMOSH_LUT_RAY_PIECES(double, r, mu, L, N, radius_at, piece);
    ASSERT_FALSE(pieces.empty());
    EXPECT_EQ(pieces.front().first, 0.0);
    EXPECT_EQ(pieces.back().second, L);
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      ASSERT_LT(pieces[i].first, pieces[i].second);
      if (i > 0) {
        ASSERT_EQ(pieces[i].first, pieces[i - 1].second);
      }
    }
    ASSERT_EQ(pieces.size(), expect.size() + 1) << "trial " << trial;
    for (std::size_t i = 0; i < expect.size(); ++i)
      EXPECT_NEAR(pieces[i].second, expect[i], 1e-6 * std::max(1.0, expect[i])) << "trial " << trial;
  }
}

TEST(SharedTraversal, PieceCountSpansAtMostOneAndAHalfScaleHeights) {
  // Radial pieces (rt2 = 0, no curvature): the altitude bound alone.
  EXPECT_EQ(sg::lut_piece_count(kR, kR + 12000.0, 12000.0, 0.0, 8000.0), 1);  // exactly 1.5 H
  EXPECT_EQ(sg::lut_piece_count(kR, kR + 12001.0, 12001.0, 0.0, 8000.0), 2);
  EXPECT_EQ(sg::lut_piece_count(kR + 5e4, kR, 5e4, 0.0, 1200.0), 28);  // ceil(50000 / 1800)
  EXPECT_EQ(sg::lut_piece_count(kR, kR + 1e6, 1e6, 0.0, 100.0), 64);   // capped
  EXPECT_EQ(sg::lut_piece_count(kR, kR + 1e6, 1e6, 0.0, 0.0), 1);      // no exponential matters
  EXPECT_EQ(sg::lut_piece_count(kR, kR + 1e6, 1e6, 0.0, std::numeric_limits<double>::infinity()), 1);
  EXPECT_EQ(sg::lut_piece_count(kR, kR, 0.0, 0.0, 8000.0), 1);
}

// A piece that starts at the tangent point: the altitude along it is ~s^2 / (2 r_t),
// so exp(-h/H) is a Gaussian in s of width sqrt(r_t H). The curvature bound splits
// it into pieces of at most sqrt(r_t H); the composite 4-point Gauss-Legendre
// rule then matches the Gaussian's closed form (erf) to 1e-8 relative, where one
// piece spanning 1.5 H in altitude (the altitude bound alone) is off by ~4e-6.
TEST(SharedTraversal, PieceCountResolvesTheTangentPoint) {
  const double H = 1200.0, rt = kR + 5000.0;
  const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  auto composite = [&](double len, int m) {
    double sum = 0.0;
    for (int p = 0; p < m; ++p)
      for (int g = 0; g < 4; ++g) {
        const double s = len * (p + 0.5 * (1.0 + x[g])) / m;
        sum += 0.5 * w[g] * (len / m) * std::exp(-s * s / (2.0 * rt * H));
      }
    return sum;
  };
  for (double span : {0.1, 0.5, 1.0, 1.5, 3.0, 10.0}) {  // altitude span in scale heights
    const double len = std::sqrt(2.0 * rt * span * H);
    const double exact = std::sqrt(M_PI * rt * H / 2.0) * std::erf(len / std::sqrt(2.0 * rt * H));
    const int m = sg::lut_piece_count(rt, std::sqrt(rt * rt + len * len), len, rt * rt, H);
    EXPECT_GE(m, static_cast<int>(std::ceil(len / std::sqrt(rt * H)))) << span;
    EXPECT_LT(std::abs(composite(len, m) - exact) / exact, 1e-8) << span << " " << m;
  }
  const double len = std::sqrt(2.0 * rt * 1.5 * H);
  const double exact = std::sqrt(M_PI * rt * H / 2.0) * std::erf(len / std::sqrt(2.0 * rt * H));
  EXPECT_GT(std::abs(composite(len, 1) - exact) / exact, 1e-6);  // the altitude bound alone
}}  // namespace

namespace {
// The single-scattering pieces (shared/scatter.glsl.hpp): the densest point is the
// point nearest the planet's centre, the split keeps each part at most max_tau,
// and the node loop is a composite Gauss-Legendre rule — exact for polynomials of
// degree 2n - 1 on every part (closed-form integrals).
TEST(SharedScatter, DensestPointSplitAndNodes) {
  const double r = kR + 1000.0;
  for (double mu : {-0.3, -0.01, 0.0, 0.2, 1.0}) {
    const double st = -r * mu;
    for (auto [a, b] : {std::pair{0.0, 1e4}, std::pair{5e4, 3e5}, std::pair{1e3, 2e3}}) {
      const double s = sg::piece_densest_point(r, mu, st, a, b);
      // Brute force: the radius along the ray is smallest there.
      double best = a, rbest = sg::radius_along(r, mu, a);
      for (int i = 1; i <= 20000; ++i) {
        const double si = a + (b - a) * i / 20000.0, ri = sg::radius_along(r, mu, si);
        if (ri < rbest) best = si, rbest = ri;
      }
      EXPECT_NEAR(sg::radius_along(r, mu, s), rbest, 1e-6 * r) << mu << " " << a << " " << b << " " << best;
    }
  }
  EXPECT_EQ(sg::piece_parts(0.0, 0.1), 1);
  EXPECT_EQ(sg::piece_parts(0.25, 0.1), 3);
  EXPECT_EQ(sg::piece_parts(0.3, 0.1), 3);
  EXPECT_EQ(sg::piece_parts(1e9, 0.1), 64);
  // 4 parts of [2, 7] with the 3-point rule on each: x^5 exactly; sum of weights = length.
  const double x3[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  double integral = 0, weights = 0, last = -1, last_b = 2.0;
  int count = 0;
  auto part = [&](double a, double b) {
    EXPECT_EQ(a, last_b);  // contiguous
    last_b = b;
    for (int q = 0; q < 3; ++q) {
      const double s = 0.5 * (a + b) + 0.5 * (b - a) * x3[q], w = 0.5 * (b - a) * w3[q];
      integral += w * std::pow(s, 5);
      weights += w;
      EXPECT_GT(s, last);  // in order along the ray
      last = s;
      ++count;
    }
  };
  const int parts = 4;
  for (int p = 0; p < parts; ++p) part(sg::sky_part_end(2.0, 7.0, p, parts), sg::sky_part_end(2.0, 7.0, p + 1, parts));
  EXPECT_EQ(last_b, 7.0);  // the last part ends exactly at the piece's end
  EXPECT_EQ(count, 12);
  EXPECT_NEAR(weights, 5.0, 1e-14);
  EXPECT_NEAR(integral, (std::pow(7.0, 6) - std::pow(2.0, 6)) / 6, 1e-12 * std::pow(7.0, 6));
  EXPECT_DOUBLE_EQ(sg::scattering_term(0.5, 2.0, 3.0, 5.0, 7.0), 0.5 * (2 * 5 + 3 * 7));
  EXPECT_DOUBLE_EQ(sg::column_optical_depth(1, 2, 3, 4, 5, 6), 32.0);
  EXPECT_NEAR(sg::ground_term(0.3, 0.5, 0.8), 0.3 / M_PI * 0.5 * 0.8, 1e-16);
}
}  // namespace

namespace {
// atmosh/atmo/fast_exp.hpp against libm's exp in double: the largest relative error
// of f over 1e6 random arguments in [lo, hi] (half of them in [lo2, 2]) and the given
// edge points.
template <class F, class Fn>
double max_rel_error_vs_libm(Fn f, F lo, F hi, F lo2, std::initializer_list<F> edges, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<F> U(lo, hi), V(lo2, F(2));
  double worst = 0;
  auto check = [&](F x) {
    const double e = std::exp(-double(x));
    worst = std::max(worst, std::abs(double(f(x)) - e) / e);
  };
  for (int i = 0; i < 1000000; ++i) check(i % 2 ? U(rng) : V(rng));
  for (F x : edges) check(x);
  return worst;
}

// The headers' stated bounds: double within 4 ulp over [-700, 700].
TEST(FastExp, ExpNegMatchesLibmToFourUlpRelative) {
  const double worst = max_rel_error_vs_libm<double>([](double x) { return atmosh::atmo::exp_neg(x); }, -700.0,
                                                     700.0, -2.0, {0.0, 1e-300, -1e-300, 0.5 * std::log(2.0),
                                                                   699.999, -699.999, -700.0}, 3);
  EXPECT_LT(worst, 4e-16);
  EXPECT_EQ(atmosh::atmo::exp_neg(0.0), 1.0);
  EXPECT_EQ(atmosh::atmo::exp_neg(700.0), 0.0);
  EXPECT_EQ(atmosh::atmo::exp_neg(1e300), 0.0);
  EXPECT_EQ(atmosh::atmo::exp_neg(std::numeric_limits<double>::infinity()), 0.0);
}

// Single precision: about 2 float ulp over [0, 87].
TEST(FastExp, ExpNegFloatMatchesLibmToAFewFloatUlp) {
  const double worst = max_rel_error_vs_libm<float>([](float x) { return atmosh::atmo::exp_neg_f(x); }, 0.0f, 87.0f,
                                                    0.0f, {0.0f, 1e-30f, 0.34657359f, 86.999f}, 5);
  std::printf("  exp_neg_f: max rel error %.3g\n", worst);
  EXPECT_LT(worst, 2e-7);
  EXPECT_EQ(atmosh::atmo::exp_neg_f(0.0f), 1.0f);
  EXPECT_EQ(atmosh::atmo::exp_neg_f(87.0f), 0.0f);
  EXPECT_EQ(atmosh::atmo::exp_neg_f(1e30f), 0.0f);
  EXPECT_EQ(atmosh::atmo::exp_neg_f(std::numeric_limits<float>::infinity()), 0.0f);
}
}  // namespace

// The GPU's log1p (shared log1p_series, the atanh series on [-0.5, 1]) in the C++
// double build against the C library's log1p: a few ulp, also for tiny |x| where
// log(1 + x) would lose everything, and at the ends of the series' range.
TEST(SharedLog1p, SeriesMatchesLibmLog1p) {
  std::vector<double> xs = {-0.5, -0.49999999, 0.99999999, 1.0, 1.00000001, 3.0, 1e6, -0.9, -0.5000001};
  for (double a = 1e-300; a < 1.0; a *= 3.7) {
    xs.push_back(a);
    xs.push_back(-a);
  }
  double worst = 0.0;
  for (double x : xs) {
    if (!(x > -1.0)) continue;
    const double ref = std::log1p(x), got = sg::log1p_series(x);
    const double ulp = std::abs(std::nextafter(ref, 2 * ref) - ref);
    const double err = std::abs(got - ref) / ulp;
    worst = std::max(worst, err);
    EXPECT_LE(err, 4.0) << "x = " << x << ": " << got << " vs " << ref;
  }
  std::printf("log1p_series: worst %.2f ulp over %zu arguments\n", worst, xs.size());
}
