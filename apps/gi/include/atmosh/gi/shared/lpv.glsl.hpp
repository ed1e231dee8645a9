// atmosh/gi/shared/lpv.glsl.hpp — the math of a light propagation volume (atmosh/gi/lpv.hpp,
// Kaplanyan & Dachsbacher 2010), written once for the CPU (apps/gi/src/lpv.cpp) and the GPU
// (gpu/shaders/gi_lpv_*: the separate passes and the GPU-resident frame of gpu/gi_raster.hpp).
//
// Common subset of C++/GLM and GLSL, as radiosity.glsl.hpp (whose gi_sh_eval and
// gi_sh_irradiance this block uses, so it is pasted after that block): real = double,
// real3 = glm::dvec3, real4 = glm::dvec4 on the CPU; float, vec3, vec4 on the GPU (a shader
// #defines real4 vec4 before pasting). Cells hold the radiant intensity I(w) of the light
// travelling along w as SH bands 0-1 (4 coefficients, index l (l + 1) + m, atmosh/sh/basis.hpp)
// per channel; the grid's cell (i, j, k) has index (k ny + j) nx + i, its corners
// (k (ny + 1) + j) (nx + 1) + i.
//
// The volume is reached through functions the caller provides (found by
// argument-dependent lookup on the context type in C++; plain functions in a shader, declared
// before the block is pasted):
//   real4 gi_lpv_fetch(ctx, ivec3 s, int ch)    cell s's coefficients of channel ch (0..2);
//   real  gi_lpv_open(ctx, ivec3 t, ivec3 s, int d, int f)
//                                               1 - blocking of face f of the light that cell s
//                                               sends to its neighbour t = s + step(d) (along
//                                               gi_lpv_face_direction(d, f));
//   real4 gi_lpv_face_y(ctx, int d, int f)      gi_lpv_sh4(gi_lpv_face_direction(d, f)), and
//   real4 gi_lpv_face_reemit(ctx, int d, int f) gi_lpv_reemit_choice(reemission, d, f): the
//                                               gather's per-face constants (a table on the CPU;
//                                               in a shader gi_lpv_decl.glsl computes them);
//   real  gi_lpv_fetch_corner(ctx, int c, int q)  the geometry volume's coefficient q (0..8) at
//                                               corner c.
// Units: lengths in the scene's unit; I in the lights' radiance unit x length^2. Accuracy:
// exact up to rounding in `real`; the face solid angles are derived in docs/gi.md.
#pragma once

#include <glm/glm.hpp>

#include "atmosh/gi/shared/radiosity.glsl.hpp"

namespace atmosh::gi::shared {

using real4 = glm::dvec4;  // GLSL: vec4 (#define real4 vec4)

// ATMOSH_GLSL_BEGIN

// Y_00, Y_1-1, Y_10, Y_11 at the unit direction d (Condon–Shortley phase).
ATMOSH_FN real4 gi_lpv_sh4(real3 d) {
  return real4(real(0.28209479177387814), real(-0.48860251190291992) * d.y, real(0.48860251190291992) * d.z,
               real(-0.48860251190291992) * d.x);
}

// A Lambertian emitter of unit flux about the unit normal n, I(w) = max(0, n . w) / pi: its
// coefficients 1 / pi A_l Y_lm(n) with A_0 = pi, A_1 = 2 pi / 3: Y_00, 2/3 Y_1m.
ATMOSH_FN real4 gi_lpv_lobe(real3 n) {
  real c = real(2) / real(3);
  return gi_lpv_sh4(n) * real4(real(1), c, c, c);
}

// Exact solid angles, seen from the source cell's centre, of the neighbour's far face
// (4 asin(1/10)) and of one of its four side faces (2 (atan(3 / sqrt(11)) - pi / 6)); unit
// cells; the 30 faces of the 6 neighbours partition the sphere (docs/gi.md).
ATMOSH_FN real gi_lpv_front_solid_angle() { return real(4) * glm::asin(real(0.1)); }
ATMOSH_FN real gi_lpv_side_solid_angle() {
  return real(2) * (glm::atan(real(3) / glm::sqrt(real(11))) - real(3.14159265358979324) / real(6));
}

// Propagation direction d in 0..5: axis d / 2, sign + for even d (the unit step e).
ATMOSH_FN glm::ivec3 gi_lpv_step(int d) {
  glm::ivec3 e = glm::ivec3(0);
  e[d / 2] = (d % 2 == 0) ? 1 : -1;
  return e;
}

// Normal of face f of the neighbour along direction d: f = 0 the far face (normal e); f = 1..4
// the side faces, the two other axes in increasing order, sign + then -.
ATMOSH_FN real3 gi_lpv_face_normal(int d, int f) {
  int axis = d / 2;
  real3 n = real3(0);
  if (f == 0) {
    n[axis] = (d % 2 == 0) ? real(1) : real(-1);
    return n;
  }
  int idx = f - 1;
  int other = (idx / 2 == 0) ? (axis == 0 ? 1 : 0) : (axis == 2 ? 1 : 2);
  n[other] = (idx % 2 == 0) ? real(1) : real(-1);
  return n;
}

// Unit direction from the source cell's centre to the centre of face f (unit cells): e for the
// far face, normalize(e + n_f / 2) for a side face.
ATMOSH_FN real3 gi_lpv_face_direction(int d, int f) {
  real3 e = real3(gi_lpv_step(d));
  if (f == 0) return e;
  return glm::normalize(e + real(0.5) * gi_lpv_face_normal(d, f));
}

// The SH-4 per unit flux with which the light crossing face f of the neighbour along d is
// re-emitted from the neighbour's centre: the band-limited direction w_f of the face's centre,
// Y_lm(w_f) (c_00 = Y00: flux 1; band 1 = Y_1m(w_f): net flux vector w_f). Summed over the 30
// faces, sum_f dOmega_f Y_1m(w_f) Y_1m'(w_f) = delta_mm' (cubic symmetry: sum dOmega_f w_f w_f^T
// = 4 pi / 3 I), so a step in empty space keeps both the flux and the net flux vector (band 1)
// exactly. Kaplanyan & Dachsbacher 2010 re-emit a Lambertian lobe about the face normal
// (gi_lpv_lobe(gi_lpv_face_normal(d, f))), which keeps only (2 Omega_F + 8 Omega_S / sqrt 5) /
// (2 pi) = 0.369 of band 1 per step: a step forgets a fixed share of the light's direction
// whatever the cell size, so the finer the grid, the more the light diffuses before it has
// travelled a given distance, and surfaces light themselves (docs/gi.md, "Why the LPV's error
// grew with its grid").
ATMOSH_FN real4 gi_lpv_reemit_sh(int d, int f) { return gi_lpv_sh4(gi_lpv_face_direction(d, f)); }

// The re-emission by choice (atmosh/gi/lpv.hpp, LpvReemission): 0 gi_lpv_reemit_sh (the default);
// 1 Kaplanyan & Dachsbacher 2010's Lambertian lobe of unit flux about the face normal,
// gi_lpv_lobe(gi_lpv_face_normal(d, f)), for comparison with the published method.
ATMOSH_FN real4 gi_lpv_reemit_choice(int reemission, int d, int f) {
  if (reemission == 1) return gi_lpv_lobe(gi_lpv_face_normal(d, f));
  return gi_lpv_reemit_sh(d, f);
}

// The cell holding p (clamped into the grid; a non-finite coordinate gives cell 0).
ATMOSH_FN glm::ivec3 gi_lpv_cell_of(real3 p, real3 lo, real h, glm::ivec3 dims) {
  glm::ivec3 c = glm::ivec3(0);
  for (int k = 0; k < 3; ++k) {
    real x = (p[k] - lo[k]) / h;
    if (glm::isnan(x) || glm::isinf(x)) {
      c[k] = 0;
    } else {
      x = glm::clamp(x, real(-1), real(dims[k]));
      c[k] = glm::clamp(int(glm::floor(x)), 0, dims[k] - 1);
    }
  }
  return c;
}

// The geometry volume's blocking at the face cell s shares with its neighbour along d, for
// light travelling along unit w: the mean of the face's 4 corners (3-band SH of the covered
// fraction of the cross-section) evaluated at w, clamped to [0, 1].
ATMOSH_GI_TEMPLATE ATMOSH_FN real gi_lpv_face_blocking(ATMOSH_GI_CTX glm::ivec3 s, int d, glm::ivec3 dims, real3 w) {
  int axis = d / 2;
  glm::ivec3 c = s;
  if (d % 2 == 0) c[axis] += 1;
  int a1 = (axis + 1) % 3;
  int a2 = (axis + 2) % 3;
  real acc[9];
  for (int q = 0; q < 9; ++q) acc[q] = real(0);
  for (int u = 0; u < 2; ++u) {
    for (int v = 0; v < 2; ++v) {
      glm::ivec3 p = c;
      p[a1] += u;
      p[a2] += v;
      int idx = (p.z * (dims.y + 1) + p.y) * (dims.x + 1) + p.x;
      for (int q = 0; q < 9; ++q) acc[q] += real(0.25) * gi_lpv_fetch_corner(ATMOSH_GI_CTX_ARG idx, q);
    }
  }
  return glm::clamp(gi_sh_eval(acc, 3, w), real(0), real(1));
}

// The coefficients of one cell, per channel.
struct GiLpvRgb {
  real4 r;
  real4 g;
  real4 b;
};

// One propagation step into cell c (a gather): from each face neighbour s = c - e that holds
// light, the flux through the 5 faces of c other than the shared one, dOmega_f I_s(w_f)
// open_f, re-emitted from c's centre along w_f (gi_lpv_reemit_sh, through the caller's
// gi_lpv_face_reemit); the three channels at once. `blocking` false: every face open (gi_lpv_open is not called).
ATMOSH_GI_TEMPLATE ATMOSH_FN GiLpvRgb gi_lpv_gather(ATMOSH_GI_CTX glm::ivec3 c, glm::ivec3 dims, bool blocking) {
  real front = gi_lpv_front_solid_angle();
  real side = gi_lpv_side_solid_angle();
  GiLpvRgb sum;
  sum.r = real4(0);
  sum.g = real4(0);
  sum.b = real4(0);
  for (int d = 0; d < 6; ++d) {
    glm::ivec3 s = c - gi_lpv_step(d);
    if (glm::any(glm::lessThan(s, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(s, dims))) continue;
    real4 sr = gi_lpv_fetch(ATMOSH_GI_CTX_ARG s, 0);
    real4 sg = gi_lpv_fetch(ATMOSH_GI_CTX_ARG s, 1);
    real4 sb = gi_lpv_fetch(ATMOSH_GI_CTX_ARG s, 2);
    if (sr.x == real(0) && sr.y == real(0) && sr.z == real(0) && sr.w == real(0) && sg.x == real(0) &&
        sg.y == real(0) && sg.z == real(0) && sg.w == real(0) && sb.x == real(0) && sb.y == real(0) &&
        sb.z == real(0) && sb.w == real(0)) {
      continue;
    }
    for (int f = 0; f < 5; ++f) {
      real v = blocking ? gi_lpv_open(ATMOSH_GI_CTX_ARG c, s, d, f) : real(1);
      if (v <= real(0)) continue;
      real om = (f == 0 ? front : side) * v;
      real4 y = gi_lpv_face_y(ATMOSH_GI_CTX_ARG d, f);
      real4 e = gi_lpv_face_reemit(ATMOSH_GI_CTX_ARG d, f);
      // component by component (vector temporaries are memcpy calls in a sanitizer build)
      real kr = om * (sr.x * y.x + sr.y * y.y + sr.z * y.z + sr.w * y.w);
      real kg = om * (sg.x * y.x + sg.y * y.y + sg.z * y.z + sg.w * y.w);
      real kb = om * (sb.x * y.x + sb.y * y.y + sb.z * y.z + sb.w * y.w);
      sum.r.x += kr * e.x;
      sum.r.y += kr * e.y;
      sum.r.z += kr * e.z;
      sum.r.w += kr * e.w;
      sum.g.x += kg * e.x;
      sum.g.y += kg * e.y;
      sum.g.z += kg * e.z;
      sum.g.w += kg * e.w;
      sum.b.x += kb * e.x;
      sum.b.y += kb * e.y;
      sum.b.z += kb * e.z;
      sum.b.w += kb * e.w;
    }
  }
  return sum;
}

// Irradiance at unit normal n of the intensity coefficients c read as radiance I / h^2 of the
// light travelling against n: (1 / h^2) sum A_l c_lm Y_lm(-n), clamped at 0.
ATMOSH_FN real gi_lpv_irradiance4(real4 c, real3 n, real h) {
  real co[9];
  co[0] = c.x;
  co[1] = c.y;
  co[2] = c.z;
  co[3] = c.w;
  for (int q = 4; q < 9; ++q) co[q] = real(0);
  return glm::max(real(0), gi_sh_irradiance(co, 2, -n) * (real(1) / (h * h)));
}

// The LPV's irradiance at a receiver x with unit normal n (turned towards the viewer): the
// cells' coefficients interpolated trilinearly (cell centres, clamped) at x + h/2 n, then
// gi_lpv_irradiance4 per channel.
ATMOSH_GI_TEMPLATE ATMOSH_FN real3 gi_lpv_receiver_irradiance(ATMOSH_GI_CTX real3 x, real3 n, real3 lo, real h,
                                                              glm::ivec3 dims) {
  real3 p = x + real(0.5) * h * n;
  glm::ivec3 i0 = glm::ivec3(0);
  glm::ivec3 i1 = glm::ivec3(0);
  real3 f = real3(0);
  for (int k = 0; k < 3; ++k) {
    real t = (p[k] - lo[k]) / h - real(0.5);
    if (glm::isnan(t) || glm::isinf(t)) t = real(0);
    t = glm::clamp(t, real(0), real(dims[k] - 1));
    i0[k] = glm::min(int(glm::floor(t)), dims[k] - 1);
    i1[k] = glm::min(i0[k] + 1, dims[k] - 1);
    f[k] = t - real(i0[k]);
  }
  real3 E = real3(0);
  for (int ch = 0; ch < 3; ++ch) {
    real4 c = real4(0);
    for (int q = 0; q < 8; ++q) {
      real w = ((q & 1) != 0 ? f.x : real(1) - f.x) * ((q & 2) != 0 ? f.y : real(1) - f.y) *
               ((q & 4) != 0 ? f.z : real(1) - f.z);
      if (w == real(0)) continue;
      glm::ivec3 e = glm::ivec3((q & 1) != 0 ? i1.x : i0.x, (q & 2) != 0 ? i1.y : i0.y, (q & 4) != 0 ? i1.z : i0.z);
      c += w * gi_lpv_fetch(ATMOSH_GI_CTX_ARG e, ch);
    }
    E[ch] = gi_lpv_irradiance4(c, n, h);
  }
  return E;
}

// A surfel of unit normal n covering the fraction a = A_s / h^2 of a cell's cross-section
// blocks a |n . w| of the light along w: as 3-band SH, lambda_l Y_lm(n) a with the Funk–Hecke
// factors of |cos| lambda_0 = 2 pi, lambda_1 = 0, lambda_2 = pi / 2. Coefficient q (0..8).
ATMOSH_FN real gi_lpv_surfel(real3 n, real a, int q) {
  real pi = real(3.14159265358979324);
  if (q == 0) return real(2) * pi * real(0.28209479177387814) * a;
  if (q < 4) return real(0);
  real y = real(0);
  if (q == 4) y = real(1.0925484305920792) * n.x * n.y;
  if (q == 5) y = real(-1.0925484305920792) * n.y * n.z;
  if (q == 6) y = real(0.31539156525252005) * (real(3) * n.z * n.z - real(1));
  if (q == 7) y = real(-1.0925484305920792) * n.x * n.z;
  if (q == 8) y = real(0.54627421529603959) * (n.x * n.x - n.y * n.y);
  return real(0.5) * pi * y * a;
}

// The 2-level nested cascade (atmosh/gi/lpv.hpp, LpvCascade): is p inside the fine box
// [lo, hi] (closed)? A VPL (at the fine level's half-cell shift) inside it goes into the fine
// level and the coarse inner grid, one outside into the coarse outer grid.
ATMOSH_FN bool gi_lpv_in_box(real3 p, real3 lo, real3 hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

// The cascade's weight of the fine level at a receiver x: 0 outside the fine box
// [fine_lo, fine_hi]; inside, min(1, distance to the nearest face / h) over the faces that lie
// inside the coarse grid [lo, hi] (h its cell edge); a face on the coarse grid's boundary (within
// h / 1000: faces lie on the coarse lattice) neither fades nor bounds (a receiver rounded past
// the grid's boundary is read clamped into the grid). A NaN coordinate gives 0.
ATMOSH_FN real gi_lpv_cascade_weight(real3 x, real3 fine_lo, real3 fine_hi, real3 lo, real3 hi, real h) {
  real w = real(1);
  for (int a = 0; a < 3; ++a) {
    if (glm::isnan(x[a])) return real(0);
    bool open_lo = glm::abs(fine_lo[a] - lo[a]) >= real(0.001) * h;
    bool open_hi = glm::abs(fine_hi[a] - hi[a]) >= real(0.001) * h;
    if ((open_lo && x[a] < fine_lo[a]) || (open_hi && x[a] > fine_hi[a])) return real(0);
    if (open_lo) w = glm::min(w, (x[a] - fine_lo[a]) / h);
    if (open_hi) w = glm::min(w, (fine_hi[a] - x[a]) / h);
  }
  return glm::clamp(w, real(0), real(1));
}

// The cascade's irradiance from its levels' (each gi_lpv_receiver_irradiance of its grid):
// E = E_outer + w E_fine + (1 - w) E_inner.
ATMOSH_FN real3 gi_lpv_cascade_blend(real3 e_outer, real3 e_fine, real3 e_inner, real w) {
  return e_outer + w * e_fine + (real(1) - w) * e_inner;
}

// ATMOSH_GLSL_END

}  // namespace atmosh::gi::shared
