// Private helpers of the rasterised gi passes (raster_gpu.cpp, lpv_gpu.cpp): the scene's
// per-triangle attributes as atmosh::gpu reads them, the environment's direct-light quadrature
// and the sun's reflective-shadow-map view.
#pragma once

#ifdef ATMOSH_GI_HAVE_GPU
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/gpu/gi_raster.hpp"
#include "atmosh/gpu/prt.hpp"

namespace atmosh::gi::detail {

struct MeshAttrs {
  std::vector<glm::dvec3> normal, albedo, emission;
  std::vector<std::uint8_t> one_sided;
  const Scene& s;
  explicit MeshAttrs(const Scene& scene);
  gpu::GiMeshView view() const;
};

/// `cam` as the G-buffer passes take it: unit right, up and back (-forward), the tangent of
/// half the vertical field of view, a width x height image.
gpu::PrtCamera pass_camera(const Camera& cam, int width, int height);
/// Unit direction through the centre of pixel (col, row) of `pc` (row 0 at the top).
glm::dvec3 pixel_ray(const gpu::PrtCamera& pc, int col, int row);

/// The environment's directions for gpu::GiSkyOptions: n spherical-Fibonacci directions, each
/// with environment_radiance x 4 pi / n; depth maps of resolution^2 texels.
gpu::GiSkyOptions sky_quadrature(const Scene& scene, int n, int resolution);

/// The sun's RSM over the CPU injection's rectangle (the box's cross-section seen from the sun)
/// with m = sun_rays x ceil(longer side / h) texels a side (lpv_vpls_rsm). The scene has a sun.
gpu::GiRsmView rsm_view(const Scene& scene, const LpvOptions& opt, const LpvGrid& g);

/// The geometry volume's surfels (lpv_geometry's, in its order) for the GPU-resident frame.
std::vector<gpu::GiLpvSurfel> lpv_surfels(const Scene& scene, const LpvGrid& g);

}  // namespace atmosh::gi::detail
#endif
