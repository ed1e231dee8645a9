// The multi-bounce radiosity approximation on the CPU (see radiosity.hpp).
#include "atmosh/gi/radiosity.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/shared/radiosity.glsl.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/projection.hpp"
#include "common.hpp"
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
  detail::trilinear_corners(g, p, idx, w);
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

// Trilinear blend at p of one of the volume's per-probe vectors (normal, albedo).
static glm::dvec3 volume_blend(const RadiosityVolume& v, const std::vector<glm::dvec3>& field, const glm::dvec3& p) {
  std::size_t idx[8];
  double w[8];
  corners(v, p, idx, w);
  glm::dvec3 s(0.0);
  for (int q = 0; q < 8; ++q) s += w[q] * field[idx[q]];
  return s;
}

glm::dvec3 volume_normal(const RadiosityVolume& v, const glm::dvec3& p) { return volume_blend(v, v.normal, p); }

glm::dvec3 volume_albedo(const RadiosityVolume& v, const glm::dvec3& p) { return volume_blend(v, v.albedo, p); }

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

// ---- The GPU pass's CPU twin and its inputs --------------------------------------------

void add_direct_volume(const Scene& scene, RadiosityVolume& v, int normals, int samples, std::uint64_t seed,
                       int threads) {
  if (normals < 4 || normals > 4096)
    throw InputError("gi radiosity: direct-light normals must be in 4..4096, got " + std::to_string(normals));
  if (samples < 1 || samples > 4096)
    throw InputError("gi radiosity: direct-light samples must be in 1..4096, got " + std::to_string(samples));
  validate(scene);
  const std::size_t np = static_cast<std::size_t>(v.n) * v.n * v.n;
  if (v.n < 1 || v.normal.size() != np) throw InputError("gi radiosity: the volume's arrays do not match its size");
  const auto t0 = Clock::now();
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight direct(scene, rays);
  // Spherical Fibonacci directions (golden-angle spiral, equal-area bands in z).
  std::vector<glm::dvec3> dir(static_cast<std::size_t>(normals));
  const double ga = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < normals; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / normals, r = std::sqrt(std::max(0.0, 1 - z * z));
    dir[static_cast<std::size_t>(k)] = {r * std::cos(ga * k), r * std::sin(ga * k), z};
  }
  const double w = 4 * std::numbers::pi / normals;
  v.direct.assign(np, {});
  std::vector<std::uint64_t> counts(np, 0);
  parallel_for_ranges(np, 1, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const int i = static_cast<int>(p % v.n), j = static_cast<int>(p / v.n % v.n), k = static_cast<int>(p / v.n / v.n);
      const glm::dvec3 x = v.position(i, j, k);
      detail::Rng rng(seed, p, detail::kLightSalt ^ 0x5bd1e995ULL);
      std::array<double, 12> c{};
      for (const glm::dvec3& n : dir) {
        glm::dvec3 E(0.0);
        for (int s = 0; s < samples; ++s) E += direct.irradiance(rng, x, n, counts[p]);
        E /= samples;
        const double y[4] = {0.28209479177387814, -0.48860251190291992 * n.y, 0.48860251190291992 * n.z,
                             -0.48860251190291992 * n.x};
        for (int ch = 0; ch < 3; ++ch)
          for (int q = 0; q < 4; ++q) c[static_cast<std::size_t>(ch * 4 + q)] += w * E[ch] * y[q];
      }
      v.direct[p] = c;
    }
  });
  for (auto c : counts) v.rays += c;
  v.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
}

void radiosity_walk_box(const RadiosityVolume& v, glm::dvec3& lo, glm::dvec3& hi) {
  const glm::dvec3 margin = 0.1 * (v.hi - v.lo) + 1e-9 * glm::length(v.hi - v.lo);
  lo = v.lo - margin;
  hi = v.hi + margin;
}

namespace detail {
// The CPU twin's context: the volume's fetches and its direct-light SH at the walk vertices.
struct VolumeDirectCtx {
  const RadiosityVolume* v;
};
inline double gi_fetch_distance(const VolumeDirectCtx& c, const glm::dvec3& p, const glm::dvec3& d) {
  return volume_distance(*c.v, p, d);
}
inline glm::dvec3 gi_fetch_normal(const VolumeDirectCtx& c, const glm::dvec3& q) { return volume_normal(*c.v, q); }
inline glm::dvec3 gi_fetch_albedo(const VolumeDirectCtx& c, const glm::dvec3& q) { return volume_albedo(*c.v, q); }
inline glm::dvec3 gi_direct_irradiance(const VolumeDirectCtx& c, const glm::dvec3& q, const glm::dvec3& n) {
  std::size_t idx[8];
  double w[8];
  corners(*c.v, q, idx, w);
  glm::dvec3 E(0.0);
  for (int ch = 0; ch < 3; ++ch) {
    double s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int k = 0; k < 8; ++k)
      if (w[k] != 0)
        for (int i = 0; i < 4; ++i) s[i] += w[k] * c.v->direct[idx[k]][static_cast<std::size_t>(ch * 4 + i)];
    E[ch] = std::max(shared::gi_sh_eval(s, 2, n), 0.0);
  }
  return E;
}
}  // namespace detail

std::vector<glm::dvec3> shade_receivers_cpu(const RadiosityVolume& v, const RadiosityReceivers& r, int bounces) {
  const std::size_t np = static_cast<std::size_t>(v.n) * v.n * v.n;
  if (v.n < 1 || v.distance.size() != np || v.normal.size() != np || v.albedo.size() != np || v.direct.size() != np)
    throw InputError("gi radiosity: the volume's arrays (direct light included) do not match its size");
  if (bounces < 0 || bounces > 16) throw InputError("gi radiosity: bounces must be in 0..16, got " + std::to_string(bounces));
  glm::dvec3 lo, hi;
  radiosity_walk_box(v, lo, hi);
  const detail::VolumeDirectCtx ctx{&v};
  std::vector<glm::dvec3> out(r.size());
  parallel_for_ranges(r.size(), 256, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::dvec3 Lin = shared::gi_radiosity_incident(ctx, r.position[i], r.normal[i], bounces, lo, hi);
      const glm::dvec3 E = glm::max(r.direct[i] + std::numbers::pi * Lin, glm::dvec3(0.0));
      out[i] = r.emission[i] + r.albedo[i] / std::numbers::pi * E;
    }
  });
  return out;
}

RadiosityGBuffer radiosity_gbuffer(const Scene& scene, const Camera& cam, int width, int height, int samples,
                                   std::uint64_t seed, int threads) {
  validate(scene);
  check_view(cam, width, height);
  if (samples < 1 || samples > 1000000)
    throw InputError("gi radiosity: direct-light samples per pixel must be in 1..1000000, got " + std::to_string(samples));
  const glm::dvec3 rx = glm::cross(cam.forward, cam.up);
  const glm::dvec3 f = glm::normalize(cam.forward), right = glm::normalize(rx), up = glm::cross(right, f);
  const double th = std::tan(0.5 * cam.vertical_fov_deg * std::numbers::pi / 180),
               aspect = static_cast<double>(width) / height;
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight direct(scene, rays);
  const std::vector<glm::dvec3>& normal = direct.normals();
  const bool has_env = scene.env_bands > 0 || scene.env_map.has_value();
  const std::size_t np = static_cast<std::size_t>(width) * height;
  // Per pixel first (hit or not), compacted afterwards in pixel order.
  std::vector<char> hit(np, 0);
  RadiosityReceivers all;
  for (auto* a : {&all.position, &all.normal, &all.albedo, &all.emission, &all.direct}) a->assign(np, glm::dvec3(0.0));
  RadiosityGBuffer g;
  g.background.assign(np, glm::dvec3(0.0));
  std::vector<std::uint64_t> counts(np, 0);
  parallel_for_ranges(np, 64, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const int row = static_cast<int>(i / width), col = static_cast<int>(i % width);
      const double x = (2.0 * (col + 0.5) / width - 1.0) * th * aspect, y = (1.0 - 2.0 * (row + 0.5) / height) * th;
      const glm::dvec3 d = glm::normalize(f + x * right + y * up);
      std::uint32_t prim;
      float u, vv;
      double t;
      ++counts[i];
      if (!rays.intersect(cam.eye, d, rays.offset(), prim, u, vv, t)) {
        if (has_env) g.background[i] = environment_radiance(scene, d);
        continue;
      }
      hit[i] = 1;
      const glm::dvec3 p = cam.eye + t * d;
      const glm::dvec3 n = glm::dot(normal[prim], d) < 0 ? normal[prim] : -normal[prim];
      const Material& mat = scene.materials[scene.material[prim]];
      all.position[i] = p;
      all.normal[i] = n;
      all.albedo[i] = mat.albedo;
      if (!mat.one_sided || glm::dot(normal[prim], -d) > 0) all.emission[i] = mat.emission;
      detail::Rng rng(seed, i, detail::kReceiverSalt);
      glm::dvec3 E(0.0);
      for (int s = 0; s < samples; ++s) E += direct.irradiance(rng, p, n, counts[i]);
      all.direct[i] = E / static_cast<double>(samples);
    }
  });
  for (std::size_t i = 0; i < np; ++i) {
    g.rays += counts[i];
    if (!hit[i]) continue;
    g.pixel.push_back(i);
    g.receivers.position.push_back(all.position[i]);
    g.receivers.normal.push_back(all.normal[i]);
    g.receivers.albedo.push_back(all.albedo[i]);
    g.receivers.emission.push_back(all.emission[i]);
    g.receivers.direct.push_back(all.direct[i]);
  }
  return g;
}

RadianceImage render_radiosity_gbuffer(const Scene& scene, const Camera& camera, int width, int height,
                                       RadiosityVolume& volume, const RadiosityOptions& opt, bool gpu) {
  check(opt);
  if (volume.direct.empty()) add_direct_volume(scene, volume, 32, 4, opt.seed, opt.threads);
  const auto t0 = Clock::now();
  const RadiosityGBuffer g =
      gpu ? radiosity_gbuffer_gpu(scene, camera, width, height, opt.samples, opt.seed, opt.threads)
          : radiosity_gbuffer(scene, camera, width, height, opt.samples, opt.seed, opt.threads);
  const std::vector<glm::dvec3> L =
      gpu ? shade_receivers_gpu(volume, g.receivers, opt.bounces) : shade_receivers_cpu(volume, g.receivers, opt.bounces);
  RadianceImage img = detail::gbuffer_image(g, L, width, height);
  img.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return img;
}

}  // namespace atmosh::gi
