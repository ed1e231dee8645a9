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
// The table's sun coordinate: x = 2u - 1 in [-1, 1], mu_s = x (a + (1 - a)|x|) with
// a = 1/4: four times denser near the horizon (mu_s = 0) than uniform, where Psi
// changes fastest (the terminator), and the inverse.
constexpr double kSunA = 0.25;
double ms_sun_cosine(double u) {
  const double x = 2.0 * u - 1.0;
  return x * (kSunA + (1.0 - kSunA) * std::fabs(x));
}
double ms_sun_coordinate(double mu_s) {
  const double m = std::fabs(mu_s);
  const double x = (-kSunA + std::sqrt(kSunA * kSunA + 4.0 * (1.0 - kSunA) * m)) / (2.0 * (1.0 - kSunA));
  return 0.5 * (1.0 + std::copysign(x, mu_s));
}
constexpr double kPsiFloor = 1e-200;  // [1/sr]: below, Psi is stored as this (and read as 0)

// Everything an entry of the table needs, independent of the entry.
struct PsiSetup {
  const Atmosphere& atm;
  const OpticalDepthLut& sun;
  std::size_t nw;
  std::vector<double> er, em, eo, sr, sm;  // [wavelength] extinction and scattering [1/m]
  PhaseFunction pr, pm;
  int zenith_n = 0;  // zenith cosines of the sphere rule (zenith_rule)
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
    mu.clear();
    w.clear();
    const double R = atm.ground_radius();
    const double mu_h = -std::sqrt(std::max(0.0, 1.0 - (R / r) * (R / r)));
    const int n_lo = std::max(1, zenith_n / 4), n_hi = zenith_n - n_lo;
    const auto lo = sh::gauss_legendre(n_lo), hi = sh::gauss_legendre(n_hi);
    for (std::size_t k = 0; k < lo.nodes.size(); ++k) {
      const double v = 0.5 * (lo.nodes[k] + 1.0);
      mu.push_back(mu_h - (mu_h + 1.0) * v * v);
      w.push_back((mu_h + 1.0) * 2.0 * v * 0.5 * lo.weights[k]);
    }
    for (std::size_t k = 0; k < hi.nodes.size(); ++k) {
      const double v = 0.5 * (hi.nodes[k] + 1.0);
      mu.push_back(mu_h + (1.0 - mu_h) * v * v);
      w.push_back((1.0 - mu_h) * 2.0 * v * 0.5 * hi.weights[k]);
    }
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
    const int na = o.ms_azimuth_directions;
    for (int k = 0; k < na; ++k) {
      const double phi = kPi * (k + 0.5) / na;
      cos_phi.push_back(std::cos(phi));
      sin_phi.push_back(std::sin(phi));
    }
    w_phi = 2.0 * kPi / na;  // [0, pi] mirrored onto [0, 2 pi)
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
  const double R = S.atm.ground_radius(), T = S.atm.top_radius();
  ray.ground = sg::ray_hits_ground(r, mu, R);
  const double d = ray.ground ? sg::distance_to_ground(r, mu, R) : sg::distance_to_top(r, mu, T);
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
  for (int k = 0; k < n; ++k) {
    const double u = double(k) / S.steps;
    ray.t[k] = d * u * std::sqrt(u);
    ray.r[k] = k == n - 1 && ray.ground ? R : sg::radius_along(r, mu, ray.t[k]);
    rho[k] = S.atm.density(std::max(ray.r[k] - R, 0.0));
    ray.rho_r[k] = rho[k][kRayleigh];
    ray.rho_m[k] = rho[k][kMie];
  }
  for (int k = 1; k < n; ++k) {
    const double dt = ray.t[k] - ray.t[k - 1];
    ray.col[k] = ray.col[k - 1] + 0.5 * dt * (rho[k - 1] + rho[k]);
    ray.wt[k - 1] += 0.5 * dt;
    ray.wt[k] += 0.5 * dt;
  }
  ray.tview.resize(S.nw);
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 x = ray.col[k];
    double* ts = &ray.ts[static_cast<std::size_t>(k) * S.nw];
    for (std::size_t i = 0; i < S.nw; ++i) {
      const double tr = exp_neg(S.er[i] * x[0] + S.em[i] * x[1] + S.eo[i] * x[2]);
      ts[i] = (S.sr[i] * rho[k][kRayleigh] + S.sm[i] * rho[k][kMie]) * tr;
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
    const double wdir = w_w[j] * 2.0 * kPi * pu;
    for (int k = 0; k < rays[j].n; ++k) {
      const double* ts = &rays[j].ts[static_cast<std::size_t>(k) * nw];
      for (std::size_t i = 0; i < nw; ++i) f[i] += wdir * rays[j].wt[k] * ts[i];
    }
  }
  // Per sun direction s and direction q = (j, a) of the rule: cos(w, l) and the phase
  // functions, normalised to 1 over the rule.
  const std::size_t nq = static_cast<std::size_t>(nz * na);
  std::vector<double> nu_v(ns * nq), pr_v(ns * nq), pm_v(ns * nq);
  for (int s = 0; s < ns; ++s) {
    const double ms = mu_s[s], ss = std::sqrt(std::max(0.0, 1.0 - ms * ms));
    double norm_r = 0, norm_m = 0;
    for (int j = 0; j < nz; ++j)
      for (int a = 0; a < na; ++a) {
        const double sw = std::sqrt(std::max(0.0, 1.0 - mu_w[j] * mu_w[j]));
        const std::size_t q = s * nq + static_cast<std::size_t>(j * na + a);
        nu_v[q] = std::clamp(sw * S.cos_phi[a] * ss + mu_w[j] * ms, -1.0, 1.0);
        pr_v[q] = S.pr.value(nu_v[q]);
        pm_v[q] = S.pm.value(nu_v[q]);
        norm_r += w_w[j] * S.w_phi * pr_v[q];
        norm_m += w_w[j] * S.w_phi * pm_v[q];
      }
    for (std::size_t q = 0; q < nq; ++q) {
      pr_v[s * nq + q] /= norm_r;
      pm_v[s * nq + q] /= norm_m;
    }
  }
  std::vector<double> l2(static_cast<std::size_t>(ns) * nw, 0.0);
  for (int j = 0; j < nz; ++j) {
    const SphereRay& ray = rays[j];
    const double wdir = w_w[j] * S.w_phi * pu;
    for (int k = 0; k < ray.n; ++k) {
      // The sun table at this point's radius, reduced once for every sun and azimuth.
      const OpticalDepthLut::SunAtRadius sun_at = S.sun.sun_at(ray.r[k]);
      const double w = wdir * ray.wt[k];
      for (int s = 0; s < ns; ++s) {
        double* acc = &l2[static_cast<std::size_t>(s) * nw];
        for (int a = 0; a < na; ++a) {
          const std::size_t q = s * nq + static_cast<std::size_t>(j * na + a);
          const double mus_y = std::clamp((r * mu_s[s] + ray.t[k] * nu_v[q]) / ray.r[k], -1.0, 1.0);
          const LutColumn c = sun_at(mus_y);
          if (c.hits_ground) continue;  // the Earth's shadow
          const glm::dvec3 x = ray.col[k] + c.column;
          const double rr = ray.rho_r[k] * pr_v[q] * w, rm = ray.rho_m[k] * pm_v[q] * w;
          for (std::size_t i = 0; i < nw; ++i)
            acc[i] += (S.sr[i] * rr + S.sm[i] * rm) * exp_neg(S.er[i] * x[0] + S.em[i] * x[1] + S.eo[i] * x[2]);
        }
      }
    }
    if (!ray.ground || !(S.albedo > 0)) continue;
    // The ground at the ray's end, lit by the sun (Lambertian).
    for (int s = 0; s < ns; ++s)
      for (int a = 0; a < na; ++a) {
        const std::size_t q = s * nq + static_cast<std::size_t>(j * na + a);
        const double mus_g = (r * mu_s[s] + ray.t[ray.n - 1] * nu_v[q]) / R;
        if (!(mus_g > 0)) continue;
        const LutColumn c = S.sun.sun(R, std::min(mus_g, 1.0));
        if (c.hits_ground) continue;
        const double g = wdir * S.albedo / kPi * mus_g;
        double* acc = &l2[static_cast<std::size_t>(s) * nw];
        for (std::size_t i = 0; i < nw; ++i)
          acc[i] += g * ray.tview[i] * exp_neg(S.er[i] * c.column[0] + S.em[i] * c.column[1] + S.eo[i] * c.column[2]);
      }
  }
  for (int s = 0; s < ns; ++s)
    for (std::size_t i = 0; i < nw; ++i)
      out[static_cast<std::size_t>(s) * nw + i] = l2[static_cast<std::size_t>(s) * nw + i] / std::max(1.0 - f[i], 1e-12);
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
  for (int s = 0; s < ns_; ++s) mus[s] = ms_sun_cosine(double(s) / (ns_ - 1));
  parallel_for(static_cast<std::size_t>(na_), o.threads, [&](std::size_t a) {
    const double u = double(a) / (na_ - 1);
    const double h = top_ * u * u;
    std::vector<double> row(static_cast<std::size_t>(ns_) * nw_);
    psi_row(S, R_ + h, mus.data(), ns_, row.data());
    // Logarithms: in the Earth's shadow Psi falls by orders of magnitude between
    // neighbouring sun directions, which bilinear interpolation of the values would
    // smear; the interpolation of the logarithms follows exponential falls exactly.
    for (std::size_t k = 0; k < row.size(); ++k)
      table_[a * static_cast<std::size_t>(ns_) * nw_ + k] = std::log(std::max(row[k], kPsiFloor));
  });
  build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void MultipleScatteringLut::psi(double r, double mu_s, double* out) const {
  const double h = std::clamp((r - R_) / top_, 0.0, 1.0);
  const double ua = std::sqrt(h) * (na_ - 1), us = ms_sun_coordinate(std::clamp(mu_s, -1.0, 1.0)) * (ns_ - 1);
  const int a0 = std::min(static_cast<int>(ua), na_ - 2), s0 = std::min(static_cast<int>(us), ns_ - 2);
  const double fa = ua - a0, fs = us - s0;
  const double w00 = (1 - fa) * (1 - fs), w01 = (1 - fa) * fs, w10 = fa * (1 - fs), w11 = fa * fs;
  const double* p00 = &table_[(static_cast<std::size_t>(a0) * ns_ + s0) * nw_];
  const double* p01 = p00 + nw_;
  const double* p10 = p00 + static_cast<std::size_t>(ns_) * nw_;
  const double* p11 = p10 + nw_;
  for (std::size_t i = 0; i < nw_; ++i) {
    const double v = std::exp(w00 * p00[i] + w01 * p01[i] + w10 * p10[i] + w11 * p11[i]);
    out[i] = v > 2 * kPsiFloor ? v : 0.0;
  }
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
