// The main job's scene-lighting step (see studies_gi.hpp).
#include "atmosh/studies/studies_gi.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/gi/methods.hpp"
#include "atmosh/gi/probes.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky.hpp"
#include "atmosh/studies/sky_studies.hpp"

namespace atmosh::studies {

namespace {
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

double exposure_of(const gi::RadianceImage& img) {
  std::vector<float> lum(img.mean[1]);
  std::sort(lum.begin(), lum.end());
  const double p = lum.empty() ? 1.0 : lum[static_cast<std::size_t>(0.99 * (lum.size() - 1))];
  return p > 0 ? 1.0 / p : 1.0;
}

void write_image(const fs::path& dir, const std::string& stem, const gi::RadianceImage& img, const gi::RadianceImage* ref,
                 double exposure, const io::Provenance& prov, std::vector<fs::path>& written) {
  std::vector<std::string> names = {"R", "G", "B"};
  if (ref != nullptr) names.insert(names.end(), {"error.R", "error.G", "error.B"});
  io::ExrImage ex(img.width, img.height, names);
  for (int c = 0; c < 3; ++c) {
    ex.data[c] = img.mean[c];
    if (ref != nullptr) {
      ex.data[3 + c] = img.mean[c];
      for (std::size_t i = 0; i < ex.data[3 + c].size(); ++i) ex.data[3 + c][i] -= ref->mean[c][i];
    }
  }
  ex.string_attributes["atmosh:quantity"] =
      "radiance (R, G, B; linear sRGB, cd/m^2)" + std::string(ref != nullptr ? "; error.* = this minus the reference" : "");
  const fs::path exr = dir / (stem + ".exr"), png = dir / (stem + ".png");
  io::write_exr(exr, ex, prov);
  io::write_tonemapped_png(png, img.width, img.height, img.mean[0], img.mean[1], img.mean[2], exposure, "reinhard");
  written.push_back(exr);
  written.push_back(png);
  written.push_back(io::write_tone_map_side_file(png, "reinhard v/(1+v) on linear RGB, then the sRGB transfer curve",
                                                 exposure, "1 / (99th percentile of G of the path-traced reference)",
                                                 exr.filename().string()));
}
}  // namespace

std::vector<fs::path> demo_gi(const fs::path& dir, bool quick) {
  std::vector<fs::path> written;
  const scene::Scene sc = scene::default_scene();
  const SunPlacement sun = sun_of_scene(sc);
  const auto model = make_sky_model(sc, SkySettings{}.sky(sc), sun.distance_au);
  const SkySh sky = project_sky_sh(*model, sun, 3);
  const atmo::SkySummary sm = atmo::summarize_sky(*model->sky, std::max(sun.observer_height_m, 0.0), sun.direction());
  const atmo::Rgb sun_rgb = atmo::linear_srgb_from_xyz(sm.sun_transmitted);

  gi::Scene s = gi::builtin_scene("cornell-box");
  for (auto& m : s.materials) m.emission = glm::dvec3(0.0);  // the ceiling light off: sun and sky only
  // Turn the box (its up stays +y) so that its open side (-z) faces the sun's azimuth:
  // north = (-sin az, 0, -cos az) puts the sun's horizontal direction along -z.
  const double az = sun.azimuth_deg * kPi / 180;
  s.north = glm::dvec3(-std::sin(az), 0, -std::cos(az));
  if (sun.elevation_deg > 0)
    s.sun = gi::Sun{gi::sun_direction(s, sun.azimuth_deg, sun.elevation_deg),
                    glm::max(glm::dvec3(sun_rgb.r, sun_rgb.g, sun_rgb.b), glm::dvec3(0.0)), 0};
  s.env_bands = sky.bands;
  for (int c = 0; c < 3; ++c) s.env_sh[c] = sky.coeffs[c];
  gi::validate(s);

  const int size = quick ? 40 : 192;
  auto prov = io::Provenance::current();
  prov.add("scene", "builtin:cornell-box, its light off, open side turned towards the sun")
      .add("sun", sun.describe())
      .add("sun_rgb_lux", io::format_double(sun_rgb.r) + "," + io::format_double(sun_rgb.g) + "," +
                              io::format_double(sun_rgb.b))
      .add("sky", "3-band SH of the default scene's sky (linear sRGB radiance, cd/m^2), frame east, north, up");

  gi::MethodOptions ref_opt;
  ref_opt.method = "path";
  ref_opt.samples = quick ? 64 : 1024;
  ref_opt.seed = 3;
  const gi::MethodResult ref = gi::render_method(s, s.camera, size, size, ref_opt);
  const double exposure = exposure_of(ref.image);
  {
    auto p = prov;
    p.add("method", "path").add("samples", std::to_string(ref_opt.samples));
    write_image(dir, "cornell_path", ref.image, nullptr, exposure, p, written);
  }
  io::StudySpec spec;
  spec.title = "gi converge: Cornell box under the default scene's sun and sky (reference: " +
               std::to_string(ref_opt.samples) + " paths/pixel)";
  spec.extra_columns = {"build_s", "shade_s", "mean_rel"};
  std::vector<io::StudyRow> rows;
  auto add_row = [&](const std::string& method, const std::string& setting, const gi::MethodResult& r) {
    const gi::ImageError e = gi::image_error(r.image, ref.image);
    rows.push_back({method, setting, e.max_rel, e.rms_rel, r.build_seconds + r.shade_seconds,
                    {r.build_seconds, r.shade_seconds, e.mean_rel}});
  };
  {
    gi::MethodOptions m;
    m.method = "path";
    m.samples = 4;
    m.seed = 5;
    add_row("path", "spp=4", gi::render_method(s, s.camera, size, size, m));
  }
  // One image per method at its default settings here (rows: these and a few more).
  struct Setting {
    std::string method;
    int grid, bands, bounces;
    bool image;
  };
  std::vector<Setting> settings = {{"probes", 4, 3, -1, true},     {"radiosity", 8, 2, 0, false},
                                   {"radiosity", 8, 2, 1, false},  {"radiosity", 8, 2, 2, true},
                                   {"radiosity", 8, 1, 2, false},  {"lpv", 16, 2, -1, true},
                                   {"lpv", 8, 2, -1, false}};
  if (!quick) settings.push_back({"radiosity", 16, 2, 2, false}), settings.push_back({"lpv", 32, 2, -1, false});
  for (const auto& st : settings) {
    gi::MethodOptions m;
    m.method = st.method;
    m.grid = st.grid;
    m.bands = st.bands;
    m.bounces = st.bounces;
    m.samples = 4;  // probes: paths per texel
    m.pixel_samples = quick ? 4 : 16;
    m.seed = 7;
    const gi::MethodResult r = gi::render_method(s, s.camera, size, size, m);
    std::string setting = "grid=" + std::to_string(st.grid);
    if (st.method != "lpv") setting += " bands=" + std::to_string(st.bands);
    if (st.method == "radiosity") setting += " bounces=" + std::to_string(st.bounces);
    add_row(st.method, setting, r);
    if (st.image) {
      auto p = prov;
      p.add("method", st.method).add("setting", setting);
      write_image(dir, "cornell_" + st.method, r.image, &ref.image, exposure, p, written);
    }
  }
  auto sp = prov;
  sp.add("errors", "relative to the reference's mean radiance over pixels and channels")
      .add("image", std::to_string(size) + "x" + std::to_string(size));
  for (const auto& f : io::write_study(dir / "gi_converge", spec, rows, sp)) written.push_back(f);
  return written;
}

}  // namespace atmosh::studies
