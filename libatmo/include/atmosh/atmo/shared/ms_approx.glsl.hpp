// atmosh/atmo/shared/ms_approx.glsl.hpp — the all-orders approximation of multiple
// scattering (Hillaire 2020; multiple_scattering.hpp): the per-entry math of its table
// Psi_ms(altitude, mu_s) and the table's lookup, written once for the CPU
// (MultipleScatteringLut, SkyIntegrator; real = double) and the GPU
// (gpu/shaders/ms_build.comp builds the table, gpu/shaders/sky.comp looks it up). Same
// common subset and conventions as geometry.glsl.hpp.
//
// The GPU pastes this block twice, in float and then in double (GLSL overloads the
// functions by their argument types), so it declares no struct and no constant; the
// functions that need exp or log (GLSL has them in float only) or take integers only
// are in the part guarded by ATMOSH_SHARED_MS_ONCE, compiled once, at the first (float)
// paste.
//
// Table (multiple_scattering.hpp): row a of na at altitude h = top u^2, u = a / (na - 1);
// column s of ns at the sun's zenith cosine mu_s = x (1/4 + 3/4 |x|), x = 2 v - 1,
// v = s / (ns - 1); entries are log Psi [log(1/sr)], log(1e-200) for Psi below 1e-200
// (0 included); the lookup interpolates the logarithms bilinearly and reads values
// below 2e-200 as 0.
//
// An entry integrates, over a zenith rule (Gauss-Legendre on both sides of the local
// horizon cosine mu_h, a quarter of the nodes below, gathered toward it) x azimuths
// phi_k = pi (k + 1/2) / n_phi (mirrored: weight 2 pi / n_phi) x trapezoid steps
// t_k = d (k / steps)^1.5 along each ray:
//   f_ms  = sum_rays w_zenith 2 pi / (4 pi) sum_k w_k sigma_s(y_k) T(x, y_k)
//   L_2nd = sum_rays w_zenith w_phi / (4 pi) [sum_k w_k T(x, y_k) T_sun(y_k)
//           (beta_R rho_R p_R + beta_M rho_M p_M)(nu) + ground term]
//   Psi   = L_2nd / max(1 - f_ms, 1e-12).
// Accuracy: exact up to rounding in the real type (the quadrature's own error:
// docs/sky.md, "Multiple scattering").
#pragma once

#include <glm/glm.hpp>

#include "atmosh/atmo/shared/geometry.glsl.hpp"

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

// ---- the table's coordinates ----

// Altitude [m] of row a of na (>= 2) for an atmosphere of height top [m]: top u^2.
ATMOSH_FN real ms_row_altitude(int a, int na, real top) {
  real u = real(a) / real(na - 1);
  return top * u * u;
}

// The sun's zenith cosine of the table coordinate v in [0, 1]: x = 2 v - 1,
// mu_s = x (1/4 + 3/4 |x|), four times denser at the horizon than uniform.
ATMOSH_FN real ms_sun_cosine(real v) {
  real x = real(2) * v - real(1);
  return x * (real(0.25) + (real(1) - real(0.25)) * glm::abs(x));
}

// Its inverse: the coordinate v in [0, 1] of mu_s in [-1, 1].
ATMOSH_FN real ms_sun_coordinate(real mu_s) {
  real m = glm::abs(mu_s);
  real x = (-real(0.25) + glm::sqrt(real(0.25) * real(0.25) + real(4) * (real(1) - real(0.25)) * m)) /
           (real(2) * (real(1) - real(0.25)));
  return real(0.5) * (real(1) + (mu_s < real(0) ? -x : x));
}

// The lookup's continuous row coordinate of radius r [m] (ground R, height top):
// sqrt(h / top) (na - 1), h clamped to [0, top].
ATMOSH_FN real ms_altitude_index(real r, real R, real top, int na) {
  real h = glm::clamp((r - R) / top, real(0), real(1));
  return glm::sqrt(h) * real(na - 1);
}

// The continuous column coordinate of mu_s (clamped to [-1, 1]) in a table of ns.
ATMOSH_FN real ms_sun_index(real mu_s, int ns) {
  return ms_sun_coordinate(glm::clamp(mu_s, real(-1), real(1))) * real(ns - 1);
}

// The first row (column) of the interpolation cell of coordinate u in a table of n.
ATMOSH_FN int ms_cell_start(real u, int n) { return glm::min(int(u), n - 2); }

// Bilinear interpolation of the logarithms at the corners (row a0 or a0 + 1, column s0
// or s0 + 1) with fractions fa, fs: l00 (a0, s0), l01 (a0, s0 + 1), l10, l11.
ATMOSH_FN real ms_log_bilinear(real fa, real fs, real l00, real l01, real l10, real l11) {
  real w00 = (real(1) - fa) * (real(1) - fs), w01 = (real(1) - fa) * fs, w10 = fa * (real(1) - fs), w11 = fa * fs;
  return w00 * l00 + w01 * l01 + w10 * l10 + w11 * l11;
}

// ---- an entry: the sphere rule ----

// Cosine of the horizon seen from radius r above a ground of radius R (<= 0).
ATMOSH_FN real ms_horizon_cosine(real r, real R) {
  return -glm::sqrt(glm::max(real(0), real(1) - (R / r) * (R / r)));
}

// Zenith cosine and weight of the rule's node with Gauss-Legendre node x and weight wx
// (on [-1, 1]) on the side `below` (toward the ground) or above the horizon cosine mu_h:
// mu = mu_h -/+ (1 +/- mu_h) v^2, v = (x + 1) / 2.
ATMOSH_FN real ms_zenith_mu(real mu_h, bool below, real x) {
  real v = real(0.5) * (x + real(1));
  return below ? mu_h - (mu_h + real(1)) * v * v : mu_h + (real(1) - mu_h) * v * v;
}
ATMOSH_FN real ms_zenith_weight(real mu_h, bool below, real x, real wx) {
  real v = real(0.5) * (x + real(1));
  return (below ? mu_h + real(1) : real(1) - mu_h) * real(2) * v * real(0.5) * wx;
}

// The weight of a direction of the rule in f_ms (every azimuth alike: zenith weight
// w_zenith x 2 pi) and in L_2nd (w_zenith x the azimuth weight), times p_u = 1 / (4 pi).
ATMOSH_FN real ms_direction_weight(real w_zenith, real w_azimuth, real inv_four_pi) {
  return w_zenith * w_azimuth * inv_four_pi;
}

// Cosine of the angle between the rule's direction (zenith cosine mu, azimuth cosine
// cos_phi from the sun's vertical plane) and the sun (zenith cosine mu_s).
ATMOSH_FN real ms_scattering_cosine(real mu, real cos_phi, real mu_s) {
  real ss = glm::sqrt(glm::max(real(0), real(1) - mu_s * mu_s));
  real sw = glm::sqrt(glm::max(real(0), real(1) - mu * mu));
  return glm::clamp(sw * cos_phi * ss + mu * mu_s, real(-1), real(1));
}

// Node j of the zenith rule at horizon cosine mu_h, n_lo nodes below the horizon and n_hi
// above it: its zenith cosine into MU and weight into W, from the Gauss-Legendre nodes and
// weights on [-1, 1] read through RULE(i) as x_lo[n_lo], w_lo[n_lo], x_hi[n_hi], w_hi[n_hi].
// (A macro over an accessor: a std::vector on the CPU, a storage buffer on the GPU.)
#define ATMOSH_MS_ZENITH_NODE(MU, W, j, n_lo, n_hi, mu_h, RULE)       \
  {                                                                   \
    bool ms_below_ = (j) < (n_lo);                                    \
    int ms_o_ = ms_below_ ? (j) : (n_lo) + (j);                       \
    int ms_n_ = ms_below_ ? (n_lo) : (n_hi);                          \
    MU = ms_zenith_mu(mu_h, ms_below_, RULE(ms_o_));                  \
    W = ms_zenith_weight(mu_h, ms_below_, RULE(ms_o_), RULE(ms_o_ + ms_n_)); \
  }

// The sums over the rule's directions (zenith node j, azimuth a) of the phase functions
// weighted by the rule, into NORM_R and NORM_M (which the caller zeroes; an entry divides
// its phase functions by them: normalised to 1 over the rule), for the sun at zenith
// cosine mu_s: per direction its scattering cosine ms_nu_ and phase functions ms_pr_ =
// PHASE(0, ms_nu_) (Rayleigh), ms_pm_ = PHASE(1, ms_nu_) (Mie) are in scope for VISIT(j,
// a). RULE as ATMOSH_MS_ZENITH_NODE's, COS_PHI(a) the cosine of azimuth a, w_phi its weight.
#define ATMOSH_MS_PHASE_NORMS(NORM_R, NORM_M, REAL, nz, naz, n_lo, n_hi, mu_h, RULE, COS_PHI, mu_s, w_phi, PHASE, VISIT) \
  {                                                                                     \
    REAL ms_mu_, ms_w_;                                                                 \
    for (int ms_j_ = 0; ms_j_ < (nz); ++ms_j_) {                                        \
      ATMOSH_MS_ZENITH_NODE(ms_mu_, ms_w_, ms_j_, n_lo, n_hi, mu_h, RULE);              \
      for (int ms_a_ = 0; ms_a_ < (naz); ++ms_a_) {                                     \
        REAL ms_nu_ = ms_scattering_cosine(ms_mu_, COS_PHI(ms_a_), mu_s);               \
        REAL ms_pr_ = PHASE(0, ms_nu_);                                                 \
        REAL ms_pm_ = PHASE(1, ms_nu_);                                                 \
        VISIT(ms_j_, ms_a_);                                                            \
        NORM_R += ms_w_ * (w_phi) * ms_pr_;                                             \
        NORM_M += ms_w_ * (w_phi) * ms_pm_;                                             \
      }                                                                                 \
    }                                                                                   \
  }

// ---- an entry: the steps along a ray of the rule ----

// Distance [m] of step k of `steps` along a ray of length d: d (k / steps)^1.5.
ATMOSH_FN real ms_step_distance(real d, int k, int steps) {
  real u = real(k) / real(steps);
  return d * u * glm::sqrt(u);
}

// Radius [m] of the point at distance t along the ray from radius r with zenith cosine
// mu; the ground's radius R exactly at the end of a ray that ends on it.
ATMOSH_FN real ms_step_radius(real r, real mu, real t, bool end_on_ground, real R) {
  return end_on_ground ? R : radius_along(r, mu, t);
}

// Trapezoid weight [m] of a step between the intervals dt_before and dt_after (0 at
// the ray's ends).
ATMOSH_FN real ms_step_weight(real dt_before, real dt_after) {
  return real(0) + real(0.5) * dt_before + real(0.5) * dt_after;
}

// The walk along the rule's ray from radius r with zenith cosine mu (ground radius R, top
// radius T) in `steps` steps: for k = 0..steps, with ms_ground_ (the ray ends on the
// ground), ms_t_ (distance [m]), ms_ry_ (radius [m]), ms_rho_ (relative densities,
// REAL3 of DENSITY(altitude [m])), ms_col_ (the view column from r [m], trapezoid rule)
// and ms_wt_ (the step's trapezoid weight [m]) in scope, VISIT(k). REAL and REAL3 are the
// scalar and vector types (double / dvec3 on both sides).
#define ATMOSH_MS_RAY_STEPS(REAL, REAL3, r, mu, R, T, steps, DENSITY, VISIT)                              \
  {                                                                                                     \
    bool ms_ground_ = ray_hits_ground(r, mu, R);                                                        \
    REAL ms_d_ = ms_ground_ ? distance_to_ground(r, mu, R) : distance_to_top(r, mu, T);                 \
    REAL3 ms_col_ = REAL3(0), ms_rho_prev_ = REAL3(0);                                                  \
    REAL ms_t_prev_ = REAL(0);                                                                          \
    for (int ms_k_ = 0; ms_k_ <= (steps); ++ms_k_) {                                                    \
      REAL ms_t_ = ms_step_distance(ms_d_, ms_k_, steps);                                               \
      REAL ms_ry_ = ms_step_radius(r, mu, ms_t_, ms_k_ == (steps) && ms_ground_, R);                    \
      REAL3 ms_rho_ = DENSITY(glm::max(ms_ry_ - (R), REAL(0)));                                         \
      if (ms_k_ > 0) ms_col_ += REAL(0.5) * (ms_t_ - ms_t_prev_) * (ms_rho_prev_ + ms_rho_);            \
      REAL ms_wt_ = ms_step_weight(ms_k_ > 0 ? ms_t_ - ms_t_prev_ : REAL(0),                            \
                                   ms_k_ < (steps) ? ms_step_distance(ms_d_, ms_k_ + 1, steps) - ms_t_ : REAL(0)); \
      VISIT(ms_k_);                                                                                     \
      ms_t_prev_ = ms_t_;                                                                               \
      ms_rho_prev_ = ms_rho_;                                                                           \
    }                                                                                                   \
  }

// The sun's zenith cosine at distance t along a ray of scattering cosine nu from radius
// r (sun zenith cosine mu_s there), at radius ry (the point's), clamped to [-1, 1].
ATMOSH_FN real ms_point_sun_cosine(real r, real mu_s, real t, real nu, real ry) {
  return glm::clamp((r * mu_s + t * nu) / ry, real(-1), real(1));
}

// The same at the ground (radius R) where the ray of length t ends on it (unclamped:
// a ground point with mu_s <= 0 is not lit).
ATMOSH_FN real ms_ground_sun_cosine(real r, real mu_s, real t, real nu, real R) {
  return (r * mu_s + t * nu) / R;
}

// The Lambertian ground's weight in L_2nd: the direction's weight x albedo / pi x mu_s
// at the ground (times the view and sun transmittances, the caller's).
ATMOSH_FN real ms_ground_weight(real w_direction, real albedo, real mu_s_ground) {
  return w_direction * albedo / real(3.14159265358979323846) * mu_s_ground;
}

// The Lambertian ground at the end (distance d) of a ray from radius r with scattering
// cosine nu, the sun at zenith cosine mu_s at r: where the sun is above the ground's
// horizon, SUN(mu) declares ms_lit_ (not in the Earth's shadow) and ms_sun_ (the column
// from the ground toward the sun) for the sun's zenith cosine mu there, and where lit,
// ADD(g, ms_sun_) adds the ground's light with its weight g (ms_ground_weight).
#define ATMOSH_MS_GROUND(REAL, r, mu_s, d, nu, R, w_direction, albedo, SUN, ADD)   \
  {                                                                                \
    REAL ms_mus_g_ = ms_ground_sun_cosine(r, mu_s, d, nu, R);                      \
    if (ms_mus_g_ > REAL(0)) {                                                     \
      SUN(glm::min(ms_mus_g_, REAL(1)));                                           \
      if (ms_lit_) ADD(ms_ground_weight(w_direction, albedo, ms_mus_g_), ms_sun_); \
    }                                                                              \
  }

// The entry: Psi = L_2nd / (1 - f_ms) (the all-orders series), 1 - f_ms kept >= 1e-12.
ATMOSH_FN real ms_psi_entry(real l2, real f) { return l2 / glm::max(real(1) - f, real(1e-12)); }

// Along the sky's view ray: the term sigma_s(x) Psi_ms T(observer, x) w of a node, at
// one wavelength: (beta_R rr + beta_M rm) psi transmittance, rr = rho_R w, rm = rho_M w.
ATMOSH_FN real ms_sky_term(real transmittance, real psi, real sca_r, real sca_m, real rr, real rm) {
  return (sca_r * rr + sca_m * rm) * psi * transmittance;
}

// Once (GLSL: at the float paste): functions that use exp or log, or whose parameters
// are all integers (a second paste would redefine them).
#ifndef ATMOSH_SHARED_MS_ONCE
#define ATMOSH_SHARED_MS_ONCE
// Nodes of the zenith rule below the horizon (of n >= 2): a quarter, at least one.
ATMOSH_FN int ms_zenith_below(int n) { return glm::max(1, n / 4); }

// Azimuth k of n over [0, pi] (midpoints; mirrored onto [0, 2 pi): weight 2 pi / n).
ATMOSH_FN real ms_azimuth(int k, int n) { return real(3.14159265358979323846) * (real(k) + real(0.5)) / real(n); }
ATMOSH_FN real ms_azimuth_weight(int n) { return real(2) * real(3.14159265358979323846) / real(n); }

// log(1e-200): the table's value of Psi below 1e-200 (the Earth's shadow far from light).
ATMOSH_FN real ms_log_psi_floor() { return real(-460.51701859880916); }

// The table's value of an entry Psi >= 0: log(max(Psi, 1e-200)).
ATMOSH_FN real ms_table_value(real psi) {
  return psi > real(0) ? glm::max(glm::log(psi), ms_log_psi_floor()) : ms_log_psi_floor();
}

// Psi of an interpolated logarithm: 0 below log(2e-200) (the floor's neighbourhood).
ATMOSH_FN real ms_psi_of_log(real l) {
  return l > ms_log_psi_floor() + real(0.69314718055994531) ? glm::exp(l) : real(0);
}
#endif

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
