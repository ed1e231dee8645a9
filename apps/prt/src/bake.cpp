// Per-vertex transfer bakes with Embree 3, transfer files, relit images (see bake.hpp).
#include "atmosh/prt/bake.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include <glm/geometric.hpp>

#include "atmosh/check.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/basis.hpp"
#if ATMOSH_HAVE_GPU
#include "atmosh/gpu/prt.hpp"
#endif

namespace atmosh::prt {

namespace {
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;
}  // namespace

Device parse_device(const std::string& name) {
  if (name == "cpu") return Device::cpu;
  if (name == "gpu") return Device::gpu;
  throw InputError("prt device: unknown device '" + name + "' (cpu, gpu)");
}

// ---- Embree scene ---------------------------------------------------------------------
struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

RayScene::RayScene(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  // With ATMOSH_NO_AVX512 set (atmosh/dispatch.hpp) Embree is held to its AVX2 kernels
  // too: its AVX-512 traversal can differ in the last bits of a hit, and the golden
  // output digests are recorded on AVX2 code paths.
  impl_->device = rtcNewDevice(std::getenv("ATMOSH_NO_AVX512") == nullptr ? "verbose=0" : "verbose=0,max_isa=avx2");
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), mesh.positions.size()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), mesh.triangles.size()));
  if (vb == nullptr || ib == nullptr) {
    rtcReleaseGeometry(g);
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
    throw std::runtime_error("Embree: cannot allocate geometry buffers");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(mesh.positions[i][k]);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = mesh.triangles[i][k];
  rtcCommitGeometry(g);
  rtcAttachGeometry(impl_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(impl_->scene);
  offset_ = 1e-4 * std::max(bounding_diagonal(mesh), 1e-30);
}

RayScene::~RayScene() {
  if (impl_) {
    rtcReleaseScene(impl_->scene);
    rtcReleaseDevice(impl_->device);
  }
}

namespace {
void fill_ray(RTCRay& r, const glm::dvec3& o, const glm::dvec3& d, double tnear, double tfar) {
  r.org_x = static_cast<float>(o.x);
  r.org_y = static_cast<float>(o.y);
  r.org_z = static_cast<float>(o.z);
  r.dir_x = static_cast<float>(d.x);
  r.dir_y = static_cast<float>(d.y);
  r.dir_z = static_cast<float>(d.z);
  r.tnear = static_cast<float>(tnear);
  r.tfar = static_cast<float>(std::min(tfar, 1e30));
  r.time = 0.0f;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
}
}  // namespace

bool RayScene::unoccluded(const glm::dvec3& org, const glm::dvec3& dir, double tnear, double tfar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  fill_ray(r, org, dir, tnear, tfar);
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar >= 0.0f;  // Embree sets tfar = -inf on a hit
}

bool RayScene::intersect(const glm::dvec3& org, const glm::dvec3& dir, double tnear, std::uint32_t& prim, float& u,
                         float& v, double& t) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  fill_ray(rh.ray, org, dir, tnear, 1e30);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  prim = rh.hit.primID;
  u = rh.hit.u;
  v = rh.hit.v;
  t = rh.ray.tfar;
  return true;
}

// ---- camera -------------------------------------------------------------------------------
PixelCamera::PixelCamera(const Mesh& mesh, int width_, int height_, const glm::dvec3& view_dir)
    : width(width_), height(height_) {
  require_image_size(width, height, "prt");
  if (!(glm::length(view_dir) > 0) || !std::isfinite(glm::length(view_dir)))
    throw InputError("view direction is zero or not finite");
  glm::dvec3 lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * glm::length(hi - lo);
  const double fov = 40.0 * kPi / 180.0;
  w = glm::normalize(view_dir);
  eye = centre + w * (radius / std::sin(0.5 * fov) * 1.02);
  const glm::dvec3 up0 = std::abs(w.z) > 0.99 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  right = glm::normalize(glm::cross(up0, w));
  up = glm::cross(w, right);
  tan_half_fov = std::tan(0.5 * fov);
  aspect = static_cast<double>(width) / height;
}

glm::dvec3 PixelCamera::ray(int row, int col) const {
  const double x = (2.0 * (col + 0.5) / width - 1.0) * tan_half_fov * aspect,
               y = (1.0 - 2.0 * (row + 0.5) / height) * tan_half_fov;
  return glm::normalize(-w + x * right + y * up);
}

// ---- bake -------------------------------------------------------------------------------
Transfer bake(const Mesh& mesh_in, const BakeOptions& opt) {
  if (opt.device == Device::gpu)
    throw InputError("prt bake: the GPU depth-map method is per-pixel (bake_pixels); per-vertex bakes run on the CPU");
  if (opt.bands < 1 || opt.bands > 16) throw InputError("prt bake: bands must be in 1..16, got " + std::to_string(opt.bands));
  if (opt.strata < 1 || opt.strata > 2000)
    throw InputError("prt bake: strata per side must be in 1..2000, got " + std::to_string(opt.strata));
  if (opt.bounces < 0 || opt.bounces > 100) throw InputError("prt bake: bounces must be in 0..100, got " + std::to_string(opt.bounces));
  resolve_threads(opt.threads);  // the toolkit's policy: 0..1024, 0 = the CPUs this process may use
  if (!(opt.default_albedo >= 0 && opt.default_albedo <= 1))
    throw InputError("prt bake: albedo must be in [0, 1], got " + std::to_string(opt.default_albedo));
  validate(mesh_in);

  Transfer tr;
  tr.mesh = mesh_in;
  if (tr.mesh.normals.size() != tr.mesh.positions.size()) compute_normals(tr.mesh);
  if (tr.mesh.albedo.empty()) tr.mesh.albedo.assign(tr.mesh.positions.size(), opt.default_albedo);
  tr.bands = opt.bands;
  tr.mode = opt.mode;
  tr.seed = opt.seed;
  tr.bounces = opt.mode == sh::prt::TransferMode::interreflected ? opt.bounces : 0;
  const std::size_t nv = tr.mesh.positions.size();
  const std::size_t K = static_cast<std::size_t>(opt.bands) * opt.bands;
  tr.coeffs.assign(nv * K, 0.0);
  tr.ao.assign(nv, 1.0);

  const Mesh& m = tr.mesh;
  if (opt.mode == sh::prt::TransferMode::unshadowed) {
    tr.samples = 0;
    for (std::size_t v = 0; v < nv; ++v) sh::prt::unshadowed_transfer(opt.bands, m.normals[v], m.albedo[v], tr.coeffs.data() + v * K);
    if (opt.progress) opt.progress(1.0);
    return tr;
  }

  const sh::prt::SampleSet samples = sh::prt::jittered_samples(opt.bands, opt.strata, opt.seed);
  tr.samples = static_cast<int>(samples.dirs.size());
  const RayScene scene(m);
  const double eps = scene.offset();
  const bool inter = opt.mode == sh::prt::TransferMode::interreflected;
  sh::prt::HitList hits(inter ? nv : 0);
  // Face normals for the back-face test of interreflection hits.
  std::vector<glm::dvec3> face_n;
  if (inter) {
    face_n.reserve(m.triangles.size());
    for (const auto& t : m.triangles)
      face_n.push_back(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
  }

  const int threads = resolve_threads(opt.threads);
  std::atomic<std::uint64_t> rays{0};
  const auto t0 = Clock::now();
  parallel_for_ranges(nv, 16, threads, [&](std::size_t b, std::size_t e) {
    std::uint64_t local_rays = 0;
    for (std::size_t v = b; v < e; ++v) {
      const glm::dvec3 n = m.normals[v];
      const glm::dvec3 org = m.positions[v] + eps * n;
      std::vector<sh::prt::Hit>* hv = inter ? &hits[v] : nullptr;
      tr.ao[v] = sh::prt::shadowed_transfer(samples, n, m.albedo[v],
                                            [&](std::size_t s) {
                                              ++local_rays;
                                              const glm::dvec3& d = samples.dirs[s];
                                              if (!inter) return scene.unoccluded(org, d, eps);
                                              std::uint32_t prim;
                                              float u, w;
                                              double t;
                                              if (!scene.intersect(org, d, eps, prim, u, w, t)) return true;
                                              if (glm::dot(face_n[prim], d) < 0.0) {  // front face: reflects
                                                const auto& tri = m.triangles[prim];
                                                hv->push_back({{tri[0], tri[1], tri[2]}, u, w,
                                                               static_cast<float>(glm::dot(n, d))});
                                              }
                                              return false;
                                            },
                                            tr.coeffs.data() + v * K);
    }
    rays += local_rays;
  }, opt.progress);
  tr.ray_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  tr.rays = rays.load();

  if (inter) {
    sh::prt::BounceReport rep;
    tr.coeffs = sh::prt::interreflect(tr.coeffs, opt.bands, m.albedo, hits, samples.weight, opt.bounces, threads, &rep);
    tr.bounce_energy = rep.energy;
  }
  if (opt.progress) opt.progress(1.0);
  return tr;
}

// ---- per-pixel transfer -------------------------------------------------------------------
namespace {
// The GPU depth-map method (atmosh/gpu/prt.hpp) behind bake_pixels.
PixelTransfer gpu_pixels(const Mesh& m, const PixelCamera& cam, const BakeOptions& opt) {
#if ATMOSH_HAVE_GPU
  const bool shadowed = opt.mode == sh::prt::TransferMode::shadowed;
  const sh::prt::SampleSet samples = sh::prt::jittered_samples(opt.bands, opt.strata, opt.seed);
  const gpu::Context ctx;
  const gpu::PrtCamera gc{.eye = cam.eye, .right = cam.right, .up = cam.up, .back = cam.w,
                          .tan_half_fov = cam.tan_half_fov, .width = cam.width, .height = cam.height};
  const gpu::PrtPixelOptions go{.depth_resolution = opt.depth_resolution, .visibility = shadowed,
                                .offset = 1e-4 * std::max(bounding_diagonal(m), 1e-30)};  // the CPU ray offset
  gpu::PrtPixelResult g =
      gpu::prt_pixel_transfer(ctx, gpu::PrtMeshView{&m.positions, &m.normals, &m.albedo, &m.triangles}, gc, samples, go);
  PixelTransfer px{.width = g.width, .height = g.height, .bands = g.bands, .samples = g.samples,
                   .coeffs = std::move(g.coeffs), .ao = std::move(g.ao), .mask = std::move(g.mask),
                   .device = Device::gpu, .rays = 0, .ray_seconds = g.seconds,
                   .depth_resolution = g.depth_resolution, .seconds_per_direction = g.seconds_per_direction};
  if (opt.progress) opt.progress(1.0);
  return px;
#else
  (void)m, (void)cam, (void)opt;
  throw InputError("prt bake: the GPU depth-map method needs atmosh built with ATMOSH_WITH_GPU=ON");
#endif
}
}  // namespace

PixelTransfer bake_pixels(const Mesh& mesh_in, const BakeOptions& opt, int width, int height, const glm::dvec3& view_dir) {
  if (opt.mode == sh::prt::TransferMode::interreflected)
    throw InputError("prt bake: per-pixel transfer is unshadowed or shadowed, not interreflected");
  if (opt.bands < 1 || opt.bands > 16) throw InputError("prt bake: bands must be in 1..16, got " + std::to_string(opt.bands));
  if (opt.strata < 1 || opt.strata > 2000)
    throw InputError("prt bake: strata per side must be in 1..2000, got " + std::to_string(opt.strata));
  resolve_threads(opt.threads);  // the toolkit's policy: 0..1024, 0 = the CPUs this process may use
  if (!(opt.default_albedo >= 0 && opt.default_albedo <= 1))
    throw InputError("prt bake: albedo must be in [0, 1], got " + std::to_string(opt.default_albedo));
  validate(mesh_in);
  Mesh m = mesh_in;
  if (m.normals.size() != m.positions.size()) compute_normals(m);
  if (m.albedo.empty()) m.albedo.assign(m.positions.size(), opt.default_albedo);
  if (opt.device == Device::gpu && (opt.depth_resolution < 16 || opt.depth_resolution > 16384))
    throw InputError("prt bake: depth_resolution must be in 16..16384, got " + std::to_string(opt.depth_resolution));
  const PixelCamera cam(m, width, height, view_dir);
  const bool shadowed = opt.mode == sh::prt::TransferMode::shadowed;
  if (opt.device == Device::gpu) return gpu_pixels(m, cam, opt);
  const RayScene scene(m);
  const double eps = scene.offset();
  const sh::prt::SampleSet samples = sh::prt::jittered_samples(opt.bands, shadowed ? opt.strata : 1, opt.seed);
  const std::size_t K = static_cast<std::size_t>(opt.bands) * opt.bands, np = static_cast<std::size_t>(width) * height;
  PixelTransfer px;
  px.width = width;
  px.height = height;
  px.bands = opt.bands;
  px.samples = shadowed ? static_cast<int>(samples.dirs.size()) : 0;
  px.coeffs.assign(np * K, 0.0);
  px.ao.assign(np, 0.0);
  px.mask.assign(np, 0.0f);
  std::atomic<std::uint64_t> rays{0};
  const auto t0 = Clock::now();
  parallel_for_ranges(static_cast<std::size_t>(height), 1, opt.threads, [&](std::size_t r0, std::size_t r1) {
    std::uint64_t nr = 0;
    for (int r = static_cast<int>(r0); r < static_cast<int>(r1); ++r) {
      for (int c = 0; c < width; ++c) {
        const std::size_t p = static_cast<std::size_t>(r) * width + c;
        std::uint32_t prim;
        float u, v;
        double t;
        if (!scene.intersect(cam.eye, cam.ray(r, c), 0.0, prim, u, v, t)) continue;
        const auto& tri = m.triangles[prim];
        const double b0 = 1.0 - u - v;
        const glm::dvec3 pos = b0 * m.positions[tri[0]] + double(u) * m.positions[tri[1]] + double(v) * m.positions[tri[2]];
        glm::dvec3 n = b0 * m.normals[tri[0]] + double(u) * m.normals[tri[1]] + double(v) * m.normals[tri[2]];
        if (!(glm::length(n) > 0)) n = m.normals[tri[0]];
        n = glm::normalize(n);
        const double albedo = std::clamp(b0 * m.albedo[tri[0]] + u * m.albedo[tri[1]] + v * m.albedo[tri[2]], 0.0, 1.0);
        px.mask[p] = 1.0f;
        if (!shadowed) {
          sh::prt::unshadowed_transfer(opt.bands, n, albedo, px.coeffs.data() + p * K);
          px.ao[p] = 1.0;
          continue;
        }
        const glm::dvec3 org = pos + eps * n;
        px.ao[p] = sh::prt::shadowed_transfer(
            samples, n, albedo,
            [&](std::size_t s) {
              ++nr;
              return scene.unoccluded(org, samples.dirs[s], eps);
            },
            px.coeffs.data() + p * K);
      }
    }
    rays += nr;
  }, opt.progress);
  px.ray_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  px.rays = rays.load();
  if (opt.progress) opt.progress(1.0);
  return px;
}

// ---- transfer files -------------------------------------------------------------------
void write_transfer(const std::filesystem::path& file, const Transfer& t, const io::Provenance& prov) {
  std::string ext = file.extension().string();
  if (ext != ".ply") throw InputError(file.string() + ": per-vertex transfer is written as .ply");
  const std::size_t nv = t.mesh.positions.size(), K = static_cast<std::size_t>(t.bands) * t.bands;
  std::string s;
  s.reserve(nv * (K + 8) * 14 + t.mesh.triangles.size() * 24 + 4096);
  s += "ply\nformat ascii 1.0\n";
  s += "comment atmosh_prt bands " + std::to_string(t.bands) + "\n";
  s += std::string("comment atmosh_prt mode ") + sh::prt::transfer_mode_name(t.mode) + "\n";
  s += "comment atmosh_prt samples " + std::to_string(t.samples) + "\n";
  s += "comment atmosh_prt seed " + std::to_string(t.seed) + "\n";
  s += "comment atmosh_prt bounces " + std::to_string(t.bounces) + "\n";
  s += "comment atmosh_prt sh real orthonormal, Condon-Shortley phase, index l(l+1)+m\n";
  for (const auto& [k, v] : prov.entries) {
    std::string val = v;
    std::replace(val.begin(), val.end(), '\n', ' ');
    s += "comment atmosh:" + k + " " + val + "\n";
  }
  s += "element vertex " + std::to_string(nv) + "\n";
  for (const char* p : {"x", "y", "z", "nx", "ny", "nz", "albedo", "ao"}) s += std::string("property float ") + p + "\n";
  for (std::size_t i = 0; i < K; ++i) s += "property float t" + std::to_string(i) + "\n";
  s += "element face " + std::to_string(t.mesh.triangles.size()) + "\n";
  s += "property list uchar int vertex_indices\nend_header\n";
  char buf[64];
  auto num = [&](double x) {
    const int n = std::snprintf(buf, sizeof buf, "%.9g", x);
    s.append(buf, n);
  };
  for (std::size_t v = 0; v < nv; ++v) {
    const auto& p = t.mesh.positions[v];
    const auto& n = t.mesh.normals[v];
    const double head[8] = {p.x, p.y, p.z, n.x, n.y, n.z, t.mesh.albedo[v], t.ao[v]};
    for (int i = 0; i < 8; ++i) num(head[i]), s += ' ';
    for (std::size_t i = 0; i < K; ++i) num(t.coeffs[v * K + i]), s += (i + 1 < K ? ' ' : '\n');
  }
  for (const auto& tri : t.mesh.triangles)
    s += "3 " + std::to_string(tri[0]) + " " + std::to_string(tri[1]) + " " + std::to_string(tri[2]) + "\n";
  io::write_text_atomically(file, s);
}

Transfer read_transfer(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open transfer file");
  const std::string name = file.string();
  auto bad = [&](const std::string& why) { return InputError(name + ": not an atmosh transfer file (" + why + ")"); };
  std::string line;
  if (!std::getline(in, line) || line != "ply") throw bad("no 'ply' magic");
  Transfer t;
  t.mesh.name = name;
  std::size_t nv = 0, nf = 0, nprops = 0;
  bool ascii = false;
  while (std::getline(in, line)) {
    if (line == "end_header") break;
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format") {
      std::string f;
      ls >> f;
      ascii = f == "ascii";
    } else if (w == "comment") {
      std::string tag, key;
      ls >> tag >> key;
      if (tag != "atmosh_prt") continue;
      std::string val;
      ls >> val;
      if (key == "bands") t.bands = std::atoi(val.c_str());
      else if (key == "mode") t.mode = sh::prt::parse_transfer_mode(val);
      else if (key == "samples") t.samples = std::atoi(val.c_str());
      else if (key == "seed") t.seed = std::strtoull(val.c_str(), nullptr, 10);
      else if (key == "bounces") t.bounces = std::atoi(val.c_str());
    } else if (w == "element") {
      std::string e;
      std::size_t n = 0;
      ls >> e >> n;
      (e == "vertex" ? nv : nf) = n;
    } else if (w == "property") {
      std::string ty;
      ls >> ty;
      if (ty != "list") ++nprops;
    }
  }
  if (!ascii) throw bad("not ASCII");
  if (t.bands < 1 || t.bands > 16) throw bad("bands " + std::to_string(t.bands));
  const std::size_t K = static_cast<std::size_t>(t.bands) * t.bands;
  if (nprops != 8 + K) throw bad(std::to_string(nprops) + " vertex properties for " + std::to_string(t.bands) + " bands");
  if (nv == 0 || nf == 0) throw bad("no vertices or faces");
  // Counts are the header's word only: each value takes at least two bytes ("0 ").
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec || nv > bytes / (2 * (8 + K)) || nf > bytes / 8)
    throw bad(std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces cannot fit in " +
              std::to_string(ec ? 0 : bytes) + " bytes");
  t.mesh.positions.resize(nv);
  t.mesh.normals.resize(nv);
  t.mesh.albedo.resize(nv);
  t.ao.resize(nv);
  t.coeffs.resize(nv * K);
  std::vector<double> row(8 + K);
  for (std::size_t v = 0; v < nv; ++v) {
    for (auto& x : row)
      if (!(in >> x)) throw bad("vertex " + std::to_string(v) + " is short");
    t.mesh.positions[v] = {row[0], row[1], row[2]};
    t.mesh.normals[v] = {row[3], row[4], row[5]};
    t.mesh.albedo[v] = row[6];
    t.ao[v] = row[7];
    std::copy(row.begin() + 8, row.end(), t.coeffs.begin() + v * K);
  }
  t.mesh.triangles.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    long long c, a, b, d;
    const auto bad_index = [&](long long i) { return i < 0 || static_cast<unsigned long long>(i) >= nv; };
    if (!(in >> c >> a >> b >> d) || c != 3 || bad_index(a) || bad_index(b) || bad_index(d))
      throw bad("face " + std::to_string(f));
    t.mesh.triangles[f] = {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(d)};
  }
  validate(t.mesh);
  for (double x : t.coeffs)
    if (!std::isfinite(x)) throw bad("non-finite coefficient");
  return t;
}

// ---- relighting ------------------------------------------------------------------------
std::vector<std::vector<double>> relight_vertices(const Transfer& t, const std::vector<std::vector<double>>& light) {
  const int K = t.bands * t.bands;
  for (const auto& l : light)
    if (static_cast<int>(l.size()) < K)
      throw InputError("light has " + std::to_string(l.size()) + " coefficients, the transfer needs " + std::to_string(K) +
                       " (" + std::to_string(t.bands) + " bands)");
  std::vector<std::vector<double>> out(t.mesh.positions.size(), std::vector<double>(light.size()));
  for (std::size_t v = 0; v < out.size(); ++v)
    for (std::size_t c = 0; c < light.size(); ++c) out[v][c] = sh::prt::relight(t.at(v), light[c].data(), K);
  return out;
}

std::vector<std::vector<float>> render_vertex_values(const RayScene& scene, const Mesh& mesh,
                                                     const std::vector<std::vector<double>>& values, int width,
                                                     int height, const glm::dvec3& view_dir) {
  const PixelCamera cam(mesh, width, height, view_dir);
  const glm::dvec3 eye = cam.eye;
  const std::size_t C = values.empty() ? 0 : values[0].size();
  std::vector<std::vector<float>> img(C, std::vector<float>(static_cast<std::size_t>(width) * height, 0.0f));
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const glm::dvec3 d = cam.ray(r, c);
      std::uint32_t prim;
      float u, v;
      double t;
      if (!scene.intersect(eye, d, 0.0, prim, u, v, t)) continue;
      const auto& tri = mesh.triangles[prim];
      for (std::size_t k = 0; k < C; ++k)
        img[k][static_cast<std::size_t>(r) * width + c] = static_cast<float>(
            (1.0 - u - v) * values[tri[0]][k] + u * values[tri[1]][k] + v * values[tri[2]][k]);
    }
  return img;
}

}  // namespace atmosh::prt
