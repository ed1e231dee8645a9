// The radiosity approximation's per-receiver walk on the GPU (see radiosity.hpp): the
// shared block of atmosh/gi/shared/radiosity.glsl.hpp between the volume's fetches
// (gpu/shaders/gi_radiosity_fetch.glsl) and the receiver loop
// (gpu/shaders/gi_radiosity_shade.comp).
#include <algorithm>
#include <chrono>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/gi/radiosity.hpp"
#include "common.hpp"

#ifdef ATMOSH_GI_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"
#endif

namespace atmosh::gi {

std::vector<glm::dvec3> shade_receivers_gpu(const RadiosityVolume& v, const RadiosityReceivers& r, int bounces,
                                            double* gpu_seconds) {
  const std::size_t np = static_cast<std::size_t>(v.n) * v.n * v.n;
  if (v.n < 1 || v.distance.size() != np || v.normal.size() != np || v.albedo.size() != np || v.direct.size() != np)
    throw InputError("gi radiosity: the volume's arrays (direct light included) do not match its size");
  if (bounces < 0 || bounces > 16) throw InputError("gi radiosity: bounces must be in 0..16, got " + std::to_string(bounces));
  const std::size_t nr = r.size();
  if (r.normal.size() != nr || r.albedo.size() != nr || r.emission.size() != nr || r.direct.size() != nr)
    throw InputError("gi radiosity: the receivers' arrays differ in length");
  if (nr > 0x7fffffffu / 15) throw InputError("gi radiosity: too many receivers for one GPU pass");
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::Context ctx;
  gpu::Program prog({gpu::embedded_source("gpu/shaders/gi_radiosity_fetch.glsl"),
                     gpu::embedded_source("apps/gi/include/atmosh/gi/shared/radiosity.glsl.hpp"),
                     gpu::embedded_source("gpu/shaders/gi_radiosity_shade.comp")});
  std::vector<float> dist(np * 9), nrm(np * 3), alb(np * 3), dir(np * 12);
  for (std::size_t p = 0; p < np; ++p) {
    for (int i = 0; i < 9; ++i) dist[p * 9 + i] = static_cast<float>(v.distance[p][static_cast<std::size_t>(i)]);
    for (int i = 0; i < 3; ++i) {
      nrm[p * 3 + i] = static_cast<float>(v.normal[p][i]);
      alb[p * 3 + i] = static_cast<float>(v.albedo[p][i]);
    }
    for (int i = 0; i < 12; ++i) dir[p * 12 + i] = static_cast<float>(v.direct[p][static_cast<std::size_t>(i)]);
  }
  const std::vector<float> rec = detail::pack_receivers(r);
  glm::dvec3 lo, hi;
  radiosity_walk_box(v, lo, hi);
  const auto t0 = std::chrono::steady_clock::now();
  gpu::Buffer bd(dist.size() * 4, dist.data()), bn(nrm.size() * 4, nrm.data()), ba(alb.size() * 4, alb.data()),
      bdir(dir.size() * 4, dir.data()), brec(rec.size() * 4, rec.data()),
      bout(std::max<std::size_t>(nr, 1) * 4 * sizeof(float));
  bd.bind(0);
  bn.bind(1);
  ba.bind(2);
  bdir.bind(3);
  brec.bind(4);
  bout.bind(5);
  prog.use();
  prog.set("vol_lo", static_cast<float>(v.lo.x), static_cast<float>(v.lo.y), static_cast<float>(v.lo.z));
  prog.set("vol_hi", static_cast<float>(v.hi.x), static_cast<float>(v.hi.y), static_cast<float>(v.hi.z));
  prog.set("vol_n", v.n);
  prog.set("vol_bands", v.bands);
  prog.set("walk_lo", static_cast<float>(lo.x), static_cast<float>(lo.y), static_cast<float>(lo.z));
  prog.set("walk_hi", static_cast<float>(hi.x), static_cast<float>(hi.y), static_cast<float>(hi.z));
  prog.set("n_receivers", static_cast<int>(nr));
  prog.set("bounces", bounces);
  if (nr > 0) prog.dispatch(static_cast<unsigned>((nr + 63) / 64));
  std::vector<float> out(std::max<std::size_t>(nr, 1) * 4);
  bout.download(out.data(), out.size() * sizeof(float));
  if (gpu_seconds != nullptr) *gpu_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return detail::unpack_rgb(out, nr);
#else
  (void)gpu_seconds;
  throw InputError("gi radiosity: this build has no GPU library (atmosh::gpu)");
#endif
}

}  // namespace atmosh::gi
