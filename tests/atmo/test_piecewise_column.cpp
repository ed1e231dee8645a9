// Closed-form column of piecewise-linear density profiles (tent, tabulated)
// against high-precision adaptive quadrature, and the optical-depth LUT that
// uses it for the ozone layer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "integrate.hpp"  // private (libatmo/src)
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;
namespace sg = atmosh::atmo::shared;

namespace {
constexpr double kR = 6360e3;
constexpr double kTop = 60e3;

DensityProfile tent() { return DensityProfile(DensityProfileSpec::tent(10e3, 25e3, 40e3)); }

// Tabulated profiles: one starting at the ground with a non-zero value, one
// with compact support inside the atmosphere (0 outside its nodes).
DensityProfile tabulated_from_ground() {
  DensityProfileSpec s;
  s.kind = DensityProfileSpec::Kind::Tabulated;
  s.altitude_m = {0.0, 5e3, 12e3, 20e3, 33e3, 47e3, 60e3};
  s.value = {1.0, 0.6, 0.8, 0.3, 0.35, 0.05, 0.0};
  return DensityProfile(s);
}
DensityProfile tabulated_layer() {
  DensityProfileSpec s;
  s.kind = DensityProfileSpec::Kind::Tabulated;
  s.altitude_m = {8e3, 15e3, 22e3, 22.5e3, 30e3, 38e3};
  s.value = {0.0, 0.9, 1.0, 0.7, 0.2, 0.0};
  return DensityProfile(s);
}

// Independent reference: globally adaptive G7-K15 over s of the profile at the
// altitude r(s) - R (r(s) = sqrt((s + r mu)^2 + r_t^2)), split at the tangent
// point and at every node crossing, relative tolerance 1e-14 (absolute 1e-10 m).
// Also returns the length of the ray between the lowest and highest node.
struct QuadColumn {
  double value, length_in_layer;
};
QuadColumn quadrature_column(const DensityProfile& p, double r, double mu, double L) {
  std::vector<double> pts;
  double rt = std::sqrt(sg::tangent_radius_sq(r, mu));
  if (-r * mu > 0.0 && -r * mu < L) pts.push_back(-r * mu);
  for (double h : p.kinks()) {
    double k = kR + h;
    if (k < rt) continue;
    double q = std::sqrt((k - rt) * (k + rt));
    for (double s : {-r * mu - q, -r * mu + q})
      if (s > 0.0 && s < L) pts.push_back(s);
  }
  auto f = [&](double s) { return p(sg::radius_along(r, mu, s) - kR); };
  auto q = integrate_adaptive<double>(f, 0.0, L, pts, 1e-10, 1e-14, 4000);
  // Rounding noise keeps some rays from meeting 1e-14 on every piece; the
  // estimated error must still be far below the 1e-12 being tested.
  EXPECT_LT(q.error, 1e-13 * std::abs(q.value) + 1e-10) << "r-R=" << r - kR << " mu=" << mu << " L=" << L;
  pts.push_back(0.0);
  pts.push_back(L);
  std::sort(pts.begin(), pts.end());
  double inside = 0.0;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    double h = sg::radius_along(r, mu, 0.5 * (pts[i - 1] + pts[i])) - kR;
    if (h > p.kinks().front() && h < p.kinks().back()) inside += pts[i] - pts[i - 1];
  }
  return {q.value, inside};
}

// Length of the ray inside [R, R + top]: to the ground when it hits it.
double ray_length(double r, double mu) {
  return sg::ray_hits_ground(r, mu, kR) ? sg::distance_to_ground(r, mu, kR) : sg::distance_to_top(r, mu, kR + kTop);
}

// Tolerance: 1e-12 relative, plus the rounding both methods share: the density
// is a function of the altitude r - R, rounded to ~1e-16 R; with the profile's
// largest slope this is an absolute error <= 4e-16 R |slope|max times the
// length of the ray inside the layer (see PiecewiseLinearColumn). It matters
// only for rays that barely enter a piece (tangent point within ~1 km of a node):
// there the problem itself has condition number ~R / (distance to the node).
double tolerance(const DensityProfile& p, const QuadColumn& q) {
  double smax = 0.0;
  const auto& sp = p.spec();
  if (p.kind() == DensityProfileSpec::Kind::Tent) {
    smax = 1.0 / std::min(sp.peak_m - sp.bottom_m, sp.top_m - sp.peak_m);
  } else {
    for (std::size_t i = 1; i < sp.altitude_m.size(); ++i)
      smax = std::max(smax, std::abs(sp.value[i] - sp.value[i - 1]) / (sp.altitude_m[i] - sp.altitude_m[i - 1]));
  }
  return 1e-12 * std::abs(q.value) + 4e-16 * kR * smax * q.length_in_layer;
}

// Directions of the test rays from radius r: vertical, slanted, horizontal,
// downward, and rays whose tangent point lies just above / below every node and
// the ground (offsets 1 km down to 1 cm).
std::vector<double> test_mus(const DensityProfile& p, double r) {
  std::vector<double> mus = {1.0, 0.7, 0.2, 0.01, 1e-6, 0.0, -1e-6, -0.01, -0.2, -0.7, -1.0};
  std::vector<double> levels = p.kinks();
  levels.push_back(0.0);
  for (double h : levels)
    for (double d : {1e3, 10.0, 0.01, -0.01, -10.0, -1e3}) {
      double rt = kR + h + d;
      if (rt < kR || rt >= r) continue;
      double mu = -std::sqrt((r - rt) * (r + rt)) / r;  // tangent radius rt, looking down
      mus.push_back(mu);
    }
  return mus;
}

void check_profile(const DensityProfile& p, const char* name) {
  PiecewiseLinearColumn col(p, kR);
  int checked = 0;
  double worst = 0.0;
  for (double h : {0.0, 3e3, 10e3, 17e3, 25e3, 35e3, 40e3, 45e3, 59.999e3, 60e3, 500e3}) {
    double r = kR + h;
    for (double mu : test_mus(p, r)) {
      double L = ray_length(r, mu);
      if (h > kTop && !sg::ray_hits_ground(r, mu, kR)) L = 3e6;  // from outside: through the whole shell
      for (double frac : {1.0, 0.37}) {  // to the end and a partial ray
        double Lf = frac * L;
        double a = col(r, mu, Lf);
        auto b = quadrature_column(p, r, mu, Lf);
        ASSERT_TRUE(std::isfinite(a)) << name << " h=" << h << " mu=" << mu;
        EXPECT_NEAR(a, b.value, tolerance(p, b)) << name << " h=" << h << " mu=" << mu << " L=" << Lf;
        if (b.value > 0.0) worst = std::max(worst, std::abs(a - b.value) / b.value);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 200);
  ::testing::Test::RecordProperty(std::string(name) + "_worst_rel", std::to_string(worst));
}
}  // namespace

TEST(PiecewiseLinearColumn, TentMatchesQuadrature) { check_profile(tent(), "tent"); }
TEST(PiecewiseLinearColumn, TabulatedFromGroundMatchesQuadrature) { check_profile(tabulated_from_ground(), "ground"); }
TEST(PiecewiseLinearColumn, TabulatedLayerMatchesQuadrature) { check_profile(tabulated_layer(), "layer"); }

// Vertical column of the tent: area of the triangle, (40 - 10) km * 1 / 2 = 15 km;
// a vertical ray from the peak up sees half of it, 7.5 km; straight down from
// the top to the ground the same 15 km.
TEST(PiecewiseLinearColumn, VerticalTentIsTheTriangleArea) {
  PiecewiseLinearColumn col(tent(), kR);
  EXPECT_NEAR(col(kR, 1.0, kTop), 15e3, 1e-12 * 15e3);
  EXPECT_NEAR(col(kR + 25e3, 1.0, kTop), 7.5e3, 1e-12 * 7.5e3);
  EXPECT_NEAR(col(kR + kTop, -1.0, kTop), 15e3, 1e-12 * 15e3);
  // Halfway up the rising side: from 17.5 km to the top, 15 km - (7.5 km * 0.5 / 2).
  EXPECT_NEAR(col(kR + 17.5e3, 1.0, 1e6), 15e3 - 1875.0, 1e-12 * 15e3);
}

// Horizontal ray tangent at the peak of the tent: with x the distance from the
// tangent point, h(x) = 25 km + (sqrt(R_p^2 + x^2) - R_p) and the column is
// 2 int_0^X (1 - (r(x) - R_p)/15 km) dx where r(X) = R + 40 km. Closed form of
// int sqrt(x^2 + c^2) dx (Abramowitz & Stegun 3.3.43 / Gradshteyn 2.271.3):
// [x sqrt(x^2+c^2) + c^2 asinh(x/c)] / 2, evaluated here in long double.
TEST(PiecewiseLinearColumn, HorizontalThroughThePeakMatchesLongDoubleClosedForm) {
  PiecewiseLinearColumn col(tent(), kR);
  long double c = kR + 25e3L, rt = kR + 40e3L, H = 15e3L;
  long double X = std::sqrt((rt - c) * (rt + c));
  long double I = 0.5L * (X * std::sqrt(X * X + c * c) + c * c * std::asinh(X / c));
  long double expect = 2.0L * (X - (I - c * X) / H);
  double r = kR + 25e3;
  // From the tangent point outward (mu = 0) and from the far side through it.
  EXPECT_NEAR(col(r, 0.0, 1e6), static_cast<double>(expect / 2), 1e-12 * static_cast<double>(expect));
  double r_top = kR + 40e3, mu_in = -static_cast<double>(X / (kR + 40e3L));
  EXPECT_NEAR(col(r_top, mu_in, 2.0 * static_cast<double>(X)), static_cast<double>(expect),
              2e-12 * static_cast<double>(expect));
}

// Degenerate geometry: tangent radius exactly a node radius (horizontal ray from
// a node), origin on a node, mu = +-1; never NaN, and the values agree with the
// quadrature.
TEST(PiecewiseLinearColumn, DegenerateRaysAreFinite) {
  for (const auto& p : {tent(), tabulated_from_ground(), tabulated_layer()}) {
    PiecewiseLinearColumn col(p, kR);
    for (double h : p.kinks()) {
      double r = kR + h;
      for (double mu : {0.0, 1.0, -1.0, 0.5, -0.5, 1e-12, -1e-12}) {
        if (r > kR + kTop) continue;
        double L = ray_length(r, mu);
        double a = col(r, mu, L);
        ASSERT_TRUE(std::isfinite(a)) << h << " " << mu;
        auto b = quadrature_column(p, r, mu, L);
        EXPECT_NEAR(a, b.value, tolerance(p, b)) << h << " " << mu;
      }
    }
    EXPECT_EQ(col(kR, 1.0, 0.0), 0.0);
    EXPECT_EQ(col(kR, 1.0, -1.0), 0.0);
    // Rays grazing the outermost node (the tent's top) from just above it: the
    // column is ~0 and, like the density, never negative (rounding left -1e-15).
    const double rk = kR + p.kinks().back();
    for (double d : {4e-5, 1e-3, 1.0})
      for (double mu : {-3.5355483665402835e-06, -1e-7, 0.0}) {
        const double r = rk + d;
        if (r > kR + kTop) continue;
        EXPECT_GE(col(r, mu, ray_length(r, mu)), 0.0) << d << " " << mu;
      }
  }
  EXPECT_THROW(PiecewiseLinearColumn(DensityProfile(DensityProfileSpec::exponential(8000.0)), kR),
               atmosh::InputError);
}

namespace {
// Ray set of `atmosh converge lut`: altitudes from the ground to just below the
// top, uniform mu plus grazing rays either side of the horizon and of mu = 0,
// and rays with tangent points 1 mm..1 km above the ground; here also rays
// tangent just above / below each ozone node.
struct Ray {
  double r, mu;
};
std::vector<Ray> lut_rays(const Atmosphere& atm) {
  const double R = atm.ground_radius(), top = atm.top_altitude();
  std::vector<Ray> rays;
  std::vector<double> hs = {0.0, 1.0, 10.0, 100.0, 500.0, 1000.0, 2000.0, 5000.0, 10e3, 20e3, 25e3, 35e3, 40e3};
  for (double f : {0.5, 0.8, 0.99, 0.99999}) hs.push_back(f * top);
  for (double h : hs) {
    double r = R + h, muh = sg::mu_horizon(r, R);
    std::vector<double> mus;
    for (int i = 0; i <= 40; ++i) mus.push_back(-1.0 + 2.0 * i / 40.0);
    for (double e : {1e-9, 1e-7, 1e-5, 1e-3, 1e-2, 3e-2}) mus.insert(mus.end(), {muh + e, muh - e, e, -e});
    for (double th : {1e-3, 1.0, 100.0, 1000.0, 10e3 - 1.0, 10e3 + 1.0, 25e3 - 1.0, 25e3 + 1.0, 40e3 - 1.0, 40e3 + 1.0})
      if (r > R + th) mus.push_back(-std::sqrt(1.0 - std::pow((R + th) / r, 2.0)));
    for (double mu : mus)
      if (mu >= -1.0 && mu <= 1.0) rays.push_back({r, mu});
  }
  return rays;
}

double lut_max_error(const Atmosphere& atm, const OpticalDepthLut& lut, bool sun) {
  OpticalDepthReference ref(atm);
  auto k = atm.coefficients_at(550.0);
  double worst = 0.0;
  for (const auto& ray : lut_rays(atm)) {
    auto a = ref.column(ray.r, ray.mu);
    auto b = sun ? lut.sun(ray.r, ray.mu) : lut.view(ray.r, ray.mu);
    EXPECT_EQ(a.hits_ground, b.hits_ground) << ray.r << " " << ray.mu;
    double tb = optical_depth(k, b.column);
    EXPECT_TRUE(std::isfinite(tb));
    if (sun && a.hits_ground) {
      EXPECT_EQ(tb, 0.0);  // blocked
      continue;
    }
    double ta = optical_depth(k, a.column);
    if (ta > 0.0) worst = std::max(worst, std::abs(tb - ta) / ta);
  }
  return worst;
}
}  // namespace

// Default LUT (32 shells x 64 directions) on earth-graphics with the ozone tent:
// max relative error of the total optical depth at 550 nm <= 1e-4 on every ray
// of the study set (the tables hold Rayleigh and Mie; ozone is in closed form).
TEST(OpticalDepthLutPiecewise, EarthGraphicsWithOzoneWithin1e4) {
  Atmosphere atm(preset("earth-graphics"));
  ASSERT_TRUE(atm.has(kOzone));
  OpticalDepthLut lut(atm);
  EXPECT_LT(lut_max_error(atm, lut, false), 1e-4);
  EXPECT_LT(lut_max_error(atm, lut, true), 1e-4);
}

// The built-in default scene's atmosphere: earth-graphics with the top at 100 km
// instead of 60 km (exponential Rayleigh and Mie, ozone tent). Above a few scale
// heights the column fractions that place the shells saturate; the default tables
// must still meet 1e-4 on every ray up to just below the top (with shells placed by
// column fraction and rho alone the worst, upward rays from 50 km, had 2.0e-4).
TEST(OpticalDepthLutPiecewise, HundredKilometreAtmosphereWithin1e4) {
  auto spec = preset("earth-graphics");
  spec.planet.atmosphere_top_m = 100e3;
  Atmosphere atm(spec);
  OpticalDepthLut lut(atm);
  EXPECT_LT(lut_max_error(atm, lut, false), 1e-4);
  EXPECT_LT(lut_max_error(atm, lut, true), 1e-4);
}

// A tabulated ozone profile with few nodes is also computed in closed form: the
// ozone column of the LUT equals the reference to quadrature accuracy.
TEST(OpticalDepthLutPiecewise, TabulatedOzoneColumnIsExact) {
  auto spec = preset("earth-graphics");
  spec.ozone->profile = tabulated_layer().spec();
  Atmosphere atm(spec);
  OpticalDepthLut lut(atm);
  OpticalDepthReference ref(atm);
  const double R = atm.ground_radius();
  for (double h : {0.0, 8e3, 22.5e3, 50e3})
    for (double mu : {1.0, 0.3, 0.0, -0.05, -0.1, -1.0}) {
      auto a = ref.column(R + h, mu);
      auto b = lut.view(R + h, mu);
      ASSERT_EQ(a.hits_ground, b.hits_ground);
      EXPECT_NEAR(b.column[kOzone], a.column[kOzone], 1e-11 * atm.vertical_column()[kOzone] + 1e-11 * a.column[kOzone])
          << h << " " << mu;
    }
  EXPECT_LT(lut_max_error(atm, lut, false), 1e-4);
}

// Rays at the degenerate points of the ozone layer through the LUT: origin on a
// node, tangent exactly on a node, mu = +-1: finite, and the sun table still
// reports rays into the ground as blocked with zero column.
TEST(OpticalDepthLutPiecewise, DegenerateRaysFiniteAndSunBlocked) {
  Atmosphere atm(preset("earth-graphics"));
  OpticalDepthLut lut(atm);
  const double R = atm.ground_radius();
  for (double h : {0.0, 10e3, 25e3, 40e3, 60e3})
    for (double mu : {1.0, 0.0, -1.0, 1e-12, -1e-12}) {
      auto v = lut.view(R + h, mu), s = lut.sun(R + h, mu);
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(v.column[c]) && v.column[c] >= 0.0) << h << " " << mu;
        EXPECT_TRUE(std::isfinite(s.column[c]) && s.column[c] >= 0.0) << h << " " << mu;
      }
      if (s.hits_ground) {
        EXPECT_EQ(s.column, glm::dvec3(0.0));
      }
    }
  auto blocked = lut.sun(R + 30e3, -0.5);
  EXPECT_TRUE(blocked.hits_ground);
  EXPECT_EQ(blocked.column[kOzone], 0.0);
  // A view ray into the ground ends there: ozone column of that segment only.
  OpticalDepthReference ref(atm);
  auto a = ref.column(R + 30e3, -0.5);
  auto b = lut.view(R + 30e3, -0.5);
  EXPECT_TRUE(b.hits_ground);
  EXPECT_NEAR(b.column[kOzone], a.column[kOzone], 1e-11 * a.column[kOzone]);
  LutOptions o;
  o.analytic_max_nodes = -1;
  EXPECT_THROW(OpticalDepthLut(atm, o), atmosh::InputError);
}
