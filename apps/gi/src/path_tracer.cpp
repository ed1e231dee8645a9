// The diffuse path tracer (see path_tracer.hpp).
#include "atmosh/gi/path_tracer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/bake.hpp"
#include "sampling.hpp"

namespace atmosh::gi {

namespace {
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;

using detail::onb;
// One stream per pixel or query point.
struct Rng : detail::Rng {
  Rng(std::uint64_t seed, std::uint64_t index) : detail::Rng(seed, index, detail::kPathSalt) {}
};

glm::dvec3 cosine_sample(const glm::dvec3& n, double u1, double u2) {
  glm::dvec3 t, b;
  onb(n, t, b);
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  return r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * n;  // unit: t, b, n orthonormal
}

double max3(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

class Tracer {
 public:
  Tracer(const Scene& s, const TraceOptions& opt) : s_(s), rays_(s.mesh), opt_(opt) {
    const auto& m = s.mesh;
    const std::size_t nt = m.triangles.size();
    normal_.resize(nt);
    area_.resize(nt);
    mat_.resize(nt);
    for (std::size_t i = 0; i < nt; ++i) mat_[i] = &s.materials[s.material[i]];
    for (std::size_t i = 0; i < nt; ++i) {
      const auto& t = m.triangles[i];
      const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
      const double l = glm::length(c);
      area_[i] = 0.5 * l;
      normal_[i] = l > 0 ? c / l : glm::dvec3(0, 0, 1);
      const Material& mat = s.materials[s.material[i]];
      const double w = area_[i] * (mat.emission.x + mat.emission.y + mat.emission.z);
      if (w > 0) {
        emitters_.push_back(static_cast<std::uint32_t>(i));
        emitter_cdf_.push_back((emitter_cdf_.empty() ? 0.0 : emitter_cdf_.back()) + w);
      }
    }
    emitter_total_ = emitter_cdf_.empty() ? 0.0 : emitter_cdf_.back();
    off_ = rays_.offset();
    if (s.sun) {
      sun_dir_ = glm::normalize(s.sun->direction);
      const double a = s.sun->angular_radius;
      if (a > 0) {
        sun_cos_max_ = std::cos(a);
        const double omega = 2 * kPi * (1 - sun_cos_max_);
        sun_radiance_times_omega_ = s.sun->irradiance / (kPi * std::sin(a) * std::sin(a)) * omega;
      }
    }
    has_env_ = s.env_bands > 0 || s.env_map.has_value();
  }

  /// Radiance along the camera ray (o, d).
  glm::dvec3 camera_path(Rng& rng, const glm::dvec3& o, const glm::dvec3& d, Stats& st) const {
    return path(rng, o, d, nullptr, glm::dvec3(0), st);
  }
  /// Radiance leaving a white non-emitting Lambertian point p with normal n.
  glm::dvec3 surface_path(Rng& rng, const glm::dvec3& p, const glm::dvec3& n, Stats& st) const {
    return path(rng, p, glm::dvec3(0), &p, n, st);
  }

 private:
  bool intersect(const glm::dvec3& o, const glm::dvec3& d, std::uint32_t& prim, double& t, Stats& st) const {
    ++st.rays;
    log(o, d, off_, 1e30);
    float u, v;
    return rays_.intersect(o, d, off_, prim, u, v, t);
  }
  bool unoccluded(const glm::dvec3& o, const glm::dvec3& d, double tfar, Stats& st) const {
    ++st.rays;
    ++st.shadow_rays;
    log(o, d, off_, tfar);
    return rays_.unoccluded(o, d, off_, tfar);
  }
  void log(const glm::dvec3& o, const glm::dvec3& d, double tn, double tf) const {
    if (opt_.ray_log != nullptr)
      opt_.ray_log->push_back({static_cast<float>(o.x), static_cast<float>(o.y), static_cast<float>(o.z),
                               static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z),
                               static_cast<float>(tn), static_cast<float>(std::min(tf, 1e30))});
  }
  // Solid-angle pdf of the emitter sampler for a point on triangle `tri` seen at distance
  // `dist` along unit direction d.
  double emitter_pdf(std::uint32_t tri, double dist, const glm::dvec3& d) const {
    const Material& m = *mat_[tri];
    const double cos_l = std::abs(glm::dot(normal_[tri], d));
    if (cos_l <= 0) return 0;
    return (m.emission.x + m.emission.y + m.emission.z) / emitter_total_ * dist * dist / cos_l;
  }
  bool emits_towards(std::uint32_t tri, const glm::dvec3& d_to_viewer) const {
    const Material& m = *mat_[tri];
    return !m.one_sided || glm::dot(normal_[tri], d_to_viewer) > 0;
  }

  // Direct light at a surface point p (normal n towards the viewer side), reflected by a
  // Lambertian surface of albedo a, times throughput beta.
  glm::dvec3 direct(Rng& rng, const glm::dvec3& p, const glm::dvec3& n, Stats& st) const {
    glm::dvec3 L(0.0);
    if (s_.sun) {
      glm::dvec3 wl = sun_dir_;
      glm::dvec3 e = s_.sun->irradiance;
      if (sun_cos_max_ < 1) {  // uniform direction in the disc: L_sun cos / pdf with pdf = 1 / Omega
        wl = detail::sample_cone(rng, sun_dir_, sun_cos_max_);
        e = sun_radiance_times_omega_;
      }
      const double c = glm::dot(n, wl);
      if (c > 0 && max3(e) > 0 && unoccluded(p, wl, 1e30, st)) L += e * (c / kPi);
    }
    if (!emitters_.empty()) {
      const double u = rng.uniform() * emitter_total_;
      const std::size_t k = std::min<std::size_t>(
          emitters_.size() - 1, static_cast<std::size_t>(std::upper_bound(emitter_cdf_.begin(), emitter_cdf_.end(), u) -
                                                         emitter_cdf_.begin()));
      const std::uint32_t tri = emitters_[k];
      double b1 = rng.uniform(), b2 = rng.uniform();
      if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
      const auto& t = s_.mesh.triangles[tri];
      const auto& P = s_.mesh.positions;
      const glm::dvec3 q = P[t[0]] + b1 * (P[t[1]] - P[t[0]]) + b2 * (P[t[2]] - P[t[0]]);
      glm::dvec3 wl = q - p;
      const double dist = glm::length(wl);
      if (dist > 2 * off_) {
        wl /= dist;
        const double c = glm::dot(n, wl);
        if (c > 0 && emits_towards(tri, -wl)) {
          const double pdf_l = emitter_pdf(tri, dist, wl);
          const double pdf_b = c / kPi;
          if (pdf_l > 0 && unoccluded(p, wl, dist - off_, st)) {
            const double w = pdf_l * pdf_l / (pdf_l * pdf_l + pdf_b * pdf_b);
            L += mat_[tri]->emission * (c / kPi / pdf_l * w);
          }
        }
      }
    }
    return L;
  }

  glm::dvec3 path(Rng& rng, glm::dvec3 o, glm::dvec3 d, const glm::dvec3* start, glm::dvec3 start_n, Stats& st) const {
    glm::dvec3 L(0.0), beta(1.0);
    int depth = 0;          // reflections so far
    double prev_pdf = 0;    // solid-angle pdf of the hemisphere sample that made the ray
    bool from_camera = start == nullptr;
    glm::dvec3 p, n, albedo;
    if (start != nullptr) {
      p = *start;
      n = glm::normalize(start_n);
      albedo = glm::dvec3(1.0);
    }
    for (;;) {
      if (start == nullptr) {  // follow the ray (o, d) to the next surface
        std::uint32_t prim;
        double t;
        if (!intersect(o, d, prim, t, st)) {
          if (has_env_) L += beta * environment_radiance(s_, d);
          break;
        }
        p = o + t * d;
        const glm::dvec3 ng = normal_[prim];
        const bool front = glm::dot(ng, d) < 0;
        n = front ? ng : -ng;
        const Material& m = *mat_[prim];
        if (max3(m.emission) > 0 && emits_towards(prim, -d)) {
          if (from_camera) {
            L += beta * m.emission;
          } else {
            const double pl = emitter_pdf(prim, t, d), pb2 = prev_pdf * prev_pdf, den = pb2 + pl * pl;
            if (den > 0) L += beta * m.emission * (pb2 / den);
          }
        }
        albedo = m.albedo;
        if (opt_.bounces >= 0 && depth >= opt_.bounces) break;
      }
      start = nullptr;
      from_camera = false;
      if (max3(albedo) <= 0) break;
      L += beta * albedo * direct(rng, p, n, st);
      beta *= albedo;
      ++depth;
      if (depth >= opt_.rr_depth) {
        const double q = std::min(0.95, max3(beta));
        if (rng.uniform() >= q) break;
        beta /= q;
      }
      const double u1 = rng.uniform(), u2 = rng.uniform();
      d = cosine_sample(n, u1, u2);
      prev_pdf = std::max(glm::dot(n, d), 0.0) / kPi;
      o = p;
    }
    return L;
  }

  const Scene& s_;
  prt::RayScene rays_;
  const TraceOptions& opt_;
  std::vector<glm::dvec3> normal_;
  std::vector<const Material*> mat_;  // per triangle
  std::vector<double> area_;
  std::vector<std::uint32_t> emitters_;
  std::vector<double> emitter_cdf_;
  double emitter_total_ = 0, off_ = 0;
  glm::dvec3 sun_dir_{0, 0, 1}, sun_radiance_times_omega_{0.0};
  double sun_cos_max_ = 1;
  bool has_env_ = false;
};

void check_options(const TraceOptions& o) {
  if (o.samples < 2 || o.samples > 10000000)
    throw InputError("gi: samples must be in 2..10000000, got " + std::to_string(o.samples));
  if (o.bounces < -1 || o.bounces > 100000)
    throw InputError("gi: bounces must be -1 (unlimited) or 0..100000, got " + std::to_string(o.bounces));
  if (o.rr_depth < 1 || o.rr_depth > 100000)
    throw InputError("gi: Russian-roulette depth must be in 1..100000, got " + std::to_string(o.rr_depth));
  if (o.threads < 0 || o.threads > 1024) throw InputError("gi: threads must be in 0..1024, got " + std::to_string(o.threads));
  if (o.ray_log != nullptr && o.threads != 1) throw InputError("gi: a ray log needs threads = 1");
}

// Welford accumulation of one RGB estimate.
struct Acc {
  glm::dvec3 mean{0.0}, m2{0.0};
  int n = 0;
  void add(const glm::dvec3& x) {
    ++n;
    const glm::dvec3 d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  glm::dvec3 stderr_() const { return glm::sqrt(glm::max(m2, 0.0) / (static_cast<double>(n) * (n - 1))); }
};

struct AtomicStats {
  std::atomic<std::uint64_t> rays{0}, shadow{0};
  void add(const Stats& s) {
    rays.fetch_add(s.rays, std::memory_order_relaxed);
    shadow.fetch_add(s.shadow_rays, std::memory_order_relaxed);
  }
};

// The per-query estimates of irradiance() and radiance_along(): query i of n gets its own
// seeded stream and opt.samples estimates sample(tracer, rng, i, stats), averaged with
// their standard error; the queries run in parallel in chunks of `grain`.
template <class Sample>
Irradiance estimate_per_query(const Scene& scene, std::size_t n, std::size_t grain, const TraceOptions& opt,
                              Sample&& sample) {
  const auto t_setup = Clock::now();
  const Tracer tracer(scene, opt);
  const auto t0 = Clock::now();
  Irradiance out;
  out.stats.setup_seconds = std::chrono::duration<double>(t0 - t_setup).count();
  out.mean.assign(n, glm::dvec3(0.0));
  out.stderr_.assign(n, glm::dvec3(0.0));
  AtomicStats total;
  parallel_for_ranges(
      n, grain, opt.threads,
      [&](std::size_t b, std::size_t e) {
        Stats st;
        for (std::size_t i = b; i < e; ++i) {
          Rng rng(opt.seed, i);
          Acc acc;
          for (int s = 0; s < opt.samples; ++s) acc.add(sample(tracer, rng, i, st));
          out.mean[i] = acc.mean;
          out.stderr_[i] = acc.stderr_();
        }
        total.add(st);
      },
      opt.progress);
  out.stats.rays = total.rays.load();
  out.stats.shadow_rays = total.shadow.load();
  out.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return out;
}
}  // namespace

RadianceImage render(const Scene& scene, const Camera& cam, int width, int height, const TraceOptions& opt) {
  check_options(opt);
  validate(scene);
  check_view(cam, width, height);
  const glm::dvec3 f = glm::normalize(cam.forward), right = glm::normalize(glm::cross(cam.forward, cam.up)),
                   up = glm::cross(right, f);
  const double th = std::tan(0.5 * cam.vertical_fov_deg * kPi / 180), aspect = static_cast<double>(width) / height;

  const auto t_setup = Clock::now();
  const Tracer tracer(scene, opt);
  const auto t0 = Clock::now();
  RadianceImage img;
  img.stats.setup_seconds = std::chrono::duration<double>(t0 - t_setup).count();
  img.width = width;
  img.height = height;
  img.samples = opt.samples;
  const std::size_t np = static_cast<std::size_t>(width) * height;
  for (int c = 0; c < 3; ++c) img.mean[c].assign(np, 0.0f), img.stderr_[c].assign(np, 0.0f);
  AtomicStats total;
  parallel_for_ranges(
      np, 16, opt.threads,
      [&](std::size_t b, std::size_t e) {
        Stats st;
        for (std::size_t i = b; i < e; ++i) {
          const int row = static_cast<int>(i / width), col = static_cast<int>(i % width);
          Rng rng(opt.seed, i);
          Acc acc;
          for (int s = 0; s < opt.samples; ++s) {
            const double jx = rng.uniform(), jy = rng.uniform();
            const double x = (2.0 * (col + jx) / width - 1.0) * th * aspect, y = (1.0 - 2.0 * (row + jy) / height) * th;
            const glm::dvec3 d = glm::normalize(f + x * right + y * up);
            acc.add(tracer.camera_path(rng, cam.eye, d, st));
          }
          const glm::dvec3 se = acc.stderr_();
          for (int c = 0; c < 3; ++c) {
            img.mean[c][i] = static_cast<float>(acc.mean[c]);
            img.stderr_[c][i] = static_cast<float>(se[c]);
          }
        }
        total.add(st);
      },
      opt.progress);
  img.stats.rays = total.rays.load();
  img.stats.shadow_rays = total.shadow.load();
  img.stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return img;
}

Irradiance irradiance(const Scene& scene, const std::vector<glm::dvec3>& points, const std::vector<glm::dvec3>& normals,
                      const TraceOptions& opt) {
  check_options(opt);
  validate(scene);
  if (points.size() != normals.size())
    throw InputError("gi irradiance: " + std::to_string(points.size()) + " points but " + std::to_string(normals.size()) +
                     " normals");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double ln = glm::length(normals[i]);
    if (!std::isfinite(glm::length(points[i])) || !(ln > 0) || !std::isfinite(ln))
      throw InputError("gi irradiance: query " + std::to_string(i) + " has a non-finite point or a zero normal");
  }
  return estimate_per_query(scene, points.size(), 1, opt, [&](const Tracer& tracer, Rng& rng, std::size_t i, Stats& st) {
    return kPi * tracer.surface_path(rng, points[i], normals[i], st);
  });
}

Irradiance radiance_along(const Scene& scene, const std::vector<glm::dvec3>& origins, const std::vector<glm::dvec3>& dirs,
                          const TraceOptions& opt) {
  if (origins.size() != dirs.size())
    throw InputError("gi radiance: " + std::to_string(origins.size()) + " origins but " + std::to_string(dirs.size()) +
                     " directions");
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const double ln = glm::length(dirs[i]);
    if (!(ln > 0) || !std::isfinite(ln)) throw InputError("gi radiance: ray " + std::to_string(i) + " has a zero direction");
  }
  return radiance_along(
      scene, origins, [&dirs](std::size_t i, double, double, double& w) { w = 1; return dirs[i]; }, opt);
}

Irradiance radiance_along(const Scene& scene, const std::vector<glm::dvec3>& origins, const RayDirection& direction,
                          const TraceOptions& opt) {
  check_options(opt);
  validate(scene);
  if (!direction) throw InputError("gi radiance: no direction function");
  for (std::size_t i = 0; i < origins.size(); ++i)
    if (!std::isfinite(glm::length(origins[i])))
      throw InputError("gi radiance: ray " + std::to_string(i) + " has a non-finite origin");
  return estimate_per_query(scene, origins.size(), 16, opt,
                            [&](const Tracer& tracer, Rng& rng, std::size_t i, Stats& st) {
                              const double u1 = rng.uniform(), u2 = rng.uniform();
                              double w = 1;
                              glm::dvec3 d = direction(i, u1, u2, w);
                              const double ln = glm::length(d);
                              if (!(ln > 0) || !std::isfinite(ln) || !std::isfinite(w))
                                throw InputError("gi radiance: ray " + std::to_string(i) +
                                                 " got a zero or non-finite direction or weight");
                              return w * tracer.camera_path(rng, origins[i], d / ln, st);
                            });
}

}  // namespace atmosh::gi
