// atmosh/gi/shared/polygon.glsl.hpp — the irradiance from a uniformly emitting triangle,
// unoccluded, written once for the CPU (apps/gi/src/receivers.cpp) and the GPU (the rasterised
// G-buffer's area-light term, gpu/shaders/gi_gbuffer.frag): the triangle (relative to p)
// clipped to the half-space n . v >= 0 (Sutherland–Hodgman), then Lambert's formula
//   E / L = 1/2 |sum_i theta_i n . normalize(u_i x u_i+1)|,
// theta_i the angle between successive vertex directions (Arvo 1995, "Applications of
// irradiance tensors to the simulation of non-Lambertian phenomena", SIGGRAPH, eq. 1).
// Returns the factor F with E = L F for radiance L; 0 where p is on a vertex or the clipped
// polygon is empty. Exact up to rounding in `real`. Common subset of C++/GLM and GLSL (see
// radiosity.glsl.hpp): real = double, real3 = glm::dvec3 on the CPU; float, vec3 on the GPU.
#pragma once

#include <glm/glm.hpp>

namespace atmosh::gi::shared {

using real = double;
using real3 = glm::dvec3;
#ifndef ATMOSH_FN
#define ATMOSH_FN inline __attribute__((always_inline))
#endif

// ATMOSH_GLSL_BEGIN

ATMOSH_FN real gi_polygon_irradiance(real3 p, real3 n, real3 a, real3 b, real3 c) {
  real3 vin[3];
  vin[0] = a - p;
  vin[1] = b - p;
  vin[2] = c - p;
  real3 poly[4];
  int k = 0;
  for (int i = 0; i < 3; ++i) {
    real3 u = vin[i];
    real3 w = vin[(i + 1) % 3];
    real du = glm::dot(n, u);
    real dw = glm::dot(n, w);
    if (du >= real(0)) {
      poly[k] = u;
      k = k + 1;
    }
    if ((du >= real(0)) != (dw >= real(0))) {
      poly[k] = u + (du / (du - dw)) * (w - u);
      k = k + 1;
    }
  }
  if (k < 3) return real(0);
  real sum = real(0);
  for (int i = 0; i < k; ++i) {
    real lu = glm::length(poly[i]);
    real lw = glm::length(poly[(i + 1) % k]);
    if (!(lu > real(0)) || !(lw > real(0))) return real(0);  // p on a vertex: leave it out
    real3 u = poly[i] / lu;
    real3 w = poly[(i + 1) % k] / lw;
    real3 cr = glm::cross(u, w);
    real l = glm::length(cr);
    if (!(l > real(0))) continue;
    sum += glm::atan(l, glm::dot(u, w)) * glm::dot(n, cr / l);
  }
  return real(0.5) * glm::abs(sum);
}

// ATMOSH_GLSL_END

}  // namespace atmosh::gi::shared
