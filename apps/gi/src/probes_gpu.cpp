// Radiance probes of a baked surface radiance, rasterised on the GPU (see probes.hpp,
// "Probes of a baked surface radiance"): the sub-triangles with their per-vertex radiance
// drawn into cube maps by gpu::render_cube_maps (gpu/shaders/gi_probe_cube.vert/.frag).
#include <algorithm>
#include <array>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/probes.hpp"

#ifdef ATMOSH_GI_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/cube_raster.hpp"
#endif

namespace atmosh::gi::detail {

std::vector<float> surface_cubes_gpu(const SurfaceRadiance& field, const std::vector<glm::dvec3>& positions, int n,
                                     double near, double far, double* seconds) {
#ifdef ATMOSH_GI_HAVE_GPU
  gpu::CubeRasterMesh mesh;
  const std::size_t nv = field.positions.size();
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : field.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::dvec3 centre = nv > 0 ? 0.5 * (lo + hi) : glm::dvec3(0.0);
  mesh.origin = {centre.x, centre.y, centre.z};
  mesh.vertices.reserve(nv * gpu::kCubeRasterVertexFloats);
  for (std::size_t v = 0; v < nv; ++v) {
    const glm::dvec3 p = field.positions[v] - centre;
    for (const glm::dvec3& q : {p, field.normals[v], field.front[v], field.back[v]})
      for (int c = 0; c < 3; ++c) mesh.vertices.push_back(static_cast<float>(q[c]));
  }
  mesh.indices.reserve(field.triangles.size() * 3);
  for (const auto& t : field.triangles) mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
  std::vector<std::array<double, 3>> centres;
  centres.reserve(positions.size());
  for (const auto& p : positions) centres.push_back({p.x, p.y, p.z});
  gpu::CubeRasterOptions opt;
  opt.size = n;
  opt.near = near;
  opt.far = far;
  const gpu::Context ctx;
  gpu::CubeRasterResult r = gpu::render_cube_maps(ctx, mesh, centres, opt);
  if (seconds != nullptr) *seconds = r.seconds;
  return std::move(r.texels);
#else
  (void)field, (void)positions, (void)n, (void)near, (void)far, (void)seconds;
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

}  // namespace atmosh::gi::detail
