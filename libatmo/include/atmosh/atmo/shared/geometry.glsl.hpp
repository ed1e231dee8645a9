// atmosh/atmo/shared/geometry.glsl.hpp — ray geometry in a spherical atmosphere,
// density profiles and phase functions, written once for the CPU and the GPU.
//
// The code between ATMOSH_GLSL_BEGIN and ATMOSH_GLSL_END is in the common subset
// of C++ with GLM and GLSL: only `real` scalars, glm:: functions that GLSL has
// under the same name, no std:: (except in `#ifndef ATMOSH_GLSL` branches,
// which the GPU prelude's `#define ATMOSH_GLSL 1` removes), no recursion, no
// pointers. A shader gets it by
// pasting that block after `#define real float` (or double), `#define
// ATMOSH_FN` and deleting every "glm::" qualifier. The CPU reference uses real =
// double.
//
// Geometry conventions (all lengths in metres, angles as cosines):
//   r   distance of a point from the planet centre;
//   mu  cosine of the zenith angle of a ray direction at that point (mu = 1 is
//       straight up, mu = 0 horizontal, mu = -1 straight down);
//   s   distance travelled along the ray from its origin (s >= 0);
//   R   ground radius, T top-of-atmosphere radius (R < T).
// The radius along the ray is r(s) = sqrt((s + r mu)^2 + r_t^2) with the
// tangent radius r_t = r sqrt(1 - mu^2); this form (rather than
// sqrt(r^2 + 2 r mu s + s^2)) keeps full relative precision near the tangent
// point. Discriminants are formed as differences of products that do not cancel
// catastrophically for grazing rays and are clamped at 0 against rounding.
//
// Phase functions are normalised to 1 over the sphere (per steradian) and take
// cos_theta = cosine of the scattering angle between the direction the light
// travelled before scattering and the direction after it: cos_theta = 1 is
// exact forward scattering (for a sky seen along view direction v with the sun
// in direction l, both unit vectors pointing away from the observer,
// cos_theta = dot(v, l)). A positive g means forward-peaked.
//
// Arrays are fixed-size parameters (`const real a[N]`): a copy in GLSL, a pointer
// in C++ (where N is not enforced).
//
// Accuracy: every function is exact up to rounding in the real type (a few ulp,
// except the tent density, which is exact, and the distances, whose absolute
// error is ~1e-16 * r for double).
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline __attribute__((always_inline))  // hot loops on the CPU

// ATMOSH_GLSL_BEGIN

// Squared tangent radius r^2 (1 - mu^2), computed as r^2 (1 - mu)(1 + mu).
ATMOSH_FN real tangent_radius_sq(real r, real mu) {
  return glm::max(r * r * ((real(1) - mu) * (real(1) + mu)), real(0));
}

// Distance along the ray from its origin to the tangent (closest-approach)
// point; negative when the tangent point lies behind the origin (mu > 0).
ATMOSH_FN real tangent_distance(real r, real mu) { return -r * mu; }

// Radius at distance s along the ray (see header comment for the stable form).
ATMOSH_FN real radius_along(real r, real mu, real s) {
  real d = s + r * mu;
  return glm::sqrt(d * d + tangent_radius_sq(r, mu));
}

// Cosine of the zenith angle of the ray at distance s (radius rs = radius_along).
ATMOSH_FN real mu_along(real r, real mu, real s, real rs) {
  return glm::clamp((r * mu + s) / rs, real(-1), real(1));
}

// Discriminant r^2 (mu^2 - 1) + k^2 for a sphere of radius k, written as
// (k - r)(k + r) + r^2 mu^2 so that no large terms cancel when r ~ k.
ATMOSH_FN real sphere_discriminant(real r, real mu, real k) {
  return (k - r) * (k + r) + r * r * mu * mu;
}

// True when the ray from radius r (r >= R) with cosine mu meets the ground.
ATMOSH_FN bool ray_hits_ground(real r, real mu, real R) {
  return mu < real(0) && sphere_discriminant(r, mu, R) >= real(0);
}

// Distance to the ground along a ray that hits it (ray_hits_ground is true).
// Uses the conjugate form ((r - R)(r + R)) / (-r mu + sqrt(disc)) so that the
// distance stays accurate when the origin is just above the ground.
ATMOSH_FN real distance_to_ground(real r, real mu, real R) {
  real disc = glm::max(sphere_discriminant(r, mu, R), real(0));
  real den = -r * mu + glm::sqrt(disc);
  real num = glm::max((r - R) * (r + R), real(0));
  return den > real(0) ? num / den : real(0);
}

// Distance to the top of the atmosphere (radius T) for an origin inside it
// (r <= T); 0 on the top looking outward.
ATMOSH_FN real distance_to_top(real r, real mu, real T) {
  real disc = glm::max(sphere_discriminant(r, mu, T), real(0));
  real q = glm::sqrt(disc);
  real num = glm::max((T - r) * (T + r), real(0));
  // mu >= 0: -r mu + q cancels, use num / (r mu + q).
  return mu >= real(0) ? ((r * mu + q) > real(0) ? num / (r * mu + q) : real(0)) : -r * mu + q;
}

// Distance at which a ray from outside (r > T) enters the sphere of radius T;
// negative when it misses (then the ray never enters the atmosphere).
ATMOSH_FN real distance_to_top_from_outside(real r, real mu, real T) {
  real disc = sphere_discriminant(r, mu, T);
  if (disc < real(0) || mu >= real(0)) return real(-1);
  return (r - T) * (r + T) / (-r * mu + glm::sqrt(disc));
}

// Cosine of the zenith angle of the horizon (the ray grazing the ground) seen
// from radius r >= R: -sqrt(1 - (R/r)^2).
ATMOSH_FN real mu_horizon(real r, real R) {
  return -glm::sqrt(glm::max((r - R) * (r + R), real(0))) / r;
}

// The rest (densities, closed-form columns, phase functions) is pasted once, in
// float: a shader may paste this block a second time after `#define real double`
// for double overloads of the ray geometry above (gpu::sky_parts); GLSL has no
// double exp, and the constant and struct below must not be declared twice.
#ifndef ATMOSH_SHARED_GEOMETRY_ONCE
#define ATMOSH_SHARED_GEOMETRY_ONCE

// 1/(4 pi), 3/(16 pi), 3/(8 pi).
ATMOSH_FN real inv_four_pi() { return real(0.079577471545947667884); }

// ---- density profiles (relative density, dimensionless, of altitude h [m]) ----

ATMOSH_FN real density_exponential(real h, real scale_height) {
  return glm::exp(-h / scale_height);
}

// Value at h of the function linear from (ha, va) to (hb, vb): a tabulated profile
// between two of its nodes (DensityProfile, sky_lib.glsl's density_nodes); va where
// hb <= ha.
ATMOSH_FN real linear_between(real h, real ha, real hb, real va, real vb) {
  return hb > ha ? va + (h - ha) / (hb - ha) * (vb - va) : va;
}

// 0 below bottom and above top, 1 at peak, linear in between.
ATMOSH_FN real density_tent(real h, real bottom, real peak, real top) {
  if (h <= bottom || h >= top) return real(0);
  if (h <= peak) return (h - bottom) / (peak - bottom);
  return (top - h) / (top - peak);
}

// ---- closed-form column of a profile linear in radius along a ray piece ----

// log(1 + x) for x > -1, accurate to a few ulp also for tiny x, without a log1p
// (which GLSL lacks) and without log near 1: GLSL guarantees log only to an
// absolute 2^-21 for arguments in [0.5, 2] (GLSL 4.30 spec, sec. 4.7.1), which
// would leave log(1 + x) ~ 1e-3 relative error at x ~ 1e-3 on a GPU. For
// 1 + x in [0.5, 2] the series log(1 + x) = 2 atanh(z) = 2 (z + z^3/3 + z^5/5
// + ...) with z = x / (2 + x), |z| <= 1/3, is summed to 20 terms (truncation
// < (1/9)^20 / 41 ~ 1e-20 relative); elsewhere log(1 + x) (1 + x exact for
// x < -0.5 by Sterbenz's lemma, and log well conditioned for x > 1). Compiled on
// both sides (the CPU tests it against log1p: test_shared_traversal.cpp).
ATMOSH_FN real log1p_series(real x) {
  if (x < real(-0.5) || x > real(1)) return glm::log(real(1) + x);
  real z = x / (real(2) + x);
  real z2 = z * z;
  real sum = real(0);
  for (int k = 20; k >= 1; --k) sum = (sum + real(1) / real(2 * k + 1)) * z2;
  return real(2) * z * (real(1) + sum);
}

// log(1 + x): log1p_series on the GPU; on the CPU (C++, ATMOSH_GLSL undefined) the
// C library's log1p, correctly rounded to ~1 ulp and ~10x cheaper than the series,
// which matters because the optical-depth tables call this per ray piece at every
// lookup.
ATMOSH_FN real log1p_accurate(real x) {
#ifdef ATMOSH_GLSL
  return log1p_series(x);
#else
  return std::log1p(x);
#endif
}

// With u = s + r mu the radius along the ray is sqrt(u^2 + c_sq) (c_sq = tangent
// radius squared). On a piece [ua, ub] that does not contain the tangent point
// in its interior (ua * ub >= 0) and on which the density is v0 + slope (r - r0),
// the column is v0 (ub - ua) + slope (I - r0 (ub - ua)) with
//   I = integral sqrt(u^2 + c^2) du = [u r + c^2 asinh(u / c)] / 2 |_ua^ub.
// Both differences are formed without cancellation (m = (ra + rb)/2,
// t = (ua + ub) / (2 m)):
//   ub rb - ua ra = (ub - ua) m (1 + t^2)            (rb - ra = (ub - ua) t),
//   asinh(ub/c) - asinh(ua/c) = log((|u_f| + r_f) / (|u_n| + r_n))
//                             = log1p((ub - ua)(1 + |t|) / (|u_n| + r_n))
// with n / f the ends nearer to / farther from the tangent point; this stays
// finite as c -> 0 (vertical rays: the c^2 term vanishes). ra, rb are the radii
// at ua, ub (pass the exact node radius where the piece ends on a sphere). The
// only rounding beyond a few ulp is in I - r0 (ub - ua), an absolute error
// ~1e-16 r0 (ub - ua) |slope|: the same as evaluating the density at the
// rounded altitude r - R, which every quadrature of the profile does too.
ATMOSH_FN real linear_piece_column(real ua, real ub, real ra, real rb, real c_sq, real v0, real slope, real r0) {
  real du = ub - ua;
  if (!(du > real(0))) return real(0);
  real m = real(0.5) * (ra + rb);
  if (!(m > real(0))) return v0 * du;
  real t = real(0.5) * (ua + ub) / m;
  real near_sum = (ua >= real(0)) ? ua + ra : rb - ub;
  real dasinh = (c_sq > real(0) && near_sum > real(0))
                    ? log1p_accurate(du * (real(1) + glm::abs(t)) / near_sum) : real(0);
  real integral_r = real(0.5) * (du * m * (real(1) + t * t) + c_sq * dasinh);
  return v0 * du + slope * (integral_r - r0 * du);
}

// ---- column of a piecewise-linear profile along a ray (closed form) ----

// Node capacity of the GLSL build, whose array parameters have a fixed size.
// In C++ an array parameter is a pointer, so the CPU build takes any node count.
const int kMaxLinearNodes = 16;

// State of the walk along a ray in piecewise_linear_column: the current
// position u = ua (radius ra), the column so far, idx = number of nodes below
// the current position (0: below the profile, n: above it; density 0 there),
// done once the end of the ray is reached.
struct LinearColumnWalk {
  real ua;
  real ra;
  real sum;
  int idx;
  bool done;
};

// One breakpoint of the walk at u (radius ru) after which the position lies in
// node interval idx_after: adds the piece up to min(u, u1) when the current
// interval has density, then moves there (breakpoints behind the current
// position only update idx). u1, r1: the end of the ray and its radius.
ATMOSH_FN LinearColumnWalk linear_column_cross(LinearColumnWalk w, real u, real ru, int idx_after, real u1, real r1,
                                               real c2, const real radius[kMaxLinearNodes],
                                               const real value[kMaxLinearNodes], const real slope[kMaxLinearNodes],
                                               int n) {
  if (u >= u1) {
    if (w.idx > 0 && w.idx < n)
      w.sum += linear_piece_column(w.ua, u1, w.ra, r1, c2, value[w.idx - 1], slope[w.idx - 1], radius[w.idx - 1]);
    w.done = true;
    return w;
  }
  if (u > w.ua) {
    if (w.idx > 0 && w.idx < n)
      w.sum += linear_piece_column(w.ua, u, w.ra, ru, c2, value[w.idx - 1], slope[w.idx - 1], radius[w.idx - 1]);
    w.ua = u;
    w.ra = ru;
  }
  w.idx = idx_after;
  return w;
}

// Column [m] (integral of the relative density over distance) along the ray
// from radius r with cosine mu over s in [0, len] of a profile given at n >= 2
// nodes: radius[i] ascending [m], value[i], slope[i] = d value / d radius on
// (radius[i], radius[i+1]) [1/m]; linear in radius between the nodes and 0
// outside them. With u = s + r mu the breakpoints are walked in their order
// along the ray: the inward crossings of the node spheres (u = -q_k, outermost
// first), the tangent point (u = 0), the outward crossings (u = +q_k), where
// q_k = sqrt(sphere_discriminant(r, mu, radius[k])); every piece between two
// consecutive breakpoints inside [0, len] gets linear_piece_column. Coming from
// u = -infinity the state is idx = n; crossing node k inward sets idx = k,
// outward idx = k + 1. q: scratch for n values (written here, not read by the
// caller). Accuracy: that of linear_piece_column, summed over at most 2 n + 1
// pieces.
ATMOSH_FN real piecewise_linear_column(real r, real mu, real len, const real radius[kMaxLinearNodes],
                                       const real value[kMaxLinearNodes], const real slope[kMaxLinearNodes], int n,
                                       real q[kMaxLinearNodes]) {
  if (!(len > real(0)) || n < 2) return real(0);
  real c2 = tangent_radius_sq(r, mu);
  real u0 = r * mu;
  real u1 = u0 + len;
  // Lowest radius on the ray: the tangent radius if the tangent point (u = 0)
  // is on it, else an end. A ray entirely above the last node or below the
  // first has no column.
  real r1sq = u1 * u1 + c2;
  real rmin_sq = (u0 < real(0) && u1 > real(0)) ? c2 : glm::min(r * r, r1sq);
  real rmax_sq = glm::max(r * r, r1sq);
  if (rmin_sq >= radius[n - 1] * radius[n - 1] || rmax_sq <= radius[0] * radius[0]) return real(0);
  real r1 = glm::sqrt(r1sq);
  int first = n;  // innermost node sphere the ray's line crosses (the discriminant grows with the radius)
  for (int k = n - 1; k >= 0; --k) {
    real D = sphere_discriminant(r, mu, radius[k]);
    if (!(D > real(0))) break;
    q[k] = glm::sqrt(D);
    first = k;
  }
  LinearColumnWalk w;
  w.ua = u0;
  w.ra = r;
  w.sum = real(0);
  w.idx = n;
  w.done = false;
  if (u0 < real(0)) {
    for (int k = n - 1; k >= first && !w.done; --k)
      w = linear_column_cross(w, -q[k], radius[k], k, u1, r1, c2, radius, value, slope, n);
    if (!w.done) w = linear_column_cross(w, real(0), glm::sqrt(c2), w.idx, u1, r1, c2, radius, value, slope, n);
  } else {
    w.idx = first;  // the state at the tangent point (behind the origin)
  }
  for (int k = first; k < n && !w.done; ++k)
    w = linear_column_cross(w, q[k], radius[k], k + 1, u1, r1, c2, radius, value, slope, n);
  if (!w.done && w.idx > 0 && w.idx < n)
    w.sum += linear_piece_column(w.ua, u1, w.ra, r1, c2, value[w.idx - 1], slope[w.idx - 1], radius[w.idx - 1]);
  // Values of either sign: a density's column (values >= 0) may come out ~-1e-15
  // from rounding in pieces where it nearly vanishes (a ray grazing a tent's top):
  // its callers clamp at 0.
  return w.sum;
}

// ---- column of quadratic ramps along a ray ----

// Nodes x_i > 0 and weights w_i of the 8-point Gauss-Legendre rule on [-1, 1]
// (symmetric: the nodes are +-x_i; Abramowitz & Stegun 1964, table 25.4).
ATMOSH_FN real gauss8_node(int i) {
  return i == 0 ? real(0.18343464249564980494) : i == 1 ? real(0.52553240991632898582)
       : i == 2 ? real(0.79666647741362673959) : real(0.96028985649753623168);
}
ATMOSH_FN real gauss8_weight(int i) {
  return i == 0 ? real(0.36268378337836198297) : i == 1 ? real(0.31370664587788728734)
       : i == 2 ? real(0.22238103445337447054) : real(0.10122853629037625915);
}

// Integral over u in [lo, hi] (inside |u| <= a, a^2 = k^2 - c_sq) of e(u)^2 with
// e(u) = k - sqrt(u^2 + c_sq), formed without cancellation as
// (a - u)(a + u) / (k + r(u)): a quartic in u times 1 / (k + r)^2, which varies by
// less than (k - c) / k over the chord. One 8-point Gauss-Legendre rule over the
// whole interval, also across the tangent point u = 0 (for c_sq >= R^2, the rays
// above the ground, r(u) is analytic in |u| < c): relative error <= 2e-15 for
// chords of shells up to 86 km above an Earth-sized ground (tested against
// composite high-order quadrature), and the result is smooth in the ray's
// direction. A ray through the planet (c < R with u = 0 inside) gets no such bound.
ATMOSH_FN real ramp_square_chord(real lo, real hi, real a, real k, real c_sq) {
  real h = real(0.5) * (hi - lo);
  if (!(h > real(0))) return real(0);
  real m = real(0.5) * (lo + hi);
  real sum = real(0);
  for (int i = 0; i < 4; ++i) {
    real x = gauss8_node(i) * h;
    real u1 = m - x, u2 = m + x;
    real e1 = (a - u1) * (a + u1) / (k + glm::sqrt(u1 * u1 + c_sq));
    real e2 = (a - u2) * (a + u2) / (k + glm::sqrt(u2 * u2 + c_sq));
    sum += gauss8_weight(i) * (e1 * e1 + e2 * e2);
  }
  return sum * h;
}

// Column [m] along the ray from radius r with cosine mu over s in [0, len] of
// q(r) = sum_k half_curv[k] (radius[k] - r)_+^2 for n ramps (radius[k] [m],
// half_curv[k] [1/m^2]; n <= kMaxLinearNodes in GLSL): each ramp's support on the
// ray is |u| < a_k = sqrt(sphere_discriminant(r, mu, radius[k])) (u = s + r mu),
// cut to [r mu, r mu + len]. A radius at or below the tangent radius adds nothing.
// The caller stops the ray at the ground.
ATMOSH_FN real quadratic_ramps_column(real r, real mu, real len, const real radius[kMaxLinearNodes],
                                      const real half_curv[kMaxLinearNodes], int n) {
  if (!(len > real(0))) return real(0);
  real c2 = tangent_radius_sq(r, mu);
  real u0 = r * mu;
  real u1 = u0 + len;
  real sum = real(0);
  for (int k = 0; k < n; ++k) {
    real D = sphere_discriminant(r, mu, radius[k]);
    if (!(D > real(0))) continue;
    real a = glm::sqrt(D);
    sum += half_curv[k] * ramp_square_chord(glm::max(u0, -a), glm::min(u1, a), a, radius[k], c2);
  }
  return sum;
}

// The ramps themselves at altitude h [m] (QuadraticRampsColumn::at, the GPU table
// build's table_density): sum_k half_curv[k] ((radius[k] - R) - h)_+^2, 0 below the
// ground (h < 0).
ATMOSH_FN real quadratic_ramps_at(real h, const real radius[kMaxLinearNodes], const real half_curv[kMaxLinearNodes],
                                  int n, real R) {
  real q = real(0);
  if (h < real(0)) return q;
  for (int k = 0; k < n; ++k) {
    real d = glm::max(real(0), (radius[k] - R) - h);
    q += half_curv[k] * d * d;
  }
  return q;
}

// A table column with its subtracted kinks' closed-form columns added back (linear
// pieces and quadratic ramps; OpticalDepthLut::add_closed_form, sky_lib.glsl's
// sun_lookup): at least 0.
ATMOSH_FN real column_added_back(real column, real linear, real ramps) {
  return glm::max(real(0), column + linear + ramps);
}

// ---- phase functions [1/sr], cos_theta as defined in the header comment ----

// Rayleigh with depolarisation factor rho_n (Chandrasekhar 1950, sec. 18):
// gamma = rho_n / (2 - rho_n), p = 3 / (16 pi (1 + 2 gamma)) (1 + 3 gamma + (1 - gamma) mu^2).
ATMOSH_FN real phase_rayleigh(real cos_theta, real depolarization) {
  real gamma = depolarization / (real(2) - depolarization);
  return real(3) / (real(16) * real(3.14159265358979323846) * (real(1) + real(2) * gamma)) *
         (real(1) + real(3) * gamma + (real(1) - gamma) * cos_theta * cos_theta);
}

// Henyey & Greenstein (1941): (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^{3/2}); the
// denominator is formed as (1 - g)^2 + 2 g (1 - mu), free of cancellation near
// mu = 1, g -> 1 (and (1 + g)^2 - 2 g (1 + mu) for g < 0).
ATMOSH_FN real hg_denominator(real cos_theta, real g) {
  return g >= real(0) ? (real(1) - g) * (real(1) - g) + real(2) * g * (real(1) - cos_theta)
                      : (real(1) + g) * (real(1) + g) - real(2) * g * (real(1) + cos_theta);
}

ATMOSH_FN real phase_hg(real cos_theta, real g) {
  real d = hg_denominator(cos_theta, g);
  return inv_four_pi() * (real(1) - g) * (real(1) + g) / (d * glm::sqrt(d));
}

// Cornette & Shanks (1992), eq. (4):
// 3 (1 - g^2) (1 + mu^2) / (8 pi (2 + g^2) (1 + g^2 - 2 g mu)^{3/2}).
// g is a shape parameter, not the mean cosine.
ATMOSH_FN real phase_cornette_shanks(real cos_theta, real g) {
  real d = hg_denominator(cos_theta, g);
  return real(3) / (real(8) * real(3.14159265358979323846)) * (real(1) - g) * (real(1) + g) *
         (real(1) + cos_theta * cos_theta) / ((real(2) + g * g) * d * glm::sqrt(d));
}

// Two-lobe Henyey-Greenstein: w HG(g1) + (1 - w) HG(g2).
ATMOSH_FN real phase_double_hg(real cos_theta, real g1, real g2, real w) {
  return w * phase_hg(cos_theta, g1) + (real(1) - w) * phase_hg(cos_theta, g2);
}

// The analytic phase function of model code `model` (the order of PhaseSpec::Model:
// 0 Rayleigh, 1 Henyey-Greenstein, 2 Cornette-Shanks, 3 double HG) with parameters a
// (the depolarisation factor for Rayleigh, else g), g2 and w (double HG's second lobe
// and the first lobe's weight).
ATMOSH_FN real phase_analytic(int model, real cos_theta, real a, real g2, real w) {
  if (model == 0) return phase_rayleigh(cos_theta, a);
  if (model == 1) return phase_hg(cos_theta, a);
  if (model == 2) return phase_cornette_shanks(cos_theta, a);
  return phase_double_hg(cos_theta, a, g2, w);
}

#endif  // ATMOSH_SHARED_GEOMETRY_ONCE

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
