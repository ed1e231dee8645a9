// A 2-level nested LPV cascade on the CPU (LpvCascade, atmosh/gi/lpv.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/lpv.hpp"
#include "atmosh/gi/shared/lpv.glsl.hpp"
#include "atmosh/prt/bake.hpp"
#include "common.hpp"
#include "receivers.hpp"

namespace atmosh::gi {

namespace {
using Clock = std::chrono::steady_clock;

struct Cells {
  const LpvGrid* g;
};
[[maybe_unused]] glm::dvec4 gi_lpv_fetch(const Cells& c, glm::ivec3 s, int ch) {
  const LpvCell& x = c.g->cells[c.g->index(s.x, s.y, s.z)];
  return {x[ch * 4], x[ch * 4 + 1], x[ch * 4 + 2], x[ch * 4 + 3]};
}

glm::dvec3 level_irradiance(const LpvGrid& g, const glm::dvec3& x, const glm::dvec3& n) {
  return shared::gi_lpv_receiver_irradiance(Cells{&g}, x, n, g.lo, g.h, glm::ivec3(g.nx, g.ny, g.nz));
}

Lpv propagate(const Scene& scene, const LpvOptions& opt, LpvGrid injected, int iterations) {
  Lpv l;
  l.injected = std::move(injected);
  if (opt.blocking) l.geometry = lpv_geometry(scene, l.injected);
  l.iterations = iterations;
  l.accumulated = lpv_propagate(l.injected, opt.blocking ? &l.geometry : nullptr, iterations, opt.reemission);
  return l;
}
}  // namespace

LpvCascadeLayout lpv_cascade_layout(const Scene& scene, const LpvOptions& opt, const glm::dvec3* focus) {
  validate(scene);
  if (opt.grid < 2 || opt.grid > 256) throw InputError("gi lpv cascade: grid must be in 2..256, got " + std::to_string(opt.grid));
  if (focus != nullptr && !std::isfinite(focus->x + focus->y + focus->z))
    throw InputError("gi lpv cascade: the focus must be finite");
  LpvCascadeLayout L;
  L.coarse = lpv_grid(scene, opt.grid);
  const LpvGrid& coarse = L.coarse;
  const double h = coarse.h, hf = 0.5 * h;
  const glm::dvec3 coarse_hi = coarse.lo + h * glm::dvec3(coarse.nx, coarse.ny, coarse.nz);
  // The fine box: half the coarse grid's cells per axis (at least one), about the focus, inside
  // the coarse grid, its corners on the coarse lattice.
  const glm::ivec3 nc(coarse.nx, coarse.ny, coarse.nz);
  const glm::dvec3 f = focus != nullptr ? *focus : coarse.lo + 0.5 * (coarse_hi - coarse.lo);
  glm::ivec3 lo_cell, n_half;
  for (int a = 0; a < 3; ++a) {
    n_half[a] = std::max(1, (nc[a] + 1) / 2);
    const double start = (f[a] - coarse.lo[a]) / h - 0.5 * n_half[a];
    lo_cell[a] = std::clamp(static_cast<int>(std::floor(start)), 0, nc[a] - n_half[a]);
  }
  LpvGrid& fine = L.fine;
  fine.lo = coarse.lo + h * glm::dvec3(lo_cell);
  fine.h = hf;
  fine.nx = 2 * n_half.x, fine.ny = 2 * n_half.y, fine.nz = 2 * n_half.z;
  fine.cells.assign(static_cast<std::size_t>(fine.nx) * fine.ny * fine.nz, LpvCell{});
  L.fine_lo = fine.lo;
  L.fine_hi = fine.lo + h * glm::dvec3(n_half);
  return L;
}

LpvCascade lpv_cascade_from_vpls(const Scene& scene, const LpvOptions& opt, const LpvCascadeLayout& layout,
                                 const std::vector<Vpl>& vpls) {
  if (opt.iterations < -1 || opt.iterations > 1024)
    throw InputError("gi lpv: iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(opt.iterations));
  const auto t0 = Clock::now();
  LpvCascade c;
  c.fine_lo = layout.fine_lo;
  c.fine_hi = layout.fine_hi;
  const double h = layout.coarse.h;
  LpvGrid fine = layout.fine, inner = layout.coarse, outer = layout.coarse;
  for (const Vpl& v : vpls) {
    if (shared::gi_lpv_in_box(v.p, c.fine_lo, c.fine_hi)) {
      lpv_add_vpl(fine, v.p, v.n, v.flux);
      lpv_add_vpl(inner, v.p + 0.25 * h * v.n, v.n, v.flux);  // the coarse level's half-cell shift h/2
    } else {
      lpv_add_vpl(outer, v.p + 0.25 * h * v.n, v.n, v.flux);
    }
  }
  const auto t1 = Clock::now();
  c.iterations = opt.iterations < 0 ? 2 * opt.grid : opt.iterations;
  c.fine = propagate(scene, opt, std::move(fine), c.iterations);
  c.inner = propagate(scene, opt, std::move(inner), c.iterations);
  c.outer = propagate(scene, opt, std::move(outer), c.iterations);
  c.inject_seconds = std::chrono::duration<double>(t1 - t0).count();
  c.propagate_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return c;
}

LpvCascade build_lpv_cascade(const Scene& scene, const LpvOptions& opt, const glm::dvec3* focus) {
  if (opt.iterations < -1 || opt.iterations > 1024)
    throw InputError("gi lpv: iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(opt.iterations));
  const auto t0 = Clock::now();
  const LpvCascadeLayout layout = lpv_cascade_layout(scene, opt, focus);
  // The VPLs at the fine level's density, shifted hf/2 along n; each into one place.
  std::uint64_t rays = 0;
  const std::vector<Vpl> vpls = lpv_vpls(scene, opt, layout.fine, &rays);
  const double vpl_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  LpvCascade c = lpv_cascade_from_vpls(scene, opt, layout, vpls);
  c.rays = rays;
  c.inject_seconds += vpl_seconds;
  return c;
}

glm::dvec3 lpv_cascade_irradiance(const LpvCascade& c, const glm::dvec3& x, const glm::dvec3& n) {
  const LpvGrid& g = c.outer.accumulated;
  const glm::dvec3 hi = g.lo + g.h * glm::dvec3(g.nx, g.ny, g.nz);
  const double w = shared::gi_lpv_cascade_weight(x, c.fine_lo, c.fine_hi, g.lo, hi, g.h);
  const glm::dvec3 E_outer = level_irradiance(c.outer.accumulated, x, n);
  const glm::dvec3 E_fine = w > 0 ? level_irradiance(c.fine.accumulated, x, n) : glm::dvec3(0.0);
  const glm::dvec3 E_inner = w < 1 ? level_irradiance(c.inner.accumulated, x, n) : glm::dvec3(0.0);
  return shared::gi_lpv_cascade_blend(E_outer, E_fine, E_inner, w);
}

RadianceImage render_lpv_cascade(const Scene& scene, const Camera& camera, int width, int height, const LpvCascade& c,
                                 const LpvOptions& opt) {
  validate(scene);
  if (opt.samples < 1 || opt.samples > 1000000)
    throw InputError("gi lpv: camera rays per pixel must be in 1..1000000, got " + std::to_string(opt.samples));
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight direct(scene, rays);
  return detail::render_receivers(
      scene, rays, camera, width, height, opt.samples, opt.seed, opt.threads,
      [&](detail::Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint32_t, std::uint64_t& nr) {
        return direct.irradiance(rng, p, n, nr) + lpv_cascade_irradiance(c, p, n);
      });
}

}  // namespace atmosh::gi
