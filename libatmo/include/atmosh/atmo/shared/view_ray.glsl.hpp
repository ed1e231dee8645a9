// atmosh/atmo/shared/view_ray.glsl.hpp — a view ray of the single-scattering sky:
// its set-up (observer inside the atmosphere or entering it from above), its cut
// points and the walk along it that yields the quadrature nodes with their densities
// and view columns, written once for the CPU (SkyIntegrator; real = double) and the
// GPU (gpu/shaders/sky.comp, which pastes this block once after redefining real as
// double: cut positions need double, a float distance carries ~0.1 m at 1000 km).
// Same common subset and conventions as geometry.glsl.hpp; structs are returned by
// value (no out parameters).
//
// Accuracy: exact up to rounding in the real type.
#pragma once

#include <glm/glm.hpp>

#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/atmo/shared/scatter.glsl.hpp"

namespace atmosh::atmo::shared {

using real = double;
using real3 = glm::dvec3;  // GLSL: dvec3 (gpu::real_type_part)
// Arrays of real indexed at run time hold real_array elements, read by ATMOSH_GET(a, i)
// and written as ATMOSH_PUT(value): plain doubles here; in GLSL's double build uvec2
// through packDouble2x32 / unpackDouble2x32 (gpu::real_type_part), because NVIDIA's
// driver 580 keeps dynamically indexed local double arrays, and struct member arrays
// of doubles, at float precision (docs/gpu.md, "Double-precision local arrays").
using real_array = double;
#define ATMOSH_GET(a, i) (a)[i]
#define ATMOSH_PUT(v) (v)
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
  real_array s[kMaxViewCuts];
  int n;
};

// The cuts without the shadow edges: they depend on the view ray only (an image
// row of one zenith angle shares them; SkyIntegrator::radiance_same_zenith).
ATMOSH_FN ViewRayCuts view_ray_sphere_cuts(real r, real mu, real s_end, real rt2,
                                           const real_array radii[kMaxCutSpheres], int n_radii) {
  ViewRayCuts c;
  c.s[0] = ATMOSH_PUT(real(0));
  c.n = 1;
  real t = -r * mu;  // tangent_distance
  for (int k = n_radii - 1; k >= 0; --k) {
    real disc = ATMOSH_GET(radii, k) * ATMOSH_GET(radii, k) - rt2;
    if (disc < real(0)) continue;
    real s = t - glm::sqrt(disc);
    if (s > real(0) && s < s_end) {
      c.s[c.n] = ATMOSH_PUT(s);
      c.n += 1;
    }
  }
  if (t > real(0) && t < s_end) {
    c.s[c.n] = ATMOSH_PUT(t);
    c.n += 1;
  }
  for (int k = 0; k < n_radii; ++k) {
    real disc = ATMOSH_GET(radii, k) * ATMOSH_GET(radii, k) - rt2;
    if (disc < real(0)) continue;
    real s = t + glm::sqrt(disc);
    if (s > real(0) && s < s_end) {
      c.s[c.n] = ATMOSH_PUT(s);
      c.n += 1;
    }
  }
  c.s[c.n] = ATMOSH_PUT(s_end);
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
                                    const real_array radii[kMaxCutSpheres], int n_radii) {
  ViewRayCuts c = view_ray_sphere_cuts(r, mu, s_end, rt2, radii, n_radii);
  for (int i = 0; i < 2; ++i) {
    real se = shadow_edge_distance(r, mu, mu_s, nu, R, i);
    if (se > real(0) && se < s_end) {
      int j = c.n;
      for (; j > 0; j -= 1) {  // read, then compare: a packed read in a while condition gave
        real prev = ATMOSH_GET(c.s, j - 1);  // wrong cuts on Mesa 22.3 llvmpipe
        if (!(prev > se)) break;
        c.s[j] = c.s[j - 1];
      }
      c.s[j] = ATMOSH_PUT(se);
      c.n += 1;
    }
  }
  return c;
}

// ---- the view ray of a pixel ----

// A view ray reduced to the planet-centred 2-D geometry and clipped to the
// atmosphere (lengths in m): origin radius r and view zenith cosine mu (at the
// entry point for an observer above the top), sun zenith cosine mu_s there,
// nu = cos(view, sun) (constant along the ray), s_end the length inside the
// atmosphere; empty: the ray misses it; ground: it ends on the ground.
struct SkyViewRay {
  real r;
  real mu;
  real mu_s;
  real nu;
  real s_end;
  bool empty;
  bool ground;
};

// The view ray from radius r >= R (view zenith cosine mu, sun zenith cosine mu_s,
// nu = cos(view, sun) in [-1, 1]) in the atmosphere between R and T: an observer
// above the top is moved to the entry point (radius T exactly, cosines carried along
// the ray), or the ray is empty when it misses the atmosphere.
ATMOSH_FN SkyViewRay sky_view_ray(real r, real mu, real mu_s, real nu, real R, real T) {
  SkyViewRay ray;
  ray.r = r;
  ray.mu = mu;
  ray.mu_s = mu_s;
  ray.nu = nu;
  ray.s_end = real(0);
  ray.empty = false;
  ray.ground = false;
  if (r > T) {
    real d = distance_to_top_from_outside(r, mu, T);
    if (d < real(0)) {
      ray.empty = true;
      return ray;
    }
    ray.mu = glm::clamp((r * mu + d) / T, real(-1), real(1));
    ray.mu_s = glm::clamp((r * mu_s + d * nu) / T, real(-1), real(1));
    ray.r = T;
  }
  ray.ground = ray_hits_ground(ray.r, ray.mu, R);
  ray.s_end = ray.ground ? distance_to_ground(ray.r, ray.mu, R) : distance_to_top(ray.r, ray.mu, T);
  return ray;
}

// The view ray of direction v from radius r with the sun in direction l (unit vectors
// in the observer's frame, z up): sky_view_ray of their zenith cosines and cos(v, l).
ATMOSH_FN SkyViewRay sky_view_ray_toward(real r, real3 v, real3 l, real R, real T) {
  return sky_view_ray(r, v.z, l.z, glm::clamp(glm::dot(v, l), real(-1), real(1)), R, T);
}

// Altitude [m] of the point of radius rs above the ground sphere R as the densities
// take it: rs - R, and the ground where rounding puts a ray's end on it below.
ATMOSH_FN real sky_altitude(real rs, real R) { return glm::max(rs - R, real(0)); }

// Cosine of the sun's zenith angle where the ray meets the ground (ray.ground).
ATMOSH_FN real sky_ground_sun_cosine(SkyViewRay ray) {
  return cos_zenith_along(ray.r, ray.mu_s, ray.nu, ray.s_end, radius_along(ray.r, ray.mu, ray.s_end));
}

// Whether the ground at the end of the ray reflects sunlight: the ray ends on it, the
// albedo is positive and the sun is above the horizon there (mus_g =
// sky_ground_sun_cosine(ray) > 0).
ATMOSH_FN bool sky_ground_lit(SkyViewRay ray, real albedo, real mus_g) {
  return ray.ground && albedo > real(0) && mus_g > real(0);
}

// ---- the walk along the ray: quadrature nodes, densities, view columns ----

const int kMaxPartWeights = (kMaxPartNodes + 1) * (kMaxPartNodes + 2);  // sky_part_column_weights

// A quadrature node of a view ray: distance s from the origin and radius r [m],
// quadrature weight w [m], relative densities rho and the view column from the origin
// to the node [m] (Rayleigh, Mie, ozone).
struct SkyViewNode {
  real s;
  real r;
  real w;
  real3 rho;
  real3 column;
};

// Cosine of the sun's zenith angle at the node nd of the ray.
ATMOSH_FN real sky_node_sun_cosine(SkyViewRay ray, SkyViewNode nd) {
  return cos_zenith_along(ray.r, ray.mu_s, ray.nu, nd.s, nd.r);
}

// What the spectral loop needs of a node outside the Earth's shadow, in single
// precision: the column sun -> node -> observer x [m] (Rayleigh, Mie, ozone: the
// node's view column plus sun_column, its column toward the sun) and the scattering
// weights sr = rho_R P_R w and sm = rho_M P_M w (P [1/sr] the phase functions at nu).
struct SkyNodeTerms {
  float x[3];
  float sr;
  float sm;
};
ATMOSH_FN SkyNodeTerms sky_node_terms(SkyViewNode nd, real3 sun_column, real p_ray, real p_mie) {
  SkyNodeTerms t;
  real3 x = nd.column + sun_column;
  t.x[0] = float(x[0]);
  t.x[1] = float(x[1]);
  t.x[2] = float(x[2]);
  t.sr = float(nd.rho[0] * p_ray * nd.w);
  t.sm = float(nd.rho[1] * p_mie * nd.w);
  return t;
}

// The column from the start of a part (half its length: half_len [m]) to its node `row`
// (row n_nodes: to its end), from the densities at the part's start, nodes and end
// and the weights part_w of sky_part_column_weights ((n + 1) x (n + 2), row-major).
// nq_rho: the nodes' densities, 3 per node.
ATMOSH_FN real3 sky_part_column(const real_array part_w[kMaxPartWeights], int row, int n_nodes, real half_len,
                                real3 rho_start, const real_array nq_rho[3 * kMaxPartNodes], real3 rho_end) {
  int o = row * (n_nodes + 2);
  real3 x = ATMOSH_GET(part_w, o) * rho_start + ATMOSH_GET(part_w, o + n_nodes + 1) * rho_end;
  for (int j = 0; j < n_nodes; ++j)
    x += ATMOSH_GET(part_w, o + j + 1) *
         real3(ATMOSH_GET(nq_rho, 3 * j), ATMOSH_GET(nq_rho, 3 * j + 1), ATMOSH_GET(nq_rho, 3 * j + 2));
  return half_len * x;
}

// The walk needs two functions of the caller: sky_density(h), the relative densities
// at altitude h [m] (real3), and sky_visit(node), called for every node in order
// along the ray. On the CPU they are the arguments (lambdas); a shader that defines
// ATMOSH_SKY_TRACE defines them as functions, declared here.
#ifdef ATMOSH_GLSL
#define ATMOSH_SKY_HOOK_TEMPLATE
#define ATMOSH_SKY_HOOKS
#define ATMOSH_SKY_HOOK_ARGS
#ifdef ATMOSH_SKY_TRACE
real3 sky_density(real h);
void sky_visit(SkyViewNode nd);
#endif
#else
#define ATMOSH_SKY_HOOK_TEMPLATE template <class SkyDensity, class SkyVisit>
#define ATMOSH_SKY_HOOKS , SkyDensity&& sky_density, SkyVisit&& sky_visit
#define ATMOSH_SKY_HOOK_ARGS , sky_density, sky_visit
#endif

#if !defined(ATMOSH_GLSL) || defined(ATMOSH_SKY_TRACE)
// The nodes of the view ray cut at cuts[0..nc) (view_ray_cuts), in order: each piece
// between two cuts is split into piece_parts equal parts by its extinction optical
// depth at its densest point (extinction per constituent ext_max [1/m]: the largest
// over the wavelengths; max_tau), each part gets the n_nodes-point Gauss-Legendre rule
// (nodes gx, weights gw on [-1, 1]) and the view column is accumulated along the ray
// with the part weights part_w. Returns the ray's whole view column [m]. The density
// at a piece's end that is its densest point is evaluated once.
ATMOSH_SKY_HOOK_TEMPLATE
ATMOSH_FN real3 sky_trace(SkyViewRay ray, const real_array cuts[kMaxViewCuts], int nc, real R, real3 ext_max,
                          real max_tau, const real_array gx[kMaxPartNodes], const real_array gw[kMaxPartNodes],
                          int n_nodes, const real_array part_w[kMaxPartWeights] ATMOSH_SKY_HOOKS) {
  real st = tangent_distance(ray.r, ray.mu);
  real3 column = real3(0);
  real3 rho_start = sky_density(ray.r - R);  // r >= R
  real_array nq_s[kMaxPartNodes], nq_r[kMaxPartNodes], nq_w[kMaxPartNodes], nq_rho[3 * kMaxPartNodes];  // a part's nodes
  for (int k = 1; k < nc; ++k) {
    real a0 = ATMOSH_GET(cuts, k - 1);
    real b0 = ATMOSH_GET(cuts, k);
    if (!(b0 > a0)) continue;
    real sd = piece_densest_point(ray.r, ray.mu, st, a0, b0);
    bool end_known = false;  // the density at b0, when it is the densest point
    real3 rho_d = rho_start;
    if (sd == b0) {
      rho_d = sky_density(sky_altitude(radius_along(ray.r, ray.mu, b0), R));
      end_known = true;
    } else if (sd != a0) {
      rho_d = sky_density(sky_altitude(radius_along(ray.r, ray.mu, sd), R));
    }
    real3 rho_b0 = rho_d;
    int parts = piece_parts(glm::dot(ext_max, rho_d) * (b0 - a0), max_tau);
    for (int p = 0; p < parts; ++p) {
      real a = sky_part_end(a0, b0, p, parts);
      real b = sky_part_end(a0, b0, p + 1, parts);
      real half_len = real(0.5) * (b - a);
      real mid = real(0.5) * (a + b);
      for (int q = 0; q < n_nodes; ++q) {
        real s = mid + half_len * ATMOSH_GET(gx, q);
        real rs = radius_along(ray.r, ray.mu, s);
        real3 rho = sky_density(sky_altitude(rs, R));
        nq_s[q] = ATMOSH_PUT(s);
        nq_r[q] = ATMOSH_PUT(rs);
        nq_w[q] = ATMOSH_PUT(half_len * ATMOSH_GET(gw, q));
        for (int c = 0; c < 3; ++c) nq_rho[3 * q + c] = ATMOSH_PUT(rho[c]);
      }
      real3 rho_end = (end_known && b == b0) ? rho_b0 : sky_density(sky_altitude(radius_along(ray.r, ray.mu, b), R));
      for (int q = 0; q < n_nodes; ++q) {
        SkyViewNode nd;
        nd.s = ATMOSH_GET(nq_s, q);
        nd.r = ATMOSH_GET(nq_r, q);
        nd.w = ATMOSH_GET(nq_w, q);
        nd.rho = real3(ATMOSH_GET(nq_rho, 3 * q), ATMOSH_GET(nq_rho, 3 * q + 1), ATMOSH_GET(nq_rho, 3 * q + 2));
        nd.column = column + glm::max(sky_part_column(part_w, q, n_nodes, half_len, rho_start, nq_rho, rho_end), real3(0));
        sky_visit(nd);
      }
      column += glm::max(sky_part_column(part_w, n_nodes, n_nodes, half_len, rho_start, nq_rho, rho_end), real3(0));
      rho_start = rho_end;
    }
  }
  return column;
}

// The walk along the whole view ray (SkyIntegrator::radiance, sky.comp): its cuts at the
// spheres cut_radii[0..n_cuts) (view_ray_cuts), then sky_trace along them.
ATMOSH_SKY_HOOK_TEMPLATE
ATMOSH_FN real3 sky_walk(SkyViewRay ray, const real_array cut_radii[kMaxCutSpheres], int n_cuts, real R,
                         real3 ext_max, real max_tau, const real_array gx[kMaxPartNodes],
                         const real_array gw[kMaxPartNodes], int n_nodes,
                         const real_array part_w[kMaxPartWeights] ATMOSH_SKY_HOOKS) {
  ViewRayCuts vc = view_ray_cuts(ray.r, ray.mu, ray.mu_s, ray.nu, R, ray.s_end, tangent_radius_sq(ray.r, ray.mu),
                                 cut_radii, n_cuts);
  return sky_trace(ray, vc.s, vc.n, R, ext_max, max_tau, gx, gw, n_nodes, part_w ATMOSH_SKY_HOOK_ARGS);
}
#endif

// ATMOSH_GLSL_END

#undef ATMOSH_FN
#undef ATMOSH_SKY_HOOK_TEMPLATE
#undef ATMOSH_SKY_HOOKS
#undef ATMOSH_SKY_HOOK_ARGS
#undef ATMOSH_GET
#undef ATMOSH_PUT

}  // namespace atmosh::atmo::shared
