// atmosh/atmo/shared/lut.glsl.hpp — table parametrisation and interpolation
// weights of the optical-depth tables (OpticalDepthLut) and the light-path
// geometry of the single-scattering integrand, written once for the CPU
// (SkyIntegrator, OpticalDepthLut; real = double) and the GPU (gpu/shaders/;
// real = float). Same common subset and conventions as geometry.glsl.hpp.
//
// Accuracy: exact up to rounding in the real type (a few ulp).
#pragma once

#include <glm/glm.hpp>

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

// Direction coordinate of a table ray (Bruneton 2017): x = (d - d_min) /
// (d_max - d_min) in [0, 1], d the distance to the end of the ray (top or
// ground), d_min / d_max its smallest and largest value at that radius; 0 when
// the range is empty (the ground or top shell itself).
ATMOSH_FN real lut_x(real d, real d_min, real d_max) {
  return d_max > d_min ? glm::clamp((d - d_min) / (d_max - d_min), real(0), real(1)) : real(0);
}

// The ray of a table entry, the inverse of lut_x: from the shell of radius r
// (rho = sqrt(r^2 - R^2)) at direction sample x in [0, 1], its length d [m] (d_min =
// T - r, d_max = rho + Hh toward the top, Hh = sqrt(T^2 - R^2); r - R and rho toward
// the ground) and its zenith cosine mu (the ray of length d from r ending on the
// top, resp. the ground, sphere). d <= 0 is the degenerate ray (the entry is the
// density at r), whose mu is not used.
ATMOSH_FN real lut_table_distance(real r, real rho, real x, real R, real T, real Hh, bool ground) {
  real d_min = ground ? r - R : T - r;
  real d_max = ground ? rho : rho + Hh;
  return d_min + x * (d_max - d_min);
}
ATMOSH_FN real lut_table_mu(real r, real rho, real d, real T, bool ground) {
  real m = ground ? -(rho * rho + d * d) : (T - r) * (T + r) - d * d;
  return glm::clamp(m / (real(2) * r * d), real(-1), real(1));
}

// Weight of sample i (0..3) of the cubic Lagrange interpolant through equally
// spaced samples at 0, 1, 2, 3, evaluated at p (p in [0, 3] inside the window).
ATMOSH_FN real lagrange_cubic_weight(real p, int i) {
  if (i == 0) return -(p - real(1)) * (p - real(2)) * (p - real(3)) / real(6);
  if (i == 1) return p * (p - real(2)) * (p - real(3)) / real(2);
  if (i == 2) return -p * (p - real(1)) * (p - real(3)) / real(2);
  return p * (p - real(1)) * (p - real(2)) / real(6);
}

// ---- table lookup (OpticalDepthLut::interpolate): window choice and weights ----
// A table holds samples at shells rho_0 < ... < rho_{S-1} (rho = sqrt(r^2 - R^2))
// times directions x_j = j / (n - 1); a lookup interpolates a 4 x 4 window of
// them with cubic Lagrange weights in rho and in x.

// First direction sample of the 4-sample window around x in [0, 1] (n >= 4
// samples): the cell j = floor(x (n - 1)) (clamped to [0, n - 2]) and its
// neighbours, shifted inward at the ends.
ATMOSH_FN int lut_direction_window(real x, int n) {
  int j = glm::clamp(int(x * real(n - 1)), 0, n - 2);
  return glm::clamp(j - 1, 0, n - 4);
}

// Position of x inside the window starting at jw, in sample units (0..3 inside).
ATMOSH_FN real lut_direction_offset(real x, int n, int jw) { return x * real(n - 1) - real(jw); }

// Table build: equal sub-pieces of a piece of length len [m] whose ends are at
// radii ra, rb, of a ray with squared tangent radius rt2, so that on each the
// exponent h/H of an exp(-h/H) density (H [m] the smallest scale height there;
// H <= 0 or >= 1e30: none matters, one piece) changes by at most 1.5 and its
// curvature term len_sub^2 kappa / (2 H) is at most 1/2, kappa = rt2 / r_lo^3 the
// largest curvature of the altitude along the piece (r_lo its lowest radius; the
// ray's altitude is smallest at the tangent point, where kappa ~ 1/r). Without the
// curvature bound a piece starting at the tangent point and spanning 1.5 H, a
// Gaussian in s over 1.7 of its widths, had 4e-6 relative error with 4
// Gauss-Legendre points; with it, at most 8e-9 (tangent pieces of any length).
// At most 64 sub-pieces.
ATMOSH_FN int lut_piece_count(real ra, real rb, real len, real rt2, real H) {
  if (!(H > real(0) && H < real(1e30))) return 1;
  real r_lo = glm::min(ra, rb);
  real kappa = rt2 / (r_lo * r_lo * r_lo);
  real m_alt = glm::ceil(glm::abs(rb - ra) / (real(1.5) * H));
  real m_curv = glm::ceil(len * glm::sqrt(kappa / H));
  return glm::clamp(int(glm::min(glm::max(m_alt, m_curv), real(64))), 1, 64);
}

// Lagrange weight of node i (0..3) of the shell window (r0..r3 the window's rho
// values, inv_den = 1 / prod_{j != i} (r_i - r_j), precomputed per window) at rho.
ATMOSH_FN real lut_shell_weight(real rho, real inv_den, real r0, real r1, real r2, real r3, int i) {
  real p = inv_den;
  if (i != 0) p *= rho - r0;
  if (i != 1) p *= rho - r1;
  if (i != 2) p *= rho - r2;
  if (i != 3) p *= rho - r3;
  return p;
}

#ifndef ATMOSH_SHARED_LUT_ONCE  // parts without `real`: once, however often the block is pasted
#define ATMOSH_SHARED_LUT_ONCE

// First shell of the 4-shell window for the shell interval k (S >= 4 shells).
ATMOSH_FN int lut_window_start(int k, int S) { return glm::clamp(k - 1, 0, S - 4); }

// Shell search: k = (number of shells with rho_i <= rho) - 1 (k = -1 below the
// first shell, S - 1 at or above the last; rho_i ascending), by bisection.
// RHO_AT names a function or lambda int i -> rho_i. A macro because the shells
// live in a std::vector on the CPU and in a storage buffer on the GPU, and the
// common subset has no pointers.
#define ATMOSH_LUT_SHELL_INDEX(k, S, rho, RHO_AT) \
  {                                               \
    int lut_lo_ = 0;                              \
    int lut_hi_ = (S);                            \
    while (lut_lo_ < lut_hi_) {                   \
      int lut_mid_ = (lut_lo_ + lut_hi_) / 2;     \
      if (RHO_AT(lut_mid_) > (rho))               \
        lut_hi_ = lut_mid_;                       \
      else                                        \
        lut_lo_ = lut_mid_ + 1;                   \
    }                                             \
    (k) = lut_lo_ - 1;                            \
  }

// The lookup's window in rho (OpticalDepthLut::shell_weights, sky_lib.glsl's
// interpolate): its first shell w for the shell interval k of S shells and the four
// Lagrange weights lw[0..3] at rho; RHO_AT(i) the shells' rho, DEN_AT(i) their inverse
// denominators (OpticalDepthLut::shell_inverse_denominators: window w, node i at 4 w + i).
#define ATMOSH_LUT_SHELL_WEIGHTS(lw, w, k, S, rho, RHO_AT, DEN_AT)                                           \
  {                                                                                                           \
    (w) = lut_window_start((k), (S));                                                                         \
    for (int lut_i_ = 0; lut_i_ < 4; ++lut_i_)                                                                \
      (lw)[lut_i_] = lut_shell_weight((rho), DEN_AT((w) * 4 + lut_i_), RHO_AT(w), RHO_AT((w) + 1), RHO_AT((w) + 2), \
                                      RHO_AT((w) + 3), lut_i_);                                               \
  }

// The lookup's window in x: its first direction sample jw of n around x and the four
// cubic Lagrange weights xw[0..3] at x.
#define ATMOSH_LUT_DIRECTION_WEIGHTS(xw, jw, x, n)                                                   \
  {                                                                                                   \
    (jw) = lut_direction_window((x), (n));                                                            \
    for (int lut_m_ = 0; lut_m_ < 4; ++lut_m_)                                                        \
      (xw)[lut_m_] = lagrange_cubic_weight(lut_direction_offset((x), (n), (jw)), lut_m_);             \
  }

// The lookup's 4 x 4 window sum (OpticalDepthLut::interpolate's window_sum,
// sky_lib.glsl's interpolate): acc = sum_i lw[i] (xw[0] e_i0 + xw[1] e_i1 + xw[2] e_i2 +
// xw[3] e_i3), e_im = ENTRY(i, m) the entry of shell w + i and direction jw + m (a
// vector of the constituents, type T3; ZERO its zero), in this order on both sides.
#define ATMOSH_LUT_WINDOW_SUM(T3, ZERO, acc, lw, xw, ENTRY)                                                     \
  {                                                                                                           \
    acc = ZERO;                                                                                               \
    for (int lut_i_ = 0; lut_i_ < 4; ++lut_i_) {                                                              \
      T3 lut_e0_ = ENTRY(lut_i_, 0), lut_e1_ = ENTRY(lut_i_, 1), lut_e2_ = ENTRY(lut_i_, 2), lut_e3_ = ENTRY(lut_i_, 3); \
      acc += (lw)[lut_i_] * ((xw)[0] * lut_e0_ + (xw)[1] * lut_e1_ + (xw)[2] * lut_e2_ + (xw)[3] * lut_e3_);  \
    }                                                                                                         \
  }

// A stored table value decoded to the mean relative density along the table ray: the
// exponential where the table holds its logarithm, else the value (at least 0). Float
// on the GPU (pasted once; GLSL has no double exp).
ATMOSH_FN real lut_decode(real v, bool log_encoded) { return log_encoded ? glm::exp(v) : glm::max(v, real(0)); }

// Table build: the sub-pieces of the piece [a, b] of the ray from radius r with
// zenith cosine mu (squared tangent radius rt2), lut_piece_count of them for the scale
// height H, each with the n-point rule of RULE_X(g) in (0, 1) and weights RULE_W(g)
// summing to 1: NODE(s, w) for every node (distance s, weight w [m]), in order.
#define ATMOSH_LUT_PIECE_NODES(T, r, mu, rt2, a, b, H, n, RULE_X, RULE_W, NODE)                      \
  {                                                                                                 \
    T lut_ra_ = radius_along((r), (mu), (a));                                                       \
    T lut_rb_ = radius_along((r), (mu), (b));                                                       \
    int lut_m_ = lut_piece_count(lut_ra_, lut_rb_, (b) - (a), (rt2), (H));                          \
    T lut_h_ = ((b) - (a)) / T(lut_m_);                                                             \
    for (int lut_p_ = 0; lut_p_ < lut_m_; ++lut_p_) {                                               \
      T lut_lo_ = (a) + T(lut_p_) * lut_h_;                                                         \
      for (int lut_g_ = 0; lut_g_ < (n); ++lut_g_) NODE(lut_lo_ + RULE_X(lut_g_) * lut_h_, RULE_W(lut_g_) * lut_h_); \
    }                                                                                               \
  }

// Table build (OpticalDepthLut::build_column, gpu/shaders/lut_build.comp): the ray
// from radius r with zenith cosine mu over s in [0, L] is cut at the tangent point
// s_t = -r mu and wherever it crosses one of the N sorted radii (s = s_t -+ q,
// q = sqrt(radius^2 - r_t^2), r_t the tangent radius): the inward crossings, largest
// radius first, then s_t, then the outward crossings — already in order along the
// ray, so no sort. PIECE(a, b) is called for each piece 0 = a < b ... b = L between
// consecutive cuts inside (0, L); T is the scalar type (double on both sides),
// RADIUS_AT(i) the i-th radius. A macro for the reason given above.
#define ATMOSH_LUT_RAY_PIECES(T, r, mu, L, N, RADIUS_AT, PIECE)              \
  {                                                                          \
    T lut_rt2_ = (r) * (r) * ((T(1) - (mu)) * (T(1) + (mu)));                \
    T lut_rt_ = glm::sqrt(lut_rt2_ > T(0) ? lut_rt2_ : T(0));                  \
    T lut_t_ = -(r) * (mu);                                                  \
    T lut_prev_ = T(0);                                                      \
    for (int lut_k_ = (N) - 1; lut_k_ >= 0; --lut_k_) {                      \
      T lut_kr_ = RADIUS_AT(lut_k_);                                         \
      if (lut_kr_ < lut_rt_) break;                                          \
      T lut_s_ = lut_t_ - glm::sqrt((lut_kr_ - lut_rt_) * (lut_kr_ + lut_rt_));\
      if (lut_s_ > lut_prev_ && lut_s_ < (L)) {                              \
        PIECE(lut_prev_, lut_s_);                                            \
        lut_prev_ = lut_s_;                                                  \
      }                                                                      \
    }                                                                        \
    if (lut_t_ > lut_prev_ && lut_t_ < (L)) {                                \
      PIECE(lut_prev_, lut_t_);                                              \
      lut_prev_ = lut_t_;                                                    \
    }                                                                        \
    for (int lut_k_ = 0; lut_k_ < (N); ++lut_k_) {                           \
      T lut_kr_ = RADIUS_AT(lut_k_);                                         \
      if (lut_kr_ < lut_rt_) continue;                                       \
      T lut_s_ = lut_t_ + glm::sqrt((lut_kr_ - lut_rt_) * (lut_kr_ + lut_rt_));\
      if (lut_s_ > lut_prev_ && lut_s_ < (L)) {                              \
        PIECE(lut_prev_, lut_s_);                                            \
        lut_prev_ = lut_s_;                                                  \
      }                                                                      \
    }                                                                        \
    if ((L) > lut_prev_) PIECE(lut_prev_, (L));                              \
  }

#endif

// Cosine of the zenith angle of a fixed direction (cosine c at the ray's origin,
// radius r; cosine nu with the ray direction) at distance s along a ray whose
// radius there is rs: (r c + s nu) / rs — the sun's zenith cosine at a sample of
// a view ray (c = mu_s), clamped to [-1, 1] against rounding.
ATMOSH_FN real cos_zenith_along(real r, real c, real nu, real s, real rs) {
  return glm::clamp((r * c + s * nu) / rs, real(-1), real(1));
}

// Distance along a view ray (origin radius r, view cosine mu, sun cosine mu_s,
// cos(view, sun) nu) at which the sun ray from the point grazes the ground sphere R:
// root i (0 or 1) of (1 - nu^2) s^2 + 2 r (mu - mu_s nu) s + (r^2 - R^2 - r^2 mu_s^2)
// = 0, i.e. |P|^2 - (P.l)^2 = R^2, kept only where P.l = r mu_s + s nu < 0 (the sun
// below the point's horizon side) and s > 0; -1 otherwise. The single-scattering
// integrand jumps there (the edge of the Earth's shadow), so the integrators cut
// the view ray at these distances. Stable root formulas (no cancellation in q).
ATMOSH_FN real shadow_edge_distance(real r, real mu, real mu_s, real nu, real R, int i) {
  real a = (real(1) - nu) * (real(1) + nu);
  real b = r * (mu - mu_s * nu);
  real c = (r - R) * (r + R) - r * r * mu_s * mu_s;
  real s = real(-1);
  if (a < real(1e-12)) {
    if (i == 0 && b != real(0)) s = -c / (real(2) * b);
  } else {
    real disc = b * b - a * c;
    if (disc >= real(0)) {
      real q = -(b + (b >= real(0) ? real(1) : real(-1)) * glm::sqrt(disc));
      if (q != real(0)) s = (i == 0) ? q / a : c / q;
    }
  }
  return (s > real(0) && r * mu_s + s * nu < real(0)) ? s : real(-1);
}

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
