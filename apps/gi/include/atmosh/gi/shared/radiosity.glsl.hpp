// atmosh/gi/shared/radiosity.glsl.hpp — the per-receiver math of the multi-bounce
// radiosity approximation (atmosh/gi/radiosity.hpp), written once for the CPU and the GPU.
//
// The code between ATMOSH_GLSL_BEGIN and ATMOSH_GLSL_END is in the common subset of C++
// with GLM and GLSL (the convention of libatmo/include/atmosh/atmo/shared/, docs/gpu.md):
// `real` scalars and `real3` vectors, glm:: functions that GLSL has under the same name
// (dot, reflect, normalize, lessThan, any), no std::, no pointers, no recursion; arrays
// are fixed-size parameters. The CPU build uses real = double, real3 = glm::dvec3.
//
// The volume is reached through four functions the caller provides (`fetch` functions):
//   real  gi_fetch_distance(ctx, p, d)  distance from p to the first surface along unit d
//                                       (the probe volume's SH distance, interpolated at p);
//   real3 gi_fetch_normal(ctx, q)       the volume's (bent) surface normal near q, of length
//                                       0..1 (its coherence; below 0.3 the walk turns back);
//   real3 gi_fetch_albedo(ctx, q)       the material volume's reflectivity near q (0..1);
//   real3 gi_direct_irradiance(ctx, q, n)  the direct irradiance at q on a surface of normal n
//                                       (sun, emitters, sky; shadowed as the caller can).
// In C++ they are found by argument-dependent lookup on the context type (the loop is a
// function template over it); a shader defines them (without the context argument) before
// pasting the block with
//   #define real float
//   #define real3 vec3
//   #define ATMOSH_FN
//   #define ATMOSH_GI_TEMPLATE
//   #define ATMOSH_GI_CTX
//   #define ATMOSH_GI_CTX_ARG
// (and every "glm::" deleted, as cmake/AtmoshEmbedGlsl.cmake does).
//
// The approximation (one ray per bounce): the irradiance a receiver at x with normal n gets
// from other surfaces is taken as pi L_in(x, n), L_in the radiance arriving along the single
// direction n (exact for an incident field that is constant over the hemisphere). L_in is
// found by walking: from p = x along d = n by the SH distance s to q = p + s d; there the
// volume gives the surface normal n_q (turned to face p; -d where the volume's normal is
// shorter than 0.3, i.e. incoherent) and the reflectivity rho_q; q leaves
// rho_q / pi E_direct(q) towards p; the walk reflects, d <- reflect(d, n_q), and repeats:
//   L_in = sum_{b=1..B} (prod_{k<b} rho_k) rho_b / pi E_direct(q_b),
// ending early where the walk leaves the volume's box (the sky it would see there is direct
// light of the vertex it left, already in that vertex's E_direct).
// Receiver radiance (the caller's): L = L_e + a / pi (E_direct(x, n) + pi L_in(x, n)).
// Units: lengths in the scene's unit, radiance in the lights' (see scene.hpp).
// Accuracy: the formulas are exact up to rounding in `real`; the method's error against the
// path tracer is measured (docs/gi.md).
#pragma once

#include <glm/glm.hpp>

namespace atmosh::gi::shared {

using real = double;
using real3 = glm::dvec3;  // GLSL: vec3 (#define real3 vec3)
#ifndef ATMOSH_FN
#define ATMOSH_FN inline __attribute__((always_inline))
#endif
#define ATMOSH_GI_TEMPLATE template <class Ctx>
#define ATMOSH_GI_CTX const Ctx &ctx,
#define ATMOSH_GI_CTX_ARG ctx,

// ATMOSH_GLSL_BEGIN

// Real SH of bands 0..2 (atmosh/sh/basis.hpp: orthonormal, Condon–Shortley phase, index
// l (l + 1) + m) at the unit direction d, dotted with c: sum_{i < bands^2} c_i Y_i(d).
// bands in 1..3.
ATMOSH_FN real gi_sh_eval(const real c[9], int bands, real3 d) {
  real s = c[0] * real(0.28209479177387814);
  if (bands > 1) {
    s += real(0.48860251190291992) * (-c[1] * d.y + c[2] * d.z - c[3] * d.x);
  }
  if (bands > 2) {
    s += real(1.0925484305920792) * (c[4] * d.x * d.y - c[5] * d.y * d.z - c[7] * d.x * d.z);
    s += real(0.31539156525252005) * c[6] * (real(3) * d.z * d.z - real(1));
    s += real(0.54627421529603959) * c[8] * (d.x * d.x - d.y * d.y);
  }
  return s;
}

// Irradiance at unit normal n of radiance coefficients c (bands 1..3): the clamped-cosine
// convolution A_l = pi, 2 pi / 3, pi / 4 (Ramamoorthi & Hanrahan 2001, eq. 8).
ATMOSH_FN real gi_sh_irradiance(const real c[9], int bands, real3 n) {
  real s = c[0] * real(0.28209479177387814) * real(3.14159265358979324);
  if (bands > 1) {
    s += real(2.09439510239319549) * real(0.48860251190291992) * (-c[1] * n.y + c[2] * n.z - c[3] * n.x);
  }
  if (bands > 2) {
    real q = real(1.0925484305920792) * (c[4] * n.x * n.y - c[5] * n.y * n.z - c[7] * n.x * n.z);
    q += real(0.31539156525252005) * c[6] * (real(3) * n.z * n.z - real(1));
    q += real(0.54627421529603959) * c[8] * (n.x * n.x - n.y * n.y);
    s += real(0.78539816339744831) * q;
  }
  return s;
}

// True if q lies inside the box [lo, hi] widened by 1e-5 of its longest edge on every side: a
// step that ends on a face of the box (the wall of a closed room, where the fetched distance
// lands) counts as inside whatever the rounding. Without the slack, float on a GPU ends such
// walks after their first bounce: q = p + s d comes out a few ulps outside (seen on an NVIDIA
// H200, driver 580, where p + s d is fused; llvmpipe happened to round inside).
ATMOSH_FN bool gi_inside_box(real3 q, real3 lo, real3 hi) {
  real3 e = hi - lo;
  real slack = real(1e-5) * glm::max(e.x, glm::max(e.y, e.z));
  return !(glm::any(glm::lessThan(q, lo - real3(slack))) || glm::any(glm::lessThan(hi + real3(slack), q)));
}

// Radiance arriving at x along its unit normal n (the walk above), `bounces` >= 0 steps;
// the walk ends when it leaves the box [lo, hi] or after the last bounce.
ATMOSH_GI_TEMPLATE ATMOSH_FN real3 gi_radiosity_incident(ATMOSH_GI_CTX real3 x, real3 n, int bounces, real3 lo,
                                                         real3 hi) {
  real3 p = x;
  real3 d = n;
  real3 throughput = real3(1);
  real3 L = real3(0);
  for (int b = 0; b < bounces; ++b) {
    real s = glm::max(gi_fetch_distance(ATMOSH_GI_CTX_ARG p, d), real(0));
    real3 q = p + s * d;
    if (!gi_inside_box(q, lo, hi)) {
      break;
    }
    real3 nq = gi_fetch_normal(ATMOSH_GI_CTX_ARG q);
    real len = glm::length(nq);
    nq = len > real(0.3) ? nq / len : -d;  // no coherent surface there: turn back
    if (glm::dot(nq, d) > real(0)) {
      nq = -nq;  // the side facing p
    }
    real3 rho = gi_fetch_albedo(ATMOSH_GI_CTX_ARG q);
    L += throughput * rho * gi_direct_irradiance(ATMOSH_GI_CTX_ARG q, nq) * real(0.31830988618379067);
    throughput *= rho;
    d = glm::reflect(d, nq);
    p = q;
  }
  return L;
}

// ATMOSH_GLSL_END

}  // namespace atmosh::gi::shared
