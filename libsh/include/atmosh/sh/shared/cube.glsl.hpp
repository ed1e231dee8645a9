// atmosh/sh/shared/cube.glsl.hpp — the cube-map geometry of libsh's projection
// (atmosh/sh/projection.hpp) and a real SH basis function, written once for the CPU and the
// GPU.
//
// The code between ATMOSH_GLSL_BEGIN and ATMOSH_GLSL_END is in the common subset of C++
// with GLM and GLSL (the convention of libatmo/include/atmosh/atmo/shared/, docs/gpu.md):
// `real` scalars and `real3` vectors, glm:: functions that GLSL has under the same name
// (glm::atan(y, x) is GLSL's two-argument atan), no std::, no pointers, no recursion. The
// CPU build uses real = double, real3 = glm::dvec3; a shader pastes the block after
// `#define real float`, `#define real3 vec3`, `#define ATMOSH_FN` with every "glm::"
// deleted (cmake/AtmoshEmbedGlsl.cmake; gpu/include/atmosh/gpu/program.hpp's preamble).
// libsh's sh::cube_face_point and sh::cube_texel_solid_angle are these functions (C++
// build); the GPU probes' projection (gpu/shaders/gi_probe_project.comp) pastes them.
//
// Cube-map layout (libsh's CubeMap): faces +X -X +Y -Y +Z -Z, OpenGL orientation; texel
// (row r, column c) of an N x N face covers u in [2c/N - 1, 2(c+1)/N - 1], v likewise in r,
// its centre direction is sh_cube_face_point(f, u_c, v_c) normalised.
//
// Texel solid angle (exact): the area of the unit sphere that the square [u0, u1] x [v0, v1]
// on the plane at distance 1 subtends, Omega = F(u0, v0) - F(u0, v1) - F(u1, v0) + F(u1, v1)
// with F(u, v) = atan2(u v, sqrt(u^2 + v^2 + 1)) (the solid angle of the rectangle from the
// foot of the perpendicular to (u, v)); the texels of a face sum to 4 pi / 6 exactly. In
// float the four terms (|F| <= pi/6) cancel to Omega ~ 4 pi / (6 N^2): relative rounding
// about 1e-7 pi / (6 Omega), i.e. ~1e-5 at N = 32.
//
// SH (sh_basis_lm): real, orthonormal on the unit sphere, Condon–Shortley phase, the
// convention of atmosh/sh/basis.hpp (Y_1,-1 = -sqrt(3/4pi) y, Y_10 = sqrt(3/4pi) z, Y_11 =
// -sqrt(3/4pi) x), from the normalised associated-Legendre recurrence in z with the
// sin^m(theta) e^{i m phi} factor built as (x + i y)^m — no trigonometric functions:
//   P~_mm = (-1)^m sqrt((2m + 1)/(4 pi) prod_{k=1..m} (2k - 1)/(2k)),
//   P~_{m+1,m} = sqrt(2m + 3) z P~_mm,
//   P~_lm = a_lm (z P~_{l-1,m} - b_lm P~_{l-2,m}), a_lm = sqrt((4l^2 - 1)/(l^2 - m^2)),
//           b_lm = sqrt(((l - 1)^2 - m^2)/(4 (l - 1)^2 - 1)),
//   Y_l0 = P~_l0, Y_lm = sqrt(2) P~_l|m| Re (x + i y)^|m| (m > 0), sqrt(2) P~_l|m| Im (...) (m < 0).
// O(l) operations a value; accurate to a few ulp times l in `real` for the bands used on
// the GPU (<= 16; P~_mm stays above 1e-38 there, so float does not underflow).
// Units: directions are unit vectors (sh_basis_lm does not normalise); solid angles in sr.
#pragma once

#include <glm/glm.hpp>

namespace atmosh::sh::shared {

using real = double;
using real3 = glm::dvec3;  // GLSL: vec3 (#define real3 vec3)
#ifndef ATMOSH_FN
#define ATMOSH_FN inline __attribute__((always_inline))
#endif

// ATMOSH_GLSL_BEGIN

// The point (u, v) in [-1, 1]^2 of face f (0..5) on the cube [-1, 1]^3 (not unit length);
// f outside 0..5 gives -Z's point (the C++ caller checks f).
ATMOSH_FN real3 sh_cube_face_point(int f, real u, real v) {
  if (f == 0) return real3(real(1), -v, -u);
  if (f == 1) return real3(real(-1), -v, u);
  if (f == 2) return real3(u, real(1), v);
  if (f == 3) return real3(u, real(-1), -v);
  if (f == 4) return real3(u, -v, real(1));
  return real3(-u, -v, real(-1));
}

// F(u, v): the solid angle of the rectangle [0, u] x [0, v] on the plane at distance 1.
ATMOSH_FN real sh_cube_corner_solid_angle(real u, real v) {
  return glm::atan(u * v, glm::sqrt(u * u + v * v + real(1)));
}

// Exact solid angle of texel (col, row) of an N x N face (the same on every face).
ATMOSH_FN real sh_cube_texel_solid_angle(int col, int row, int n) {
  real u0 = real(2 * col) / real(n) - real(1);
  real u1 = real(2 * (col + 1)) / real(n) - real(1);
  real v0 = real(2 * row) / real(n) - real(1);
  real v1 = real(2 * (row + 1)) / real(n) - real(1);
  return sh_cube_corner_solid_angle(u0, v0) - sh_cube_corner_solid_angle(u0, v1) -
         sh_cube_corner_solid_angle(u1, v0) + sh_cube_corner_solid_angle(u1, v1);
}

// Unit direction of texel (col, row)'s centre on face f of an N x N cube map.
ATMOSH_FN real3 sh_cube_texel_direction(int f, int col, int row, int n) {
  real3 d = sh_cube_face_point(f, real(2 * col + 1) / real(n) - real(1), real(2 * row + 1) / real(n) - real(1));
  return d / glm::sqrt(glm::dot(d, d));
}

// Real SH Y_lm at the unit direction d (l >= 0, |m| <= l), libsh's convention (see above).
ATMOSH_FN real sh_basis_lm(int l, int m, real3 d) {
  int am = m < 0 ? -m : m;
  // (x + i y)^|m| = sin^|m|(theta) e^{i |m| phi}
  real cr = real(1);
  real ci = real(0);
  for (int k = 0; k < am; ++k) {
    real t = cr * d.x - ci * d.y;
    ci = cr * d.y + ci * d.x;
    cr = t;
  }
  real pmm = real(1) / (real(4) * real(3.14159265358979324));
  for (int k = 1; k <= am; ++k) pmm *= real(2 * k - 1) / real(2 * k);
  pmm = glm::sqrt(real(2 * am + 1) * pmm);
  if (am % 2 == 1) pmm = -pmm;
  real p = pmm;
  if (l > am) {
    real prev = pmm;
    p = glm::sqrt(real(2 * am + 3)) * d.z * pmm;
    for (int k = am + 2; k <= l; ++k) {
      real a = glm::sqrt(real(4 * k * k - 1) / real(k * k - am * am));
      real b = glm::sqrt(real((k - 1) * (k - 1) - am * am) / real(4 * (k - 1) * (k - 1) - 1));
      real next = a * (d.z * p - b * prev);
      prev = p;
      p = next;
    }
  }
  if (m == 0) return p;
  return real(1.41421356237309505) * p * (m > 0 ? cr : ci);
}

// The band l and order m of the linear index i = l (l + 1) + m.
ATMOSH_FN int sh_index_band(int i) {
  int l = 0;
  while ((l + 1) * (l + 1) <= i) ++l;
  return l;
}

// ---- Every real SH value of bands 0..bands-1 at once (appended) ----
//
// sh_basis_all(bands, d, y) writes Y_i(d), i = l (l + 1) + m < bands^2, into y: the same
// values as sh_basis_lm (libsh's convention, see above) by the same normalised
// associated-Legendre recurrence, run once per order m over l = m..bands-1 (the stable
// three-term recurrence in l for fixed m; P~_mm from P~_{m-1,m-1} by the factor
// -sqrt((2m + 1)/(2m)), (x + i y)^m from (x + i y)^{m-1}): O(bands^2) operations for all
// bands^2 values, no trigonometry. ATMOSH_SH_MAX_BANDS (default 16; a shader may #define a
// smaller one before the block, e.g. the band count of its probes) sizes y; bands must be
// in 1..ATMOSH_SH_MAX_BANDS. In C++ y is the caller's array (at least bands^2 elements); in
// GLSL an `out` parameter of ATMOSH_SH_MAX_BANDS^2 elements. Accuracy: a few ulp times l in
// `real` (float on the GPU: P~_mm >= 1e-5 at bands <= 16, no underflow).
// Irradiance (Ramamoorthi & Hanrahan 2001): E(n) = sum_i A_l c_i Y_i(n), A_l the clamped-cosine
// factors of libsh (sh::irradiance_factors, any band); sh_basis_scale multiplies band l of
// y by f[l] (A_l, or a window), so that E is one dot product with the coefficients.
#ifndef ATMOSH_SH_MAX_BANDS
#define ATMOSH_SH_MAX_BANDS 16
#endif
#ifdef ATMOSH_GLSL
#define ATMOSH_SH_OUT out
#define ATMOSH_SH_INOUT inout
#else
#define ATMOSH_SH_OUT
#define ATMOSH_SH_INOUT
#endif

ATMOSH_FN void sh_basis_all(int bands, real3 d, ATMOSH_SH_OUT real y[ATMOSH_SH_MAX_BANDS * ATMOSH_SH_MAX_BANDS]) {
  real cr = real(1);  // Re, Im (x + i y)^m = sin^m(theta) e^{i m phi}
  real ci = real(0);
  real pmm = real(0.28209479177387814);  // P~_00 = sqrt(1 / (4 pi))
  for (int m = 0; m < bands; ++m) {
    if (m > 0) {
      real t = cr * d.x - ci * d.y;
      ci = cr * d.y + ci * d.x;
      cr = t;
      pmm = -glm::sqrt(real(2 * m + 1) / real(2 * m)) * pmm;
    }
    real prev = real(0);
    real p = pmm;
    for (int l = m; l < bands; ++l) {
      if (l > m) {
        real a = glm::sqrt(real(4 * l * l - 1) / real(l * l - m * m));
        real b = real(0);
        if (l > m + 1) b = glm::sqrt(real((l - 1) * (l - 1) - m * m) / real(4 * (l - 1) * (l - 1) - 1));
        real next = a * (d.z * p - b * prev);
        prev = p;
        p = next;
      }
      int c = l * (l + 1);
      if (m == 0) {
        y[c] = p;
      } else {
        y[c + m] = real(1.41421356237309505) * p * cr;
        y[c - m] = real(1.41421356237309505) * p * ci;
      }
    }
  }
}

// y_i *= f[l] for i < bands^2 (f per band: A_l for irradiance, a window's w_l).
ATMOSH_FN void sh_basis_scale(int bands, const real f[ATMOSH_SH_MAX_BANDS],
                              ATMOSH_SH_INOUT real y[ATMOSH_SH_MAX_BANDS * ATMOSH_SH_MAX_BANDS]) {
  for (int l = 0; l < bands; ++l)
    for (int i = l * l; i < (l + 1) * (l + 1); ++i) y[i] *= f[l];
}

// ATMOSH_GLSL_END

}  // namespace atmosh::sh::shared
