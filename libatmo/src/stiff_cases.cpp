#include "atmosh/atmo/stiff_cases.hpp"

#include <cmath>
#include <functional>

#include "atmosh/atmo/chapman.hpp"
#include "integrate.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/ozone.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"

namespace atmosh::atmo {

namespace {
constexpr double kPi = 3.14159265358979323846;

AtmosphereSpec single_exponential(double H, double scattering = 1e-5) {
  AtmosphereSpec s;
  s.name = "single-exponential";
  s.planet.radius_m = 6360e3;
  s.planet.atmosphere_top_m = 60.0 * H;
  RayleighSpec r;
  r.model = RayleighSpec::Model::Coefficients;
  r.scattering_per_m = scattering;
  r.reference_nm = 550.0;
  r.profile.kind = DensityProfileSpec::Kind::Exponential;
  r.profile.scale_height_m = H;
  s.rayleigh = r;
  s.mie.reset();
  s.ozone.reset();
  return s;
}

StiffCase make(const std::string& name, const std::string& quantity, double value, double reference, double bound) {
  StiffCase c{name, quantity, value, reference, 0.0, bound, false};
  c.error = reference != 0.0 ? std::abs(value - reference) / std::abs(reference) : std::abs(value);
  c.pass = std::isfinite(value) && std::isfinite(c.error) && c.error <= bound;
  return c;
}

double sphere_integral(const std::function<double(double)>& f) {
  std::vector<double> pts;
  for (double t = 1e-6; t < 1.0; t *= 2.0) {
    pts.push_back(t);
    pts.push_back(kPi - t);
  }
  auto r = integrate_adaptive<double>([&](double th) { return f(std::cos(th)) * std::sin(th); }, 0.0, kPi, pts,
                                      1e-300, 1e-13, 20000);
  return 2.0 * kPi * r.value;
}
}  // namespace

std::vector<StiffCase> run_stiff_cases(int lut_shells, int lut_directions) {
  std::vector<StiffCase> out;
  // Chapman cases: reference quadrature / (H e^{-h/H}) against the exact Chapman function.
  struct ChCase {
    const char* name;
    double H, h, tangent_h;  // tangent_h < 0: horizontal ray (mu = 0)
  };
  const ChCase ch_cases[] = {
      {"horizontal_sea_level_H8km", 8000.0, 0.0, -1.0},
      {"horizontal_sea_level_H1.2km", 1200.0, 0.0, -1.0},
      {"horizontal_at_10km_H8km", 8000.0, 10e3, -1.0},
      {"horizontal_at_10km_H1.2km", 1200.0, 10e3, -1.0},
      {"grazing_from_20km_tangent_100m_H8km", 8000.0, 20e3, 100.0},
      {"grazing_from_10km_tangent_1m_H1.2km", 1200.0, 10e3, 1.0},
      {"grazing_from_10km_tangent_1mm_H8km", 8000.0, 10e3, 1e-3},
  };
  for (const auto& cc : ch_cases) {
    Atmosphere atm(single_exponential(cc.H));
    OpticalDepthReference ref(atm);
    double R = atm.ground_radius(), r = R + cc.h;
    double mu = cc.tangent_h < 0.0 ? 0.0 : -std::sqrt(std::max(0.0, 1.0 - std::pow((R + cc.tangent_h) / r, 2.0)));
    auto c = ref.column(r, mu);
    double value = c.column[kRayleigh] / (cc.H * std::exp(-cc.h / cc.H));
    out.push_back(make(cc.name, "Chapman value (column / vertical column)", value, chapman_exact(r / cc.H, mu), 1e-9));
  }
  // Ray into the planet: straight down from 1 km, closed form H (1 - e^{-1000/H}).
  {
    Atmosphere atm(single_exponential(8000.0));
    OpticalDepthReference ref(atm);
    auto c = ref.column(atm.ground_radius() + 1000.0, -1.0);
    out.push_back(make("ray_hits_planet_nadir_from_1km", "column [m]", c.column[kRayleigh],
                       8000.0 * -std::expm1(-1000.0 / 8000.0), 1e-12));
    // Just below the horizon from 1 km: the ray meets the ground ~1 m from its tangent
    // point, so its column is that from the origin back to a tangent point on the
    // ground, H [Ch(R/H, 90 deg) - e^{-1000/H} Ch(r/H, -mu)] (the half chord minus the
    // rest of the ray beyond the origin), up to ~2 m of ground-level density (~1e-5).
    const double R = atm.ground_radius(), r = R + 1000.0, H = 8000.0;
    const double mu_h = shared::mu_horizon(r, R);
    auto g = ref.column(r, mu_h - 1e-12);
    const double half_chord = H * (chapman_horizontal_exact(R / H) - std::exp(-1000.0 / H) * chapman_exact(r / H, -mu_h));
    out.push_back(make("ray_hits_planet_just_below_horizon", "column [m] (hits the ground)",
                       g.hits_ground ? g.column[kRayleigh] : NAN, half_chord, 1e-4));
  }
  // Observer 500 km above the top of a single exponential (H = 8 km, top at 480 km)
  // looking through the limb, tangent at 30 km: the whole chord,
  // 2 H e^{-h_t/H} Ch(r_t/H, 90 deg) (Bessel form; the density beyond the top,
  // e^{-60}, is negligible).
  {
    const double H = 8000.0;
    Atmosphere atm(single_exponential(H));
    OpticalDepthReference ref(atm);
    const double R = atm.ground_radius(), T = atm.top_radius(), r = T + 500e3, rt = R + 30e3;
    const double mu = -std::sqrt((r - rt) * (r + rt)) / r;
    auto a = ref.column(r, mu);
    out.push_back(make("limb_from_500km_above_top", "column [m]", a.column[kRayleigh],
                       2.0 * H * std::exp(-30e3 / H) * chapman_horizontal_exact(rt / H), 1e-9));
  }
  // Transmittance underflow: a dense aerosol (1e-2 /m, H = 1.2 km) seen
  // horizontally at sea level has tau ~ 1e3: transmittance exactly 0, not NaN.
  {
    Atmosphere atm(single_exponential(1200.0, 1e-2));
    OpticalDepthReference ref(atm);
    auto c = ref.column(atm.ground_radius(), 0.0);
    double tau = optical_depth(atm.coefficients_at(550.0), c.column);
    double t = transmittance(tau);
    out.push_back(make("transmittance_underflow_tau_" + std::to_string(static_cast<int>(tau)), "transmittance", t, 0.0, 0.0));
    out.push_back(make("transmittance_of_infinite_depth", "transmittance", transmittance(INFINITY), 0.0, 0.0));
  }
  // Phase functions with g = +-0.999: normalisation by adaptive quadrature.
  for (double g : {0.999, -0.999}) {
    PhaseSpec s;
    s.model = PhaseSpec::Model::HenyeyGreenstein;
    s.g = g;
    PhaseFunction p(s);
    out.push_back(make("hg_normalisation_g" + std::string(g > 0 ? "+" : "-") + "0.999", "2 pi int p dmu",
                       sphere_integral([&](double mu) { return p.value(mu); }), 1.0, 1e-10));
    s.model = PhaseSpec::Model::CornetteShanks;
    PhaseFunction q(s);
    out.push_back(make("cornette_shanks_normalisation_g" + std::string(g > 0 ? "+" : "-") + "0.999", "2 pi int p dmu",
                       sphere_integral([&](double mu) { return q.value(mu); }), 1.0, 1e-10));
    out.push_back(make("hg_sampling_mean_g" + std::string(g > 0 ? "+" : "-") + "0.999", "mean of sampled cos",
                       [&] {
                         double m = 0.0;
                         const int n = 100000;
                         for (int i = 0; i < n; ++i) m += p.sample((i + 0.5) / n);
                         return m / n;
                       }(),
                       g, 1e-4));
  }
  // Cornette-Shanks at g = +-0.999: Legendre moments chi_0 = 1 and chi_1 = the closed
  // mean cosine 3 g (4 + g^2) / (5 (2 + g^2)) through the zonal projection, and the
  // probability of the hemisphere away from the peak (mu <= 0 for g > 0, mu > 0 for
  // g < 0; ~1.3e-4 of the total) from inverting sample() by bisection, against the
  // exact integral over that hemisphere by adaptive quadrature.
  for (double g : {0.999, -0.999}) {
    PhaseSpec s;
    s.model = PhaseSpec::Model::CornetteShanks;
    s.g = g;
    PhaseFunction p(s);
    const std::string tag = std::string(g > 0 ? "+" : "-") + "0.999";
    const auto m = p.legendre_moments(64);
    out.push_back(make("cornette_shanks_chi0_g" + tag, "chi_0 (zonal projection)", m.chi[0], 1.0, 1e-10));
    out.push_back(make("cornette_shanks_chi1_g" + tag, "chi_1 (zonal projection)", m.chi[1],
                       3.0 * g * (4.0 + g * g) / (5.0 * (2.0 + g * g)), 1e-9));
    double lo = 0.0, hi = 1.0;  // u with sample(u) = 0
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      (p.sample(mid) < 0.0 ? lo : hi) = mid;
    }
    const double u0 = 0.5 * (lo + hi);  // P(mu <= 0) by sampling
    const double tail = sphere_integral([&](double mu) { return (g > 0.0 ? mu <= 0.0 : mu > 0.0) ? p.value(mu) : 0.0; });
    out.push_back(make("cornette_shanks_sampling_tail_g" + tag, "probability away from the peak, from sample()",
                       g > 0.0 ? u0 : 1.0 - u0, tail, 1e-5));
  }
  // Wavelengths at the ends of the grid (360 and 830 nm).
  //  * Physical Rayleigh: the cross-section (King factor, refractive index of air)
  //    times Bodhaine et al. (1999)'s column, P A / (m_a g) with g at the column's
  //    mass-weighted height (their eqs. 10-11, 17, 27), against their eq. (30) fit,
  //    good to 0.01 %.
  //  * Ozone, a consistency check of the column: the vertical optical depth through
  //    the preset's tent (its extinction times the reference quadrature's column) must
  //    be sigma(lambda) x the column in Dobson units x 2.6867811e20 m^-2, i.e. the
  //    quadrature must reproduce the tent's area that scales the number density.
  {
    const double z = 5517.56, gz = (980.6160 - 3.085462e-4 * z + 7.254e-11 * z * z - 1.517e-17 * z * z * z) * 1e-2;
    const double column = 101325.0 * 6.0221367e23 / ((15.0556 * 360e-6 + 28.9595) * 1e-3 * gz);
    Atmosphere atm(preset("earth-graphics"));
    OpticalDepthReference ref(atm);
    const auto c = ref.column(atm.ground_radius(), 1.0);
    for (double nm : {360.0, 830.0}) {
      const std::string w = std::to_string(static_cast<int>(nm));
      out.push_back(make("rayleigh_physical_" + w + "nm_vs_bodhaine_eq30", "tau_R (Bodhaine's column)",
                         rayleigh_cross_section(nm, 360.0) * column, bodhaine_eq30_optical_depth(nm), 1e-4));
      const double dtau = atm.coefficients_at(nm).extinction[kOzone] * c.column[kOzone];
      out.push_back(make("ozone_vertical_column_consistency_" + w + "nm", "tau_O3, vertical from the ground", dtau,
                         ozone_cross_section(nm) * atm.spec().ozone->column_du * kDobsonUnitPerM2, 1e-9));
    }
  }
  // LUT on grazing and tangent rays (earth-graphics) against the reference.
  {
    Atmosphere atm(preset("earth-graphics"));
    OpticalDepthReference ref(atm);
    LutOptions o;
    o.shells = lut_shells;
    o.view_directions = lut_directions;
    o.sun_directions = lut_directions;
    OpticalDepthLut lut(atm, o);
    auto k = atm.coefficients_at(550.0);
    double R = atm.ground_radius();
    struct L { const char* name; double h, dmu; };
    const L cases[] = {{"lut_horizontal_sea_level", 0.0, 0.0}, {"lut_tangent_1m_above_ground_from_5km", 5000.0, 1.0},
                       {"lut_just_below_horizon_from_5km", 5000.0, -1e-9}, {"lut_horizontal_at_30km", 30000.0, -2.0}};
    for (const auto& c : cases) {
      double r = R + c.h, mu;
      if (c.dmu == -2.0) mu = 0.0;
      else if (c.dmu == 1.0) mu = -std::sqrt(1.0 - std::pow((R + 1.0) / r, 2.0));
      else mu = shared::mu_horizon(r, R) + c.dmu;
      double a = optical_depth(k, ref.column(r, mu).column), b = optical_depth(k, lut.view(r, mu).column);
      out.push_back(make(c.name, "optical depth at 550 nm (LUT)", b, a, 1e-4));
    }
  }
  return out;
}

}  // namespace atmosh::atmo
