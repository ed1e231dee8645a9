// The JSON summaries of one-shot results (atmosh/studies/summaries.hpp).
#include "atmosh/studies/summaries.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <sstream>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/budget.hpp"
#include "atmosh/memory.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/studies/scene_run.hpp"

namespace atmosh::studies {

namespace {
using nlohmann::json;
json rgb_json(const atmo::Rgb& c) { return json::array({c.r, c.g, c.b}); }
// A chromaticity [x, y], or null when the colour has none.
json xy_json(const atmo::Xyz& c) {
  const atmo::Chromaticity q = atmo::xy_chromaticity_or_nan(c);
  return std::isnan(q.x) ? json(nullptr) : json::array({q.x, q.y});
}
json text_or_null(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }
std::string printf_string(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string printf_string(const char* format, ...) {
  va_list a, b;
  va_start(a, format);
  va_copy(b, a);
  std::string out(static_cast<std::size_t>(std::vsnprintf(nullptr, 0, format, a)), '\0');
  va_end(a);
  std::vsnprintf(out.data(), out.size() + 1, format, b);
  va_end(b);
  return out;
}
json jd_or_null(const std::optional<double>& jd) { return jd ? json(atmo::format_iso8601_utc(*jd)) : json(nullptr); }
}  // namespace

json sky_json(const SkyModel& model, const SunPlacement& sun, const atmo::SkyImage& img, double exposure,
              const std::string& device, const SkyFiles& files) {
  const atmo::SkyIntegrator& sky = *model.sky;
  const double h = std::max(sun.observer_height_m, 0.0);
  const atmo::SkySummary sm = atmo::summarize_sky(sky, h, sun.direction());
  json j = {{"exr", text_or_null(files.exr)},
            {"png", text_or_null(files.png)},
            {"sun_elevation_deg", sun.elevation_deg},
            {"sun_azimuth_deg", sun.azimuth_deg},
            {"zenith_luminance_cd_m2", sm.zenith.xyz.Y},
            {"zenith_srgb", rgb_json(sm.zenith.srgb)},
            {"zenith_xy", xy_json(sm.zenith.xyz)},
            {"horizon_srgb", rgb_json(sm.horizon_toward_sun.srgb)},
            {"horizon_luminance_cd_m2", sm.horizon_toward_sun.xyz.Y},
            {"horizon_away_srgb", rgb_json(sm.horizon_away.srgb)},
            {"srgb_units", "linear sRGB (D65), scaled so that Y is luminance in cd/m^2"},
            {"sun_model", atmo::sun_model_name(sky.options().sun_model)},
            {"sun_angular_radius_deg", atmo::sun_angular_radius_rad(sun.distance_au) * 57.29577951308232},
            {"exposure", exposure},
            {"rays", img.rays},
            {"device", device},
            {"render_time_s", img.seconds},
            {"table_build_time_s", model.build_time_s},
            {"rays_per_s", img.seconds > 0 ? img.rays / img.seconds : 0.0},
            {"scattering", atmo::scattering_method_name(sky.method())}};
  if (sky.method() == atmo::ScatteringMethod::Orders) j["scattering_orders"] = sky.options().scattering.orders;
  const atmo::SkyIrradiance irr = atmo::sky_irradiance(sky, h, sun.direction());
  j["irradiance_direct_lux"] = irr.direct_lux;
  j["irradiance_diffuse_lux"] = irr.diffuse_lux;
  j["irradiance_direct_w_m2_nm"] = irr.direct;
  j["irradiance_diffuse_w_m2_nm"] = irr.diffuse;
  j["wavelengths_nm"] = model.atmosphere->wavelengths_nm();
  if (sun.spa) j["apparent_sun_elevation_deg"] = sun.spa->apparent_elevation_deg;
  if (!files.netcdf.empty()) j["netcdf"] = files.netcdf;
  return j;
}

json sun_position_json(const atmo::SunQuery& q, const atmo::SunPosition& s) {
  const glm::dvec3 d = atmo::enu_direction_from_zenith(s.zenith_deg, s.azimuth_deg);
  return {{"zenith_deg", s.zenith_deg},
          {"azimuth_deg", s.azimuth_deg},
          {"elevation_deg", s.elevation_deg},
          {"apparent_zenith_deg", s.apparent_zenith_deg},
          {"apparent_elevation_deg", s.apparent_elevation_deg},
          {"declination_deg", s.declination_deg},
          {"hour_angle_deg", s.hour_angle_deg},
          {"equation_of_time_min", s.equation_of_time_min},
          {"earth_sun_distance_au", s.earth_sun_distance_au},
          {"sunrise_utc", jd_or_null(s.sunrise_jd_utc)},
          {"transit_utc", jd_or_null(s.transit_jd_utc)},
          {"sunset_utc", jd_or_null(s.sunset_jd_utc)},
          {"polar", s.polar == atmo::Polar::None ? json(nullptr) : json(atmo::polar_name(s.polar))},
          {"time_utc", atmo::format_iso8601_utc(q.jd_utc, 3)},
          {"delta_t_s", s.delta_t_s},
          {"delta_ut1_s", q.delta_ut1_s},
          {"algorithm", atmo::sun_algorithm_name(q.algorithm)},
          {"sun_direction_enu", {d.x, d.y, d.z}}};
}

json optical_depth_json(const OpticalDepthAnswer& q, const std::string& method, double nm, const std::string& atmosphere) {
  return {{"rayleigh", q.rayleigh}, {"mie", q.mie}, {"ozone", q.ozone}, {"total", q.total},
          {"transmittance", atmo::transmittance(q.total)}, {"method", method},
          {"error_estimate", q.error_estimate}, {"time_s", q.time_s}, {"hits_ground", q.hits_ground},
          {"wavelength_nm", nm}, {"atmosphere", atmosphere}};
}

json phase_json(const atmo::PhaseFunction& p, const std::string& model, double mu) {
  return {{"value", p.value(mu)}, {"mean_cosine", p.mean_cosine()}, {"model", model}, {"cos_theta", mu}};
}

json stability_json(const std::vector<atmo::StiffCase>& cases) {
  json arr = json::array();
  bool all = true;
  for (const auto& k : cases) {
    all = all && k.pass;
    arr.push_back({{"case", k.name}, {"quantity", k.quantity}, {"value", k.value}, {"reference", k.reference},
                   {"error", k.error}, {"bound", k.bound}, {"pass", k.pass}});
  }
  return {{"cases", arr}, {"all_pass", all}};
}

json rt_slab_json(const RtSlabRequest& o, const atmo::SlabResult& r) {
  return {{"tau", o.tau}, {"omega", o.omega}, {"phase", o.phase}, {"g", o.g}, {"ground_albedo", o.ground_albedo},
          {"mu0", o.mu0}, {"mu", o.mu}, {"phi_deg", o.phi_deg}, {"reflection", r.reflection},
          {"reflection_stderr", r.reflection_stderr}, {"transmission", r.transmission},
          {"transmission_stderr", r.transmission_stderr}, {"paths", r.paths}, {"seed", o.run.seed},
          {"orders", o.orders}, {"threads", resolve_threads(o.run.threads)}, {"time_s", r.time_s}};
}

json rt_sky_json(const RtSkyRequest& o, const scene::Scene& s, const atmo::RtSkyResult& r) {
  return {{"scene", s.source}, {"sun_elevation_deg", o.view.sun_elevation_deg},
          {"sun_azimuth_deg", o.view.sun_azimuth_deg}, {"view_elevation_deg", o.view.view_elevation_deg},
          {"view_azimuth_deg", o.view.view_azimuth_deg}, {"observer_height_m", o.view.observer_height_m},
          {"ground_albedo", o.ground_albedo >= 0 ? o.ground_albedo : s.atmosphere.planet.ground_albedo},
          {"wavelengths_nm", r.wavelengths_nm}, {"radiance_w_m2_sr_nm", r.radiance},
          {"radiance_stderr_w_m2_sr_nm", r.radiance_stderr}, {"luminance_cd_m2", r.luminance},
          {"luminance_stderr_cd_m2", r.luminance_stderr}, {"xyz", {r.xyz.X, r.xyz.Y, r.xyz.Z}},
          {"xyz_stderr", {r.xyz_stderr.X, r.xyz_stderr.Y, r.xyz_stderr.Z}}, {"paths", r.paths},
          {"paths_per_wavelength", r.paths_per_wavelength}, {"mean_orders", r.mean_orders}, {"orders", o.orders},
          {"seed", o.run.seed}, {"threads", resolve_threads(o.run.threads)}, {"sun_depth", o.sun_depth},
          {"line_estimate", o.line_estimate}, {"guide", o.guide}, {"sun_depth_rel_error", r.sun_depth_rel_error}, {"time_s", r.time_s}};
}

json prt_bake_json(const prt::Transfer& t, const std::string& file, double dt) {
  double ao_min = 1, ao_mean = 0;
  for (double a : t.ao) ao_min = std::min(ao_min, a), ao_mean += a;
  ao_mean /= static_cast<double>(t.ao.size());
  return {{"file", file}, {"vertices", t.mesh.positions.size()}, {"triangles", t.mesh.triangles.size()},
          {"bands", t.bands}, {"coefficients", t.bands * t.bands}, {"samples", t.samples},
          {"mode", sh::prt::transfer_mode_name(t.mode)}, {"bounces", t.bounces}, {"rays", t.rays},
          {"ray_seconds", t.ray_seconds},
          {"rays_per_s", t.ray_seconds > 0 ? static_cast<double>(t.rays) / t.ray_seconds : 0.0},
          {"time_s", dt}, {"ao_min", ao_min}, {"ao_mean", ao_mean}, {"bounce_energy", t.bounce_energy}};
}

json prt_pixel_bake_json(const prt::PixelTransfer& px, sh::prt::TransferMode mode, const std::string& file, double dt) {
  return {{"file", file}, {"width", px.width}, {"height", px.height}, {"bands", px.bands},
          {"coefficients", px.bands * px.bands}, {"samples", px.samples},
          {"mode", sh::prt::transfer_mode_name(mode)}, {"device", px.device == prt::Device::gpu ? "gpu" : "cpu"},
          {"rays", px.rays}, {"ray_seconds", px.ray_seconds},
          {"rays_per_s", px.ray_seconds > 0 ? static_cast<double>(px.rays) / px.ray_seconds : 0.0},
          {"depth_map", px.depth_resolution}, {"seconds_per_direction", px.seconds_per_direction}, {"time_s", dt}};
}

json plan_json(const scene::Scene& s, const std::vector<scene::Pass>& passes) {
  json j;
  j["scene"] = s.source;
  j["passes"] = json::array();
  for (const auto& p : passes) j["passes"].push_back({{"pass", p.name}, {"needed", p.needed}, {"reason", p.reason}});
  const auto mem = scene_peak_memory(s, {});
  const auto work = scene_work(s, {});
  j["estimate"] = {{"peak_memory_bytes", mem.bytes}, {"cpu_seconds", work.cpu_seconds()},
                   {"workers", available_cpus()}, {"wall_seconds", work.wall_seconds(available_cpus())},
                   {"units", work.units}, {"unit", work.unit}, {"seconds_per_unit", work.seconds_per_unit}};
  return j;
}

std::string plan_text(const scene::Scene& s, const std::vector<scene::Pass>& passes) {
  std::string t = "plan for " + s.source + "\n";
  for (const auto& p : passes)
    t += (p.needed ? "  run   " : "  skip  ") + p.name + std::string(p.name.size() < 34 ? 34 - p.name.size() : 1, ' ') +
         p.reason + "\n";
  const auto mem = scene_peak_memory(s, {});
  const auto work = scene_work(s, {});
  return t + "  estimate: memory " +
         (mem.bytes > 0 ? format_bytes(static_cast<double>(mem.bytes)) + " at most (" + mem.what + ")" : "small") +
         ", computing " + (work.units > 0 ? describe_work(work, 0) : "small") + "\n";
}

std::string sun_position_text(const atmo::SunQuery& q, const atmo::SunPosition& s) {
  using atmo::format_iso8601_utc;
  const glm::dvec3 d = atmo::enu_direction_from_zenith(s.zenith_deg, s.azimuth_deg);
  std::ostringstream o;
  o.precision(8);
  o << "time (UTC)            " << format_iso8601_utc(q.jd_utc, 3) << "\n"
    << "algorithm             " << atmo::sun_algorithm_name(q.algorithm) << " (delta T " << s.delta_t_s
    << " s, UT1-UTC " << q.delta_ut1_s << " s)\n"
    << "zenith                " << s.zenith_deg << " deg (geometric; apparent " << s.apparent_zenith_deg << ")\n"
    << "elevation             " << s.elevation_deg << " deg (geometric; apparent " << s.apparent_elevation_deg
    << ")\n"
    << "azimuth               " << s.azimuth_deg << " deg (from north, eastward)\n"
    << "declination           " << s.declination_deg << " deg\n"
    << "hour angle            " << s.hour_angle_deg << " deg\n"
    << "equation of time      " << s.equation_of_time_min << " min\n"
    << "Earth-Sun distance    " << s.earth_sun_distance_au << " AU\n"
    << "sun direction (ENU)   " << d.x << ", " << d.y << ", " << d.z << "\n";
  auto line = [&](const char* name, const std::optional<double>& jd) {
    o << name << (jd ? format_iso8601_utc(*jd) : std::string("none")) << "\n";
  };
  line("sunrise               ", s.sunrise_jd_utc);
  line("transit               ", s.transit_jd_utc);
  line("sunset                ", s.sunset_jd_utc);
  if (s.polar != atmo::Polar::None) o << "polar                 " << atmo::polar_name(s.polar) << "\n";
  return o.str();
}

std::string optical_depth_text(const OpticalDepthAnswer& a, const std::string& method, double nm, double alt,
                               double zen, const std::string& atmosphere) {
  return printf_string("optical depth at %g nm, altitude %g m, zenith %g deg (%s, %s)%s\n", nm, alt, zen,
                       atmosphere.c_str(), method.c_str(), a.hits_ground ? ", ray hits the ground" : "") +
         printf_string("  rayleigh %.12g\n  mie      %.12g\n  ozone    %.12g\n  total    %.12g (+- %.3g)\n"
                       "  transmittance %.12g\n  time %.3g s\n",
                       a.rayleigh, a.mie, a.ozone, a.total, a.error_estimate, atmo::transmittance(a.total), a.time_s);
}

std::string stability_text(const std::vector<atmo::StiffCase>& cases) {
  std::string out = printf_string("%-44s %22s %22s %10s %8s  %s\n", "case", "value", "reference", "error", "bound", "result");
  bool all = true;
  for (const auto& k : cases) {
    all = all && k.pass;
    out += printf_string("%-44s %22.15g %22.15g %10.2e %8.1e  %s\n", k.name.c_str(), k.value, k.reference, k.error,
                         k.bound, k.pass ? "PASS" : "FAIL");
  }
  return out + (all ? "all cases pass\n" : "SOME CASES FAIL\n");
}

std::string rt_slab_text(const atmo::SlabResult& r) {
  return printf_string("reflection   R = %.10g +- %.3g\ntransmission T = %.10g +- %.3g\n(%lld paths each, %.3f s)\n",
                       r.reflection, r.reflection_stderr, r.transmission, r.transmission_stderr,
                       static_cast<long long>(r.paths), r.time_s);
}

std::string rt_sky_text(const atmo::RtSkyResult& r) {
  std::string out = printf_string("luminance %.8g +- %.3g cd/m^2 (%lld paths, %.3f s)\n", r.luminance,
                                  r.luminance_stderr, static_cast<long long>(r.paths), r.time_s);
  for (std::size_t i = 0; i < r.radiance.size(); ++i)
    out += printf_string("  %7.2f nm  %.8g +- %.3g W m^-2 sr^-1 nm^-1\n", r.wavelengths_nm[i], r.radiance[i],
                         r.radiance_stderr[i]);
  return out;
}

std::string prt_bake_text(const json& j) {
  std::ostringstream o;
  o << "wrote " << j["file"].get<std::string>() << " (";
  if (j.contains("width"))  // per pixel
    o << j["width"].get<int>() << "x" << j["height"].get<int>() << " pixels, " << j["coefficients"].get<int>()
      << " coefficients)\n";
  else
    o << j["vertices"].get<std::size_t>() << " vertices, " << j["coefficients"].get<int>() << " coefficients, "
      << j["rays"].get<std::uint64_t>() << " rays in " << j["ray_seconds"].get<double>() << " s)\n";
  return o.str();
}

}  // namespace atmosh::studies
