#include "atmosh/atmo/multiple_scattering.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "atmosh/atmo/atmosphere.hpp"
#include "fast_exp.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/ms_approx.glsl.hpp"
#include "atmosh/atmo/shared/scatter.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::atmo {

namespace sg = shared;

const char* scattering_method_name(ScatteringMethod m) {
  switch (m) {
    case ScatteringMethod::Single: return "single";
    case ScatteringMethod::Orders: return "orders";
    case ScatteringMethod::Approximate: return "approximate";
  }
  return "single";
}

ScatteringMethod parse_scattering_method(const std::string& name, const std::string& key) {
  if (name == "single") return ScatteringMethod::Single;
  if (name == "orders") return ScatteringMethod::Orders;
  if (name == "approximate") return ScatteringMethod::Approximate;
  throw InputError(key + " = \"" + name + "\": must be \"single\", \"orders\" or \"approximate\"");
}

void validate(const MultipleScatteringOptions& o) {
  auto at_least = [](int v, int lo, const char* name) {
    if (v < lo) throw InputError(std::string("scattering.") + name + " = " + std::to_string(v) + ": must be >= " +
                                 std::to_string(lo));
  };
  auto at_most = [](int v, int hi, const char* name) {
    if (v > hi) throw InputError(std::string("scattering.") + name + " = " + std::to_string(v) + ": must be <= " +
                                 std::to_string(hi));
  };
  at_least(o.orders, 1, "orders");
  at_most(o.orders, 64, "orders");
  at_least(o.ms_altitudes, 2, "ms_altitudes");
  at_least(o.ms_sun_directions, 2, "ms_sun_directions");
  at_least(o.ms_zenith_directions, 2, "ms_zenith_directions");
  at_least(o.ms_azimuth_directions, 1, "ms_azimuth_directions");
  at_least(o.ms_ray_steps, 4, "ms_ray_steps");
  at_most(o.ms_altitudes, 1024, "ms_altitudes");
  at_most(o.ms_sun_directions, 1024, "ms_sun_directions");
  at_most(o.ms_zenith_directions, 256, "ms_zenith_directions");
  at_most(o.ms_azimuth_directions, 256, "ms_azimuth_directions");
  at_most(o.ms_ray_steps, 4096, "ms_ray_steps");
  at_least(o.orders_radii, 4, "orders_radii");
  at_least(o.orders_view_directions, 8, "orders_view_directions");
  if (o.orders_view_directions % 2 != 0)
    throw InputError("scattering.orders_view_directions = " + std::to_string(o.orders_view_directions) +
                     ": must be even");
  at_least(o.orders_sun_directions, 4, "orders_sun_directions");
  at_least(o.orders_azimuths, 4, "orders_azimuths");
  at_least(o.orders_sphere_zenith, 4, "orders_sphere_zenith");
  at_least(o.orders_sphere_azimuth, 4, "orders_sphere_azimuth");
  at_least(o.orders_ray_steps, 4, "orders_ray_steps");
  at_most(o.orders_radii, 256, "orders_radii");
  at_most(o.orders_view_directions, 1024, "orders_view_directions");
  at_most(o.orders_sun_directions, 256, "orders_sun_directions");
  at_most(o.orders_azimuths, 256, "orders_azimuths");
  at_most(o.orders_sphere_zenith, 256, "orders_sphere_zenith");
  at_most(o.orders_sphere_azimuth, 256, "orders_sphere_azimuth");
  at_most(o.orders_ray_steps, 4096, "orders_ray_steps");
  resolve_threads(o.threads, "scattering.threads");  // the toolkit's policy: 0..1024
}

namespace {

constexpr double kPi = 3.14159265358979323846;
// The table's coordinates, the sphere rule, the steps and the entry's terms:
// shared/ms_approx.glsl.hpp (the GPU's ms_build.comp and sky.comp use the same code).
// The sun coordinate is four times denser near the horizon (mu_s = 0) than uniform,
// where Psi changes fastest (the terminator).

// Everything an entry of the table needs, independent of the entry.
struct PsiSetup {
  const Atmosphere& atm;
  const OpticalDepthLut& sun;
  std::size_t nw;
  std::vector<double> er, em, eo, sr, sm;  // [wavelength] extinction and scattering [1/m]
  PhaseFunction pr, pm;
  int zenith_n = 0;  // zenith cosines of the sphere rule (zenith_rule)
  int zenith_lo = 0, zenith_hi = 0;  // below and above the horizon
  std::vector<double> zenith_gl;     // their Gauss-Legendre rules: x_lo, w_lo, x_hi, w_hi
  std::vector<double> cos_phi, sin_phi;
  double w_phi = 0;               // weight of one azimuth (mirrored)
  int steps = 0;
  double albedo = 0;

  // The zenith rule at radius r: Gauss-Legendre on each side of the horizon cosine
  // mu_h = -sqrt(1 - R^2/r^2) (ground below, sky above: the integrand jumps there),
  // a quarter of the points below; on both sides mu = mu_h -+ (1 +- mu_h) v^2 (v
  // Gauss-Legendre on [0, 1]) gathers them toward the horizon, where the grazing rays'
  // columns change fastest and twilight's light comes from.
  void zenith_rule(double r, std::vector<double>& mu, std::vector<double>& w) const {
    using namespace sg;  // the macro's functions
    mu.assign(static_cast<std::size_t>(zenith_n), 0.0);
    w.assign(static_cast<std::size_t>(zenith_n), 0.0);
    const double mu_h = ms_horizon_cosine(r, atm.ground_radius());
#define ATMOSH_MS_RULE(i) zenith_gl[static_cast<std::size_t>(i)]
    for (int j = 0; j < zenith_n; ++j) ATMOSH_MS_ZENITH_NODE(mu[j], w[j], j, zenith_lo, zenith_hi, mu_h, ATMOSH_MS_RULE);
#undef ATMOSH_MS_RULE
  }

  PsiSetup(const Atmosphere& a, const OpticalDepthLut& s, const MultipleScatteringOptions& o)
      : atm(a),
        sun(s),
        nw(a.wavelengths_nm().size()),
        pr(a.spec().rayleigh ? a.spec().rayleigh->phase : PhaseSpec::of(PhaseSpec::Model::Rayleigh), "rayleigh.phase"),
        pm(a.spec().mie ? a.spec().mie->phase : PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0), "mie.phase") {
    for (std::size_t i = 0; i < nw; ++i) {
      const auto& k = a.coefficients(i);
      er.push_back(a.has(kRayleigh) ? k.extinction[kRayleigh] : 0.0);
      em.push_back(a.has(kMie) ? k.extinction[kMie] : 0.0);
      eo.push_back(a.has(kOzone) ? k.extinction[kOzone] : 0.0);
      sr.push_back(a.has(kRayleigh) ? k.scattering[kRayleigh] : 0.0);
      sm.push_back(a.has(kMie) ? k.scattering[kMie] : 0.0);
    }
    zenith_n = o.ms_zenith_directions;
    zenith_lo = sg::ms_zenith_below(zenith_n);
    zenith_hi = zenith_n - zenith_lo;
    for (int n : {zenith_lo, zenith_hi}) {  // the GPU's rule buffer (gpu/src/sky.cpp) too
      const auto gl = sh::gauss_legendre(n);
      zenith_gl.insert(zenith_gl.end(), gl.nodes.begin(), gl.nodes.end());
      zenith_gl.insert(zenith_gl.end(), gl.weights.begin(), gl.weights.end());
    }
    const int na = o.ms_azimuth_directions;
    for (int k = 0; k < na; ++k) {
      const double phi = sg::ms_azimuth(k, na);
      cos_phi.push_back(std::cos(phi));
      sin_phi.push_back(std::sin(phi));
    }
    w_phi = sg::ms_azimuth_weight(na);  // [0, pi] mirrored onto [0, 2 pi)
    steps = o.ms_ray_steps;
    albedo = a.spec().planet.ground_albedo;
  }
};

// One ray of the sphere rule from radius r (zenith cosine mu): what does not depend
// on the sun.
struct SphereRay {
  int n = 0;                      // points (steps + 1)
  bool ground = false;
  std::vector<double> t, r;       // distance along the ray, radius of each point
  std::vector<double> wt;         // trapezoid weight of each point [m]
  std::vector<double> ts;         // [point][wavelength] sigma_s(y) T(x, y) [1/m]
  std::vector<double> tview;      // [wavelength] T(x, end of the ray)
  std::vector<glm::dvec3> col;    // view column from x to each point [m]
  std::vector<double> rho_r, rho_m;
};

void trace_sphere_ray(const PsiSetup& S, double r, double mu, SphereRay& ray) {
  using namespace sg;  // the macro's functions
  const double R = S.atm.ground_radius(), T = S.atm.top_radius();
  const int n = S.steps + 1;
  ray.n = n;
  ray.t.resize(n);
  ray.r.resize(n);
  ray.wt.assign(n, 0.0);
  ray.col.assign(n, glm::dvec3(0.0));
  ray.rho_r.resize(n);
  ray.rho_m.resize(n);
  ray.ts.assign(static_cast<std::size_t>(n) * S.nw, 0.0);
  std::vector<glm::dvec3> rho(n);
  // The shared walk (ms_build.comp's too): distances, radii, densities, view columns and
  // trapezoid weights of the steps.
#define ATMOSH_MS_DENSITY(h) S.atm.density(h)
#define ATMOSH_MS_STORE(k)     \
  ray.ground = ms_ground_;     \
  ray.t[k] = ms_t_;            \
  ray.r[k] = ms_ry_;           \
  rho[k] = ms_rho_;            \
  ray.rho_r[k] = ms_rho_[kRayleigh]; \
  ray.rho_m[k] = ms_rho_[kMie];      \
  ray.col[k] = ms_col_;        \
  ray.wt[k] = ms_wt_;
  ATMOSH_MS_RAY_STEPS(double, glm::dvec3, r, mu, R, T, S.steps, ATMOSH_MS_DENSITY, ATMOSH_MS_STORE)
#undef ATMOSH_MS_STORE
#undef ATMOSH_MS_DENSITY
  ray.tview.resize(S.nw);
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 x = ray.col[k];
    double* ts = &ray.ts[static_cast<std::size_t>(k) * S.nw];
    for (std::size_t i = 0; i < S.nw; ++i) {
      const double tr = exp_neg(S.er[i] * x[0] + S.em[i] * x[1] + S.eo[i] * x[2]);
      ts[i] = sg::scattering_term(tr, S.sr[i], S.sm[i], rho[k][kRayleigh], rho[k][kMie]);
      if (k == n - 1) ray.tview[i] = tr;
    }
  }
}

// One altitude row: Psi_ms for every sun direction in mu_s[0..ns) into out[s * nw + i].
void psi_row(const PsiSetup& S, double r, const double* mu_s, int ns, double* out) {
  const std::size_t nw = S.nw;
  const int nz = S.zenith_n, na = static_cast<int>(S.cos_phi.size());
  const double R = S.atm.ground_radius();
  const double pu = sg::inv_four_pi();
  std::vector<double> mu_w, w_w;
  S.zenith_rule(r, mu_w, w_w);
  std::vector<SphereRay> rays(nz);
  std::vector<double> f(nw, 0.0);
  for (int j = 0; j < nz; ++j) {
    trace_sphere_ray(S, r, mu_w[j], rays[j]);
    // f_ms: no sun. The inner integral over the ray, then the sphere (every azimuth alike).
    const double wdir = sg::ms_direction_weight(w_w[j], 2.0 * kPi, pu);
    for (int k = 0; k < rays[j].n; ++k) {
      const double* ts = &rays[j].ts[static_cast<std::size_t>(k) * nw];
      for (std::size_t i = 0; i < nw; ++i) f[i] += wdir * rays[j].wt[k] * ts[i];
    }
  }
  // Per sun direction s and direction q = (j, a) of the rule: cos(w, l) and the phase
  // functions, normalised to 1 over the rule.
  const std::size_t nq = static_cast<std::size_t>(nz * na);
  std::vector<double> nu_v(ns * nq), pr_v(ns * nq), pm_v(ns * nq);
  {
    using namespace sg;  // the macros' functions
    const double mu_h = ms_horizon_cosine(r, R);
#define ATMOSH_MS_RULE(i) S.zenith_gl[static_cast<std::size_t>(i)]
#define ATMOSH_MS_COS_PHI(a) S.cos_phi[static_cast<std::size_t>(a)]
#define ATMOSH_MS_PHASE(c, nu) ((c) == 0 ? S.pr : S.pm).value(nu)
#define ATMOSH_MS_STORE(j, a)                                              \
  const std::size_t q = s * nq + static_cast<std::size_t>((j) * na + (a)); \
  nu_v[q] = ms_nu_;                                                        \
  pr_v[q] = ms_pr_;                                                        \
  pm_v[q] = ms_pm_;
  for (int s = 0; s < ns; ++s) {
    double norm_r = 0, norm_m = 0;
    ATMOSH_MS_PHASE_NORMS(norm_r, norm_m, double, nz, na, S.zenith_lo, S.zenith_hi, mu_h, ATMOSH_MS_RULE,
                          ATMOSH_MS_COS_PHI, mu_s[s], S.w_phi, ATMOSH_MS_PHASE, ATMOSH_MS_STORE)
#undef ATMOSH_MS_STORE
#undef ATMOSH_MS_PHASE
#undef ATMOSH_MS_COS_PHI
#undef ATMOSH_MS_RULE
    for (std::size_t q = 0; q < nq; ++q) {
      pr_v[s * nq + q] /= norm_r;
      pm_v[s * nq + q] /= norm_m;
    }
  }
  }
  std::vector<double> l2(static_cast<std::size_t>(ns) * nw, 0.0);
  for (int j = 0; j < nz; ++j) {
    const SphereRay& ray = rays[j];
    const double wdir = sg::ms_direction_weight(w_w[j], S.w_phi, pu);
    for (int k = 0; k < ray.n; ++k) {
      // The sun table at this point's radius, reduced once for every sun and azimuth.
      const OpticalDepthLut::SunAtRadius sun_at = S.sun.sun_at(ray.r[k]);
      const double w = wdir * ray.wt[k];
      for (int s = 0; s < ns; ++s) {
        double* acc = &l2[static_cast<std::size_t>(s) * nw];
        for (int a = 0; a < na; ++a) {
          const std::size_t q = s * nq + static_cast<std::size_t>(j * na + a);
          const double mus_y = sg::ms_point_sun_cosine(r, mu_s[s], ray.t[k], nu_v[q], ray.r[k]);
          const LutColumn c = sun_at(mus_y);
          if (c.hits_ground) continue;  // the Earth's shadow
          const glm::dvec3 x = ray.col[k] + c.column;
          const double rr = ray.rho_r[k] * pr_v[q] * w, rm = ray.rho_m[k] * pm_v[q] * w;
          for (std::size_t i = 0; i < nw; ++i)
            acc[i] += sg::scattering_term(exp_neg(sg::column_optical_depth(S.er[i], S.em[i], S.eo[i], x[0], x[1], x[2])),
                                          S.sr[i], S.sm[i], rr, rm);
        }
      }
    }
    if (!ray.ground || !(S.albedo > 0)) continue;
    // The ground at the ray's end, lit by the sun (Lambertian).
    using namespace sg;  // the macro's functions (ms_build.comp's ground too)
#define ATMOSH_MS_SUN(mu)                    \
  const LutColumn ms_c_ = S.sun.sun(R, mu);  \
  const bool ms_lit_ = !ms_c_.hits_ground;   \
  const glm::dvec3 ms_sun_ = ms_c_.column;
#define ATMOSH_MS_ADD(g, col)                \
  for (std::size_t i = 0; i < nw; ++i)       \
    acc[i] += (g) * ray.tview[i] * exp_neg(column_optical_depth(S.er[i], S.em[i], S.eo[i], col[0], col[1], col[2]));
    for (int s = 0; s < ns; ++s)
      for (int a = 0; a < na; ++a) {
        const std::size_t q = s * nq + static_cast<std::size_t>(j * na + a);
        double* acc = &l2[static_cast<std::size_t>(s) * nw];
        ATMOSH_MS_GROUND(double, r, mu_s[s], ray.t[ray.n - 1], nu_v[q], R, wdir, S.albedo, ATMOSH_MS_SUN, ATMOSH_MS_ADD)
      }
#undef ATMOSH_MS_ADD
#undef ATMOSH_MS_SUN
  }
  for (int s = 0; s < ns; ++s)
    for (std::size_t i = 0; i < nw; ++i)
      out[static_cast<std::size_t>(s) * nw + i] = sg::ms_psi_entry(l2[static_cast<std::size_t>(s) * nw + i], f[i]);
}

}  // namespace

MultipleScatteringLut::MultipleScatteringLut(const Atmosphere& atmosphere, const OpticalDepthLut& sun,
                                             const MultipleScatteringOptions& o) {
  validate(o);
  const auto t0 = std::chrono::steady_clock::now();
  const PsiSetup S(atmosphere, sun, o);
  R_ = atmosphere.ground_radius();
  top_ = atmosphere.top_altitude();
  na_ = o.ms_altitudes;
  ns_ = o.ms_sun_directions;
  nw_ = S.nw;
  table_.assign(static_cast<std::size_t>(na_) * ns_ * nw_, 0.0);
  std::vector<double> mus(static_cast<std::size_t>(ns_));
  for (int s = 0; s < ns_; ++s) mus[s] = sg::ms_sun_cosine(double(s) / (ns_ - 1));
  parallel_for(static_cast<std::size_t>(na_), o.threads, [&](std::size_t a) {
    const double h = sg::ms_row_altitude(static_cast<int>(a), na_, top_);
    std::vector<double> row(static_cast<std::size_t>(ns_) * nw_);
    psi_row(S, R_ + h, mus.data(), ns_, row.data());
    // Logarithms: in the Earth's shadow Psi falls by orders of magnitude between
    // neighbouring sun directions, which bilinear interpolation of the values would
    // smear; the interpolation of the logarithms follows exponential falls exactly.
    for (std::size_t k = 0; k < row.size(); ++k)
      table_[a * static_cast<std::size_t>(ns_) * nw_ + k] = sg::ms_table_value(row[k]);
  });
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void MultipleScatteringLut::psi(double r, double mu_s, double* out) const {
  // The shared lookup (sky.comp's too).
  const double ua = sg::ms_altitude_index(r, R_, top_, na_), us = sg::ms_sun_index(mu_s, ns_);
  const int a0 = sg::ms_cell_start(ua, na_), s0 = sg::ms_cell_start(us, ns_);
  const double fa = ua - double(a0), fs = us - double(s0);
  const double* p00 = &table_[(static_cast<std::size_t>(a0) * ns_ + s0) * nw_];
  const double* p10 = p00 + static_cast<std::size_t>(ns_) * nw_;
  for (std::size_t i = 0; i < nw_; ++i)
    out[i] = sg::ms_psi_of_log(sg::ms_log_bilinear(fa, fs, p00[i], p00[nw_ + i], p10[i], p10[nw_ + i]));
}

std::vector<double> MultipleScatteringLut::psi_direct(const Atmosphere& atmosphere, const OpticalDepthLut& sun,
                                                      const MultipleScatteringOptions& o, double r, double mu_s) {
  validate(o);
  const PsiSetup S(atmosphere, sun, o);
  std::vector<double> out(S.nw);
  psi_row(S, r, &mu_s, 1, out.data());
  return out;
}

}  // namespace atmosh::atmo
