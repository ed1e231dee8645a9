// Phase functions: normalisation, mean cosine, sampling, moments, delta-M.
#include <gtest/gtest.h>

#include <cmath>

#include "integrate.hpp"  // private (libatmo/src)
#include "atmosh/atmo/phase.hpp"
#include "atmosh/error.hpp"

using namespace atmosh::atmo;

namespace {
constexpr double kPi = 3.14159265358979323846;

PhaseSpec make(PhaseSpec::Model m, double g, double g2 = -0.3, double w = 0.9) {
  PhaseSpec s;
  s.model = m;
  s.g = g;
  s.g2 = g2;
  s.weight = w;
  return s;
}

// 2 pi int f(mu) dmu by adaptive Gauss-Kronrod in theta, with breakpoints that
// resolve forward/backward peaks of width ~ (1 - |g|).
double sphere_integral(const std::function<double(double)>& f, std::vector<double> pts = {}) {
  for (double t = 1e-6; t < 1.0; t *= 2.0) {
    pts.push_back(t);
    pts.push_back(kPi - t);
  }
  auto r = integrate_adaptive<double>([&](double th) { return f(std::cos(th)) * std::sin(th); }, 0.0, kPi, pts,
                                      1e-300, 1e-13, 20000);
  return 2.0 * kPi * r.value;
}

std::vector<PhaseSpec> all_models() {
  std::vector<PhaseSpec> v;
  auto ray = make(PhaseSpec::Model::Rayleigh, 0.0);
  ray.depolarization = 0.0279;
  v.push_back(ray);
  for (double g : {0.0, 0.5, 0.9, 0.999, -0.999, -0.7}) {
    v.push_back(make(PhaseSpec::Model::HenyeyGreenstein, g));
    v.push_back(make(PhaseSpec::Model::CornetteShanks, g));
  }
  v.push_back(make(PhaseSpec::Model::DoubleHenyeyGreenstein, 0.9, -0.4, 0.8));
  v.push_back(make(PhaseSpec::Model::DoubleHenyeyGreenstein, 0.999, -0.999, 0.5));
  PhaseSpec t;
  t.model = PhaseSpec::Model::Tabulated;
  t.cos_theta = {-1.0, 0.0, 0.5, 1.0};
  t.value = {1.0, 2.0, 5.0, 20.0};
  v.push_back(t);
  return v;
}
}  // namespace

// Every model integrates to 1 over the sphere (to 1e-10), and its mean cosine
// equals the quadrature of mu p.
TEST(Phase, NormalisedAndMeanCosine) {
  for (const auto& s : all_models()) {
    PhaseFunction p(s);
    std::vector<double> kinks;  // tabulated: split at the nodes (theta = acos(mu_i))
    for (double c : s.cos_theta) kinks.push_back(std::acos(c));
    EXPECT_NEAR(sphere_integral([&](double mu) { return p.value(mu); }, kinks), 1.0, 1e-10)
        << static_cast<int>(s.model) << " g=" << s.g;
    EXPECT_NEAR(sphere_integral([&](double mu) { return mu * p.value(mu); }, kinks), p.mean_cosine(), 1e-10)
        << static_cast<int>(s.model) << " g=" << s.g;
  }
}

// Cornette-Shanks mean cosine closed form 3g(4+g^2)/(5(2+g^2)) differs from g.
TEST(Phase, CornetteShanksGIsNotTheMeanCosine) {
  PhaseFunction p(make(PhaseSpec::Model::CornetteShanks, 0.8));
  EXPECT_NEAR(p.mean_cosine(), 3 * 0.8 * (4 + 0.64) / (5 * 2.64), 1e-15);
  EXPECT_GT(std::abs(p.mean_cosine() - 0.8), 0.01);
  // Forward peak is at cos_theta = +1 for g > 0.
  EXPECT_GT(p.value(1.0), p.value(-1.0));
}

// Sampling: the inverse-CDF map averaged over a fine uniform grid of u gives the
// mean cosine (midpoint rule in u, error ~1e-6 for these smooth maps).
TEST(Phase, SamplingReproducesMeanCosine) {
  for (const auto& s : all_models()) {
    PhaseFunction p(s);
    const int n = 200000;
    double m = 0.0;
    for (int i = 0; i < n; ++i) {
      double mu = p.sample((i + 0.5) / n);
      ASSERT_TRUE(std::isfinite(mu));
      ASSERT_LE(std::abs(mu), 1.0);
      m += mu;
    }
    EXPECT_NEAR(m / n, p.mean_cosine(), 2e-4) << static_cast<int>(s.model) << " g=" << s.g;
  }
}

// HG moments are g^l (closed form); the zonal projection of Cornette-Shanks gives
// chi_0 = 1 and chi_1 = its closed-form mean cosine.
TEST(Phase, LegendreMoments) {
  PhaseFunction hg(make(PhaseSpec::Model::HenyeyGreenstein, 0.7));
  auto m = hg.legendre_moments(8);
  for (int l = 0; l < 8; ++l) EXPECT_NEAR(m.chi[l], std::pow(0.7, l), 1e-14);
  PhaseFunction cs(make(PhaseSpec::Model::CornetteShanks, 0.7));
  auto c = cs.legendre_moments(8);
  EXPECT_NEAR(c.chi[0], 1.0, 1e-12);
  EXPECT_NEAR(c.chi[1], cs.mean_cosine(), 1e-12);
  // Double HG: moments are w g1^l + (1-w) g2^l.
  PhaseFunction d(make(PhaseSpec::Model::DoubleHenyeyGreenstein, 0.8, -0.3, 0.9));
  auto dm = d.legendre_moments(6);
  for (int l = 0; l < 6; ++l) EXPECT_NEAR(dm.chi[l], 0.9 * std::pow(0.8, l) + 0.1 * std::pow(-0.3, l), 1e-10);
}

// Cornette-Shanks is (3 / (2 (2 + g^2))) (1 + mu^2) HG(mu), so its moments follow in
// closed form from the HG moments g^l and the recurrence
// mu^2 P_l = [(l+1)(l+2) P_{l+2} / (2l+3) + ((l+1)^2/(2l+3) + l^2/(2l-1)) P_l
//             + l(l-1) P_{l-2} / (2l-1)] / (2l+1):
// chi_l = 3 / (2 (2 + g^2)) (g^l + m_l), m_l the bracket with P_k -> g^k. Checked for
// the forward- and backward-peaked extremes g = +-0.999 (a peak 5e-7 wide in 1 - mu,
// which a single 4096-point Gauss-Legendre rule missed by 1.8e-3 in chi_0), up to
// l = 255; and double HG, w g1^l + (1 - w) g2^l, with a g = 0.999 lobe. Delta-M of
// such a function keeps chi*_0 = 1.
TEST(Phase, LegendreMomentsOfPeakedFunctionsMatchClosedForms) {
  auto cs_moment = [](double g, int l) {
    auto gp = [g](int k) { return k < 0 ? 0.0 : std::pow(g, k); };
    const double L = l;
    const double m = ((L + 1) * (L + 2) * gp(l + 2) / (2 * L + 3) +
                      ((L + 1) * (L + 1) / (2 * L + 3) + (l > 0 ? L * L / (2 * L - 1) : 0.0)) * gp(l) +
                      (l > 1 ? L * (L - 1) * gp(l - 2) / (2 * L - 1) : 0.0)) /
                     (2 * L + 1);
    return 3.0 / (2.0 * (2.0 + g * g)) * (gp(l) + m);
  };
  const int n = 256;
  for (double g : {0.7, 0.999, -0.999}) {
    const PhaseFunction cs(make(PhaseSpec::Model::CornetteShanks, g));
    const auto m = cs.legendre_moments(n);
    // 1e-10, the normalisation tolerance: at g = 0.999 the nodes within 5e-7 of
    // mu = 1 carry ~2e-10 relative rounding in 1 - mu (ulp(1) / s0), 3e-11 in chi_l.
    for (int l = 0; l < n; ++l) EXPECT_NEAR(m.chi[l], cs_moment(g, l), 1e-10) << "g=" << g << " l=" << l;
    EXPECT_NEAR(m.chi[1], cs.mean_cosine(), 1e-10);
    EXPECT_LT(m.error_estimate, 1e-10);
  }
  const PhaseFunction d(make(PhaseSpec::Model::DoubleHenyeyGreenstein, 0.999, -0.5, 0.9));
  const auto dm = d.legendre_moments(n);
  for (int l = 0; l < n; ++l)
    EXPECT_NEAR(dm.chi[l], 0.9 * std::pow(0.999, l) + 0.1 * std::pow(-0.5, l), 1e-10) << l;
  const PhaseFunction cs(make(PhaseSpec::Model::CornetteShanks, 0.999));
  for (int nt : {16, 32}) {
    const auto t = cs.delta_m(nt);
    // (chi_l - f) / (1 - f) amplifies the moments' errors (~3.4e-11, see above) by up to
    // 2 / (1 - f): 131 at nt = 16 (f = 0.985), 64 at nt = 32, so ~4.5e-9 at most.
    EXPECT_NEAR(t.f, cs_moment(0.999, nt), 1e-10);
    EXPECT_NEAR(t.truncated[0], 1.0, 5e-9);
    EXPECT_NEAR(t.truncated[1], (cs_moment(0.999, 1) - t.f) / (1.0 - t.f), 5e-9);
  }
}

// Cornette-Shanks sampling inverts its CDF to 1e-9 in u (phase.hpp), also for the
// extreme g = +-0.999, whose backward (forward) hemisphere holds only ~1e-4 of the
// probability: the exact CDF by adaptive quadrature in theta (sphere_integral, cut
// at the angle of mu), then |CDF(sample(CDF(mu))) - CDF(mu)|. Before the table had
// nodes uniform in mu, g = 0.999 was off by 1.8e-5 at mu = 0 (14 % of the tail).
TEST(Phase, CornetteShanksSamplingInvertsTheExactCdf) {
  for (double g : {0.999, -0.999, 0.7, 0.0005}) {
    const PhaseFunction p(make(PhaseSpec::Model::CornetteShanks, g));
    auto cdf = [&](double mu) {
      return sphere_integral([&](double m) { return m <= mu ? p.value(m) : 0.0; }, {std::acos(mu)});
    };
    for (double mu : {-0.999999, -0.9, -0.5, 0.0, 0.5, 0.9, 0.999999}) {
      const double u = cdf(mu);
      EXPECT_NEAR(cdf(p.sample(u)), u, 1e-9) << "g=" << g << " mu=" << mu;
    }
  }
}

// A tabulated phase function is piecewise linear in mu: its Legendre moments, by the
// composite rule over its nodes, against adaptive Gauss-Kronrod in mu split at the
// same nodes (tolerance 1e-14) — the kinks at the nodes are what a single rule missed —
// and exactly 0 beyond l = 1 for a table that is linear in mu.
TEST(Phase, TabulatedLegendreMomentsResolveTheKinks) {
  PhaseSpec t;
  t.model = PhaseSpec::Model::Tabulated;
  t.cos_theta = {-1.0, -0.2, 0.5, 0.9, 0.99, 1.0};
  t.value = {0.1, 0.3, 1.0, 4.0, 20.0, 35.0};
  const PhaseFunction p(t);
  const int n = 40;
  const auto m = p.legendre_moments(n);
  for (int l = 0; l < n; ++l) {
    auto r = integrate_adaptive<double>(
        [&](double mu) { return 2.0 * kPi * p.value(mu) * std::legendre(static_cast<unsigned>(l), mu); }, -1.0, 1.0,
        {-0.2, 0.5, 0.9, 0.99}, 1e-300, 1e-14, 20000);
    EXPECT_NEAR(m.chi[l], r.value, 1e-13) << l;
  }
  EXPECT_NEAR(m.chi[0], 1.0, 1e-14);
  EXPECT_NEAR(m.chi[1], p.mean_cosine(), 1e-14);
  t.cos_theta = {-1.0, 0.3, 1.0};
  t.value = {0.5, 1.15, 1.5};  // 1 + 0.5 mu at the nodes: linear
  const auto ml = PhaseFunction(t).legendre_moments(8);
  EXPECT_NEAR(ml.chi[1], 1.0 / 6.0, 1e-14);  // 2 pi int (1 + mu/2) mu dmu / (4 pi)
  for (int l = 2; l < 8; ++l) EXPECT_NEAR(ml.chi[l], 0.0, 1e-14) << l;
}

// Delta-M for HG: f = g^n and truncated moments (g^l - g^n)/(1 - g^n).
TEST(Phase, DeltaM) {
  PhaseFunction hg(make(PhaseSpec::Model::HenyeyGreenstein, 0.999));
  auto d = hg.delta_m(16);
  EXPECT_NEAR(d.f, std::pow(0.999, 16), 1e-14);
  EXPECT_NEAR(d.truncated[0], 1.0, 1e-12);
  EXPECT_NEAR(d.truncated[1], (0.999 - d.f) / (1.0 - d.f), 1e-12);
  // Backward-peaked functions are not truncated (chi_n alternates in sign).
  EXPECT_THROW(PhaseFunction(make(PhaseSpec::Model::CornetteShanks, -0.999)).delta_m(32), atmosh::InputError);
  EXPECT_THROW(PhaseFunction(make(PhaseSpec::Model::HenyeyGreenstein, -0.5)).delta_m(4), atmosh::InputError);
}

TEST(Phase, ExtremeGStaysFinite) {
  for (double g : {0.999, -0.999}) {
    PhaseFunction p(make(PhaseSpec::Model::HenyeyGreenstein, g));
    for (double mu : {-1.0, -0.5, 0.0, 0.999999, 1.0}) EXPECT_TRUE(std::isfinite(p.value(mu)));
    // Peak value (1+|g|)/(4 pi (1-|g|)^2) (closed form at mu = sign(g)).
    EXPECT_NEAR(p.value(g > 0 ? 1.0 : -1.0), (1 + 0.999) / (4 * kPi * 0.001 * 0.001), 1e-6 * 1.6e5);
  }
  EXPECT_THROW(PhaseFunction(make(PhaseSpec::Model::HenyeyGreenstein, 1.0)), atmosh::InputError);
}
