// Shared parts of the approximate lighting methods (see receivers.hpp).
#include "receivers.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/gi/shared/polygon.glsl.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::gi::detail {

namespace {
constexpr double kPi = std::numbers::pi;
}

double polygon_irradiance_factor(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& a, const glm::dvec3& b,
                                 const glm::dvec3& c) {
  // the shared C++/GLSL block (also the GPU G-buffer's area-light term)
  return shared::gi_polygon_irradiance(p, n, a, b, c);
}

std::vector<glm::dvec3> triangle_normals(const prt::Mesh& m) {
  std::vector<glm::dvec3> normal(m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    const double l = glm::length(c);
    normal[i] = l > 0 ? c / l : glm::dvec3(0, 0, 1);
  }
  return normal;
}

void mesh_bounds(const prt::Mesh& m, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (const auto& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
}

DirectLight::DirectLight(const Scene& s, const prt::RayScene& rays) : s_(s), rays_(rays) {
  normal_ = triangle_normals(s.mesh);
  area.resize(normal_.size());
  for (std::size_t i = 0; i < normal_.size(); ++i) {
    const auto& t = s.mesh.triangles[i];
    area[i] = 0.5 * glm::length(glm::cross(s.mesh.positions[t[1]] - s.mesh.positions[t[0]],
                                           s.mesh.positions[t[2]] - s.mesh.positions[t[0]]));
    const Material& m = s.materials[s.material[i]];
    const double w = area[i] * (m.emission.x + m.emission.y + m.emission.z);
    if (w > 0) {
      emitters_.push_back(static_cast<std::uint32_t>(i));
      cdf_.push_back((cdf_.empty() ? 0.0 : cdf_.back()) + w);
    }
  }
  total_ = cdf_.empty() ? 0.0 : cdf_.back();
  off_ = rays.offset();
  if (s.sun) {
    sun_dir_ = glm::normalize(s.sun->direction);
    sun_e_ = s.sun->irradiance;
    const double a = s.sun->angular_radius;
    if (a > 0) {
      sun_cos_max_ = std::cos(a);
      sun_e_ = s.sun->irradiance / (kPi * std::sin(a) * std::sin(a)) * (2 * kPi * (1 - sun_cos_max_));
    }
  }
  has_env_ = s.env_bands > 0 || s.env_map.has_value();
}

glm::dvec3 DirectLight::irradiance(Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint64_t& nrays) const {
  glm::dvec3 E(0.0);
  if (s_.sun) {
    glm::dvec3 wl = sun_dir_;
    if (sun_cos_max_ < 1) {  // uniform direction in the disc
      wl = sample_cone(rng, sun_dir_, sun_cos_max_);
    }
    const double c = glm::dot(n, wl);
    if (c > 0) {
      ++nrays;
      if (rays_.unoccluded(p, wl, off_)) E += sun_e_ * c;
    }
  }
  for (const std::uint32_t tri : emitters_) {  // exact unshadowed irradiance x one visibility ray
    const auto& t = s_.mesh.triangles[tri];
    const Material& m = s_.materials[s_.material[tri]];
    const glm::dvec3 v0 = s_.mesh.positions[t[0]], v1 = s_.mesh.positions[t[1]], v2 = s_.mesh.positions[t[2]];
    if (m.one_sided && glm::dot(normal_[tri], p - v0) <= 0) continue;  // behind a one-sided emitter
    // evaluated 1 % of a ray offset (1e-6 x the box diagonal) above the surface: the
    // receiver's own triangle (in its tangent plane) then lies wholly below it and drops
    // out, as do emitters through p; the shadow ray leaves a whole ray offset above it
    const glm::dvec3 pa = p + off_ * n;
    const double e = polygon_irradiance_factor(p + 0.01 * off_ * n, n, v0, v1, v2);
    if (!(e > 0)) continue;
    double b1 = rng.uniform(), b2 = rng.uniform();
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    const glm::dvec3 to = v0 + b1 * (v1 - v0) + b2 * (v2 - v0) - pa;
    const double d = glm::length(to);
    ++nrays;
    if (d <= 2 * off_ || rays_.unoccluded(pa, to / d, 0.0, d - off_)) E += m.emission * e;
  }
  if (has_env_) {
    glm::dvec3 t, b;
    onb(n, t, b);
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const double r = std::sqrt(u1), phi = 2 * kPi * u2;
    const glm::dvec3 w = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * n;
    ++nrays;
    if (rays_.unoccluded(p, w, off_)) E += kPi * environment_radiance(s_, w);
  }
  return E;
}

RadianceImage render_receivers(const Scene& scene, const prt::RayScene& rays, const Camera& cam, int width, int height,
                               int samples, std::uint64_t seed, int threads, const ReceiverShade& shade,
                               std::uint64_t salt) {
  check_view(cam, width, height);
  if (samples < 1 || samples > 1000000)
    throw InputError("gi: camera rays per pixel must be in 1..1000000, got " + std::to_string(samples));
  const glm::dvec3 rx = glm::cross(cam.forward, cam.up);
  const glm::dvec3 f = glm::normalize(cam.forward), right = glm::normalize(rx), up = glm::cross(right, f);
  const double th = std::tan(0.5 * cam.vertical_fov_deg * kPi / 180), aspect = static_cast<double>(width) / height;
  const std::vector<glm::dvec3> normal = triangle_normals(scene.mesh);
  const bool has_env = scene.env_bands > 0 || scene.env_map.has_value();
  const double off = rays.offset();
  const auto t0 = std::chrono::steady_clock::now();
  RadianceImage img;
  img.width = width;
  img.height = height;
  img.samples = samples;
  const std::size_t np = static_cast<std::size_t>(width) * height;
  for (int c = 0; c < 3; ++c) img.mean[c].assign(np, 0.0f), img.stderr_[c].assign(np, 0.0f);
  std::atomic<std::uint64_t> nrays{0};
  parallel_for_ranges(np, 16, threads, [&](std::size_t b, std::size_t e) {
    std::uint64_t r = 0;
    for (std::size_t i = b; i < e; ++i) {
      const int row = static_cast<int>(i / width), col = static_cast<int>(i % width);
      Rng rng(seed, i, salt);
      glm::dvec3 sum(0.0), sum2(0.0);
      for (int s = 0; s < samples; ++s) {
        const double jx = rng.uniform(), jy = rng.uniform();
        const double x = (2.0 * (col + jx) / width - 1.0) * th * aspect, y = (1.0 - 2.0 * (row + jy) / height) * th;
        const glm::dvec3 d = glm::normalize(f + x * right + y * up);
        glm::dvec3 L(0.0);
        std::uint32_t prim;
        float u, v;
        double t;
        ++r;
        if (!rays.intersect(cam.eye, d, off, prim, u, v, t)) {
          if (has_env) L = environment_radiance(scene, d);
        } else {
          const glm::dvec3 p = cam.eye + t * d;
          const glm::dvec3 n = glm::dot(normal[prim], d) < 0 ? normal[prim] : -normal[prim];
          const Material& mat = scene.materials[scene.material[prim]];
          if (!mat.one_sided || glm::dot(normal[prim], -d) > 0) L += mat.emission;
          const glm::dvec3 E = glm::max(shade(rng, p, n, prim, r), glm::dvec3(0.0));
          L += mat.albedo / kPi * E;
        }
        sum += L;
        sum2 += L * L;
      }
      const double ns = samples;
      const glm::dvec3 mean = sum / ns;
      const glm::dvec3 var = ns > 1 ? glm::max((sum2 - ns * mean * mean) / (ns - 1), 0.0) : glm::dvec3(0.0);
      for (int c = 0; c < 3; ++c) {
        img.mean[c][i] = static_cast<float>(mean[c]);
        img.stderr_[c][i] = static_cast<float>(std::sqrt(var[c] / ns));
      }
    }
    nrays.fetch_add(r, std::memory_order_relaxed);
  });
  img.stats.rays = nrays.load();
  img.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return img;
}

}  // namespace atmosh::gi::detail
