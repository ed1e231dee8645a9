// Light propagation volumes on the CPU (see lpv.hpp).
#include "atmosh/gi/lpv.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/shared/lpv.glsl.hpp"
#include "atmosh/gi/shared/radiosity.glsl.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "common.hpp"
#include "raster_gpu.hpp"
#include "receivers.hpp"

#ifdef ATMOSH_GI_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"
#endif

namespace atmosh::gi {

namespace {
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;

void check(const LpvOptions& o) {
  if (o.grid < 1 || o.grid > 256) throw InputError("gi lpv: grid must be in 1..256, got " + std::to_string(o.grid));
  if (o.iterations < -1 || o.iterations > 1024)
    throw InputError("gi lpv: iterations must be -1 (2 x grid) or 0..1024, got " + std::to_string(o.iterations));
  if (o.sun_rays < 1 || o.sun_rays > 256)
    throw InputError("gi lpv: sun rays per cell must be in 1..256, got " + std::to_string(o.sun_rays));
  if (o.emitter_photons < 0 || o.emitter_photons > 100000000)
    throw InputError("gi lpv: emitter photons must be in 0..1e8, got " + std::to_string(o.emitter_photons));
  if (o.samples < 1 || o.samples > 1000000)
    throw InputError("gi lpv: camera rays per pixel must be in 1..1000000, got " + std::to_string(o.samples));
  if (o.emitter_rsm != 0 && (o.emitter_rsm < 2 || o.emitter_rsm > 1024))
    throw InputError("gi lpv: the emitters' RSM resolution must be 0 (photon rays) or 2..1024, got " +
                     std::to_string(o.emitter_rsm));
  if (o.reemission != LpvReemission::direction && o.reemission != LpvReemission::face_lobe)
    throw InputError("gi lpv: unknown re-emission " + std::to_string(static_cast<int>(o.reemission)));
}

#ifdef ATMOSH_GI_HAVE_GPU
// An LPV shader with the shared blocks pasted before it (gi_lpv_decl.glsl, radiosity.glsl.hpp,
// lpv.glsl.hpp).
std::vector<gpu::ShaderPart> lpv_shader(const char* path) {
  return {gpu::embedded_source("gpu/shaders/gi_lpv_decl.glsl"),
          gpu::embedded_source("apps/gi/include/atmosh/gi/shared/radiosity.glsl.hpp"),
          gpu::embedded_source("apps/gi/include/atmosh/gi/shared/lpv.glsl.hpp"), gpu::embedded_source(path)};
}
#endif

void check_grid(const LpvGrid& g) {
  if (g.nx < 1 || g.ny < 1 || g.nz < 1 || !(g.h > 0) ||
      g.cells.size() != static_cast<std::size_t>(g.nx) * g.ny * g.nz)
    throw InputError("gi lpv: the grid's cells do not match its size");
}

// The CPU's views of the volume for the shared LPV block (atmosh/gi/shared/lpv.glsl.hpp): a
// field's cells and, for the propagation, the table of open faces (1 - blocking, float).
struct CpuField {
  const LpvGrid* g;
  const std::vector<float>* vis;  // [(t * 6 + d) * 5 + f]; null: every face open
  int reemission = 0;             // LpvReemission: the row of the face table's re-emission
};
[[maybe_unused]] glm::dvec4 gi_lpv_fetch(const CpuField& c, glm::ivec3 s, int ch) {
  const LpvCell& x = c.g->cells[c.g->index(s.x, s.y, s.z)];
  return {x[ch * 4], x[ch * 4 + 1], x[ch * 4 + 2], x[ch * 4 + 3]};
}
[[maybe_unused]] double gi_lpv_open(const CpuField& c, glm::ivec3 t, glm::ivec3, int d, int f) {
  return c.vis == nullptr ? 1.0 : static_cast<double>((*c.vis)[(c.g->index(t.x, t.y, t.z) * 6 + d) * 5 + f]);
}
// The gather's per-face constants, tabulated once from the shared functions.
struct FaceTable {
  glm::dvec4 y[30], reemit[2][30];  // reemit[LpvReemission][d * 5 + f]
  FaceTable() {
    for (int d = 0; d < 6; ++d)
      for (int f = 0; f < 5; ++f) {
        y[d * 5 + f] = shared::gi_lpv_sh4(shared::gi_lpv_face_direction(d, f));
        for (int r = 0; r < 2; ++r) reemit[r][d * 5 + f] = shared::gi_lpv_reemit_choice(r, d, f);
      }
  }
};
const FaceTable& face_table() {
  static const FaceTable t;
  return t;
}
// (built element by element: a copy of the table's entry is a memcpy call under AddressSanitizer)
[[maybe_unused]] glm::dvec4 gi_lpv_face_y(const CpuField&, int d, int f) {
  const glm::dvec4& v = face_table().y[d * 5 + f];
  return {v.x, v.y, v.z, v.w};
}
[[maybe_unused]] glm::dvec4 gi_lpv_face_reemit(const CpuField& c, int d, int f) {
  const glm::dvec4& v = face_table().reemit[c.reemission][d * 5 + f];
  return {v.x, v.y, v.z, v.w};
}
struct CpuGeometry {
  const GeometryVolume* gv;
};
[[maybe_unused]] double gi_lpv_fetch_corner(const CpuGeometry& c, int idx, int q) {
  return c.gv->corners[static_cast<std::size_t>(idx)][q];
}
glm::ivec3 dims(const LpvGrid& g) { return {g.nx, g.ny, g.nz}; }
}  // namespace

const char* lpv_reemission_name(LpvReemission r) {
  return r == LpvReemission::face_lobe ? "paper" : "direction";
}

LpvReemission lpv_reemission_from_name(const std::string& name) {
  if (name == "direction") return LpvReemission::direction;
  if (name == "paper") return LpvReemission::face_lobe;
  throw InputError("--lpv-reemission: unknown re-emission '" + name + "' (direction, paper)");
}

LpvFaceAngles lpv_face_solid_angles() {
  // Unit cells, source centre at the origin, neighbour centre at (0, 0, 1).
  // Far face: the square |x|, |y| <= 1/2 in the plane z = 3/2, centred on the axis. A
  // rectangle a x b at distance d centred on the axis subtends 4 asin(ab / sqrt((a^2 + 4 d^2)
  // (b^2 + 4 d^2))): 4 asin(1 / sqrt(10 * 10)) = 4 asin(1/10).
  // Side face: x = 1/2, |y| <= 1/2, 1/2 <= z <= 3/2. A rectangle [0, a] x [0, b] in a plane at
  // distance d with a corner at the foot of the perpendicular subtends
  // F(a, b) = atan(ab / (d sqrt(d^2 + a^2 + b^2))); by symmetry in y and subtraction in z,
  // side = 2 (F(1/2, 3/2) - F(1/2, 1/2)) at d = 1/2 = 2 (atan(3 / sqrt(11)) - atan(1 / sqrt(3))).
  LpvFaceAngles a;
  a.front = shared::gi_lpv_front_solid_angle();
  a.side = shared::gi_lpv_side_solid_angle();
  return a;
}

LpvGrid lpv_grid(const Scene& scene, int grid) {
  if (grid < 1 || grid > 256) throw InputError("gi lpv: grid must be in 1..256, got " + std::to_string(grid));
  glm::dvec3 lo, hi;
  detail::mesh_bounds(scene.mesh, lo, hi);
  const glm::dvec3 ext = hi - lo;
  const double longest = std::max(ext.x, std::max(ext.y, ext.z));
  if (!(longest > 0) || !std::isfinite(longest)) throw InputError("gi lpv: the scene's bounding box is empty");
  LpvGrid g;
  g.lo = lo;
  g.h = longest / grid;
  auto cells = [&](double e) { return std::max(1, static_cast<int>(std::ceil(e / g.h - 1e-9))); };
  g.nx = cells(ext.x), g.ny = cells(ext.y), g.nz = cells(ext.z);
  g.cells.assign(static_cast<std::size_t>(g.nx) * g.ny * g.nz, LpvCell{});
  return g;
}

namespace {
void cell_of(const LpvGrid& g, const glm::dvec3& p, int& i, int& j, int& k) {
  const glm::ivec3 c = shared::gi_lpv_cell_of(p, g.lo, g.h, dims(g));
  i = c.x, j = c.y, k = c.z;
}
}  // namespace

void lpv_add_vpl(LpvGrid& g, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& flux, bool isotropic) {
  check_grid(g);
  int i, j, k;
  cell_of(g, p, i, j, k);
  LpvCell& c = g.cells[g.index(i, j, k)];
  const glm::dvec4 y = shared::gi_lpv_lobe(n);  // Phi / pi A_l Y_lm(n) at Phi = 1
  for (int ch = 0; ch < 3; ++ch) {
    if (isotropic) {  // I = Phi / (4 pi): c_00 = Phi / (4 pi) sqrt(4 pi)
      c[ch * 4] += flux[ch] / std::sqrt(4 * kPi);
      continue;
    }
    for (int q = 0; q < 4; ++q) c[ch * 4 + q] += flux[ch] * y[q];
  }
}

std::vector<Vpl> lpv_vpls(const Scene& scene, const LpvOptions& opt, const LpvGrid& g, std::uint64_t* nrays) {
  check(opt);
  validate(scene);
  check_grid(g);
  std::vector<Vpl> out;
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight dl(scene, rays);
  const std::vector<glm::dvec3>& normal = dl.normals();
  const double off = rays.offset();
  std::uint64_t count = 0;
  glm::dvec3 lo, hi;
  detail::mesh_bounds(scene.mesh, lo, hi);
  const double diag = glm::length(hi - lo);
  auto deposit = [&](const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& flux) {
    std::uint32_t prim;
    float u, v;
    double t;
    ++count;
    if (!rays.intersect(o, d, off, prim, u, v, t)) return;
    const glm::dvec3 p = o + t * d;
    const glm::dvec3 n = glm::dot(normal[prim], d) < 0 ? normal[prim] : -normal[prim];
    const glm::dvec3 phi = scene.materials[scene.material[prim]].albedo * flux;
    if (phi.x + phi.y + phi.z > 0) out.push_back({p + 0.5 * g.h * n, n, phi});
  };
  if (scene.sun && scene.sun->irradiance.x + scene.sun->irradiance.y + scene.sun->irradiance.z > 0) {
    const glm::dvec3 s = glm::normalize(scene.sun->direction);
    glm::dvec3 t, b;
    detail::onb(s, t, b);
    double t0 = 1e300, t1 = -1e300, b0 = 1e300, b1 = -1e300;
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 q(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
      t0 = std::min(t0, glm::dot(q, t)), t1 = std::max(t1, glm::dot(q, t));
      b0 = std::min(b0, glm::dot(q, b)), b1 = std::max(b1, glm::dot(q, b));
    }
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double ct = glm::dot(centre, t), cb = glm::dot(centre, b);
    const int m = std::max(1, opt.sun_rays * static_cast<int>(std::ceil(std::max(t1 - t0, b1 - b0) / g.h)));
    const double dt = (t1 - t0) / m, db = (b1 - b0) / m;
    const glm::dvec3 flux = scene.sun->irradiance * (dt * db);
    detail::Rng rng(opt.seed, 0, detail::kLightSalt);
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < m; ++c) {
        const double tt = t0 + (c + rng.uniform()) * dt - ct, bb = b0 + (r + rng.uniform()) * db - cb;
        deposit(centre + tt * t + bb * b + 2 * diag * s, -s, flux);
      }
  }
  const auto& em = dl.emitters();
  if (!em.empty() && opt.emitter_photons > 0) {
    const double total = dl.emitter_cdf().back();
    detail::Rng rng(opt.seed, 1, detail::kLightSalt);
    const int np = opt.emitter_photons;
    for (int q = 0; q < np; ++q) {
      const double u = (q + rng.uniform()) / np * total;  // stratified over the cdf
      const std::size_t k = std::min<std::size_t>(
          em.size() - 1, static_cast<std::size_t>(std::upper_bound(dl.emitter_cdf().begin(), dl.emitter_cdf().end(), u) -
                                                   dl.emitter_cdf().begin()));
      const std::uint32_t tri = em[k];
      const Material& m = scene.materials[scene.material[tri]];
      double b1 = rng.uniform(), b2 = rng.uniform();
      if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
      const auto& tv = scene.mesh.triangles[tri];
      const glm::dvec3 y = scene.mesh.positions[tv[0]] + b1 * (scene.mesh.positions[tv[1]] - scene.mesh.positions[tv[0]]) +
                           b2 * (scene.mesh.positions[tv[2]] - scene.mesh.positions[tv[0]]);
      glm::dvec3 n = normal[tri];
      const int sides = m.one_sided ? 1 : 2;
      if (!m.one_sided && rng.uniform() < 0.5) n = -n;
      glm::dvec3 tt, bb;
      detail::onb(n, tt, bb);
      const double u1 = rng.uniform(), u2 = rng.uniform(), r = std::sqrt(u1), phi = 2 * kPi * u2;
      const glm::dvec3 d = r * std::cos(phi) * tt + r * std::sin(phi) * bb + std::sqrt(std::max(0.0, 1 - u1)) * n;
      // power of the triangle pi L_e A x sides, over its selection probability, over np
      const double w_tri = dl.area[tri] * (m.emission.x + m.emission.y + m.emission.z);
      const glm::dvec3 flux = m.emission * (kPi * dl.area[tri] * sides) * (total / w_tri) / static_cast<double>(np);
      deposit(y, d, flux);
    }
  }
  if (nrays != nullptr) *nrays = count;
  return out;
}

LpvGrid lpv_inject(const Scene& scene, const LpvOptions& opt, std::uint64_t* nrays) {
  check(opt);
  validate(scene);
  LpvGrid g = lpv_grid(scene, opt.grid);
  for (const Vpl& v : lpv_vpls(scene, opt, g, nrays)) lpv_add_vpl(g, v.p, v.n, v.flux);
  return g;
}

namespace {
// The geometry volume's surfels (see lpv.hpp): surfel(corner, triangle, as / h^2) per surfel,
// triangles in order, each triangle's surfels in row order.
template <class F>
void geometry_surfels(const Scene& scene, const LpvGrid& g, F&& surfel) {
  const double h2 = g.h * g.h;
  for (std::size_t tri = 0; tri < scene.mesh.triangles.size(); ++tri) {
    const auto& tv = scene.mesh.triangles[tri];
    const glm::dvec3 a = scene.mesh.positions[tv[0]], e1 = scene.mesh.positions[tv[1]] - a,
                     e2 = scene.mesh.positions[tv[2]] - a;
    const double area = 0.5 * glm::length(glm::cross(e1, e2));
    if (!(area > 0)) continue;
    // the triangle cut into s^2 congruent triangles (edges in s parts): s^2 surfels at their
    // centroids, about 16 per h^2
    const int s = std::clamp(static_cast<int>(std::ceil(std::sqrt(16 * area / h2))), 1, 1024);
    const double as = area / (static_cast<double>(s) * s);
    for (int r = 0; r < s; ++r)
      for (int c = 0; c < s - r; ++c)
        for (int up = 0; up < 2; ++up) {
          if (up == 1 && c + r + 1 >= s) continue;
          // centroid of the small triangle in barycentric coordinates (u along e1, v along e2)
          const double u = up == 0 ? (c + 1.0 / 3) / s : (c + 2.0 / 3) / s;
          const double v = up == 0 ? (r + 1.0 / 3) / s : (r + 2.0 / 3) / s;
          const glm::dvec3 p = a + u * e1 + v * e2;
          const glm::dvec3 f = (p - g.lo) / g.h;
          const long i = std::lround(f.x), j = std::lround(f.y), k = std::lround(f.z);
          // a surfel nearest to no corner of the grid (outside a cascade's sub-grid) is left out
          if (i < 0 || j < 0 || k < 0 || i > g.nx || j > g.ny || k > g.nz) continue;
          surfel((static_cast<std::size_t>(k) * (g.ny + 1) + j) * (g.nx + 1) + i, tri, as / h2);
        }
  }
}
}  // namespace

GeometryVolume lpv_geometry(const Scene& scene, const LpvGrid& g) {
  check_grid(g);
  GeometryVolume gv;
  gv.nx = g.nx, gv.ny = g.ny, gv.nz = g.nz;
  gv.corners.assign(static_cast<std::size_t>(g.nx + 1) * (g.ny + 1) * (g.nz + 1), {});
  const std::vector<glm::dvec3> normal = detail::triangle_normals(scene.mesh);
  geometry_surfels(scene, g, [&](std::size_t corner, std::size_t tri, double w) {
    auto& dst = gv.corners[corner];
    for (int q = 0; q < 9; ++q) dst[q] += shared::gi_lpv_surfel(normal[tri], w, q);
  });
  return gv;
}

#ifdef ATMOSH_GI_HAVE_GPU
std::vector<gpu::GiLpvSurfel> detail::lpv_surfels(const Scene& scene, const LpvGrid& g) {
  check_grid(g);
  const std::vector<glm::dvec3> normal = detail::triangle_normals(scene.mesh);
  std::vector<gpu::GiLpvSurfel> out;
  geometry_surfels(scene, g, [&](std::size_t corner, std::size_t tri, double w) {
    out.push_back({static_cast<std::uint32_t>(corner), normal[tri], w});
  });
  return out;
}
#endif

namespace {
void check_gv(const LpvGrid& in, const GeometryVolume* gv) {
  if (gv != nullptr && (gv->nx != in.nx || gv->ny != in.ny || gv->nz != in.nz ||
                        gv->corners.size() != static_cast<std::size_t>(in.nx + 1) * (in.ny + 1) * (in.nz + 1)))
    throw InputError("gi lpv: the geometry volume does not match the grid");
}

// 1 - blocking for every (target cell, direction, face): [(t * 6 + d) * 5 + f] (the shared
// gi_lpv_face_blocking at the face the source shares with the target).
std::vector<float> visibility_table(const LpvGrid& in, const GeometryVolume& gv) {
  std::vector<float> vis(in.cells.size() * 30, 1.0f);
  const CpuGeometry geo{&gv};
  const glm::ivec3 n = dims(in);
  parallel_for_ranges(in.cells.size(), 64, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const glm::ivec3 c(static_cast<int>(t % in.nx), static_cast<int>(t / in.nx % in.ny),
                         static_cast<int>(t / in.nx / in.ny));
      for (int d = 0; d < 6; ++d) {
        const glm::ivec3 s = c - shared::gi_lpv_step(d);
        if (glm::any(glm::lessThan(s, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(s, n))) continue;
        for (int f = 0; f < 5; ++f)
          vis[(t * 6 + d) * 5 + f] = static_cast<float>(
              1.0 - shared::gi_lpv_face_blocking(geo, s, d, n, shared::gi_lpv_face_direction(d, f)));
      }
    }
  });
  return vis;
}

// One propagation step: every cell gathers from its neighbours (the shared gi_lpv_gather).
LpvGrid step(const LpvGrid& in, const std::vector<float>* vis, LpvReemission reemission) {
  LpvGrid out = in;
  const CpuField field{&in, vis, reemission == LpvReemission::face_lobe ? 1 : 0};
  const glm::ivec3 n = dims(in);
  parallel_for_ranges(in.cells.size(), 64, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const glm::ivec3 c(static_cast<int>(t % in.nx), static_cast<int>(t / in.nx % in.ny),
                         static_cast<int>(t / in.nx / in.ny));
      LpvCell& dst = out.cells[t];
      const shared::GiLpvRgb v = shared::gi_lpv_gather(field, c, n, vis != nullptr);
      for (int q = 0; q < 4; ++q) dst[q] = v.r[q], dst[4 + q] = v.g[q], dst[8 + q] = v.b[q];
    }
  });
  return out;
}
}  // namespace

LpvGrid lpv_step(const LpvGrid& in, const GeometryVolume* gv, LpvReemission reemission) {
  check_grid(in);
  check_gv(in, gv);
  if (gv == nullptr) return step(in, nullptr, reemission);
  const std::vector<float> vis = visibility_table(in, *gv);
  return step(in, &vis, reemission);
}

LpvGrid lpv_propagate(const LpvGrid& injected, const GeometryVolume* gv, int iterations, LpvReemission reemission) {
  if (iterations < 0 || iterations > 1024)
    throw InputError("gi lpv: iterations must be in 0..1024, got " + std::to_string(iterations));
  check_grid(injected);
  check_gv(injected, gv);
  std::vector<float> vis;
  if (gv != nullptr && iterations > 1) vis = visibility_table(injected, *gv);
  LpvGrid acc = injected, field = injected;
  for (int it = 0; it < iterations; ++it) {
    field = step(field, it == 0 || gv == nullptr ? nullptr : &vis, reemission);
    for (std::size_t c = 0; c < acc.cells.size(); ++c)
      for (int q = 0; q < 12; ++q) acc.cells[c][q] += field.cells[c][q];
  }
  return acc;
}

LpvGrid lpv_propagate_gpu(const LpvGrid& injected, const GeometryVolume* gv, int iterations, double* gpu_seconds,
                          LpvReemission reemission) {
  if (iterations < 0 || iterations > 1024)
    throw InputError("gi lpv: iterations must be in 0..1024, got " + std::to_string(iterations));
  check_grid(injected);
  check_gv(injected, gv);
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::Context ctx;
  gpu::Program prog(lpv_shader("gpu/shaders/gi_lpv_propagate.comp"));
  std::vector<float> vis(1, 1.0f);
  if (gv != nullptr && iterations > 1) vis = visibility_table(injected, *gv);
  const std::size_t n = injected.cells.size();
  std::vector<float> cells(n * 12);
  for (std::size_t c = 0; c < n; ++c)
    for (int q = 0; q < 12; ++q) cells[c * 12 + q] = static_cast<float>(injected.cells[c][q]);
  const auto t0 = Clock::now();
  gpu::Buffer a(cells.size() * sizeof(float), cells.data()), b(cells.size() * sizeof(float)),
      acc(cells.size() * sizeof(float), cells.data()), bv(vis.size() * sizeof(float), vis.data());
  prog.use();
  prog.set("nx", injected.nx);
  prog.set("ny", injected.ny);
  prog.set("nz", injected.nz);
  prog.set("lpv_reemission", reemission == LpvReemission::face_lobe ? 1 : 0);
  bv.bind(1);
  acc.bind(3);
  for (int it = 0; it < iterations; ++it) {
    (it % 2 == 0 ? a : b).bind(0);
    (it % 2 == 0 ? b : a).bind(2);
    prog.set("use_vis", it > 0 && gv != nullptr && iterations > 1 ? 1 : 0);
    prog.dispatch(static_cast<unsigned>((n + 63) / 64));
  }
  acc.download(cells.data(), cells.size() * sizeof(float));
  if (gpu_seconds != nullptr) *gpu_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  LpvGrid out = injected;
  for (std::size_t c = 0; c < n; ++c)
    for (int q = 0; q < 12; ++q) out.cells[c][q] = cells[c * 12 + q];
  return out;
#else
  (void)gpu_seconds;
  (void)reemission;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

#ifdef ATMOSH_GI_HAVE_GPU
namespace {
// Stable counting sort of items by bin: start (bins + 1 offsets) and the order of the items.
void bin_items(const std::vector<std::size_t>& bin, std::size_t bins, std::vector<std::uint32_t>& start,
               std::vector<std::size_t>& order) {
  start.assign(bins + 1, 0);
  for (std::size_t b : bin) ++start[b + 1];
  for (std::size_t b = 0; b < bins; ++b) start[b + 1] += start[b];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  order.assign(bin.size(), 0);
  for (std::size_t i = 0; i < bin.size(); ++i) order[fill[bin[i]]++] = i;
}

// One dispatch of `shader` over `bins` bins: start (binding 0), items (binding 1, `stride`
// floats each), out (binding 2, `out_stride` floats a bin).
std::vector<float> binned_sum_gpu(const char* shader, const std::vector<std::uint32_t>& start,
                                  const std::vector<float>& items, std::size_t bins, int out_stride,
                                  double* gpu_seconds) {
  const gpu::Context ctx;
  gpu::Program prog(lpv_shader(shader));
  const auto t0 = Clock::now();
  const std::vector<float> one(1, 0.0f);
  gpu::Buffer bs(start.size() * sizeof(std::uint32_t), start.data()),
      bi(std::max<std::size_t>(items.size(), 1) * sizeof(float), items.empty() ? one.data() : items.data()),
      bo(bins * out_stride * sizeof(float));
  bs.bind(0);
  bi.bind(1);
  bo.bind(2);
  prog.use();
  prog.set("n_bins", static_cast<int>(bins));
  prog.dispatch(static_cast<unsigned>((bins + 63) / 64));
  std::vector<float> out(bins * out_stride);
  bo.download(out.data(), out.size() * sizeof(float));
  if (gpu_seconds != nullptr) *gpu_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return out;
}
}  // namespace
#endif

LpvGrid lpv_inject_vpls_gpu(const LpvGrid& grid, const std::vector<Vpl>& vpls, double* gpu_seconds) {
  check_grid(grid);
  LpvGrid g = grid;
#ifdef ATMOSH_GI_HAVE_GPU
  std::vector<std::size_t> bin(vpls.size()), order;
  for (std::size_t v = 0; v < vpls.size(); ++v) {
    int i, j, k;
    cell_of(g, vpls[v].p, i, j, k);
    bin[v] = g.index(i, j, k);
  }
  std::vector<std::uint32_t> start;
  bin_items(bin, g.cells.size(), start, order);
  std::vector<float> items(vpls.size() * 6);
  for (std::size_t r = 0; r < order.size(); ++r)
    for (int c = 0; c < 3; ++c) {
      items[r * 6 + c] = static_cast<float>(vpls[order[r]].n[c]);
      items[r * 6 + 3 + c] = static_cast<float>(vpls[order[r]].flux[c]);
    }
  const std::vector<float> out = binned_sum_gpu("gpu/shaders/gi_lpv_inject.comp", start, items, g.cells.size(), 12,
                                                gpu_seconds);
  for (std::size_t c = 0; c < g.cells.size(); ++c)
    for (int q = 0; q < 12; ++q) g.cells[c][q] = out[c * 12 + q];
  return g;
#else
  (void)vpls;
  (void)gpu_seconds;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

LpvGrid lpv_inject_gpu(const Scene& scene, const LpvOptions& opt, std::uint64_t* nrays, double* gpu_seconds) {
  check(opt);
  validate(scene);
  const LpvGrid g = lpv_grid(scene, opt.grid);
  double rsm_s = 0, inj_s = 0;
  std::vector<Vpl> vpls = lpv_vpls_rsm(scene, opt, g, &rsm_s);  // the sun, rasterised
  std::uint64_t count = 0;
  bool emitters = false;
  for (const Material& m : scene.materials) emitters = emitters || m.emission.x + m.emission.y + m.emission.z > 0;
  if (emitters && opt.emitter_photons > 0) {  // area emitters: rays on the CPU
    Scene rest = scene;
    rest.sun.reset();
    const std::vector<Vpl> e = lpv_vpls(rest, opt, g, &count);
    vpls.insert(vpls.end(), e.begin(), e.end());
  }
  if (nrays != nullptr) *nrays = count;
  LpvGrid out = lpv_inject_vpls_gpu(g, vpls, &inj_s);
  if (gpu_seconds != nullptr) *gpu_seconds = rsm_s + inj_s;
  return out;
}

GeometryVolume lpv_geometry_gpu(const Scene& scene, const LpvGrid& g, double* gpu_seconds) {
  check_grid(g);
  GeometryVolume gv;
  gv.nx = g.nx, gv.ny = g.ny, gv.nz = g.nz;
  const std::size_t nc = static_cast<std::size_t>(g.nx + 1) * (g.ny + 1) * (g.nz + 1);
  gv.corners.assign(nc, {});
#ifdef ATMOSH_GI_HAVE_GPU
  const std::vector<glm::dvec3> normal = detail::triangle_normals(scene.mesh);
  std::vector<std::size_t> bin, order;
  std::vector<std::array<double, 4>> surfel;
  geometry_surfels(scene, g, [&](std::size_t corner, std::size_t tri, double w) {
    bin.push_back(corner);
    surfel.push_back({normal[tri].x, normal[tri].y, normal[tri].z, w});
  });
  std::vector<std::uint32_t> start;
  bin_items(bin, nc, start, order);
  std::vector<float> items(surfel.size() * 4);
  for (std::size_t r = 0; r < order.size(); ++r)
    for (int q = 0; q < 4; ++q) items[r * 4 + q] = static_cast<float>(surfel[order[r]][q]);
  const std::vector<float> out = binned_sum_gpu("gpu/shaders/gi_lpv_geometry.comp", start, items, nc, 9, gpu_seconds);
  for (std::size_t c = 0; c < nc; ++c)
    for (int q = 0; q < 9; ++q) gv.corners[c][q] = out[c * 9 + q];
  return gv;
#else
  (void)scene;
  (void)gpu_seconds;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

namespace {
void check_receivers(const RadiosityReceivers& r) {
  const std::size_t n = r.size();
  if (r.normal.size() != n || r.albedo.size() != n || r.emission.size() != n || r.direct.size() != n)
    throw InputError("gi lpv: the receivers' arrays differ in length");
  if (n > 0x7fffffffu / 15) throw InputError("gi lpv: too many receivers for one pass");
}
}  // namespace

std::vector<glm::dvec3> shade_lpv_receivers_cpu(const LpvGrid& g, const RadiosityReceivers& r) {
  check_grid(g);
  check_receivers(r);
  const CpuField field{&g, nullptr};
  std::vector<glm::dvec3> out(r.size());
  parallel_for_ranges(r.size(), 256, 0, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const glm::dvec3 E = shared::gi_lpv_receiver_irradiance(field, r.position[i], r.normal[i], g.lo, g.h, dims(g));
      out[i] = r.emission[i] + r.albedo[i] / kPi * glm::max(r.direct[i] + E, glm::dvec3(0.0));
    }
  });
  return out;
}

std::vector<glm::dvec3> shade_lpv_receivers_gpu(const LpvGrid& g, const RadiosityReceivers& r, double* gpu_seconds) {
  check_grid(g);
  check_receivers(r);
#ifdef ATMOSH_GI_HAVE_GPU
  const gpu::Context ctx;
  gpu::Program prog(lpv_shader("gpu/shaders/gi_lpv_apply.comp"));
  const std::size_t nr = r.size();
  const std::vector<float> rec = detail::pack_receivers(r);
  std::vector<float> cells(g.cells.size() * 12);
  for (std::size_t c = 0; c < g.cells.size(); ++c)
    for (int q = 0; q < 12; ++q) cells[c * 12 + q] = static_cast<float>(g.cells[c][q]);
  const auto t0 = Clock::now();
  gpu::Buffer brec(rec.size() * sizeof(float), rec.data()), bout(std::max<std::size_t>(nr, 1) * 4 * sizeof(float)),
      bl(cells.size() * sizeof(float), cells.data());
  brec.bind(4);
  bout.bind(5);
  bl.bind(6);
  prog.use();
  prog.set("n_receivers", static_cast<int>(nr));
  prog.set("lpv_lo", static_cast<float>(g.lo.x), static_cast<float>(g.lo.y), static_cast<float>(g.lo.z));
  prog.set("lpv_h", static_cast<float>(g.h));
  prog.set("lpv_nx", g.nx);
  prog.set("lpv_ny", g.ny);
  prog.set("lpv_nz", g.nz);
  if (nr > 0) prog.dispatch(static_cast<unsigned>((nr + 63) / 64));
  std::vector<float> out(std::max<std::size_t>(nr, 1) * 4);
  bout.download(out.data(), out.size() * sizeof(float));
  if (gpu_seconds != nullptr) *gpu_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return detail::unpack_rgb(out, nr);
#else
  (void)gpu_seconds;
  throw InputError("gi lpv: this build has no GPU library (atmosh::gpu)");
#endif
}

RadianceImage render_lpv_gbuffer(const Scene& scene, const Camera& camera, int width, int height, const Lpv& lpv,
                                 const LpvOptions& opt, bool gpu) {
  check(opt);
  check_grid(lpv.accumulated);
  const auto t0 = Clock::now();
  const RadiosityGBuffer g =
      gpu ? radiosity_gbuffer_gpu(scene, camera, width, height, opt.samples, opt.seed, opt.threads)
          : radiosity_gbuffer(scene, camera, width, height, opt.samples, opt.seed, opt.threads);
  const std::vector<glm::dvec3> L =
      gpu ? shade_lpv_receivers_gpu(lpv.accumulated, g.receivers) : shade_lpv_receivers_cpu(lpv.accumulated, g.receivers);
  RadianceImage img = detail::gbuffer_image(g, L, width, height);
  img.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return img;
}

glm::dvec3 lpv_flux(const LpvGrid& g) {
  glm::dvec3 s(0.0);
  for (const auto& c : g.cells)
    for (int ch = 0; ch < 3; ++ch) s[ch] += c[ch * 4];
  return s * std::sqrt(4 * kPi);
}

LpvCell lpv_sample(const LpvGrid& g, const glm::dvec3& p) {
  check_grid(g);
  int i0[3], i1[3];
  double f[3];
  const int n[3] = {g.nx, g.ny, g.nz};
  for (int a = 0; a < 3; ++a) {
    double x = (p[a] - g.lo[a]) / g.h - 0.5;
    if (!std::isfinite(x)) x = 0;
    x = std::clamp(x, 0.0, static_cast<double>(n[a] - 1));
    i0[a] = std::min(static_cast<int>(std::floor(x)), n[a] - 1);
    i1[a] = std::min(i0[a] + 1, n[a] - 1);
    f[a] = x - i0[a];
  }
  LpvCell out{};
  for (int c = 0; c < 8; ++c) {
    const double w = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
    if (w == 0) continue;
    const LpvCell& q = g.cells[g.index(c & 1 ? i1[0] : i0[0], c & 2 ? i1[1] : i0[1], c & 4 ? i1[2] : i0[2])];
    for (int k = 0; k < 12; ++k) out[k] += w * q[k];
  }
  return out;
}

Lpv build_lpv(const Scene& scene, const LpvOptions& opt) {
  check(opt);
  Lpv l;
  const auto t0 = Clock::now();
  l.injected = lpv_inject(scene, opt, &l.rays);
  if (opt.blocking) l.geometry = lpv_geometry(scene, l.injected);
  const auto t1 = Clock::now();
  l.iterations = opt.iterations < 0 ? 2 * opt.grid : opt.iterations;
  l.accumulated = lpv_propagate(l.injected, opt.blocking ? &l.geometry : nullptr, l.iterations, opt.reemission);
  l.inject_seconds = std::chrono::duration<double>(t1 - t0).count();
  l.propagate_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  return l;
}

RadianceImage render_lpv(const Scene& scene, const Camera& camera, int width, int height, const Lpv& lpv,
                         const LpvOptions& opt) {
  check(opt);
  validate(scene);
  check_grid(lpv.accumulated);
  const prt::RayScene rays(scene.mesh);
  const detail::DirectLight direct(scene, rays);
  const LpvGrid& g = lpv.accumulated;
  const CpuField field{&g, nullptr};
  return detail::render_receivers(
      scene, rays, camera, width, height, opt.samples, opt.seed, opt.threads,
      [&](detail::Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint32_t, std::uint64_t& nr) {
        const glm::dvec3 E = shared::gi_lpv_receiver_irradiance(field, p, n, g.lo, g.h, dims(g));
        return direct.irradiance(rng, p, n, nr) + E;
      });
}

}  // namespace atmosh::gi
