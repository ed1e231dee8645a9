// atmosh/atmo/shared/view_ray.glsl.hpp — the cut points of a view ray of the
// single-scattering integrand, written once for the CPU (SkyIntegrator::radiance;
// real = double) and the GPU (gpu/shaders/sky.comp, which pastes this block once
// after redefining real as double: cut positions need double, a float distance
// carries ~0.1 m at 1000 km). Same common subset and conventions as
// geometry.glsl.hpp; the struct is returned by value (no out parameters).
//
// Accuracy: exact up to rounding in the real type.
#pragma once

#include <glm/glm.hpp>

#include "atmosh/atmo/shared/lut.glsl.hpp"

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

const int kMaxCutSpheres = 64;                    // spheres that cut a view ray
const int kMaxViewCuts = 2 * kMaxCutSpheres + 5;  // + 2 shadow edges, the tangent point, both ends

// Distances s [m] along the view ray, ascending, that split it into the pieces
// the integrator integrates: 0, the crossings of the spheres radii[0..n_radii)
// (ascending radii [m], n_radii <= kMaxCutSpheres) inside (0, s_end), the
// tangent point, the edges of the Earth's shadow (shadow_edge_distance) and
// s_end. r, mu: origin radius and view zenith cosine; mu_s, nu: sun zenith
// cosine at the origin and cos(view, sun); R ground radius; s_end the ray's
// length inside the atmosphere; rt2 = tangent_radius_sq(r, mu). The sphere
// crossings are generated in order (inward ones outermost first, the tangent
// point, outward ones innermost first: t -/+ sqrt(k^2 - rt2) is monotone in k
// also after rounding), the two shadow edges are inserted, so no sort is needed.
// Pieces of zero length (repeated values) may occur; callers skip them.
struct ViewRayCuts {
  real s[kMaxViewCuts];
  int n;
};

// The cuts without the shadow edges: they depend on the view ray only (an image
// row of one zenith angle shares them; SkyIntegrator::radiance_same_zenith).
ATMOSH_FN ViewRayCuts view_ray_sphere_cuts(real r, real mu, real s_end, real rt2, const real radii[kMaxCutSpheres],
                                           int n_radii) {
  ViewRayCuts c;
  c.s[0] = real(0);
  c.n = 1;
  real t = -r * mu;  // tangent_distance
  for (int k = n_radii - 1; k >= 0; --k) {
    real disc = radii[k] * radii[k] - rt2;
    if (disc < real(0)) continue;
    real s = t - glm::sqrt(disc);
    if (s > real(0) && s < s_end) {
      c.s[c.n] = s;
      c.n += 1;
    }
  }
  if (t > real(0) && t < s_end) {
    c.s[c.n] = t;
    c.n += 1;
  }
  for (int k = 0; k < n_radii; ++k) {
    real disc = radii[k] * radii[k] - rt2;
    if (disc < real(0)) continue;
    real s = t + glm::sqrt(disc);
    if (s > real(0) && s < s_end) {
      c.s[c.n] = s;
      c.n += 1;
    }
  }
  c.s[c.n] = s_end;
  c.n += 1;
  return c;
}

// True when the view ray crosses an edge of the Earth's shadow inside (0, s_end):
// exactly when view_ray_cuts has more cuts than view_ray_sphere_cuts.
ATMOSH_FN bool view_ray_crosses_shadow(real r, real mu, real mu_s, real nu, real R, real s_end) {
  for (int i = 0; i < 2; ++i) {
    real se = shadow_edge_distance(r, mu, mu_s, nu, R, i);
    if (se > real(0) && se < s_end) return true;
  }
  return false;
}

ATMOSH_FN ViewRayCuts view_ray_cuts(real r, real mu, real mu_s, real nu, real R, real s_end, real rt2,
                                    const real radii[kMaxCutSpheres], int n_radii) {
  ViewRayCuts c = view_ray_sphere_cuts(r, mu, s_end, rt2, radii, n_radii);
  for (int i = 0; i < 2; ++i) {
    real se = shadow_edge_distance(r, mu, mu_s, nu, R, i);
    if (se > real(0) && se < s_end) {
      int j = c.n;
      while (j > 0 && c.s[j - 1] > se) {
        c.s[j] = c.s[j - 1];
        j -= 1;
      }
      c.s[j] = se;
      c.n += 1;
    }
  }
  return c;
}

// ATMOSH_GLSL_END

#undef ATMOSH_FN

}  // namespace atmosh::atmo::shared
