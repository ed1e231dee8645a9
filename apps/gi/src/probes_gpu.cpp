// Radiance probes of a baked surface radiance, rasterised on the GPU (see probes.hpp,
// "Probes of a baked surface radiance"): the sub-triangles with their per-vertex radiance
// drawn into cube maps by gpu::render_cube_maps (gpu/shaders/gi_probe_cube.vert/.frag),
// projected to SH on the GPU by gpu::ProbeProjector (gi_probe_project.comp, ProbeRaster::gpu_sh),
// the probe frame (ProbeFrameGpu) and the GPU-resident frame with the sun's shadow map
// (ProbeFrameResident: cube maps -> SH -> shading in one context, one read-back).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"

#ifdef ATMOSH_GI_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/cube_raster.hpp"
#include "atmosh/gpu/pixel_ray.hpp"
#include "atmosh/gpu/program.hpp"
#endif

namespace atmosh::gi::detail {

// probes.cpp
void probe_depth_range(const Scene& scene, const std::vector<glm::dvec3>& positions, double& near, double& far);
std::vector<float> texel_environment(const Scene& scene, int n);

#ifdef ATMOSH_GI_HAVE_GPU
namespace {
// The baked field as a cube-raster mesh (float, relative to its bounding-box centre).
gpu::CubeRasterMesh field_mesh(const SurfaceRadiance& field) {
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
  return mesh;
}

std::vector<std::array<double, 3>> centres_of(const std::vector<glm::dvec3>& positions) {
  std::vector<std::array<double, 3>> centres;
  centres.reserve(positions.size());
  for (const auto& p : positions) centres.push_back({p.x, p.y, p.z});
  return centres;
}
}  // namespace
#endif

std::vector<float> surface_sh_gpu(const Scene& scene, const SurfaceRadiance& field, const std::vector<glm::dvec3>& positions,
                                  int n, int s, double near, double far, const std::vector<float>& env,
                                  const ProbeOptions& opt, double* seconds) {
#ifdef ATMOSH_GI_HAVE_GPU
  const auto t0 = std::chrono::steady_clock::now();
  gpu::CubeRasterOptions co;
  co.size = n * s;
  co.near = near;
  co.far = far;
  const int nc = opt.bands * opt.bands;
  const gpu::Context ctx;
  const gpu::ProbeProjector proj(ctx, field_mesh(field), centres_of(positions), co, s, env, opt.bands, nc);
  gpu::ProbeSun sun;
  if (opt.include_sun && scene.sun) {
    const glm::dvec3 d = glm::normalize(scene.sun->direction);
    sun.on = true;
    sun.direction = {d.x, d.y, d.z};
    sun.irradiance = {scene.sun->irradiance.x, scene.sun->irradiance.y, scene.sun->irradiance.z};
  }
  proj.run(opt.bands, opt.window == sh::Window::none ? std::vector<double>{} : sh::window_weights(opt.window, opt.bands), sun);
  std::vector<float> out = proj.read_sh();
  if (seconds != nullptr) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
#else
  (void)scene, (void)field, (void)positions, (void)n, (void)s, (void)near, (void)far, (void)env, (void)opt, (void)seconds;
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

std::vector<float> surface_cubes_gpu(const SurfaceRadiance& field, const std::vector<glm::dvec3>& positions, int n,
                                     double near, double far, double* seconds) {
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::CubeRasterMesh mesh = field_mesh(field);
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

namespace atmosh::gi {

namespace {
struct Frame {  // the pinhole of render_receivers: pixel (row, col) looks along f + x right + y up
  glm::dvec3 f, right, up;
  double th = 0, aspect = 1;
  glm::dvec3 dir(int width, int height, int row, int col) const {
    const double x = (2.0 * (col + 0.5) / width - 1.0) * th * aspect, y = (1.0 - 2.0 * (row + 0.5) / height) * th;
    return glm::normalize(f + x * right + y * up);
  }
};
}  // namespace

#ifdef ATMOSH_GI_HAVE_GPU
// The camera frame, the scene as a triangle soup relative to its bounding-box centre (position,
// flat normal, albedo, emission front, back: 15 floats a vertex) and the view-projection (as
// gpu/prt.cpp: view (x, y, z) = ((p - eye).right, .up, .back), depth range the bounding sphere).
void frame_geometry(const Scene& scene, const Camera& cam, int width, int height, Frame& fr, glm::dvec3& centre,
                    std::vector<float>& vert, std::vector<std::uint32_t>& idx, float vp[16], double& radius_out,
                    glm::dvec3& eye_out) {
  const glm::dvec3 rx = glm::cross(cam.forward, cam.up);
  fr.f = glm::normalize(cam.forward);
  fr.right = glm::normalize(rx);
  fr.up = glm::cross(fr.right, fr.f);
  fr.th = std::tan(0.5 * cam.vertical_fov_deg * std::numbers::pi / 180);
  fr.aspect = static_cast<double>(width) / height;
  const auto& P = scene.mesh.positions;
  const auto& T = scene.mesh.triangles;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : P) lo = glm::min(lo, p), hi = glm::max(hi, p);
  centre = 0.5 * (lo + hi);
  // Positions relative to the bounding box's centre; one vertex per triangle corner (flat data).
  vert.reserve(T.size() * 3 * 15);
  idx.assign(T.size() * 3, 0);
  for (std::size_t t = 0; t < T.size(); ++t) {
    glm::dvec3 n = glm::cross(P[T[t][1]] - P[T[t][0]], P[T[t][2]] - P[T[t][0]]);
    const double l = glm::length(n);
    n = l > 0 && std::isfinite(l) ? n / l : glm::dvec3(0, 0, 1);
    const Material& mat = scene.materials[scene.material[t]];
    const glm::dvec3 back = mat.one_sided ? glm::dvec3(0.0) : mat.emission;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p = P[T[t][k]] - centre;
      for (const glm::dvec3& q : {p, n, mat.albedo, mat.emission, back})
        for (int c = 0; c < 3; ++c) vert.push_back(static_cast<float>(q[c]));
      idx[t * 3 + k] = static_cast<std::uint32_t>(t * 3 + k);
    }
  }
  // Projection (as gpu/prt.cpp): view (x, y, z) = ((p - eye).right, .up, .back), depth range the
  // scene's bounding sphere seen from the eye.
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-30) * 1.01;
  const glm::dvec3 eye = cam.eye - centre, back = -fr.f;
  const double dist = glm::length(eye);
  const double near_d = std::max(dist - radius, 1e-3 * radius), far_d = dist + radius;
  const double sx = 1.0 / (fr.th * fr.aspect), sy = 1.0 / fr.th;
  const double a = -(far_d + near_d) / (far_d - near_d), b = -2.0 * far_d * near_d / (far_d - near_d);
  std::fill(vp, vp + 16, 0.0f);
  auto set = [&](int r, int c, double v) { vp[c * 4 + r] = static_cast<float>(v); };
  for (int c = 0; c < 3; ++c) {
    set(0, c, sx * fr.right[c]);
    set(1, c, sy * fr.up[c]);
    set(2, c, a * back[c]);
    set(3, c, -back[c]);
  }
  set(0, 3, -sx * glm::dot(fr.right, eye));
  set(1, 3, -sy * glm::dot(fr.up, eye));
  set(2, 3, -a * glm::dot(back, eye) + b);
  set(3, 3, glm::dot(back, eye));
  radius_out = radius;
  eye_out = eye;
}

// The frame's shading program for `max_bands` bands exactly (gi_probe_shade.vert/.frag with the
// shared SH basis of libsh/include/atmosh/sh/shared/cube.glsl.hpp, ATMOSH_SH_MAX_BANDS =
// max_bands: its array's size and the shader's band count, so its loops have constant trip
// counts; and the sun's shadow-map lookup), with libsh's clamped-cosine factors A_l
// (sh::irradiance_factors) set; the program is current on return.
std::unique_ptr<gpu::Program> shade_program(int max_bands) {
  auto prog = std::make_unique<gpu::Program>(
      std::vector<gpu::ShaderPart>{gpu::embedded_source("gpu/shaders/gi_probe_shade.vert")},
      std::vector<gpu::ShaderPart>{gpu::embedded_source("libsh/include/atmosh/sh/shared/cube.glsl.hpp"),
                                   gpu::embedded_source("gpu/shaders/gi_probe_sun.glsl"),
                                   gpu::embedded_source("gpu/shaders/gi_pixel_point.glsl"),
                                   gpu::embedded_source("gpu/shaders/gi_probe_shade.frag")},
      "#define ATMOSH_SH_MAX_BANDS " + std::to_string(max_bands) + "\n");
  prog->use();
  const std::vector<double> A = sh::irradiance_factors(max_bands);
  for (int l = 0; l < max_bands; ++l) {
    const std::string name = "irradiance_factor[" + std::to_string(l) + "]";
    prog->set(name.c_str(), static_cast<float>(A[static_cast<std::size_t>(l)]));
  }
  return prog;
}

// The camera of the current shading program `prog`: its projection, the eye (relative to the
// frame's centre) and the pixel rays of gi_pixel_point.glsl (atmosh/gpu/pixel_ray.hpp).
void set_view(const gpu::Program& prog, const float* vp, const glm::vec3& eye, const Frame& fr, int width, int height) {
  prog.set_mat4("view_proj", vp);
  prog.set("eye", eye.x, eye.y, eye.z);
  gpu::set_pixel_ray(prog, fr.right, fr.up, -fr.f, fr.th, width, height);
}
#endif

namespace {
// The most bands a probe frame shades: those of the CPU probe method (ProbeOptions::bands,
// 1..16) and of the GPU projection (gpu::ProbeProjector).
constexpr int kMaxFrameBands = 16;

void check_frame_bands(int bands, int max_bands) {
  if (bands < 1 || bands > max_bands)
    throw InputError("gi probes: a probe frame shades 1.." + std::to_string(max_bands) + " bands, got " +
                     std::to_string(bands));
}

void check_frame_grid(const Scene& scene, const ProbeGrid& grid, bool grid_includes_sun, int max_bands) {
  check_frame_bands(grid.bands, max_bands);
  if (scene.sun && !grid_includes_sun)
    throw InputError("gi probes: a probe frame adds no sun: the grid must hold it (include_sun)");
  const std::size_t np_grid = static_cast<std::size_t>(grid.n) * grid.n * grid.n;
  if (grid.n < 1 || grid.probes.size() != np_grid) throw InputError("gi probes: the grid's probe count does not match n^3");
  for (const auto& q : grid.probes)
    for (const auto& c : q)
      if (c.size() != static_cast<std::size_t>(grid.bands) * grid.bands)
        throw InputError("gi probes: a probe's coefficients do not match the grid's bands");
}
}  // namespace

RadianceImage render_probes_frame(const Scene& scene, const Camera& cam, int width, int height, const ProbeGrid& grid,
                                  bool grid_includes_sun, bool gpu) {
  validate(scene);
  check_view(cam, width, height);
  check_frame_grid(scene, grid, grid_includes_sun, kMaxFrameBands);
  const glm::dvec3 rx = glm::cross(cam.forward, cam.up);
  Frame fr;
  fr.f = glm::normalize(cam.forward);
  fr.right = glm::normalize(rx);
  fr.up = glm::cross(fr.right, fr.f);
  fr.th = std::tan(0.5 * cam.vertical_fov_deg * std::numbers::pi / 180);
  fr.aspect = static_cast<double>(width) / height;
  const std::size_t npx = static_cast<std::size_t>(width) * height;
  RadianceImage img;
  img.width = width;
  img.height = height;
  img.samples = 1;
  for (int c = 0; c < 3; ++c) {
    img.mean[c].assign(npx, 0.0f);
    img.stderr_[c].assign(npx, 0.0f);
  }
  const auto& P = scene.mesh.positions;
  const auto& T = scene.mesh.triangles;
  auto tri_normal = [&](std::size_t t) {
    const glm::dvec3 n = glm::cross(P[T[t][1]] - P[T[t][0]], P[T[t][2]] - P[T[t][0]]);
    const double l = glm::length(n);
    return l > 0 && std::isfinite(l) ? n / l : glm::dvec3(0, 0, 1);
  };
  auto emission = [&](std::size_t t, bool front) {
    const Material& m = scene.materials[scene.material[t]];
    return front || !m.one_sided ? m.emission : glm::dvec3(0.0);
  };
  auto put = [&](std::size_t i, const glm::dvec3& L) {
    for (int c = 0; c < 3; ++c) img.mean[c][i] = static_cast<float>(L[c]);
  };
  if (!gpu) {
    const auto t0 = std::chrono::steady_clock::now();
    const prt::RayScene rays(scene.mesh);
    parallel_for_ranges(npx, 64, 0, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const glm::dvec3 d = fr.dir(width, height, static_cast<int>(i / width), static_cast<int>(i % width));
        std::uint32_t prim = 0;
        float u = 0, v = 0;
        double t = 0;
        if (!rays.intersect(cam.eye, d, 0.0, prim, u, v, t)) {
          put(i, environment_radiance(scene, d));
          continue;
        }
        const glm::dvec3 p = cam.eye + t * d;
        glm::dvec3 n = tri_normal(prim);
        const bool front = glm::dot(n, d) < 0;
        if (!front) n = -n;
        const glm::dvec3 E = glm::max(probe_irradiance(interpolate(grid, p), grid.bands, n), glm::dvec3(0.0));
        const Material& m = scene.materials[scene.material[prim]];
        put(i, emission(prim, front) + m.albedo / std::numbers::pi * E);
      }
    });
    img.stats.rays = npx;
    img.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return img;
  }
  const ProbeFrameGpu frame(scene, cam, width, height);
  return frame.render(grid, grid_includes_sun);
}

#ifdef ATMOSH_GI_HAVE_GPU
struct ProbeFrameGpu::Impl {
  Scene scene;
  Frame fr;
  int width = 0, height = 0;
  glm::dvec3 centre{0.0};
  float view_proj[16] = {};
  glm::vec3 eye{0.0f};
  gpu::Context ctx;
  std::unique_ptr<gpu::Program> prog;  // for prog_bands bands (made by the first render at that count)
  int prog_bands = 0;
  std::unique_ptr<gpu::MeshRaster> raster;
};
#else
struct ProbeFrameGpu::Impl {};
#endif

ProbeFrameGpu::ProbeFrameGpu(const Scene& scene, const Camera& cam, int width, int height) {
  validate(scene);
  check_view(cam, width, height);
#ifdef ATMOSH_GI_HAVE_GPU
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.scene = scene;
  m.width = width;
  m.height = height;
  std::vector<float> vert;
  std::vector<std::uint32_t> idx;
  float vp[16];
  double radius = 0;
  glm::dvec3 eye;
  frame_geometry(scene, cam, width, height, m.fr, m.centre, vert, idx, vp, radius, eye);
  std::copy(vp, vp + 16, m.view_proj);
  m.eye = glm::vec3(eye);
  m.prog = shade_program(3);  // the default band count; render() remakes it for another
  m.prog_bands = 3;
  set_view(*m.prog, m.view_proj, m.eye, m.fr, width, height);
  m.raster = std::make_unique<gpu::MeshRaster>(m.ctx, vert, std::vector<int>{3, 3, 3, 3, 3}, idx, width, height);
#else
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

ProbeFrameGpu::~ProbeFrameGpu() = default;

RadianceImage ProbeFrameGpu::render(const ProbeGrid& grid, bool grid_includes_sun) const {
#ifdef ATMOSH_GI_HAVE_GPU
  Impl& m = *impl_;
  check_frame_grid(m.scene, grid, grid_includes_sun, kMaxFrameBands);
  const std::size_t np_grid = static_cast<std::size_t>(grid.n) * grid.n * grid.n;
  const std::size_t nc = static_cast<std::size_t>(grid.bands) * grid.bands;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<float> sh(np_grid * 3 * nc, 0.0f);
  for (std::size_t q = 0; q < np_grid; ++q)
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < nc; ++i) sh[(q * 3 + c) * nc + i] = static_cast<float>(grid.probes[q][c][i]);
  m.ctx.make_current();
  if (m.prog_bands != grid.bands) {  // the shading program's basis array is sized for its band count
    m.prog = shade_program(grid.bands);
    m.prog_bands = grid.bands;
    set_view(*m.prog, m.view_proj, m.eye, m.fr, m.width, m.height);
  }
  gpu::Buffer bsh(sh.size() * sizeof(float), sh.data());
  bsh.bind(0);
  m.prog->use();
  const glm::dvec3 glo = grid.lo - m.centre, ghi = grid.hi - m.centre;
  m.prog->set("grid_lo", static_cast<float>(glo.x), static_cast<float>(glo.y), static_cast<float>(glo.z));
  m.prog->set("grid_hi", static_cast<float>(ghi.x), static_cast<float>(ghi.y), static_cast<float>(ghi.z));
  m.prog->set("grid_n", grid.n);
  m.prog->set("stride", static_cast<int>(nc));
  const std::vector<float> rgba = m.raster->draw(*m.prog);
  const std::size_t npx = static_cast<std::size_t>(m.width) * m.height;
  RadianceImage img;
  img.width = m.width;
  img.height = m.height;
  img.samples = 1;
  for (int c = 0; c < 3; ++c) {
    img.mean[c].assign(npx, 0.0f);
    img.stderr_[c].assign(npx, 0.0f);
  }
  for (std::size_t i = 0; i < npx; ++i) {
    glm::dvec3 L;
    if (rgba[i * 4 + 3] != 0.0f)
      L = {rgba[i * 4], rgba[i * 4 + 1], rgba[i * 4 + 2]};
    else
      L = environment_radiance(m.scene, m.fr.dir(m.width, m.height, static_cast<int>(i / m.width), static_cast<int>(i % m.width)));
    for (int c = 0; c < 3; ++c) img.mean[c][i] = static_cast<float>(L[c]);
  }
  img.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return img;
#else
  (void)grid, (void)grid_includes_sun;
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

// ---- The GPU-resident probe frame ----

#ifdef ATMOSH_GI_HAVE_GPU
struct ProbeFrameResident::Impl {
  Scene scene;
  ProbeFrameOptions opt;
  Frame fr;
  int width = 0, height = 0;
  glm::dvec3 centre{0.0}, grid_lo{0.0}, grid_hi{0.0};
  double radius = 1;
  std::vector<double> window;
  gpu::Context ctx;
  std::unique_ptr<gpu::ProbeProjector> projector;
  std::unique_ptr<gpu::SunShadowMap> shadow;
  std::unique_ptr<gpu::Program> prog;
  std::unique_ptr<gpu::MeshRaster> raster;
};
#else
struct ProbeFrameResident::Impl {};
#endif

ProbeFrameResident::ProbeFrameResident(const Scene& scene, const Camera& cam, int width, int height,
                                       const SurfaceRadiance& field, const ProbeFrameOptions& opt) {
  validate(scene);
  check_view(cam, width, height);
  const ProbeOptions& po = opt.probes;
  check_frame_bands(po.bands, kMaxFrameBands);
  if (po.include_sun) throw InputError("gi probes: the resident probe frame adds the sun itself (include_sun must be off)");
  if (po.cube_size < 1 || po.cube_size > 512)
    throw InputError("gi probes: cube size must be in 1..512, got " + std::to_string(po.cube_size));
  if (opt.grid < 1 || opt.grid > 64)
    throw InputError("gi probes: grid must have 1..64 probes per axis, got " + std::to_string(opt.grid));
  if (opt.supersample < 1 || opt.supersample > 16 || po.cube_size * opt.supersample > 512)
    throw InputError("gi probes: supersample must be in 1..16 with cube size x supersample <= 512, got " +
                     std::to_string(opt.supersample));
  if (opt.shadow_resolution < 16 || opt.shadow_resolution > 16384 || opt.shadow_pcf < 0 || opt.shadow_pcf > 4 ||
      !(opt.shadow_normal_offset >= 0) || !(opt.shadow_bias >= 0) ||
      !std::isfinite(opt.shadow_normal_offset + opt.shadow_bias))
    throw InputError("gi probes: shadow-map options out of range");
  const std::size_t nv = field.positions.size();
  if (field.normals.size() != nv || field.front.size() != nv || field.back.size() != nv)
    throw InputError("gi probes: the surface radiance's per-vertex arrays differ in length");
  for (const auto& t : field.triangles)
    for (auto i : t)
      if (i >= nv) throw InputError("gi probes: a surface radiance triangle indexes past its vertices");
#ifdef ATMOSH_GI_HAVE_GPU
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.scene = scene;
  m.opt = opt;
  m.width = width;
  m.height = height;
  if (po.window != sh::Window::none) m.window = sh::window_weights(po.window, po.bands);
  // the probes: positions as ProbeGrid::position over the scene's bounding box
  ProbeGrid g;
  g.lo = glm::dvec3(1e300);
  g.hi = glm::dvec3(-1e300);
  for (const auto& p : scene.mesh.positions) g.lo = glm::min(g.lo, p), g.hi = glm::max(g.hi, p);
  g.n = opt.grid;
  std::vector<glm::dvec3> pos;
  for (int k = 0; k < g.n; ++k)
    for (int j = 0; j < g.n; ++j)
      for (int i = 0; i < g.n; ++i) pos.push_back(g.position(i, j, k));
  double near = 0, far = 0;
  detail::probe_depth_range(scene, pos, near, far);
  const int NS = po.cube_size * opt.supersample;
  gpu::CubeRasterOptions co;
  co.size = NS;
  co.near = near;
  co.far = far;
  m.projector = std::make_unique<gpu::ProbeProjector>(m.ctx, detail::field_mesh(field), detail::centres_of(pos), co,
                                                      opt.supersample, detail::texel_environment(scene, NS), po.bands,
                                                      po.bands * po.bands);
  // the camera's frame
  std::vector<float> vert;
  std::vector<std::uint32_t> idx;
  float vp[16];
  glm::dvec3 eye;
  frame_geometry(scene, cam, width, height, m.fr, m.centre, vert, idx, vp, m.radius, eye);
  m.grid_lo = g.lo - m.centre;
  m.grid_hi = g.hi - m.centre;
  m.prog = shade_program(po.bands);
  set_view(*m.prog, vp, glm::vec3(eye), m.fr, width, height);
  m.prog->set("stride", m.projector->stride());
  m.raster = std::make_unique<gpu::MeshRaster>(m.ctx, vert, std::vector<int>{3, 3, 3, 3, 3}, idx, width, height);
  // the background: the environment along every pixel centre (fixed for this camera)
  std::vector<float> bg(static_cast<std::size_t>(width) * height * 4);
  parallel_for_ranges(static_cast<std::size_t>(width) * height, 256, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::dvec3 L = environment_radiance(scene, m.fr.dir(width, height, static_cast<int>(i / width),
                                                                static_cast<int>(i % width)));
      for (int c = 0; c < 3; ++c) bg[i * 4 + c] = static_cast<float>(L[c]);
      bg[i * 4 + 3] = 0.0f;
    }
  });
  m.raster->set_background(bg);
  if (scene.sun) {
    std::vector<float> soup;  // positions of the soup (15 floats a vertex)
    soup.reserve(vert.size() / 5);
    for (std::size_t v = 0; v < vert.size(); v += 15) soup.insert(soup.end(), &vert[v], &vert[v] + 3);
    m.shadow = std::make_unique<gpu::SunShadowMap>(m.ctx, soup, m.radius, opt.shadow_resolution);
  }
#else
  (void)field;
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

ProbeFrameResident::~ProbeFrameResident() = default;

RadianceImage ProbeFrameResident::render(double* pass_seconds) const {
#ifdef ATMOSH_GI_HAVE_GPU
  const Impl& m = *impl_;
  const auto t0 = std::chrono::steady_clock::now();
  auto t_pass = t0;
  auto lap = [&](int k) {
    if (pass_seconds == nullptr) return;
    gpu::finish();
    const auto t = std::chrono::steady_clock::now();
    pass_seconds[k] = std::chrono::duration<double>(t - t_pass).count();
    t_pass = t;
  };
  m.ctx.make_current();
  // 1-2. cube maps and their projection into the SH buffer
  m.projector->run(m.opt.probes.bands, m.window, gpu::ProbeSun{}, pass_seconds);
  if (pass_seconds != nullptr) t_pass = std::chrono::steady_clock::now();
  // 3. the sun's shadow map
  m.prog->use();
  m.prog->set("has_sun", m.shadow ? 1 : 0);
  if (m.shadow) {
    const glm::dvec3 s = glm::normalize(m.scene.sun->direction);
    m.shadow->render({s.x, s.y, s.z});
    float lp[16];
    m.shadow->bind(1, lp);
    const int D = m.shadow->resolution();
    m.prog->use();
    m.prog->set_mat4("sun_light_proj", lp);
    m.prog->set("sun_shadow_map", 1);
    m.prog->set("sun_dir", static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z));
    const glm::dvec3 E = m.scene.sun->irradiance;
    m.prog->set("sun_irradiance", static_cast<float>(E.x), static_cast<float>(E.y), static_cast<float>(E.z));
    m.prog->set("sun_shadow_res", D);
    m.prog->set("sun_texel", static_cast<float>(2.0 * m.radius / D));
    m.prog->set("sun_radius", static_cast<float>(m.radius));
    m.prog->set("sun_normal_offset", static_cast<float>(m.opt.shadow_normal_offset));
    m.prog->set("sun_bias", static_cast<float>(m.opt.shadow_bias));
    m.prog->set("sun_pcf", m.opt.shadow_pcf);
  }
  lap(2);
  // 4. the receivers' shading from the SH buffer
  m.projector->bind_sh(0);
  m.prog->set("grid_lo", static_cast<float>(m.grid_lo.x), static_cast<float>(m.grid_lo.y), static_cast<float>(m.grid_lo.z));
  m.prog->set("grid_hi", static_cast<float>(m.grid_hi.x), static_cast<float>(m.grid_hi.y), static_cast<float>(m.grid_hi.z));
  m.prog->set("grid_n", m.opt.grid);
  m.raster->draw_resident(*m.prog);
  // 5. the image: the frame's only read-back
  const std::vector<float> rgba = m.raster->read();
  lap(3);
  const std::size_t npx = static_cast<std::size_t>(m.width) * m.height;
  RadianceImage img;
  img.width = m.width;
  img.height = m.height;
  img.samples = 1;
  for (int c = 0; c < 3; ++c) {
    img.mean[c].resize(npx);
    img.stderr_[c].assign(npx, 0.0f);
    for (std::size_t i = 0; i < npx; ++i) img.mean[c][i] = rgba[i * 4 + c];
  }
  img.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return img;
#else
  (void)pass_seconds;
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

ProbeGrid ProbeFrameResident::grid() const {
#ifdef ATMOSH_GI_HAVE_GPU
  const Impl& m = *impl_;
  ProbeGrid g;
  g.lo = m.grid_lo + m.centre;
  g.hi = m.grid_hi + m.centre;
  g.n = m.opt.grid;
  g.bands = m.opt.probes.bands;
  const std::vector<float> c = m.projector->read_sh();
  const std::size_t np = static_cast<std::size_t>(g.n) * g.n * g.n, nc = static_cast<std::size_t>(g.bands) * g.bands;
  const std::size_t stride = static_cast<std::size_t>(m.projector->stride());
  g.probes.resize(np);
  for (std::size_t p = 0; p < np; ++p)
    for (int ch = 0; ch < 3; ++ch) g.probes[p][ch].assign(&c[(p * 3 + ch) * stride], &c[(p * 3 + ch) * stride] + nc);
  return g;
#else
  throw InputError("gi probes: this build has no GPU library (atmosh::gpu)");
#endif
}

}  // namespace atmosh::gi
