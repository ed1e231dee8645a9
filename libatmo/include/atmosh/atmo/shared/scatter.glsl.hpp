// atmosh/atmo/shared/scatter.glsl.hpp — the pieces and the integrand of the
// single-scattering integral along a view ray, written once for the CPU
// (SkyIntegrator::radiance; real = double) and the GPU (gpu/shaders/sky.comp,
// which pastes this block in double and in float). Same common subset and
// conventions as geometry.glsl.hpp.
//
// Along a view ray, L(lambda) = E_sun(lambda) sum over quadrature nodes s of
//   T(lambda, s) [beta_R(lambda) rho_R(s) P_R(nu) + beta_M(lambda) rho_M(s) P_M(nu)] w(s)
// with T = exp(-tau) the transmittance sun -> s -> observer, tau the extinction
// optical depth of the column x (per constituent, [m] of ground-density
// equivalent) and beta the scattering coefficients at the ground [1/m]. Each
// piece between two cuts (view_ray.glsl.hpp) is split into equal parts of at
// most `max_tau` extinction optical depth, judged at its densest point, and each
// part gets the same Gauss-Legendre rule. The view optical depth from the observer
// to a node is accumulated along the ray itself: the columns of the parts before it
// plus the integral, from the start of its part to the node, of the polynomial
// through the densities at the part's ends and nodes (sky_part_column_weights).
// Accuracy: exact up to rounding in the real type.
#pragma once

#include <glm/glm.hpp>

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

// Densest point of the piece [a, b] of the ray from radius r with zenith cosine mu
// (st = -r mu, the tangent point): st if inside the piece, else the end nearer the
// planet's centre (|s + r mu| is the distance from the tangent point).
ATMOSH_FN real piece_densest_point(real r, real mu, real st, real a, real b) {
  if (st > a && st < b) return st;
  return glm::abs(a + r * mu) < glm::abs(b + r * mu) ? a : b;
}

// Equal parts of a piece of extinction optical depth tau_piece (judged at its
// densest point) so that each has at most max_tau: 1..64.
ATMOSH_FN int piece_parts(real tau_piece, real max_tau) {
  return glm::max(int(glm::min(real(64), glm::ceil(tau_piece / max_tau))), 1);
}

// End of part p (p = 0..parts; part p is [sky_part_end(p), sky_part_end(p + 1)]) of a
// piece [a0, b0] split into `parts` equal parts: a0 + (b0 - a0) p / parts, and b0
// exactly for p = parts. The caller puts the n-point Gauss-Legendre rule on each part
// and accumulates the view column with the part weights of sky_part_column_weights
// (sky.hpp): sky_trace (view_ray.glsl.hpp).
ATMOSH_FN real sky_part_end(real a0, real b0, int p, int parts) {
  return p == parts ? b0 : a0 + (b0 - a0) * real(p) / real(parts);
}

// Extinction optical depth of the column x = (x_R, x_M, x_O) [m] with extinction
// coefficients e0, e1, e2 [1/m] at one wavelength.
ATMOSH_FN real column_optical_depth(real e0, real e1, real e2, real x0, real x1, real x2) {
  return e0 * x0 + e1 * x1 + e2 * x2;
}

// The integrand at one node and one wavelength: transmittance exp(-tau) (computed
// by the caller: the CPU's vectorised exp, the GPU's exp) times the scattered
// part, sca_r sr + sca_m sm with sr = rho_R P_R w and sm = rho_M P_M w.
ATMOSH_FN real scattering_term(real transmittance, real sca_r, real sca_m, real sr, real sm) {
  return transmittance * (sca_r * sr + sca_m * sm);
}

// Ground reflection seen at the end of the ray (Lambertian, albedo a): the
// irradiance fraction a / pi * mu_s at the ground, attenuated by exp(-tau).
ATMOSH_FN real ground_term(real albedo, real mu_s_ground, real transmittance) {
  return albedo / real(3.14159265358979323846) * mu_s_ground * transmittance;
}

#ifndef ATMOSH_SHARED_SCATTER_ONCE  // parts without `real`: once, however often the block is pasted
#define ATMOSH_SHARED_SCATTER_ONCE
const int kMaxPartNodes = 8;  // Gauss-Legendre nodes per part (SkyOptions::samples_per_segment <= 8)
#endif

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
