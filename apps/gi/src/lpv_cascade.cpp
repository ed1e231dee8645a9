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

bool inside(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

Lpv propagate(const Scene& scene, const LpvOptions& opt, LpvGrid injected, int iterations) {
  Lpv l;
  l.injected = std::move(injected);
  if (opt.blocking) l.geometry = lpv_geometry(scene, l.injected);
  l.iterations = iterations;
  l.accumulated = lpv_propagate(l.injected, opt.blocking ? &l.geometry : nullptr, iterations);
  return l;
}
}  // namespace

LpvCascade build_lpv_cascade(const Scene& scene, const LpvOptions& opt, const glm::dvec3* focus) {
  validate(scene);
  if (opt.grid < 2 || opt.grid > 256) throw InputError("gi lpv cascade: grid must be in 2..256, got " + std::to_string(opt.grid));
  if (opt.iterations < -1 || opt.iterations > 1024)
    throw InputError("gi lpv: iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(opt.iterations));
  if (focus != nullptr && !std::isfinite(focus->x + focus->y + focus->z))
    throw InputError("gi lpv cascade: the focus must be finite");
  const auto t0 = Clock::now();
  LpvCascade c;
  const LpvGrid coarse = lpv_grid(scene, opt.grid);
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
  LpvGrid fine;
  fine.lo = coarse.lo + h * glm::dvec3(lo_cell);
  fine.h = hf;
  fine.nx = 2 * n_half.x, fine.ny = 2 * n_half.y, fine.nz = 2 * n_half.z;
  fine.cells.assign(static_cast<std::size_t>(fine.nx) * fine.ny * fine.nz, LpvCell{});
  c.fine_lo = fine.lo;
  c.fine_hi = fine.lo + h * glm::dvec3(n_half);
  // The VPLs at the fine level's density, shifted hf/2 along n; each into one place.
  LpvOptions vo = opt;
  LpvGrid density = coarse;
  density.h = hf;  // lpv_vpls: sun rays per (fine) cell edge, the half-cell shift of the fine level
  const std::vector<Vpl> vpls = lpv_vpls(scene, vo, density, &c.rays);
  LpvGrid inner = coarse, outer = coarse;
  for (const Vpl& v : vpls) {
    if (inside(v.p, c.fine_lo, c.fine_hi)) {
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

glm::dvec3 lpv_cascade_irradiance(const LpvCascade& c, const glm::dvec3& x, const glm::dvec3& n) {
  const LpvGrid& g = c.outer.accumulated;
  const double h = g.h;
  const glm::dvec3 hi = g.lo + h * glm::dvec3(g.nx, g.ny, g.nz);
  // w: 1 inside the fine box shrunk by one coarse cell, linear to 0 at its faces — at the faces
  // inside the coarse grid; a face on the coarse grid's boundary has no light beyond it
  double w = 1;
  for (int a = 0; a < 3; ++a) {
    const double dlo = std::abs(c.fine_lo[a] - g.lo[a]) < 1e-6 * h ? 1e300 : x[a] - c.fine_lo[a];
    const double dhi = std::abs(c.fine_hi[a] - hi[a]) < 1e-6 * h ? 1e300 : c.fine_hi[a] - x[a];
    if (x[a] < c.fine_lo[a] || x[a] > c.fine_hi[a]) w = 0;
    w = std::min(w, std::clamp(std::min(dlo, dhi) / h, 0.0, 1.0));
  }
  if (!std::isfinite(w)) w = 0;
  glm::dvec3 E = level_irradiance(c.outer.accumulated, x, n);
  if (w > 0) E += w * level_irradiance(c.fine.accumulated, x, n);
  if (w < 1) E += (1 - w) * level_irradiance(c.inner.accumulated, x, n);
  return E;
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
