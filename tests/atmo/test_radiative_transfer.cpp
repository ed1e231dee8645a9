// Monte-Carlo radiative transfer (radiative_transfer.hpp) against independent
// references: published plane-parallel benchmarks (DISORT's test problems, which
// reproduce van de Hulst 1980 and Sweigart 1970), closed forms, energy
// conservation, and the exact single-scattering quadrature (SkyReference).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
#include "sanitizer_build.hpp"

using namespace atmosh::atmo;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Sanitizer builds run ~10x slower: they use fewer paths and then assert only the
// statistical bound (3 standard errors), whose width follows the path count.
using atmosh::test::kSanitized;

std::int64_t paths(std::int64_t release) { return kSanitized ? std::max<std::int64_t>(release / 8, 1000) : release; }

}  // namespace

// Reference values: DISORT test problems (Stamnes, Tsay, Wiscombe & Jayaweera 1988,
// Appl. Opt. 27, 2502), file DISOTEST.f of DISORT 4.0 (2014), BLOCK DATA CHEKDO
// "correct answers" (array TSTUU: intensities UU at the top, UTAU = 0, and at the
// bottom; TSTFUP/TSTFDN: fluxes), computed by DISORT with 16 streams:
//  * Problem 1 (isotropic scattering, checked there against "Ref. VH1, Table 12" =
//    van de Hulst 1980, Multiple Light Scattering, Vol. 1, Table 12): UMU0 = 0.1,
//    FBEAM = pi / UMU0, so mu0 F0 = pi and R = pi I / (mu0 F0) = I: the tabulated
//    intensity is R (top, mu > 0) or T (bottom, mu < 0; diffuse only). Cases a:
//    tau = 0.03125, omega = 0.2; b: 0.03125, 1.0; d: 32, 0.2.
//  * Problem 2 (Rayleigh, "Ref. SW, Table 1" = Sweigart 1970, Astrophys. J. Suppl. 22,
//    1): UMU0 = 0.080442, FBEAM = pi, so R = I / UMU0. Cases a: tau = 0.2, omega = 0.5;
//    b: 0.2, 1.0. PHI = PHI0 = 0 (our phi = 0).
//  * Problem 3 (Henyey-Greenstein g = 0.75, "Ref. VH2, Table 37" = van de Hulst 1980,
//    Vol. 2, Table 37): UMU0 = 1, FBEAM = pi, R = I. Case a: tau = 1, omega = 1.
// The 16-stream answers carry their own error: for the thin grazing-sun slabs of
// problem 1 they are up to 1.0e-3 below the exact solution of the integral equation
// (isotropic_slab below: 1b T(0.5) 0.139472 vs 0.139337, R(0.1) 0.623501 vs 0.622884).
// The bound is therefore 3 x sqrt(stderr^2 + (1e-3 ref)^2), and 0.5 % of the value.
struct SlabCase {
  const char* name;
  SlabSpec slab;
  double mu0, mu;
  bool reflection;
  double value;  // R or T
  std::int64_t paths;
};

namespace {
void run_cases(const std::vector<SlabCase>& cases) {
  for (const auto& c : cases) {
    RtOptions o;
    o.paths = paths(c.paths);
    o.seed = 2024;
    const SlabResult r = slab_reflection_transmission(c.slab, c.mu0, c.mu, 0.0, o);
    const double mc = c.reflection ? r.reflection : r.transmission;
    const double se = c.reflection ? r.reflection_stderr : r.transmission_stderr;
    const double combined = std::hypot(se, 1e-3 * c.value);
    EXPECT_LE(std::abs(mc - c.value), 3.0 * combined) << c.name << ": mc " << mc << " +- " << se << ", ref " << c.value;
    if (!kSanitized) {
      EXPECT_LE(std::abs(mc - c.value), 0.005 * c.value) << c.name << ": mc " << mc << ", ref " << c.value;
      EXPECT_LE(se, 0.002 * c.value) << c.name;  // the comparison has teeth
    }
  }
}
}  // namespace

TEST(RadiativeTransferSlab, IsotropicMatchesDisortProblem1) {
  const SlabSpec a{0.03125, 0.2, SlabPhase::Isotropic, 0.0, 0.0};
  const SlabSpec b{0.03125, 1.0, SlabPhase::Isotropic, 0.0, 0.0};
  const SlabSpec d{32.0, 0.2, SlabPhase::Isotropic, 0.0, 0.0};
  run_cases({
      {"1a R(mu=0.5)", a, 0.1, 0.5, true, 2.64170e-02, 200000},
      {"1a T(mu=1.0)", a, 0.1, 1.0, false, 1.33826e-02, 200000},
      {"1b R(mu=0.1)", b, 0.1, 0.1, true, 6.22884e-01, 200000},
      {"1b T(mu=0.5)", b, 0.1, 0.5, false, 1.39337e-01, 200000},
      {"1d R(mu=0.5)", d, 0.1, 0.5, true, 9.06967e-02, 800000},
  });
}

TEST(RadiativeTransferSlab, RayleighMatchesDisortProblem2) {
  const double mu0 = 0.080442;
  const SlabSpec a{0.2, 0.5, SlabPhase::Rayleigh, 0.0, 0.0};
  const SlabSpec b{0.2, 1.0, SlabPhase::Rayleigh, 0.0, 0.0};
  run_cases({
      {"2a R(mu=0.018014)", a, mu0, 0.018014, true, 1.61796e-01 / mu0, 200000},
      {"2a R(mu=0.538263)", a, mu0, 0.538263, true, 2.11501e-02 / mu0, 400000},
      {"2b R(mu=0.981986)", b, mu0, 0.981986, true, 1.89387e-02 / mu0, 600000},
  });
}

TEST(RadiativeTransferSlab, HenyeyGreensteinMatchesDisortProblem3) {
  const SlabSpec a{1.0, 1.0, SlabPhase::HenyeyGreenstein, 0.75, 0.0};
  run_cases({{"3a T(mu=0.5)", a, 1.0, 0.5, false, 2.66648e-01, 1200000}});
}

namespace {

// Independent solver: the integral equation of an isotropically scattering
// homogeneous slab over a Lambertian ground (Chandrasekhar 1960, Radiative Transfer,
// ch. I; van de Hulst 1980, ch. 4) for the source function J(t), t the optical depth
// from the top, with mu0 F0 = pi:
//   J(t) = omega / (4 mu0) e^{-t/mu0} + omega/2 int_0^tau E1(|t - t'|) J(t') dt'
//          + omega/2 I_g E2(tau - t),
//   I_g  = A / pi (pi e^{-tau/mu0} + 2 pi int_0^tau J(t') E2(tau - t') dt')
// (I_g the isotropic radiance leaving the ground), solved by Nystrom collocation with J
// piecewise linear on N cells and the E1 kernel integrated exactly over each cell
// (product integration: int E1 = -E2, int x E1 = -x E2 - E3). Then
// R(mu) = pi I_up(0, mu) / (mu0 F0) = I_g e^{-tau/mu} + int_0^tau J e^{-t/mu} dt/mu.
// Converged to ~1e-5 relative at N = 300 (N = 200 and 400 differ by 2e-5).
double E1(double x) { return x <= 0 ? std::numeric_limits<double>::infinity() : -std::expint(-x); }
double E2(double x) { return x <= 0 ? 1.0 : std::exp(-x) - x * E1(x); }
double E3(double x) { return x <= 0 ? 0.5 : 0.5 * (std::exp(-x) - x * E2(x)); }

double isotropic_slab_reflection(double tau, double omega, double A, double mu0, double mu, int N = 300) {
  const double h = tau / N;
  const int M = N + 2;  // J_0..J_N, I_g
  std::vector<double> t(N + 1), K(static_cast<std::size_t>(M * M), 0.0), S(M, 0.0);
  for (int i = 0; i <= N; ++i) t[i] = i * h;
  auto at = [&](int i, int j) -> double& { return K[static_cast<std::size_t>(i * M + j)]; };
  for (int i = 0; i <= N; ++i) {
    S[i] = omega / (4 * mu0) * std::exp(-t[i] / mu0);
    at(i, i) = 1.0;
    for (int c = 0; c < N; ++c) {
      const bool right = c >= i;  // cell [t_c, t_c+1] beside t_i
      const double lo = right ? t[c] - t[i] : t[i] - t[c + 1], hi = right ? t[c + 1] - t[i] : t[i] - t[c];
      const double l = std::max(lo, 0.0);
      const double I0 = E2(l) - E2(hi), I1 = (-hi * E2(hi) - E3(hi)) - (-l * E2(l) - E3(l));
      at(i, right ? c : c + 1) -= omega / 2 * (hi * I0 - I1) / h;
      at(i, right ? c + 1 : c) -= omega / 2 * (I1 - l * I0) / h;
    }
    at(i, N + 1) -= omega / 2 * E2(tau - t[i]);
  }
  const int g = N + 1;
  at(g, g) = 1.0;
  S[g] = A * std::exp(-tau / mu0);
  for (int c = 0; c < N; ++c)
    for (int q = 0; q < 32; ++q) {  // 2 A int J E2(tau - t) dt, J linear per cell
      const double tt = t[c] + (q + 0.5) * h / 32, f = (tt - t[c]) / h, w = 2 * A * E2(tau - tt) * h / 32;
      at(g, c) -= w * (1 - f);
      at(g, c + 1) -= w * f;
    }
  for (int k = 0; k < M; ++k) {  // Gaussian elimination, partial pivoting
    int p = k;
    for (int i = k + 1; i < M; ++i)
      if (std::abs(at(i, k)) > std::abs(at(p, k))) p = i;
    if (p != k) {
      for (int j = 0; j < M; ++j) std::swap(at(k, j), at(p, j));
      std::swap(S[k], S[p]);
    }
    for (int i = k + 1; i < M; ++i) {
      const double f = at(i, k) / at(k, k);
      if (f == 0) continue;
      for (int j = k; j < M; ++j) at(i, j) -= f * at(k, j);
      S[i] -= f * S[k];
    }
  }
  std::vector<double> x(M);
  for (int i = M - 1; i >= 0; --i) {
    double s = S[i];
    for (int j = i + 1; j < M; ++j) s -= at(i, j) * x[j];
    x[i] = s / at(i, i);
  }
  double r = x[N + 1] * std::exp(-tau / mu);
  for (int c = 0; c < N; ++c)
    for (int q = 0; q < 16; ++q) {
      const double tt = t[c] + (q + 0.5) * h / 16;
      const double J = x[c] + (x[c + 1] - x[c]) * (tt - t[c]) / h;
      r += J * std::exp(-tt / mu) / mu * h / 16;
    }
  return r;
}

}  // namespace

TEST(RadiativeTransferSlab, IsotropicMatchesTheIntegralEquationOverAReflectingGround) {
  // The independent solver reproduces the published values first (DISORT 1b, within
  // DISORT's own 1e-3), then MC and solver agree within 3 standard errors and 0.5 %
  // for slabs over grey and white grounds.
  EXPECT_NEAR(isotropic_slab_reflection(0.03125, 1.0, 0.0, 0.1, 0.5), 1.39763e-01, 1e-3 * 1.39763e-01);
  struct G {
    double tau, omega, A, mu0, mu;
    std::int64_t paths;
  };
  for (const G g : {G{1.0, 0.9, 0.3, 0.6, 0.5, 200000}, G{0.25, 1.0, 0.8, 0.3, 0.9, 200000},
                    G{3.0, 0.95, 1.0, 0.8, 0.2, 100000}}) {
    const double ref = isotropic_slab_reflection(g.tau, g.omega, g.A, g.mu0, g.mu);
    RtOptions o;
    o.paths = paths(g.paths);
    o.seed = 77;
    const SlabResult r = slab_reflection_transmission({g.tau, g.omega, SlabPhase::Isotropic, 0.0, g.A}, g.mu0, g.mu, 0.3, o);
    EXPECT_LE(std::abs(r.reflection - ref), 3.0 * r.reflection_stderr + 2e-5 * ref)
        << g.tau << " " << g.A << ": mc " << r.reflection << " +- " << r.reflection_stderr << ", solver " << ref;
    if (!kSanitized) {
      EXPECT_LE(std::abs(r.reflection - ref), 0.005 * ref) << g.tau << " " << g.A;
    }
  }
}

TEST(RadiativeTransferSlab, FluxesMatchPublishedBenchmarks) {
  // DISORT problem 1b (tau = 0.03125, omega = 1, mu0 = 0.1): FLUP(top) = 4.22922e-1,
  // FLDN(bottom) = 4.20233e-1 (diffuse), over mu0 F0 = pi.
  RtOptions o;
  o.paths = paths(200000);
  o.seed = 7;
  const SlabFluxResult thin = slab_fluxes({0.03125, 1.0, SlabPhase::Isotropic, 0.0, 0.0}, 0.1, o);
  EXPECT_LE(std::abs(thin.albedo - 4.22922e-01 / kPi), 3.0 * std::hypot(thin.albedo_stderr, 1e-3 * thin.albedo));
  EXPECT_LE(std::abs(thin.transmittance - 4.20233e-01 / kPi),
            3.0 * std::hypot(thin.transmittance_stderr, 1e-3 * thin.transmittance));
  // No absorption: albedo + diffuse + direct transmittance = 1.
  EXPECT_LE(std::abs(thin.albedo + thin.transmittance + std::exp(-0.03125 / 0.1) - 1.0),
            3.0 * std::hypot(thin.albedo_stderr, thin.transmittance_stderr));
}

TEST(RadiativeTransferSlab, ConservativeSlabOverWhiteGroundReturnsAllLight) {
  // omega = 1 and a white ground absorb nothing: the upward flux at the top equals the
  // incident mu0 F0 (plane albedo 1), whatever the phase function and thickness.
  RtOptions o;
  o.paths = paths(40000);
  o.seed = 11;
  for (const SlabSpec& s : {SlabSpec{1.0, 1.0, SlabPhase::Isotropic, 0.0, 1.0},
                            SlabSpec{4.0, 1.0, SlabPhase::HenyeyGreenstein, 0.8, 1.0},
                            SlabSpec{0.3, 1.0, SlabPhase::Rayleigh, 0.0, 1.0}}) {
    const SlabFluxResult f = slab_fluxes(s, 0.6, o);
    EXPECT_LE(std::abs(f.albedo - 1.0), 3.0 * f.albedo_stderr + 1e-12) << s.tau << ": " << f.albedo << " +- " << f.albedo_stderr;
    EXPECT_LT(f.albedo_stderr, kSanitized ? 0.06 : 0.02);
  }
  // And an absorbing one (omega = 0.9) returns visibly less (the estimator can fail).
  const SlabFluxResult f = slab_fluxes({4.0, 0.9, SlabPhase::Isotropic, 0.0, 1.0}, 0.6, o);
  EXPECT_LT(f.albedo + 5.0 * f.albedo_stderr, 1.0);
}

TEST(RadiativeTransferSlab, PureAbsorberOverGroundIsTheClosedForm) {
  // omega = 0: only the ground reflects, R = A exp(-tau/mu0 - tau/mu) exactly.
  const SlabSpec s{0.4, 0.0, SlabPhase::Isotropic, 0.0, 0.35};
  RtOptions o;
  o.paths = paths(100000);
  const double mu0 = 0.7, mu = 0.45;
  const SlabResult r = slab_reflection_transmission(s, mu0, mu, 1.0, o);
  const double exact = 0.35 * std::exp(-0.4 / mu0 - 0.4 / mu);
  EXPECT_LE(std::abs(r.reflection - exact), 3.0 * r.reflection_stderr) << r.reflection << " vs " << exact;
  EXPECT_EQ(r.transmission, 0.0);
}

TEST(RadiativeTransferSlab, SingleScatteringIsTheClosedForm) {
  // max_orders = 1, isotropic: the first-order reflection function in closed form,
  // R1 = omega / (4 (mu0 + mu)) (1 - exp(-tau (1/mu0 + 1/mu))) (van de Hulst 1980,
  // Multiple Light Scattering, Vol. 1, single-scattering approximation; the integral
  // of omega F0/(4 pi) exp(-t/mu0) exp(-t/mu) dt/mu over the slab, times pi/(mu0 F0)).
  const SlabSpec s{0.5, 0.8, SlabPhase::Isotropic, 0.0, 0.0};
  RtOptions o;
  o.paths = paths(100000);
  o.max_orders = 1;
  const double mu0 = 0.6, mu = 0.3;
  const SlabResult r = slab_reflection_transmission(s, mu0, mu, 0.0, o);
  const double exact = 0.8 / (4.0 * (mu0 + mu)) * (1.0 - std::exp(-0.5 * (1.0 / mu0 + 1.0 / mu)));
  EXPECT_LE(std::abs(r.reflection - exact), 3.0 * r.reflection_stderr + 1e-12) << r.reflection << " vs " << exact;
}

TEST(RadiativeTransferSlab, RejectsBadInput) {
  EXPECT_THROW(slab_reflection_transmission({-1.0, 1.0, SlabPhase::Isotropic, 0, 0}, 0.5, 0.5, 0), atmosh::InputError);
  EXPECT_THROW(slab_reflection_transmission({1.0, 1.5, SlabPhase::Isotropic, 0, 0}, 0.5, 0.5, 0), atmosh::InputError);
  EXPECT_THROW(slab_reflection_transmission({1.0, 1.0, SlabPhase::Isotropic, 0, 0}, 0.0, 0.5, 0), atmosh::InputError);
  EXPECT_THROW(slab_reflection_transmission({1.0, 1.0, SlabPhase::HenyeyGreenstein, 1.0, 0}, 0.5, 0.5, 0),
               atmosh::InputError);
  RtOptions o;
  o.paths = 0;
  EXPECT_THROW(slab_reflection_transmission({1.0, 1.0, SlabPhase::Isotropic, 0, 0}, 0.5, 0.5, 0, o), atmosh::InputError);
}

namespace {

AtmosphereSpec three_wavelengths(AtmosphereSpec s) {
  s.spectrum.wavelengths_nm = {440.0, 550.0, 680.0};
  return s;
}

SolarSpectrum flat_sun(const Atmosphere& a) { return SolarSpectrum(a.wavelengths_nm().size(), 1.8); }

// Small sun tables (40 x 64, error ~6e-5 of the optical depth): fast to build, far
// below the statistical errors asserted here.
RtSkyOptions small_tables() {
  RtSkyOptions o;
  o.table_shells = 40;
  o.table_directions = 64;
  return o;
}

}  // namespace

TEST(RadiativeTransferSky, FlatLimitMatchesTheSlab) {
  // The spherical transport (delta tracking, first-collision sampling, sun table, ground)
  // on a planet 100x Earth's radius under a homogeneous 10 km layer (a two-node
  // tabulated profile: tau = 1, omega = 0.9, isotropic, ground albedo 0.3) is the slab
  // of the same parameters: reflection against the integral-equation solver, and the
  // diffuse transmission against the slab mode. Curvature over the paths' ~20 km
  // horizontal reach changes the geometry by ~1e-5 (allowed: 1e-4).
  AtmosphereSpec s;
  s.planet.radius_m = 6.36e8;
  s.planet.atmosphere_top_m = 10000.0;
  s.planet.ground_albedo = 0.3;
  s.rayleigh.reset();
  s.ozone.reset();
  MieSpec m;
  m.single_scattering_albedo = 0.9;
  m.scattering_per_m = 0.9 * 1.0 / 10000.0;  // extinction = scattering / albedo: tau = 1
  m.profile.kind = DensityProfileSpec::Kind::Tabulated;
  m.profile.altitude_m = {0.0, 10000.0};
  m.profile.value = {1.0, 1.0};
  m.phase = PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0);
  s.mie = m;
  s.spectrum.wavelengths_nm = {550.0};
  const Atmosphere atm(s);
  RtSkyOptions so = small_tables();
  so.run.paths = paths(120000);
  so.run.seed = 21;
  const MonteCarloSky mc(atm, SolarSpectrum{1.0}, so);  // E = 1: F0 = 1
  const double mu0 = 0.6, mu = 0.5;
  const glm::dvec3 sun = enu_direction(std::asin(mu0) * 180.0 / kPi, 180.0);
  const RtSkyResult up = mc.radiance(10100.0, enu_direction(-std::asin(mu) * 180.0 / kPi, 30.0), sun);
  const double R = kPi * up.radiance[0] / mu0, R_se = kPi * up.radiance_stderr[0] / mu0;
  const double R_exact = isotropic_slab_reflection(1.0, 0.9, 0.3, mu0, mu);
  EXPECT_LE(std::abs(R - R_exact), 3.0 * R_se + 1e-4 * R_exact) << R << " +- " << R_se << " vs " << R_exact;
  const RtSkyResult down = mc.radiance(0.0, enu_direction(std::asin(mu) * 180.0 / kPi, 30.0), sun);
  const double T = kPi * down.radiance[0] / mu0, T_se = kPi * down.radiance_stderr[0] / mu0;
  RtOptions o;
  o.paths = paths(120000);
  const SlabResult slab = slab_reflection_transmission({1.0, 0.9, SlabPhase::Isotropic, 0.0, 0.3}, mu0, mu, 0.0, o);
  EXPECT_LE(std::abs(T - slab.transmission), 3.0 * std::hypot(T_se, slab.transmission_stderr) + 1e-4 * T)
      << T << " +- " << T_se << " vs slab " << slab.transmission << " +- " << slab.transmission_stderr;
  EXPECT_LT(R_se, (kSanitized ? 0.01 : 0.004) * R_exact);
}

TEST(RadiativeTransferSky, ConservativeFlatLimitOverWhiteGroundReturnsAllLight) {
  // Energy in the spherical code: omega = 1 over a white ground in the flat limit (as
  // above); the radiance leaving the top, averaged over cosine-weighted directions
  // (pi I / mu0 F0 per direction), is the plane albedo: 1.
  AtmosphereSpec s;
  s.planet.radius_m = 6.36e8;
  s.planet.atmosphere_top_m = 10000.0;
  s.planet.ground_albedo = 1.0;
  s.rayleigh.reset();
  s.ozone.reset();
  MieSpec m;
  m.single_scattering_albedo = 1.0;
  m.scattering_per_m = 0.5 / 10000.0;
  m.profile.kind = DensityProfileSpec::Kind::Tabulated;
  m.profile.altitude_m = {0.0, 10000.0};
  m.profile.value = {1.0, 1.0};
  m.phase = PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.6);
  s.mie = m;
  s.spectrum.wavelengths_nm = {550.0};
  const Atmosphere atm(s);
  const MonteCarloSky mc(atm, SolarSpectrum{1.0}, small_tables());
  const double mu0 = 0.7;
  const glm::dvec3 sun = enu_direction(std::asin(mu0) * 180.0 / kPi, 180.0);
  RtOptions o;
  o.paths = paths(2000);
  o.batches = 8;
  std::mt19937_64 gen(1234);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int K = 48;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < K; ++k) {
    const double mu = std::sqrt(1.0 - U(gen)), az = 360.0 * U(gen);  // cosine-weighted, upward light
    o.seed = 100 + static_cast<std::uint64_t>(k);
    const RtSkyResult r = mc.radiance(10100.0, enu_direction(-std::asin(mu) * 180.0 / kPi, az), sun, o);
    const double x = kPi * r.radiance[0] / mu0;
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / K, se = std::sqrt((sum2 / K - mean * mean) / (K - 1));
  EXPECT_LE(std::abs(mean - 1.0), 3.0 * se) << mean << " +- " << se;
  EXPECT_LT(se, 0.05);
}

TEST(RadiativeTransferSky, SingleScatteringLimitMatchesTheExactQuadrature) {
  // max_orders = 1 and a black ground: the Monte-Carlo estimate of the single-
  // scattering integral SkyReference evaluates by adaptive quadrature (rel. 1e-6).
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.0;
  const Atmosphere atm(spec);
  RtSkyOptions so = small_tables();
  so.run.max_orders = 1;
  so.run.paths = paths(3 * 30000);
  so.run.seed = 5;
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  const SkyReference ref(atm, flat_sun(atm));
  struct View {
    double sun_el, view_el, view_rel_az;
  };
  for (const View v : {View{30, 90, 0}, View{10, 5, 0}, View{10, 20, 150}, View{-3, 30, 0}}) {
    const glm::dvec3 sun = enu_direction(v.sun_el, 180.0), view = enu_direction(v.view_el, 180.0 + v.view_rel_az);
    const RtSkyResult r = mc.radiance(0.0, view, sun);
    const SkyReferenceResult e = ref.radiance(0.0, view, sun);
    for (std::size_t i = 0; i < 3; ++i) {
      const double tol = 3.0 * std::hypot(r.radiance_stderr[i], e.error[i]);
      EXPECT_LE(std::abs(r.radiance[i] - e.radiance[i]), tol)
          << "sun " << v.sun_el << " view " << v.view_el << "/" << v.view_rel_az << " nm " << r.wavelengths_nm[i]
          << ": mc " << r.radiance[i] << " +- " << r.radiance_stderr[i] << ", exact " << e.radiance[i];
      EXPECT_GT(e.radiance[i], 0.0);
      EXPECT_LT(r.radiance_stderr[i], (kSanitized ? 0.15 : 0.05) * e.radiance[i]);  // the comparison has teeth
    }
    EXPECT_DOUBLE_EQ(r.mean_orders, r.mean_orders);
    EXPECT_LE(r.mean_orders, 1.0);
  }
}

TEST(RadiativeTransferSky, MultipleScatteringAddsLight) {
  // All orders are brighter than single scattering at the zenith (sun 30 deg): by
  // 10-40 % in the blue for an Earth-like atmosphere (the measured deficit of
  // single scattering against Bruneton 2017 is 20-36 %); here a lower bound of 5 %,
  // many standard errors above the noise.
  const AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  const Atmosphere atm(spec);
  RtSkyOptions so = small_tables();
  so.run.paths = paths(3 * 20000);
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  RtOptions one = so.run;
  one.max_orders = 1;
  const glm::dvec3 sun = enu_direction(30, 180), zen(0, 0, 1);
  const RtSkyResult all = mc.radiance(0.0, zen, sun), single = mc.radiance(0.0, zen, sun, one);
  EXPECT_GT(all.radiance[0], 1.05 * single.radiance[0] + 3 * std::hypot(all.radiance_stderr[0], single.radiance_stderr[0]));
  EXPECT_GT(all.mean_orders, single.mean_orders);
}

TEST(RadiativeTransferSky, LineEstimateAgreesWithTheCollisionEstimate) {
  // Two estimators of the same multiply scattered radiance (next-event estimates at
  // sampled collisions vs. their expectation integrated along each flight) agree.
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.3;
  const Atmosphere atm(spec);
  RtSkyOptions off = small_tables(), on = small_tables();
  off.line_estimate = RtLineEstimate::Off;
  on.line_estimate = RtLineEstimate::On;
  off.run.paths = paths(3 * 40000);
  on.run.paths = paths(3 * 3000);
  const MonteCarloSky a(atm, flat_sun(atm), off), b(atm, flat_sun(atm), on);
  const glm::dvec3 sun = enu_direction(5, 180), view = enu_direction(35, 120);
  const RtSkyResult ra = a.radiance(0.0, view, sun), rb = b.radiance(0.0, view, sun);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_LE(std::abs(ra.radiance[i] - rb.radiance[i]), 3.0 * std::hypot(ra.radiance_stderr[i], rb.radiance_stderr[i]))
        << ra.wavelengths_nm[i] << ": " << ra.radiance[i] << " +- " << ra.radiance_stderr[i] << " vs " << rb.radiance[i]
        << " +- " << rb.radiance_stderr[i];
}

TEST(RadiativeTransferSky, GuidedScatteringAgreesWithThePlainEstimator) {
  // The guided first collision and scattering directions (a pilot's map of the light,
  // evaluated exactly in every weight) change the variance, not the mean: against the
  // plain collision estimator by day (sun 5 deg, reflecting ground) and against the
  // plain line estimator in deep twilight (sun -9 deg, 5 deg above the horizon away
  // from the sun), two independent estimators of the same radiance.
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.3;
  const Atmosphere atm(spec);
  struct Case {
    double sun_el, view_el, view_az;
    RtLineEstimate plain_line;
    std::int64_t plain_paths, guided_paths;
  };
  for (const Case c : {Case{5, 35, 120, RtLineEstimate::Off, 3 * 40000, 3 * 3000},
                       Case{-9, 5, 0, RtLineEstimate::On, 3 * 6000, 3 * 3000}}) {
    RtSkyOptions plain = small_tables(), guided = small_tables();
    plain.guide = RtLineEstimate::Off;
    plain.line_estimate = c.plain_line;
    guided.guide = RtLineEstimate::On;
    guided.guide_points = 8;
    plain.run.paths = paths(c.plain_paths);
    guided.run.paths = paths(c.guided_paths);
    guided.run.seed = 17;
    const MonteCarloSky a(atm, flat_sun(atm), plain), b(atm, flat_sun(atm), guided);
    const glm::dvec3 sun = enu_direction(c.sun_el, 180), view = enu_direction(c.view_el, c.view_az);
    const RtSkyResult ra = a.radiance(0.0, view, sun), rb = b.radiance(0.0, view, sun);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_GT(rb.radiance[i], 0.0);
      EXPECT_LE(std::abs(ra.radiance[i] - rb.radiance[i]), 3.0 * std::hypot(ra.radiance_stderr[i], rb.radiance_stderr[i]))
          << "sun " << c.sun_el << ", " << ra.wavelengths_nm[i] << " nm: plain " << ra.radiance[i] << " +- "
          << ra.radiance_stderr[i] << ", guided " << rb.radiance[i] << " +- " << rb.radiance_stderr[i];
      // The comparison has teeth (twilight: 3 000 paths per wavelength give 4-10 %).
      if (!kSanitized) {
        EXPECT_LT(rb.radiance_stderr[i], (c.sun_el < 0 ? 0.15 : 0.05) * rb.radiance[i]);
      }
    }
  }
}

TEST(RadiativeTransferSky, GuidedSingleScatteringMatchesTheExactQuadrature) {
  // max_orders = 1 with the guide on: the guided first collision alone (its density
  // drawn from the pilot, weighted exactly) still integrates single scattering.
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.0;
  const Atmosphere atm(spec);
  RtSkyOptions so = small_tables();
  so.guide = RtLineEstimate::On;
  so.guide_points = 8;
  so.run.max_orders = 1;
  so.run.paths = paths(3 * 20000);
  so.run.seed = 23;
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  const SkyReference ref(atm, flat_sun(atm));
  for (const double sun_el : {10.0, -3.0}) {
    const glm::dvec3 sun = enu_direction(sun_el, 180.0), view = enu_direction(30, 180.0);
    const RtSkyResult r = mc.radiance(0.0, view, sun);
    const SkyReferenceResult e = ref.radiance(0.0, view, sun);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_LE(std::abs(r.radiance[i] - e.radiance[i]), 3.0 * std::hypot(r.radiance_stderr[i], e.error[i]))
          << "sun " << sun_el << " nm " << r.wavelengths_nm[i] << ": mc " << r.radiance[i] << " +- "
          << r.radiance_stderr[i] << ", exact " << e.radiance[i];
      EXPECT_LT(r.radiance_stderr[i], (kSanitized ? 0.15 : 0.05) * e.radiance[i]);
    }
  }
}

TEST(RadiativeTransferSky, SunTableAgreesWithExactSunDepths) {
  // The same seed draws the same paths in both modes (sun transmittances take no random
  // numbers): the difference is the table's error alone, bounded by its stated optical
  // depth error times the slant depths (here < 1e-3 of the radiance).
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.2;
  const Atmosphere atm(spec);
  RtSkyOptions t = small_tables(), e = small_tables();
  e.sun_depth = RtSunDepth::Exact;
  t.run.paths = e.run.paths = 3 * 1500;
  const MonteCarloSky a(atm, flat_sun(atm), t), b(atm, flat_sun(atm), e);
  EXPECT_GT(a.sun_depth_rel_error(), 0.0);
  EXPECT_LT(a.sun_depth_rel_error(), 2e-4);
  for (const double sun_el : {5.0, -4.0}) {
    const glm::dvec3 sun = enu_direction(sun_el, 180), view = enu_direction(10, 150);
    const RtSkyResult ra = a.radiance(0.0, view, sun), rb = b.radiance(0.0, view, sun);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_GT(rb.radiance[i], 0.0);
      EXPECT_LE(std::abs(ra.radiance[i] - rb.radiance[i]), 1e-3 * rb.radiance[i])
          << sun_el << " " << ra.wavelengths_nm[i] << ": " << ra.radiance[i] << " vs " << rb.radiance[i];
    }
  }
}

TEST(RadiativeTransferSky, SameSeedSameBitsOnAnyThreadCount) {
  const Atmosphere atm(three_wavelengths(preset("earth-graphics")));
  RtSkyOptions so = small_tables();
  so.run.paths = 3 * 2000;
  so.run.seed = 99;
  so.run.threads = 2;
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  const glm::dvec3 sun = enu_direction(20, 180), view = enu_direction(40, 100);
  const RtSkyResult a = mc.radiance(0.0, view, sun), b = mc.radiance(0.0, view, sun);
  RtOptions one = so.run;
  one.threads = 1;
  const RtSkyResult c = mc.radiance(0.0, view, sun, one);
  RtOptions other = so.run;
  other.seed = 100;
  const RtSkyResult d = mc.radiance(0.0, view, sun, other);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(a.radiance[i], b.radiance[i]);
    EXPECT_EQ(a.radiance_stderr[i], b.radiance_stderr[i]);
    EXPECT_EQ(a.radiance[i], c.radiance[i]);
    EXPECT_NE(a.radiance[i], d.radiance[i]);
  }
  EXPECT_EQ(a.luminance, c.luminance);
  RtOptions slab;
  slab.paths = 5000;
  slab.seed = 3;
  const SlabSpec s{1.0, 0.9, SlabPhase::HenyeyGreenstein, 0.7, 0.2};
  const SlabResult s1 = slab_reflection_transmission(s, 0.5, 0.7, 1.0, slab);
  slab.threads = 1;
  const SlabResult s2 = slab_reflection_transmission(s, 0.5, 0.7, 1.0, slab);
  slab.seed = 4;
  const SlabResult s3 = slab_reflection_transmission(s, 0.5, 0.7, 1.0, slab);
  EXPECT_EQ(s1.reflection, s2.reflection);
  EXPECT_EQ(s1.transmission_stderr, s2.transmission_stderr);
  EXPECT_NE(s1.reflection, s3.reflection);
}

TEST(RadiativeTransferSky, StiffCasesAreFinite) {
  AtmosphereSpec spec = three_wavelengths(preset("earth-graphics"));
  spec.planet.ground_albedo = 0.3;
  const Atmosphere atm(spec);
  RtSkyOptions so = small_tables();
  so.run.paths = paths(3 * 1000);
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  const double R = atm.ground_radius(), T = atm.top_radius();
  const double h_space = 200e3;
  // From space: the view grazing the top of the atmosphere, and one grazing the ground.
  const double el_top = -std::acos(T / (R + h_space)) * 180.0 / kPi;
  const double el_ground = -std::acos(R / (R + h_space)) * 180.0 / kPi;
  struct Case {
    double alt, view_el, view_az, sun_el;
  };
  for (const Case c : {Case{0, 90, 0, -15}, Case{0, 0, 180, -15}, Case{0, 0, 0, -9}, Case{0, 0.0, 90, 0.0},
                       Case{h_space, el_top + 0.05, 180, 10}, Case{h_space, el_ground + 0.01, 180, 10},
                       Case{h_space, el_ground - 0.01, 180, -5}, Case{0, -10, 180, 30}, Case{h_space, 30, 0, 20}}) {
    const RtSkyResult r = mc.radiance(c.alt, enu_direction(c.view_el, c.view_az), enu_direction(c.sun_el, 180));
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_TRUE(std::isfinite(r.radiance[i]) && r.radiance[i] >= 0) << c.alt << " " << c.view_el;
      EXPECT_TRUE(std::isfinite(r.radiance_stderr[i])) << c.alt << " " << c.view_el;
    }
    EXPECT_TRUE(std::isfinite(r.luminance));
  }
  // Twilight at -9 deg: single scattering is (nearly) dark at the zenith, the multiply
  // scattered sky is not.
  const RtSkyResult tw = mc.radiance(0.0, {0, 0, 1}, enu_direction(-9, 180));
  EXPECT_GT(tw.luminance, 0.0);
  // Looking up from space: nothing to scatter.
  const RtSkyResult up = mc.radiance(h_space, {0, 0, 1}, enu_direction(30, 180));
  EXPECT_EQ(up.luminance, 0.0);
}

TEST(RadiativeTransferSky, ReferenceViewsCoverEverySunAndView) {
  const Atmosphere atm(three_wavelengths(preset("earth-graphics")));
  RtSkyOptions so = small_tables();
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  RtOptions run;
  run.paths = 3 * 200;
  const auto views = rt_reference_view_set();
  const std::vector<double> suns = {30.0, -3.0};
  const auto rows = rt_reference_views(mc, views, suns, 0.0, run);
  ASSERT_EQ(rows.size(), views.size() * suns.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(rows[k].sun_elevation_deg, suns[k / views.size()]);
    EXPECT_EQ(rows[k].view_elevation_deg, views[k % views.size()].elevation_deg);
    EXPECT_EQ(rows[k].result.radiance.size(), 3u);
    EXPECT_TRUE(std::isfinite(rows[k].result.luminance) && rows[k].result.luminance > 0) << k;
  }
  // Toward the sun at 5 deg is brighter than away from it (Mie forward peak), sun 30 deg.
  EXPECT_GT(rows[1].result.luminance, rows[3].result.luminance);
  EXPECT_EQ(rt_reference_sun_elevations().front(), 60.0);
  EXPECT_EQ(rt_reference_sun_elevations().back(), -15.0);
}

TEST(RadiativeTransferSky, RejectsBadInput) {
  const Atmosphere atm(three_wavelengths(preset("earth-graphics")));
  EXPECT_THROW(MonteCarloSky(atm, SolarSpectrum(2, 1.0)), atmosh::InputError);
  RtSkyOptions so = small_tables();
  so.run.paths = 30;
  const MonteCarloSky mc(atm, flat_sun(atm), so);
  EXPECT_THROW(mc.radiance(0.0, {0, 0, 2}, {0, 0, 1}), atmosh::InputError);
  EXPECT_THROW(mc.radiance(-5.0, {0, 0, 1}, {0, 0, 1}), atmosh::InputError);
  EXPECT_THROW(mc.radiance(0.0, {0, 0, 1}, {NAN, 0, 1}), atmosh::InputError);
}
