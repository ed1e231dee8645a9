// Radiance probes on the CPU (see probes.hpp).
#include "atmosh/gi/probes.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/basis.hpp"
#include "common.hpp"
#include "receivers.hpp"
#include "sampling.hpp"

namespace atmosh::gi {

namespace {
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;

void check(const ProbeOptions& o) {
  if (o.bands < 1 || o.bands > 16) throw InputError("gi probes: bands must be in 1..16, got " + std::to_string(o.bands));
  if (o.cube_size < 1 || o.cube_size > 512)
    throw InputError("gi probes: cube size must be in 1..512, got " + std::to_string(o.cube_size));
  if (o.samples < 2 || o.samples > 1000000)
    throw InputError("gi probes: samples per texel must be in 2..1000000, got " + std::to_string(o.samples));
}

TraceOptions trace_options(const ProbeOptions& o) {
  TraceOptions t;
  t.samples = o.samples;
  t.bounces = o.bounces;
  t.seed = o.seed;
  t.threads = o.threads;
  return t;
}

std::size_t texels(int n) { return static_cast<std::size_t>(6) * n * n; }

// Rays of probe p = ray / texels(n), texel t = ray % texels(n) (face, row, col order): the
// texel-centre direction, or (jitter) a uniform point of the texel's (u, v) square with
// weight J(u, v) A_uv / Omega_texel, J = (1 + u^2 + v^2)^(-3/2) the solid angle per unit
// (u, v) area — so E[weight L] = (1 / Omega) integral over the texel of L dOmega.
RayDirection texel_rays(int n, bool jitter) {
  const std::size_t nt = texels(n);
  std::vector<double> omega(static_cast<std::size_t>(n) * n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) omega[static_cast<std::size_t>(r) * n + c] = sh::cube_texel_solid_angle(c, r, n);
  return [n, nt, jitter, omega](std::size_t ray, double u1, double u2, double& w) {
    const std::size_t t = ray % nt;
    const int f = static_cast<int>(t / (static_cast<std::size_t>(n) * n));
    const int r = static_cast<int>(t / n % n), c = static_cast<int>(t % n);
    const double ju = jitter ? u1 : 0.5, jv = jitter ? u2 : 0.5;
    const double u = 2 * (c + ju) / n - 1, v = 2 * (r + jv) / n - 1;
    const double q = 1 + u * u + v * v;
    w = jitter ? (4.0 / (static_cast<double>(n) * n)) / (q * std::sqrt(q)) / omega[static_cast<std::size_t>(r) * n + c] : 1.0;
    return sh::cube_face_point(f, u, v);
  };
}

sh::CubeMap to_cube(const std::vector<glm::dvec3>& L, std::size_t first, int n) {
  sh::CubeMap cube;
  cube.size = n;
  cube.channels = 3;
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  for (int f = 0; f < 6; ++f) {
    cube.faces[f].assign(3 * nn, 0.0f);
    for (std::size_t t = 0; t < nn; ++t)
      for (int c = 0; c < 3; ++c) cube.faces[f][c * nn + t] = static_cast<float>(L[first + f * nn + t][c]);
  }
  return cube;
}

// Projection, sun, window: the probe's coefficients.
ShRgb project(const sh::CubeMap& cube, const Scene& scene, const ProbeOptions& o) {
  const sh::Channels ch = sh::project_cube(cube, o.bands, 1);
  ShRgb out;
  for (int c = 0; c < 3; ++c) out[c] = ch[c];
  if (o.include_sun && scene.sun) {
    if (scene.sun->angular_radius > 0)
      throw InputError("gi probes: include_sun needs a point sun (angular radius 0)");
    const std::vector<double> y = sh::evaluate(o.bands, glm::normalize(scene.sun->direction));
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < y.size(); ++i) out[c][i] += scene.sun->irradiance[c] * y[i];
  }
  if (o.window != sh::Window::none) {
    const std::vector<double> w = sh::window_weights(o.window, o.bands);
    for (int c = 0; c < 3; ++c)
      for (int l = 0; l < o.bands; ++l)
        for (int m = -l; m <= l; ++m) out[c][sh::sh_index(l, m)] *= w[l];
  }
  return out;
}

void bounds(const Scene& s, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (const auto& p : s.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
}
}  // namespace

sh::CubeMap render_probe_cube(const Scene& scene, const glm::dvec3& position, const ProbeOptions& opt, Stats* stats) {
  check(opt);
  if (!std::isfinite(glm::length(position))) throw InputError("gi probes: non-finite probe position");
  const std::vector<glm::dvec3> org(texels(opt.cube_size), position);
  const Irradiance L = radiance_along(scene, org, texel_rays(opt.cube_size, opt.jitter), trace_options(opt));
  if (stats != nullptr) *stats = L.stats;
  return to_cube(L.mean, 0, opt.cube_size);
}

Probe render_probe(const Scene& scene, const glm::dvec3& position, const ProbeOptions& opt) {
  Probe p;
  p.position = position;
  p.bands = opt.bands;
  const sh::CubeMap cube = render_probe_cube(scene, position, opt, &p.stats);
  p.radiance = project(cube, scene, opt);
  return p;
}

glm::dvec3 probe_irradiance(const ShRgb& radiance, int bands, const glm::dvec3& n) {
  const glm::dvec3 u = glm::normalize(n);
  return {sh::irradiance_at(radiance[0], bands, u), sh::irradiance_at(radiance[1], bands, u),
          sh::irradiance_at(radiance[2], bands, u)};
}

glm::dvec3 ProbeGrid::position(int i, int j, int k) const {
  const glm::dvec3 f((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
  return lo + f * (hi - lo);
}

ProbeGrid build_probe_grid(const Scene& scene, int n, const ProbeOptions& opt) {
  check(opt);
  if (n < 1 || n > 64) throw InputError("gi probes: grid must have 1..64 probes per axis, got " + std::to_string(n));
  validate(scene);
  const auto t0 = Clock::now();
  ProbeGrid g;
  bounds(scene, g.lo, g.hi);
  g.n = n;
  g.bands = opt.bands;
  const std::size_t np = static_cast<std::size_t>(n) * n * n, nt = texels(opt.cube_size);
  std::vector<glm::dvec3> org;
  org.reserve(np * nt);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) org.insert(org.end(), nt, g.position(i, j, k));
  const Irradiance L = radiance_along(scene, org, texel_rays(opt.cube_size, opt.jitter), trace_options(opt));
  g.stats = L.stats;
  g.probes.resize(np);
  parallel_for_ranges(np, 1, opt.threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) g.probes[p] = project(to_cube(L.mean, p * nt, opt.cube_size), scene, opt);
  });
  g.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return g;
}

namespace detail {
// The rasterised cube maps (probes_gpu.cpp): RGBA per texel, [((p * 6 + f) * N + row) * N + col] * 4,
// alpha 0 where no surface is; near/far the depth range along the face's axis.
std::vector<float> surface_cubes_gpu(const SurfaceRadiance& field, const std::vector<glm::dvec3>& positions, int n,
                                     double near, double far, double* seconds);
// The probes' SH on the GPU (probes_gpu.cpp): cube maps of size n s rasterised and projected
// to opt.bands (window, include_sun) without read-back of the cube maps; env 3 floats a texel
// of the n s cube; returns [(p * 3 + channel) * bands^2 + i].
std::vector<float> surface_sh_gpu(const Scene& scene, const SurfaceRadiance& field, const std::vector<glm::dvec3>& positions,
                                  int n, int s, double near, double far, const std::vector<float>& env,
                                  const ProbeOptions& opt, double* seconds);

// The depth range [near, far] of the probes' cube maps at `positions` (probes.hpp) and the
// environment radiance at the texel centres of an n x n cube (3 floats a texel, libsh's order).
void probe_depth_range(const Scene& scene, const std::vector<glm::dvec3>& positions, double& near, double& far) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : scene.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double diag = glm::length(hi - lo);
  double reach = 0;  // the farthest bounding-box corner from any position
  for (const auto& p : positions) {
    if (!std::isfinite(glm::length(p))) throw InputError("gi probes: non-finite probe position");
    for (int c = 0; c < 8; ++c)
      reach = std::max(reach, glm::length(glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z) - p));
  }
  near = 1e-3 * diag;
  far = reach + 2 * diag;
}

std::vector<float> texel_environment(const Scene& scene, int n) {
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  std::vector<float> env(6 * nn * 3);
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        const glm::dvec3 d = sh::cube_face_point(f, 2 * (c + 0.5) / n - 1, 2 * (r + 0.5) / n - 1);
        const glm::dvec3 L = environment_radiance(scene, glm::normalize(d));
        for (int ch = 0; ch < 3; ++ch) env[(f * nn + static_cast<std::size_t>(r) * n + c) * 3 + ch] = static_cast<float>(L[ch]);
      }
  return env;
}
}  // namespace detail

namespace {
double diagonal(const Scene& s) {
  glm::dvec3 lo, hi;
  bounds(s, lo, hi);
  return glm::length(hi - lo);
}

void check_field(const SurfaceRadiance& f) {
  const std::size_t nv = f.positions.size();
  if (f.normals.size() != nv || f.front.size() != nv || f.back.size() != nv)
    throw InputError("gi probes: the surface radiance's per-vertex arrays differ in length");
  for (const auto& t : f.triangles)
    for (auto i : t)
      if (i >= nv) throw InputError("gi probes: a surface radiance triangle indexes past its vertices");
}
}  // namespace

SurfaceRadiance bake_surface_radiance(const Scene& scene, const SurfaceRadianceOptions& opt) {
  validate(scene);
  if (opt.divisions < 1 || opt.divisions > 1024)
    throw InputError("gi probes: surface divisions must be in 1..1024, got " + std::to_string(opt.divisions));
  if (opt.samples < 2 || opt.samples > 1000000)
    throw InputError("gi probes: surface samples must be in 2..1000000, got " + std::to_string(opt.samples));
  const auto t0 = Clock::now();
  const double h = diagonal(scene) / opt.divisions;
  SurfaceRadiance f;
  std::vector<glm::dvec3> emit_front, emit_back, albedo, centroid;
  const auto& P = scene.mesh.positions;
  for (std::size_t t = 0; t < scene.mesh.triangles.size(); ++t) {
    const auto& tri = scene.mesh.triangles[t];
    const glm::dvec3 A = P[tri[0]], B = P[tri[1]], C = P[tri[2]];
    glm::dvec3 n = glm::cross(B - A, C - A);
    const double len = glm::length(n);
    n = len > 0 && std::isfinite(len) ? n / len : glm::dvec3(0, 0, 1);
    const double edge = std::max({glm::length(B - A), glm::length(C - B), glm::length(A - C)});
    const int k = std::clamp(static_cast<int>(std::ceil(edge / h - 1e-9)), 1, 64);
    const Material& m = scene.materials[scene.material[t]];
    const auto base = static_cast<std::uint32_t>(f.positions.size());
    auto id = [&](int i, int j) {  // vertex (i, j), i + j <= k, row by row in j
      return base + static_cast<std::uint32_t>(j * (k + 1) - j * (j - 1) / 2 + i);
    };
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i + j <= k; ++i) {
        f.positions.push_back(A + (static_cast<double>(i) / k) * (B - A) + (static_cast<double>(j) / k) * (C - A));
        f.normals.push_back(n);
        emit_front.push_back(m.emission);
        emit_back.push_back(m.one_sided ? glm::dvec3(0.0) : m.emission);
        albedo.push_back(m.albedo);
        centroid.push_back((A + B + C) / 3.0);
      }
    for (int j = 0; j < k; ++j)
      for (int i = 0; i + j < k; ++i) {
        f.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        if (i + j + 1 < k) f.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  }
  const std::size_t nv = f.positions.size();
  f.front = emit_front;
  f.back = emit_back;
  f.front_stderr.assign(nv, glm::dvec3(0.0));
  f.back_stderr.assign(nv, glm::dvec3(0.0));
  if (opt.bounces != 0) {
    // Each vertex's irradiance is taken 1e-3 x the diagonal inside its scene triangle (towards
    // the centroid, at most the whole way): the path tracer's rays leave 1e-4 x the diagonal
    // above the surface, and from an edge or corner itself grazing rays would pass the
    // adjacent surface before they may hit it (light leaking through corners).
    const double pull = 1e-3 * diagonal(scene);
    std::vector<glm::dvec3> pts(2 * nv), nrm(2 * nv);
    for (std::size_t v = 0; v < nv; ++v) {
      const glm::dvec3 to = centroid[v] - f.positions[v];
      const double d = glm::length(to);
      pts[2 * v] = pts[2 * v + 1] = f.positions[v] + (d > pull ? pull / d : 1.0) * to;
      nrm[2 * v] = f.normals[v];
      nrm[2 * v + 1] = -f.normals[v];
    }
    TraceOptions t;
    t.samples = opt.samples;
    t.bounces = opt.bounces;
    t.seed = opt.seed;
    t.threads = opt.threads;
    const Irradiance E = irradiance(scene, pts, nrm, t);
    f.stats = E.stats;
    for (std::size_t v = 0; v < nv; ++v) {
      f.front[v] += albedo[v] / kPi * E.mean[2 * v];
      f.back[v] += albedo[v] / kPi * E.mean[2 * v + 1];
      f.front_stderr[v] = albedo[v] / kPi * E.stderr_[2 * v];
      f.back_stderr[v] = albedo[v] / kPi * E.stderr_[2 * v + 1];
    }
  }
  f.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return f;
}

std::vector<sh::CubeMap> surface_probe_cubes(const Scene& scene, const SurfaceRadiance& field,
                                             const std::vector<glm::dvec3>& positions, int n, ProbeRaster where,
                                             double* raster_seconds) {
  validate(scene);
  check_field(field);
  if (n < 1 || n > 512) throw InputError("gi probes: cube size must be in 1..512, got " + std::to_string(n));
  glm::dvec3 lo, hi;
  bounds(scene, lo, hi);
  const double diag = glm::length(hi - lo);
  double reach = 0;  // the farthest bounding-box corner from any position
  for (const auto& p : positions) {
    if (!std::isfinite(glm::length(p))) throw InputError("gi probes: non-finite probe position");
    for (int c = 0; c < 8; ++c)
      reach = std::max(reach, glm::length(glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z) - p));
  }
  const double near = 1e-3 * diag, far = reach + 2 * diag;
  const std::size_t nn = static_cast<std::size_t>(n) * n, np = positions.size();
  // The environment along every texel centre (the same for every probe: it is distant).
  std::vector<glm::dvec3> env(6 * nn), dirs(6 * nn);
  for (int f = 0; f < 6; ++f)
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        const glm::dvec3 d = sh::cube_face_point(f, 2 * (c + 0.5) / n - 1, 2 * (r + 0.5) / n - 1);
        const std::size_t t = f * nn + static_cast<std::size_t>(r) * n + c;
        dirs[t] = d;
        env[t] = environment_radiance(scene, glm::normalize(d));
      }
  std::vector<sh::CubeMap> cubes(np);
  for (auto& cube : cubes) {
    cube.size = n;
    cube.channels = 3;
    for (auto& face : cube.faces) face.assign(3 * nn, 0.0f);
  }
  const auto t0 = Clock::now();
  if (where != ProbeRaster::cpu_rays) {
    const std::vector<float> tex = detail::surface_cubes_gpu(field, positions, n, near, far, raster_seconds);
    for (std::size_t p = 0; p < np; ++p)
      for (int f = 0; f < 6; ++f)
        for (std::size_t t = 0; t < nn; ++t) {
          const float* q = &tex[((p * 6 + f) * nn + t) * 4];
          for (int c = 0; c < 3; ++c)
            cubes[p].faces[f][c * nn + t] = q[3] != 0.0f ? q[c] : static_cast<float>(env[f * nn + t][c]);
        }
    return cubes;
  }
  // CPU: one ray per texel centre along the unnormalised face direction, so that t is the depth
  // along the face's axis (its largest component is 1), clipped to [near, far] as the rasteriser.
  prt::Mesh m;
  m.positions = field.positions;
  m.normals = field.normals;
  m.triangles = field.triangles;
  m.name = "surface radiance";
  const prt::RayScene rays(m);
  parallel_for_ranges(np * 6 * nn, 256, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::size_t p = i / (6 * nn), t = i % (6 * nn);
      const int f = static_cast<int>(t / nn);
      std::uint32_t prim = 0;
      float u = 0, v = 0;
      double dist = 0;
      glm::dvec3 L = env[t];
      if (rays.intersect(positions[p], dirs[t], near, prim, u, v, dist) && dist <= far) {
        const auto& tri = field.triangles[prim];
        const bool front = glm::dot(field.normals[tri[0]], dirs[t]) < 0;
        const auto& side = front ? field.front : field.back;
        L = (1.0 - u - v) * side[tri[0]] + static_cast<double>(u) * side[tri[1]] + static_cast<double>(v) * side[tri[2]];
      }
      for (int c = 0; c < 3; ++c) cubes[p].faces[f][c * nn + (t % nn)] = static_cast<float>(L[c]);
    }
  });
  if (raster_seconds != nullptr) *raster_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return cubes;
}

ProbeGrid build_probe_grid_surface(const Scene& scene, const SurfaceRadiance& field, int n, const ProbeOptions& opt,
                                   ProbeRaster where, int supersample) {
  check(opt);
  if (n < 1 || n > 64) throw InputError("gi probes: grid must have 1..64 probes per axis, got " + std::to_string(n));
  if (supersample < 1 || supersample > 16 || opt.cube_size * supersample > 512)
    throw InputError("gi probes: supersample must be in 1..16 with cube size x supersample <= 512, got " +
                     std::to_string(supersample));
  const auto t0 = Clock::now();
  ProbeGrid g;
  bounds(scene, g.lo, g.hi);
  g.n = n;
  g.bands = opt.bands;
  const std::size_t np = static_cast<std::size_t>(n) * n * n;
  std::vector<glm::dvec3> pos;
  pos.reserve(np);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) pos.push_back(g.position(i, j, k));
  const int N = opt.cube_size, S = supersample, NS = N * S;
  if (where == ProbeRaster::gpu_sh) {
    validate(scene);
    check_field(field);
    if (opt.include_sun && scene.sun && scene.sun->angular_radius > 0)
      throw InputError("gi probes: include_sun needs a point sun (angular radius 0)");
    double near = 0, far = 0;
    detail::probe_depth_range(scene, pos, near, far);
    const std::vector<float> c =
        detail::surface_sh_gpu(scene, field, pos, N, S, near, far, detail::texel_environment(scene, NS), opt, nullptr);
    const std::size_t nc = static_cast<std::size_t>(opt.bands) * opt.bands;
    g.probes.resize(np);
    for (std::size_t p = 0; p < np; ++p)
      for (int ch = 0; ch < 3; ++ch) g.probes[p][ch].assign(&c[(p * 3 + ch) * nc], &c[(p * 3 + ch) * nc] + nc);
    g.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return g;
  }
  std::vector<sh::CubeMap> cubes = surface_probe_cubes(scene, field, pos, NS, where);
  if (where == ProbeRaster::cpu_rays) g.stats.rays = np * texels(NS);
  if (S > 1) {  // texel means: sub-texels weighted by their exact solid angles over the texel's
    std::vector<double> w(static_cast<std::size_t>(NS) * NS);
    for (int r = 0; r < NS; ++r)
      for (int c = 0; c < NS; ++c)
        w[static_cast<std::size_t>(r) * NS + c] = sh::cube_texel_solid_angle(c, r, NS) / sh::cube_texel_solid_angle(c / S, r / S, N);
    const std::size_t nn = static_cast<std::size_t>(N) * N, nns = static_cast<std::size_t>(NS) * NS;
    parallel_for_ranges(np, 1, opt.threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t p = b; p < e; ++p) {
        sh::CubeMap small;
        small.size = N;
        small.channels = 3;
        for (int f = 0; f < 6; ++f) {
          std::vector<double> acc(3 * nn, 0.0);
          for (int ch = 0; ch < 3; ++ch)
            for (int r = 0; r < NS; ++r)
              for (int c = 0; c < NS; ++c)
                acc[ch * nn + static_cast<std::size_t>(r / S) * N + c / S] +=
                    w[static_cast<std::size_t>(r) * NS + c] * cubes[p].faces[f][ch * nns + static_cast<std::size_t>(r) * NS + c];
          small.faces[f].assign(acc.begin(), acc.end());
        }
        cubes[p] = std::move(small);
      }
    });
  }
  g.probes.resize(np);
  parallel_for_ranges(np, 1, opt.threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) g.probes[p] = project(cubes[p], scene, opt);
  });
  g.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return g;
}

ProbeGrid truncate_grid(const ProbeGrid& grid, int bands, sh::Window w) {
  if (bands < 1 || bands > grid.bands)
    throw InputError("gi probes: cannot truncate a grid of " + std::to_string(grid.bands) + " bands to " +
                     std::to_string(bands));
  ProbeGrid g = grid;
  g.bands = bands;
  const std::vector<double> wl = w == sh::Window::none ? std::vector<double>(bands, 1.0) : sh::window_weights(w, bands);
  for (auto& p : g.probes)
    for (auto& c : p) {
      c.resize(static_cast<std::size_t>(bands) * bands);
      for (int l = 0; l < bands; ++l)
        for (int m = -l; m <= l; ++m) c[sh::sh_index(l, m)] *= wl[l];
    }
  return g;
}

namespace {
// The 8 probes around p and their trilinear weights (p clamped to the centres' span).
void corners(const ProbeGrid& g, const glm::dvec3& p, std::size_t idx[8], double w[8]) {
  if (g.n < 1 || g.probes.size() != static_cast<std::size_t>(g.n) * g.n * g.n)
    throw InputError("gi probes: grid of " + std::to_string(g.n) + " per axis holds " + std::to_string(g.probes.size()) +
                     " probes");
  detail::trilinear_corners(g, p, idx, w);
}

ShRgb blend(const ProbeGrid& g, const std::size_t idx[8], const double w[8]) {
  const std::size_t nc = static_cast<std::size_t>(g.bands) * g.bands;
  ShRgb out;
  for (auto& c : out) c.assign(nc, 0.0);
  for (int corner = 0; corner < 8; ++corner) {
    if (w[corner] == 0) continue;
    const ShRgb& q = g.probes[idx[corner]];
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < nc; ++i) out[c][i] += w[corner] * q[c][i];
  }
  return out;
}
}  // namespace

ShRgb interpolate(const ProbeGrid& g, const glm::dvec3& p) {
  std::size_t idx[8];
  double w[8];
  corners(g, p, idx, w);
  return blend(g, idx, w);
}

RadianceImage render_probes(const Scene& scene, const Camera& cam, int width, int height, const ProbeGrid& grid,
                            bool grid_includes_sun, const ProbeRenderOptions& opt) {
  validate(scene);
  check_view(cam, width, height);
  if (opt.samples < 1 || opt.samples > 1000000)
    throw InputError("gi probes: camera rays per pixel must be in 1..1000000, got " + std::to_string(opt.samples));
  const auto ts = Clock::now();
  const prt::RayScene rays(scene.mesh);
  const double off = rays.offset();
  const bool sun_direct = scene.sun.has_value() && !grid_includes_sun;
  glm::dvec3 sun_dir(0, 0, 1), sun_e(0.0);
  double sun_cos_max = 1;
  if (scene.sun) {
    sun_dir = glm::normalize(scene.sun->direction);
    sun_e = scene.sun->irradiance;
    const double a = scene.sun->angular_radius;
    if (a > 0) {
      sun_cos_max = std::cos(a);
      sun_e = scene.sun->irradiance / (kPi * std::sin(a) * std::sin(a)) * (2 * kPi * (1 - sun_cos_max));
    }
  }
  const auto t0 = Clock::now();
  const std::size_t nc = static_cast<std::size_t>(grid.bands) * grid.bands;
  std::vector<double> a_of(nc);  // A_l of each coefficient
  {
    const std::vector<double> A = sh::irradiance_factors(grid.bands);
    for (int l = 0; l < grid.bands; ++l)
      for (int m = -l; m <= l; ++m) a_of[sh::sh_index(l, m)] = A[l];
  }
  for (const auto& q : grid.probes)
    for (const auto& c : q)
      if (c.size() != nc) throw InputError("gi probes: a probe's coefficients do not match the grid's bands");
  const detail::ReceiverShade shade = [&](detail::Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint32_t,
                                           std::uint64_t& r) {
    thread_local std::vector<double> ay;
    ay.resize(nc);
    std::size_t idx[8];
    double wt[8];
    corners(grid, p, idx, wt);
    if (opt.visibility) {  // drop the probes p cannot see; renormalise (all hidden: plain trilinear)
      double sum = 0, keep[8];
      for (int q = 0; q < 8; ++q) {
        keep[q] = 0;
        if (wt[q] == 0) continue;
        const int ii = static_cast<int>(idx[q] % grid.n), jj = static_cast<int>(idx[q] / grid.n % grid.n),
                  kk = static_cast<int>(idx[q] / grid.n / grid.n);
        glm::dvec3 to = grid.position(ii, jj, kk) - p;
        const double dist = glm::length(to);
        if (dist > 2 * off && glm::dot(to, n) <= 0) continue;  // behind the receiver's surface
        ++r;
        if (dist <= 2 * off || rays.unoccluded(p, to / dist, off, dist - off)) keep[q] = wt[q], sum += wt[q];
      }
      if (sum > 0)
        for (int q = 0; q < 8; ++q) wt[q] = keep[q] / sum;
    }
    // E_c = sum_q w_q sum_i A_l(i) Y_i(n) c_q,c,i (the same as probe_irradiance of the blend)
    sh::evaluate(grid.bands, n, ay.data());
    for (std::size_t i = 0; i < nc; ++i) ay[i] *= a_of[i];
    glm::dvec3 E(0.0);
    for (int q = 0; q < 8; ++q) {
      if (wt[q] == 0) continue;
      const ShRgb& cq = grid.probes[idx[q]];
      for (int ch = 0; ch < 3; ++ch) {
        double e = 0;
        for (std::size_t i = 0; i < nc; ++i) e += ay[i] * cq[ch][i];
        E[ch] += wt[q] * e;
      }
    }
    E = glm::max(E, glm::dvec3(0.0));
    if (sun_direct) {
      glm::dvec3 wl = sun_dir;
      if (sun_cos_max < 1) {
        wl = detail::sample_cone(rng, sun_dir, sun_cos_max);
      }
      const double c = glm::dot(n, wl);
      if (c > 0) {
        ++r;
        if (rays.unoccluded(p, wl, off)) E += sun_e * c;
      }
    }
    return E;
  };
  RadianceImage img = detail::render_receivers(scene, rays, cam, width, height, opt.samples, opt.seed, opt.threads, shade,
                                               detail::kProbeSalt);
  img.stats.setup_seconds = std::chrono::duration<double>(t0 - ts).count();
  // every ray but one camera ray per sample is a shadow ray (probe visibility, sun)
  img.stats.shadow_rays = img.stats.rays - static_cast<std::uint64_t>(width) * height * opt.samples;
  return img;
}

ImageError image_error(const RadianceImage& a, const RadianceImage& r, const std::vector<unsigned char>* skip) {
  if (a.width != r.width || a.height != r.height || a.mean[0].size() != r.mean[0].size())
    throw InputError("gi image error: images of different sizes");
  if (skip != nullptr && skip->size() != r.mean[0].size())
    throw InputError("gi image error: the pixel mask has " + std::to_string(skip->size()) + " entries for " +
                     std::to_string(r.mean[0].size()) + " pixels");
  double sum_r = 0, sum_a = 0, max_d = 0, sum_d2 = 0, leak = 0;
  std::size_t n = 0;
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < r.mean[c].size(); ++i) {
      if (skip != nullptr && (*skip)[i] != 0) continue;
      const double rv = r.mean[c][i], av = a.mean[c][i], se = r.stderr_[c].empty() ? 0.0 : r.stderr_[c][i];
      const double d = av - rv;
      sum_r += rv;
      sum_a += av;
      max_d = std::max(max_d, std::abs(d));
      sum_d2 += d * d;
      leak += std::max(0.0, d - 3 * se);
      ++n;
    }
  ImageError e;
  const double mean_r = n > 0 ? sum_r / n : 0;
  if (!(mean_r > 0)) throw InputError("gi image error: the reference image is black (where compared)");
  e.max_rel = max_d / mean_r;
  e.rms_rel = std::sqrt(sum_d2 / n) / mean_r;
  e.leak_rel = leak / sum_r;
  e.mean_rel = sum_a / sum_r;
  return e;
}

std::vector<unsigned char> emitter_mask(const RadianceImage& d, int border) {
  const int w = d.width, h = d.height;
  std::vector<unsigned char> m(static_cast<std::size_t>(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (!(d.mean[0][i] > 0 || d.mean[1][i] > 0 || d.mean[2][i] > 0)) continue;
      for (int yy = std::max(0, y - border); yy <= std::min(h - 1, y + border); ++yy)
        for (int xx = std::max(0, x - border); xx <= std::min(w - 1, x + border); ++xx)
          m[static_cast<std::size_t>(yy) * w + xx] = 1;
    }
  return m;
}

}  // namespace atmosh::gi
