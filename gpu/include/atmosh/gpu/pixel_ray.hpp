// atmosh/gpu/pixel_ray.hpp — the camera ray of a fragment's pixel centre, for the shaders that
// take a surface point from the pixel ray and the fragment's triangle plane
// (gpu/shaders/gi_pixel_point.glsl) instead of the rasteriser's interpolated position.
//
// For a W x H view with unit, orthogonal axes right, up, back (the camera looks along -back)
// and vertical half-angle tangent tan_half_fov — the frame of camera_matrix (gpu/src/
// gl_objects.hpp) and of the CPU ray casts — the ray through OpenGL window coordinates
// (x, y) (pixel centres at k + 1/2, y up) has the direction
//   d(x, y) = d0 + x dx + y dy,  d0 = -back - t a right - t up,  dx = 2 t a / W right,
//   dy = 2 t / H up  (t = tan_half_fov, a = W / H),
// unnormalised, from the eye. The uniform `pixel_ray[3]` holds d0, dx, dy in float.
#pragma once

#include <glm/vec3.hpp>

#include "atmosh/gpu/program.hpp"

namespace atmosh::gpu {

/// Sets uniform vec3 pixel_ray[3] of the current program `prog` (see above).
inline void set_pixel_ray(const Program& prog, const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& back,
                          double tan_half_fov, int width, int height) {
  const double t = tan_half_fov, a = static_cast<double>(width) / height;
  const glm::dvec3 v[3] = {-back - t * a * right - t * up, (2.0 * t * a / width) * right, (2.0 * t / height) * up};
  const char* names[3] = {"pixel_ray[0]", "pixel_ray[1]", "pixel_ray[2]"};
  for (int k = 0; k < 3; ++k)
    prog.set(names[k], static_cast<float>(v[k].x), static_cast<float>(v[k].y), static_cast<float>(v[k].z));
}

}  // namespace atmosh::gpu
