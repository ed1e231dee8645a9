// Scenes for diffuse global illumination (see scene.hpp).
#include "atmosh/gi/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "atmosh/check.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/sh/basis.hpp"

namespace atmosh::gi {

namespace {
constexpr double kPi = std::numbers::pi;

// Cornell Box Data, Cornell University Program of Computer Graphics,
// www.graphics.cornell.edu/online/box/data.html: vertices in mm, four per quad, in the
// page's order. The light is lowered 0.5 mm below the ceiling (see scene.hpp).
struct Quad {
  double v[4][3];
  int material;  // 0 white, 1 red, 2 green, 3 light
};
constexpr double kLightY = 548.8 - 0.5;
constexpr Quad kCornell[] = {
    // floor (white)
    {{{552.8, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 559.2}, {549.6, 0.0, 559.2}}, 0},
    // light
    {{{343.0, kLightY, 227.0}, {343.0, kLightY, 332.0}, {213.0, kLightY, 332.0}, {213.0, kLightY, 227.0}}, 3},
    // ceiling (white)
    {{{556.0, 548.8, 0.0}, {556.0, 548.8, 559.2}, {0.0, 548.8, 559.2}, {0.0, 548.8, 0.0}}, 0},
    // back wall (white)
    {{{549.6, 0.0, 559.2}, {0.0, 0.0, 559.2}, {0.0, 548.8, 559.2}, {556.0, 548.8, 559.2}}, 0},
    // right wall (green)
    {{{0.0, 0.0, 559.2}, {0.0, 0.0, 0.0}, {0.0, 548.8, 0.0}, {0.0, 548.8, 559.2}}, 2},
    // left wall (red)
    {{{552.8, 0.0, 0.0}, {549.6, 0.0, 559.2}, {556.0, 548.8, 559.2}, {556.0, 548.8, 0.0}}, 1},
    // short block (white)
    {{{130.0, 165.0, 65.0}, {82.0, 165.0, 225.0}, {240.0, 165.0, 272.0}, {290.0, 165.0, 114.0}}, 0},
    {{{290.0, 0.0, 114.0}, {290.0, 165.0, 114.0}, {240.0, 165.0, 272.0}, {240.0, 0.0, 272.0}}, 0},
    {{{130.0, 0.0, 65.0}, {130.0, 165.0, 65.0}, {290.0, 165.0, 114.0}, {290.0, 0.0, 114.0}}, 0},
    {{{82.0, 0.0, 225.0}, {82.0, 165.0, 225.0}, {130.0, 165.0, 65.0}, {130.0, 0.0, 65.0}}, 0},
    {{{240.0, 0.0, 272.0}, {240.0, 165.0, 272.0}, {82.0, 165.0, 225.0}, {82.0, 0.0, 225.0}}, 0},
    // tall block (white)
    {{{423.0, 330.0, 247.0}, {265.0, 330.0, 296.0}, {314.0, 330.0, 456.0}, {472.0, 330.0, 406.0}}, 0},
    {{{423.0, 0.0, 247.0}, {423.0, 330.0, 247.0}, {472.0, 330.0, 406.0}, {472.0, 0.0, 406.0}}, 0},
    {{{472.0, 0.0, 406.0}, {472.0, 330.0, 406.0}, {314.0, 330.0, 456.0}, {314.0, 0.0, 456.0}}, 0},
    {{{314.0, 0.0, 456.0}, {314.0, 330.0, 456.0}, {265.0, 330.0, 296.0}, {265.0, 0.0, 296.0}}, 0},
    {{{265.0, 0.0, 296.0}, {265.0, 330.0, 296.0}, {423.0, 330.0, 247.0}, {423.0, 0.0, 247.0}}, 0},
};

// The page's measured reflectance spectra read at 612 nm (R), 548 nm (G), 464 nm (B):
//   white 0.755 0.748 0.751, red 0.443 0.061 0.062, green 0.136 0.406 0.107.
// Light: the page's emission spectrum 400:0, 500:8, 600:15.6, 700:18.4, linearly
// interpolated: 612 nm 15.936, 548 nm 11.648, 464 nm 5.12. Its reflectance is not
// given; taken as 0.
Scene cornell_box() {
  Scene s;
  s.name = "builtin:cornell-box";
  s.materials = {
      Material{{0.755, 0.748, 0.751}, {0, 0, 0}, false},
      Material{{0.443, 0.061, 0.062}, {0, 0, 0}, false},
      Material{{0.136, 0.406, 0.107}, {0, 0, 0}, false},
      Material{{0, 0, 0}, {15.936, 11.648, 5.12}, true},
  };
  prt::Mesh& m = s.mesh;
  m.name = s.name;
  for (const Quad& q : kCornell) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const auto& v : q.v) m.positions.emplace_back(v[0], v[1], v[2]);
    std::array<std::uint32_t, 4> id{base, base + 1, base + 2, base + 3};
    if (q.material == 3) {  // the light faces down (-y): wind it so
      const glm::dvec3 n = glm::cross(m.positions[id[1]] - m.positions[id[0]], m.positions[id[2]] - m.positions[id[0]]);
      if (n.y > 0) std::swap(id[1], id[3]);
    }
    m.triangles.push_back({id[0], id[1], id[2]});
    m.triangles.push_back({id[0], id[2], id[3]});
    s.material.push_back(static_cast<std::uint32_t>(q.material));
    s.material.push_back(static_cast<std::uint32_t>(q.material));
  }
  prt::compute_normals(m);
  s.up = {0, 1, 0};
  s.north = {0, 0, 1};
  s.camera.eye = {278, 273, -800};
  s.camera.forward = {0, 0, 1};
  s.camera.up = {0, 1, 0};
  s.camera.vertical_fov_deg = 2 * std::atan(0.0125 / 0.035) * 180 / kPi;  // 25 mm film, 35 mm lens
  return s;
}

Camera default_camera(const prt::Mesh& mesh) {
  const prt::PixelCamera pc(mesh, 1, 1, glm::dvec3(1, -1.6, 1.1));
  Camera c;
  c.eye = pc.eye;
  c.forward = -pc.w;
  c.up = pc.up;
  c.vertical_fov_deg = 40;
  return c;
}

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

std::vector<std::string> builtin_scene_names() { return {"cornell-box", "sphere-on-plane", "box-occluder"}; }

Scene scene_from_mesh(const prt::Mesh& mesh, const Material& material) {
  Scene s;
  s.mesh = mesh;
  s.name = mesh.name;
  s.materials = {material};
  s.material.assign(mesh.triangles.size(), 0);
  s.camera = default_camera(mesh);
  return s;
}

namespace {
// Grey material per triangle from per-vertex albedo (mean of its vertices).
Scene grey_scene(const prt::Mesh& mesh, double default_albedo) {
  Scene s = scene_from_mesh(mesh, Material{glm::dvec3(default_albedo), glm::dvec3(0), false});
  if (mesh.albedo.size() == mesh.positions.size()) {
    s.materials.clear();
    s.material.clear();
    std::vector<std::pair<double, std::uint32_t>> seen;
    for (const auto& t : mesh.triangles) {
      const double a = (mesh.albedo[t[0]] + mesh.albedo[t[1]] + mesh.albedo[t[2]]) / 3.0;
      auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == a; });
      if (it == seen.end()) {
        seen.emplace_back(a, static_cast<std::uint32_t>(s.materials.size()));
        s.materials.push_back(Material{glm::dvec3(a), glm::dvec3(0), false});
        it = seen.end() - 1;
      }
      s.material.push_back(it->second);
    }
  }
  return s;
}
}  // namespace

Scene scene_from_mesh(const std::filesystem::path& file, double default_albedo) {
  if (!(default_albedo >= 0 && default_albedo <= 1))
    throw InputError("gi scene: default albedo must be in [0, 1], got " + std::to_string(default_albedo));
  return grey_scene(prt::load_mesh(file), default_albedo);
}

Scene builtin_scene(const std::string& name, int resolution) {
  if (name == "cornell-box") return cornell_box();
  if (name == "sphere-on-plane" || name == "box-occluder") {
    Scene s = grey_scene(prt::builtin_scene(name, resolution), 0.8);
    s.name = "builtin:" + name;
    return s;
  }
  std::string names;
  for (const auto& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError("unknown built-in gi scene '" + name + "' (" + names + ")");
}

glm::dvec3 sun_direction(const Scene& scene, double azimuth_deg, double elevation_deg) {
  if (!std::isfinite(azimuth_deg) || !std::isfinite(elevation_deg) || elevation_deg < -90 || elevation_deg > 90)
    throw InputError("sun: azimuth must be finite and elevation in [-90, 90] degrees, got " + std::to_string(azimuth_deg) +
                     ", " + std::to_string(elevation_deg));
  const double az = azimuth_deg * kPi / 180, el = elevation_deg * kPi / 180;
  const glm::dvec3 east = glm::cross(scene.north, scene.up);
  return glm::normalize(std::cos(el) * (std::cos(az) * scene.north + std::sin(az) * east) + std::sin(el) * scene.up);
}

glm::dvec3 environment_radiance(const Scene& scene, const glm::dvec3& dir) {
  glm::dvec3 out(0.0);
  if (scene.env_bands == 0 && !scene.env_map) return out;
  const glm::dvec3 east = glm::cross(scene.north, scene.up);
  const glm::dvec3 d = glm::normalize(glm::dvec3(glm::dot(dir, east), glm::dot(dir, scene.north), glm::dot(dir, scene.up)));
  if (scene.env_bands > 0)
    for (int c = 0; c < 3; ++c) out[c] = sh::reconstruct(scene.env_bands, scene.env_sh[c].data(), d);
  if (scene.env_map) {
    const EnvironmentMap& e = *scene.env_map;
    const double theta = std::acos(std::clamp(d.z, -1.0, 1.0));
    double phi = std::atan2(d.x, d.y);  // from north towards east
    if (phi < 0) phi += 2 * kPi;
    const int row = std::min(e.height - 1, static_cast<int>(theta / kPi * e.height));
    const int col = std::min(e.width - 1, static_cast<int>(phi / (2 * kPi) * e.width));
    const std::size_t i = static_cast<std::size_t>(row) * e.width + col;
    for (int c = 0; c < 3; ++c) out[c] += e.rgb[c][i];
  }
  return out;
}

EnvironmentMap read_environment_map(const std::filesystem::path& exr) {
  const io::ExrImage img = io::read_exr(exr);
  EnvironmentMap e;
  e.width = img.width;
  e.height = img.height;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    if (img.find_channel(names[c]) < 0)
      throw InputError(exr.string() + ": environment image has no channel " + names[c] + " (needs R, G, B)");
    e.rgb[c] = img.channel(names[c]);
    for (float v : e.rgb[c])
      if (!std::isfinite(v) || v < 0)
        throw InputError(exr.string() + ": environment radiance must be finite and >= 0 (channel " + names[c] + ")");
  }
  return e;
}

std::size_t emitting_triangles(const Scene& scene) {
  std::size_t n = 0;
  for (const std::uint32_t m : scene.material) {
    const glm::dvec3& L = scene.materials[m].emission;
    n += L.x + L.y + L.z > 0 ? 1 : 0;
  }
  return n;
}

void validate(const Scene& s) {
  prt::validate(s.mesh);
  if (s.material.size() != s.mesh.triangles.size())
    throw InputError("gi scene '" + s.name + "': " + std::to_string(s.material.size()) + " material indices for " +
                     std::to_string(s.mesh.triangles.size()) + " triangles");
  for (auto m : s.material)
    if (m >= s.materials.size())
      throw InputError("gi scene '" + s.name + "': material index " + std::to_string(m) + " out of range");
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = s.materials[i];
    for (int c = 0; c < 3; ++c) {
      if (!(m.albedo[c] >= 0 && m.albedo[c] <= 1))
        throw InputError("gi scene: material " + std::to_string(i) + " albedo " + std::to_string(m.albedo[c]) +
                         " is outside [0, 1]");
      if (!(m.emission[c] >= 0) || !std::isfinite(m.emission[c]))
        throw InputError("gi scene: material " + std::to_string(i) + " emission " + std::to_string(m.emission[c]) +
                         " is negative or not finite");
    }
  }
  if (s.sun) {
    const Sun& sun = *s.sun;
    if (!finite3(sun.direction) || glm::length(sun.direction) == 0)
      throw InputError("gi scene: sun direction is zero or not finite");
    for (int c = 0; c < 3; ++c)
      if (!(sun.irradiance[c] >= 0) || !std::isfinite(sun.irradiance[c]))
        throw InputError("gi scene: sun irradiance " + std::to_string(sun.irradiance[c]) + " is negative or not finite");
    if (!(sun.angular_radius >= 0 && sun.angular_radius <= 0.5))
      throw InputError("gi scene: sun angular radius " + std::to_string(sun.angular_radius) + " is outside [0, 0.5] rad");
  }
  if (s.env_bands < 0 || s.env_bands > 64)
    throw InputError("gi scene: environment SH bands must be in 0..64, got " + std::to_string(s.env_bands));
  for (int c = 0; c < 3 && s.env_bands > 0; ++c) {
    if (s.env_sh[c].size() != static_cast<std::size_t>(s.env_bands) * s.env_bands)
      throw InputError("gi scene: environment channel " + std::to_string(c) + " has " + std::to_string(s.env_sh[c].size()) +
                       " SH coefficients, expected " + std::to_string(s.env_bands * s.env_bands));
    for (double v : s.env_sh[c])
      if (!std::isfinite(v)) throw InputError("gi scene: environment SH coefficient is not finite");
  }
  if (s.env_map) {
    const EnvironmentMap& e = *s.env_map;
    if (e.width < 1 || e.height < 1) throw InputError("gi scene: empty environment image");
    for (int c = 0; c < 3; ++c)
      if (e.rgb[c].size() != static_cast<std::size_t>(e.width) * e.height)
        throw InputError("gi scene: environment image channel size does not match its width x height");
  }
  if (!finite3(s.up) || !finite3(s.north) || std::abs(glm::length(s.up) - 1) > 1e-9 ||
      std::abs(glm::length(s.north) - 1) > 1e-9 || std::abs(glm::dot(s.up, s.north)) > 1e-9)
    throw InputError("gi scene: up and north must be orthogonal unit vectors");
}

void check_view(const Camera& cam, int width, int height) {
  require_image_size(width, height, "gi");
  const glm::dvec3 rx = glm::cross(cam.forward, cam.up);
  if (!(glm::length(cam.forward) > 0) || !(glm::length(rx) > 0) || !std::isfinite(glm::length(rx)) ||
      !std::isfinite(glm::length(cam.eye)) || !(cam.vertical_fov_deg > 0 && cam.vertical_fov_deg < 180))
    throw InputError("gi: camera needs a finite eye, forward and up not parallel, and 0 < fov < 180 degrees");
}

}  // namespace atmosh::gi
