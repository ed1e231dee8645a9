// The multi-bounce radiosity approximation on the CPU (see radiosity.hpp).
#include "atmosh/gi/radiosity.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/shared/radiosity.glsl.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/projection.hpp"
#include "receivers.hpp"

namespace atmosh::gi {

namespace {
using Clock = std::chrono::steady_clock;

void check(const RadiosityOptions& o) {
  if (o.grid < 1 || o.grid > 64) throw InputError("gi radiosity: grid must be in 1..64, got " + std::to_string(o.grid));
  if (o.bands < 1 || o.bands > 3) throw InputError("gi radiosity: bands must be in 1..3, got " + std::to_string(o.bands));
  if (o.cube_size < 1 || o.cube_size > 128)
    throw InputError("gi radiosity: cube size must be in 1..128, got " + std::to_string(o.cube_size));
  if (o.bounces < 0 || o.bounces > 16)
    throw InputError("gi radiosity: bounces must be in 0..16, got " + std::to_string(o.bounces));
  if (o.samples < 1 || o.samples > 1000000)
    throw InputError("gi radiosity: camera rays per pixel must be in 1..1000000, got " + std::to_string(o.samples));
}

// The 8 probes around p and their trilinear weights (p clamped to the centres' span).
void corners(const RadiosityVolume& g, const glm::dvec3& p, std::size_t idx[8], double w[8]) {
  int i0[3], i1[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double ext = g.hi[a] - g.lo[a];
    double x = ext > 0 ? (p[a] - g.lo[a]) / ext * g.n - 0.5 : 0.0;
    if (!std::isfinite(x)) x = 0;
    x = std::clamp(x, 0.0, static_cast<double>(g.n - 1));
    i0[a] = std::min(static_cast<int>(std::floor(x)), g.n - 1);
    i1[a] = std::min(i0[a] + 1, g.n - 1);
    f[a] = x - i0[a];
  }
  for (int c = 0; c < 8; ++c) {
    const int ii = c & 1 ? i1[0] : i0[0], jj = c & 2 ? i1[1] : i0[1], kk = c & 4 ? i1[2] : i0[2];
    w[c] = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
    idx[c] = (static_cast<std::size_t>(kk) * g.n + jj) * g.n + ii;
  }
}
}  // namespace

glm::dvec3 RadiosityVolume::position(int i, int j, int k) const {
  return lo + glm::dvec3((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n) * (hi - lo);
}

RadiosityVolume build_radiosity_volume(const Scene& scene, const RadiosityOptions& opt) {
  check(opt);
  validate(scene);
  const auto t0 = Clock::now();
  RadiosityVolume v;
  detail::mesh_bounds(scene.mesh, v.lo, v.hi);
  v.n = opt.grid;
  v.bands = opt.bands;
  const prt::RayScene rays(scene.mesh);
  const std::vector<glm::dvec3> normal = detail::triangle_normals(scene.mesh);
  const int N = opt.cube_size;
  const std::size_t nn = static_cast<std::size_t>(N) * N, np = static_cast<std::size_t>(v.n) * v.n * v.n;
  std::vector<glm::dvec3> dir(6 * nn);
  std::vector<double> omega(nn);
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < N; ++r)
      for (int c = 0; c < N; ++c) dir[f * nn + r * N + c] = glm::normalize(sh::cube_texel_direction(f, c, r, N));
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) omega[r * N + c] = sh::cube_texel_solid_angle(c, r, N);
  const double far = glm::length(v.hi - v.lo);
  const double off = rays.offset();
  v.distance.assign(np, {});
  v.normal.assign(np, glm::dvec3(0.0));
  v.albedo.assign(np, glm::dvec3(0.0));
  std::vector<std::uint64_t> counts(np, 0);
  parallel_for_ranges(np, 1, opt.threads, [&](std::size_t b, std::size_t e) {
    sh::CubeMap cube;
    cube.size = N;
    cube.channels = 1;
    for (auto& face : cube.faces) face.assign(nn, 0.0f);
    for (std::size_t p = b; p < e; ++p) {
      const int i = static_cast<int>(p % v.n), j = static_cast<int>(p / v.n % v.n), k = static_cast<int>(p / v.n / v.n);
      const glm::dvec3 x = v.position(i, j, k);
      glm::dvec3 nsum(0.0), asum(0.0);
      double wsum = 0;
      for (int f = 0; f < 6; ++f)
        for (std::size_t t = 0; t < nn; ++t) {
          const glm::dvec3& d = dir[f * nn + t];
          std::uint32_t prim;
          float u, vv;
          double dist;
          double stored = far;
          if (rays.intersect(x, d, off, prim, u, vv, dist)) {
            stored = dist;
            const double w = omega[t] / std::max(dist * dist, 1e-300);
            const glm::dvec3 nt = glm::dot(normal[prim], d) < 0 ? normal[prim] : -normal[prim];
            nsum += w * nt;
            asum += w * scene.materials[scene.material[prim]].albedo;
            wsum += w;
          }
          cube.faces[f][t] = static_cast<float>(stored);
        }
      counts[p] = 6 * nn;
      const sh::Channels ch = sh::project_cube(cube, v.bands, 1);
      for (std::size_t c = 0; c < ch[0].size() && c < 9; ++c) v.distance[p][c] = ch[0][c];
      v.normal[p] = wsum > 0 ? nsum / wsum : glm::dvec3(0.0);  // length: how coherent the normals are
      v.albedo[p] = wsum > 0 ? asum / wsum : glm::dvec3(0.0);
    }
  });
  for (auto c : counts) v.rays += c;
  v.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return v;
}

RadiosityVolume truncate_volume(const RadiosityVolume& v, int bands) {
  if (bands < 1 || bands > v.bands)
    throw InputError("gi radiosity: cannot truncate a volume of " + std::to_string(v.bands) + " bands to " +
                     std::to_string(bands));
  RadiosityVolume t = v;
  t.bands = bands;
  for (auto& c : t.distance)
    for (std::size_t i = static_cast<std::size_t>(bands) * bands; i < 9; ++i) c[i] = 0;
  return t;
}

double volume_distance(const RadiosityVolume& v, const glm::dvec3& p, const glm::dvec3& d) {
  std::size_t idx[8];
  double w[8];
  corners(v, p, idx, w);
  double c[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int q = 0; q < 8; ++q)
    if (w[q] != 0)
      for (int i = 0; i < 9; ++i) c[i] += w[q] * v.distance[idx[q]][i];
  return shared::gi_sh_eval(c, v.bands, d);
}

glm::dvec3 volume_normal(const RadiosityVolume& v, const glm::dvec3& p) {
  std::size_t idx[8];
  double w[8];
  corners(v, p, idx, w);
  glm::dvec3 s(0.0);
  for (int q = 0; q < 8; ++q) s += w[q] * v.normal[idx[q]];
  return s;
}

glm::dvec3 volume_albedo(const RadiosityVolume& v, const glm::dvec3& p) {
  std::size_t idx[8];
  double w[8];
  corners(v, p, idx, w);
  glm::dvec3 s(0.0);
  for (int q = 0; q < 8; ++q) s += w[q] * v.albedo[idx[q]];
  return s;
}

namespace detail {
// The context of the shared walk on the CPU: its fetch functions (found by ADL).
struct RadiosityCtx {
  const RadiosityVolume* v;
  const DirectLight* direct;
  const Scene* scene;
  Rng* rng;
  std::uint64_t* rays;
};
inline double gi_fetch_distance(const RadiosityCtx& c, const glm::dvec3& p, const glm::dvec3& d) {
  return volume_distance(*c.v, p, d);
}
inline glm::dvec3 gi_fetch_normal(const RadiosityCtx& c, const glm::dvec3& q) { return volume_normal(*c.v, q); }
inline glm::dvec3 gi_fetch_albedo(const RadiosityCtx& c, const glm::dvec3& q) { return volume_albedo(*c.v, q); }
inline glm::dvec3 gi_direct_irradiance(const RadiosityCtx& c, const glm::dvec3& q, const glm::dvec3& n) {
  return c.direct->irradiance(*c.rng, q, n, *c.rays);
}
}  // namespace detail

RadianceImage render_radiosity(const Scene& scene, const Camera& camera, int width, int height,
                               const RadiosityVolume& volume, const RadiosityOptions& opt) {
  check(opt);
  validate(scene);
  const std::size_t np = static_cast<std::size_t>(volume.n) * volume.n * volume.n;
  if (volume.n < 1 || volume.distance.size() != np || volume.normal.size() != np || volume.albedo.size() != np ||
      volume.bands < 1 || volume.bands > 3)
    throw InputError("gi radiosity: the volume's arrays do not match its size");
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight direct(scene, rays);
  // The walk ends when it leaves the box grown by 10 % of its extent
  // a side: the SH distance to surfaces on the box's faces (walls, a ground plane) is
  // smooth and may overshoot them by a little; rays that missed stored the diagonal.
  const glm::dvec3 margin = 0.1 * (volume.hi - volume.lo) + 1e-9 * glm::length(volume.hi - volume.lo);
  const glm::dvec3 lo = volume.lo - margin, hi = volume.hi + margin;
  return detail::render_receivers(
      scene, rays, camera, width, height, opt.samples, opt.seed, opt.threads,
      [&](detail::Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint32_t, std::uint64_t& nr) {
        const detail::RadiosityCtx ctx{&volume, &direct, &scene, &rng, &nr};
        const glm::dvec3 Ed = direct.irradiance(rng, p, n, nr);
        return Ed + 3.14159265358979323846 * shared::gi_radiosity_incident(ctx, p, n, opt.bounces, lo, hi);
      });
}

}  // namespace atmosh::gi
