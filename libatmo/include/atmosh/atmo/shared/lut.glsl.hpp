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

// Weight of sample i (0..3) of the cubic Lagrange interpolant through equally
// spaced samples at 0, 1, 2, 3, evaluated at p (p in [0, 3] inside the window).
ATMOSH_FN real lagrange_cubic_weight(real p, int i) {
  if (i == 0) return -(p - real(1)) * (p - real(2)) * (p - real(3)) / real(6);
  if (i == 1) return p * (p - real(2)) * (p - real(3)) / real(2);
  if (i == 2) return -p * (p - real(1)) * (p - real(3)) / real(2);
  return p * (p - real(1)) * (p - real(2)) / real(6);
}

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
