// A sky from a scene (see atmosh/studies/sky.hpp).
#include "atmosh/studies/sky.hpp"

#include "atmosh/device.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/check.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/scene/outputs.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/orders.hpp"
#include "atmosh/gpu/sky.hpp"
#endif

namespace atmosh::studies {

void write_sky_netcdf_image(const atmo::SkyImage& img, const std::filesystem::path& file, const io::Provenance& prov,
                            const std::string& projection, const SunPlacement& sun) {
  if (projection != "equirect")
    throw InputError("projection '" + projection + "': netCDF sky images are equirect (elevation x azimuth)");
  io::NetcdfSkyImage nc;
  nc.width = img.width;
  nc.height = img.height;
  nc.wavelengths_nm = img.wavelengths_nm;
  nc.spectral = img.spectral;
  nc.X = img.X;
  nc.Y = img.Y;
  nc.Z = img.Z;
  nc.sun_zenith_deg = 90.0 - sun.elevation_deg;
  nc.sun_azimuth_deg = sun.azimuth_deg;
  io::write_sky_netcdf(file, nc, prov);
}

SkySettings SkySettings::checked() const {
  SkySettings q = *this;
  if (shells < 4 || shells > 4096) throw InputError("--shells " + std::to_string(shells) + " is outside [4, 4096]");
  const int max_segments = std::min(shells - 1, atmo::shared::kMaxCutSpheres);
  if (segments < 1 || segments > max_segments)
    throw InputError("--segments " + std::to_string(segments) + " is outside [1, " + std::to_string(max_segments) +
                     "] (at most --shells - 1 and " + std::to_string(atmo::shared::kMaxCutSpheres) + ")");
  if (samples < 1 || samples > 8) throw InputError("--samples " + std::to_string(samples) + " is outside [1, 8]");
  if (!std::isfinite(max_piece_tau) || !(max_piece_tau > 0))
    throw InputError("--max-piece-tau " + io::format_double(max_piece_tau) + " must be finite and > 0");
  q.threads = resolve_threads(threads, "--threads");
  check_device_name(device);
  if (orders && (*orders < 1 || *orders > 64))
    throw InputError("--orders " + std::to_string(*orders) + " is outside [1, 64]");
  return q;
}

scene::SweepSettings SkySettings::sweep_settings() const {
  return {{"lut_shells", std::to_string(shells)},
          {"view_segments", std::to_string(segments)},
          {"samples_per_segment", std::to_string(samples)},
          {"max_piece_optical_depth", io::format_double(max_piece_tau)},
          {"sun_model", sun_model ? atmo::sun_model_name(*sun_model) : "scene"},
          {"scattering", scattering ? atmo::scattering_method_name(*scattering) : "scene"},
          {"orders", orders ? std::to_string(*orders) : "scene"}};
}

SunPlacement place_sun(const scene::Scene& s, const SunRequest& r) {
  const bool place = r.lat_deg || r.lon_deg || !r.time_utc.empty();
  if (place && r.elevation_deg) throw InputError("give either --lat/--lon/--time or --sun-elevation, not both");
  if (place) {
    if (!r.lat_deg || !r.lon_deg || r.time_utc.empty()) throw InputError("--lat, --lon and --time go together");
    return sun_from_place(require_range(*r.lat_deg, -90, 90, "--lat"), require_range(*r.lon_deg, -180, 180, "--lon"),
                          require_range(r.height_m, -500, 1e8, "--height"), r.time_utc);
  }
  if (!r.elevation_deg) return sun_of_scene(s);
  SunPlacement p;
  p.elevation_deg = require_range(*r.elevation_deg, -90, 90, "--sun-elevation");
  p.azimuth_deg = require_range(r.azimuth_deg, -360, 360, "--sun-azimuth");
  p.observer_height_m = require_range(r.height_m, -500, 1e8, "--height");
  return p;
}

scene::Scene SkySettings::scene_for(scene::Scene s) const {
  if (scattering) s.scattering.method = *scattering;
  if (orders) s.scattering.orders = *orders;
  return s;
}

atmo::SkyOptions SkySettings::sky(const scene::Scene& s) const {
  atmo::SkyOptions o;
  o.lut.shells = shells;
  o.segments = segments;
  o.samples_per_segment = samples;
  o.max_piece_optical_depth = max_piece_tau;
  o.sun_model = sun_model ? *sun_model : atmo::parse_sun_model(s.sun_model);
  return o;
}

void check_device_name(const std::string& device) {
  if (device != "cpu" && device != "gpu" && device != "auto")
    throw InputError("--device " + device + ": must be cpu, gpu or auto");
}

atmo::SkyImage render_sky_on(const std::string& device, const atmo::SkyIntegrator& sky, atmo::SkyProjection proj,
                             int width, int height, double altitude_m, const glm::dvec3& sun, bool spectral, int threads,
                             std::string& used, const Notice& notice) {
  using namespace atmosh::atmo;
  const DeviceRequest request = parse_device_request(device);
  auto tell = [&](const DeviceDecision& d) {
    if (notice && !d.notice.empty()) notice(d.notice);
  };
  // gpu: the GPU pass or an error; auto: the GPU pass, else the CPU with a one-line
  // notice (atmosh::resolve_device, the toolkit's one device policy).
  used = "cpu";
  if (request != DeviceRequest::cpu) {
    std::optional<GpuUnusable> unusable;
#ifdef ATMOSH_HAVE_GPU
    try {
      // An orders table kept on the GPU is bound where it is: the image in its context.
      const atmo::ScatteringOrders* orders = sky.orders_tables();
      const auto* kept = orders ? dynamic_cast<const gpu::OrdersResidentTable*>(orders->device_table()) : nullptr;
      std::optional<gpu::Context> own;
      const gpu::Context& ctx = kept ? kept->context() : own.emplace();
      // auto with orders on a software renderer: the CPU image (Mesa llvmpipe renders
      // the image with orders ~18x slower than the CPU; docs/gpu.md, "The sky
      // image with orders on the GPU"); single and approximate keep the GPU pass.
      if (request == DeviceRequest::automatic && sky.method() == ScatteringMethod::Orders && ctx.info().software) {
        if (notice)
          notice("sky image with orders: rendered on the CPU (the software renderer " + ctx.info().renderer +
                 " renders it ~18x slower than the CPU)");
      } else {
        SkyImage img = gpu::render_sky(ctx, sky, proj, width, height, altitude_m, sun, spectral);
        used = "gpu";
        add_sun_disc(img, sky, proj, altitude_m, sun);  // the visible disc (CPU; a few pixels)
        return img;
      }
    } catch (const gpu::Unavailable& e) {
      unusable = GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}};
    } catch (const gpu::Unsupported& e) {
      unusable = GpuUnusable{GpuUnusable::Why::unsupported, e.what(), {}};
    }
#else
    unusable = GpuUnusable{GpuUnusable::Why::not_built, {}, {}};
#endif
    if (unusable) tell(resolve_device(request, unusable, "rendering on the CPU"));
  }
  // On the CPU every pixel looks up the orders table: a table kept on the GPU is read back
  // in full first.
  if (sky.orders_tables() && sky.orders_tables()->read_back_all() > 0 && notice)
    notice("orders tables: read back in full for the CPU's image");
  SkyImage img = render_sky(sky, proj, width, height, altitude_m, sun, spectral, threads);
  add_sun_disc(img, sky, proj, altitude_m, sun);  // the visible disc (SkyOptions::sun_model)
  return img;
}

std::string use_orders_tables_device(scene::Scene& s, const std::string& device, const Notice& notice,
                                     bool keep_on_gpu) {
  const DeviceRequest request = parse_device_request(device);
  if (request == DeviceRequest::cpu || s.scattering.method != atmo::ScatteringMethod::Orders || s.scattering.orders < 2)
    return "cpu";
  // gpu: the tables and the image on the GPU, whatever its renderer, or an error before
  // any table is built; auto: on a hardware GPU the same, else the CPU with a notice.
  constexpr const char* kFallback = "building the orders tables on the CPU";
  auto tell = [&](const std::string& why) {
    if (notice) notice("orders tables: built on the CPU (" + why + ")");
  };
#ifdef ATMOSH_HAVE_GPU
  if (atmo::spectrum_wavelengths(s.atmosphere.spectrum).size() > ATMOSH_ORDERS_MAX_WAVELENGTHS) {
    const std::string why = "more than " + std::to_string(ATMOSH_ORDERS_MAX_WAVELENGTHS) + " wavelengths";
    resolve_device(request, GpuUnusable{GpuUnusable::Why::unsupported, "orders tables with " + why, "use --device cpu"},
                   kFallback);  // gpu: throws
    tell(why);
    return "cpu";
  }
  try {
    auto ctx = std::make_shared<const gpu::Context>();
    if (request == DeviceRequest::automatic && ctx->info().software) {
      tell("the GPU is the software renderer " + ctx->info().renderer + ", which builds them ~11x slower");
      return "cpu";
    }
    s.scattering.orders_passes = gpu::make_orders_passes(
        std::move(ctx), nullptr, keep_on_gpu ? gpu::OrdersTables::Resident : gpu::OrdersTables::ReadBack);
    if (notice)
      notice(keep_on_gpu ? "orders tables: built on the GPU and kept there (nothing read back but what the CPU's "
                           "lookups at the observer need)"
                         : "orders tables: built on the GPU, read back for the CPU's lookups");
    return "gpu";
  } catch (const gpu::Unavailable& e) {
    resolve_device(request, GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}}, kFallback);  // gpu: throws
    tell(std::string("no GPU: ") + e.what());
  }
#else
  resolve_device(request, GpuUnusable{GpuUnusable::Why::not_built, {}, {}}, kFallback);  // gpu: throws
  tell("atmosh was built without ATMOSH_WITH_GPU");
#endif
  return "cpu";
}

OrdersReadBack read_back_orders_at(const SkyModel& m, double altitude_m, const glm::dvec3& sun) {
  OrdersReadBack r;
  const atmo::ScatteringOrders* o = m.sky->orders_tables();
  if (!o || !o->device_table()) return r;
  const auto t0 = std::chrono::steady_clock::now();
  const double n = glm::length(sun);
  const double mu_s = n > 0 && std::isfinite(n) ? sun.z / n : 0.0;  // make_ray checks the sun itself
  r.bytes = o->read_back_at(m.atmosphere->ground_radius() + std::max(altitude_m, 0.0), mu_s);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::string orders_tables_read_back(const SkyModel& m) {
  const atmo::ScatteringOrders* o = m.sky ? m.sky->orders_tables() : nullptr;
  if (!o) return "";
  const std::size_t all = o->texels() * o->wavelengths() * sizeof(float), here = o->bytes_on_cpu();
  if (!o->device_table() || here == all) return "all";
  if (here == 0) return "none (kept on the GPU)";
  return "part: " + std::to_string(here) + " of " + std::to_string(all) +
         " bytes (the lookups at the observer; the rest kept on the GPU)";
}

glm::dvec3 SunPlacement::direction() const { return atmo::enu_direction_from_zenith(90.0 - elevation_deg, azimuth_deg); }

std::string SunPlacement::describe() const {
  std::string s = "elevation " + io::format_double(elevation_deg) + " deg, azimuth " + io::format_double(azimuth_deg) + " deg";
  if (spa) s += " (NREL SPA; apparent elevation " + io::format_double(spa->apparent_elevation_deg) + " deg)";
  return s;
}

SunPlacement sun_from_place(double lat, double lon, double height_m, const std::string& time_utc) {
  atmo::SunQuery q;
  q.jd_utc = atmo::parse_iso8601(time_utc).jd_utc;
  q.latitude_deg = lat;
  q.longitude_deg = lon;
  q.height_m = height_m;
  q.rise_transit_set = false;
  SunPlacement p;
  p.spa = atmo::sun_position(q);
  p.elevation_deg = p.spa->elevation_deg;
  p.azimuth_deg = p.spa->azimuth_deg;
  p.distance_au = p.spa->earth_sun_distance_au;
  p.observer_height_m = height_m;
  return p;
}

SunPlacement sun_of_scene(const scene::Scene& s) {
  if (s.observer)
    return sun_from_place(s.observer->latitude_deg, s.observer->longitude_deg, s.observer->height_m,
                          s.observer->time_utc);
  if (s.sun) {
    SunPlacement p;
    p.elevation_deg = s.sun->elevation_deg;
    p.azimuth_deg = s.sun->azimuth_deg;
    return p;
  }
  throw InputError(s.source + ": the scene places no sun (give [observer] with time_utc, or [sun])");
}

std::unique_ptr<SkyModel> make_sky_model(const scene::Scene& s, const atmo::SkyOptions& options, double sun_distance_au) {
  auto m = std::make_unique<SkyModel>();
  m->scene = s;
  const auto t0 = std::chrono::steady_clock::now();
  m->atmosphere = std::make_unique<atmo::Atmosphere>(s.atmosphere);
  atmo::SkyOptions o = options;
  o.sun_distance_au = sun_distance_au;
  o.scattering = s.scattering;  // the scene's [scattering]
  m->sky = std::make_unique<atmo::SkyIntegrator>(*m->atmosphere, atmo::solar_spectrum_for_bins(s.atmosphere.spectrum), o);
  m->build_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return m;
}

std::unique_ptr<SkyModel> make_sky_model(const scene::Scene& s, const SkySettings& k, double sun_distance_au) {
  scene::Scene sc = k.scene_for(s);
  const std::string where = use_orders_tables_device(sc, k.device, k.notice);
  auto m = make_sky_model(sc, k.sky(s), sun_distance_au);
  m->orders_tables_device = where;
  return m;
}

io::Provenance sky_provenance(const SkyModel& m, const SunPlacement& sun) {
  io::Provenance p = io::Provenance::current();
  p.add("scene", m.scene.source);
  p.add("atmosphere", m.scene.atmosphere.name);
  const auto& a = m.scene.atmosphere;
  p.add("constituents", std::string(a.rayleigh ? "rayleigh " : "") + (a.mie ? "mie " : "") + (a.ozone ? "ozone" : ""));
  p.add("wavelengths", static_cast<double>(m.atmosphere->wavelengths_nm().size()));
  if (m.scene.scattering.method == atmo::ScatteringMethod::Orders) {
    p.add("orders_tables_device", m.orders_tables_device);
    if (const std::string rb = orders_tables_read_back(m); !rb.empty()) p.add("orders_tables_read_back", rb);
  }
  // NaN marks what a study varies: it is a column of the file, not one value.
  auto add_or_varied = [&p](const std::string& key, double v) {
    if (std::isnan(v))
      p.add(key, "varied by the study (column " + key + ")");
    else
      p.add(key, v);
  };
  add_or_varied("sun_elevation_deg", sun.elevation_deg);
  add_or_varied("sun_azimuth_deg", sun.azimuth_deg);
  if (std::isnan(sun.distance_au))
    p.add("earth_sun_distance_au", "varied with the time (radiances scaled by 1/d^2 per row)");
  else
    p.add("earth_sun_distance_au", sun.distance_au);
  p.add("observer_height_m", sun.observer_height_m);
  const auto& o = m.sky->options();
  p.add("lut_shells", static_cast<double>(o.lut.shells));
  p.add("view_segments", static_cast<double>(o.segments));
  p.add("samples_per_segment", static_cast<double>(o.samples_per_segment));
  p.add("max_piece_optical_depth", o.max_piece_optical_depth);
  if (o.sun_model == atmo::SunModel::Disc)
    p.add("sun_model", "disc: radius from the Earth-Sun distance (R_sun 695700 km), limb darkening mu^alpha "
                       "(Hestroffer & Magnan 1998); direct beam averaged over the visible disc");
  else
    p.add("sun_model", "point (direct beam along the disc centre; no disc in images)");
  p.add("scattering", std::string(atmo::scattering_method_name(o.scattering.method)) +
                          (o.scattering.method == atmo::ScatteringMethod::Orders
                               ? " (orders 1.." + std::to_string(o.scattering.orders) + ")"
                           : o.scattering.method == atmo::ScatteringMethod::Approximate
                               ? " (Hillaire 2020 all-orders table " + std::to_string(o.scattering.ms_altitudes) + "x" +
                                     std::to_string(o.scattering.ms_sun_directions) + ")"
                               : ""));
  p.add("solar_spectrum", "ASTM G173-03 extraterrestrial, averaged over each wavelength bin");
  p.add("colour", "CIE 1931 2-degree CMF, 683 lm/W, linear sRGB (D65)");
  return p;
}

double write_sky_image(const atmo::SkyImage& img, const std::filesystem::path& exr, const std::filesystem::path& png,
                       const io::Provenance& prov, const std::string& projection, const SunPlacement& sun) {
  std::vector<std::string> ch = {"R", "G", "B", "X", "Y", "Z"};
  const std::size_t nw = img.wavelengths_nm.size();
  const bool spectral = !img.spectral.empty();
  if (spectral)
    for (double w : img.wavelengths_nm) {
      std::ostringstream os;
      os << "L_" << std::lround(w * 10) / 10.0 << "nm";
      ch.push_back(os.str());
    }
  io::ExrImage e(img.width, img.height, ch);
  e.channel("R").assign(img.R.begin(), img.R.end());
  e.channel("G").assign(img.G.begin(), img.G.end());
  e.channel("B").assign(img.B.begin(), img.B.end());
  e.channel("X").assign(img.X.begin(), img.X.end());
  e.channel("Y").assign(img.Y.begin(), img.Y.end());
  e.channel("Z").assign(img.Z.begin(), img.Z.end());
  if (spectral)
    for (std::size_t i = 0; i < nw; ++i) {
      auto& c = e.data[6 + i];
      for (std::size_t p = 0; p < c.size(); ++p) c[p] = img.spectral[p * nw + i];
    }
  e.string_attributes["units"] =
      "R,G,B: linear sRGB (D65) scaled so that Y is luminance in cd/m^2; X,Y,Z: CIE 1931 2-degree, Y in cd/m^2; "
      "L_<nm>nm: spectral radiance in W m^-2 sr^-1 nm^-1";
  e.string_attributes["value_units"] = "cd/m^2";  // of R,G,B,X,Y,Z (what `sh project` carries on)
  e.string_attributes["projection"] = projection == "fisheye"
                                          ? "fisheye: azimuthal equidistant, zenith at centre, north up, east left"
                                          : "equirect: azimuth 0..360 deg from north towards east left to right, "
                                            "elevation +90..-90 deg top to bottom";
  e.string_attributes["sun"] = sun.describe();
  e.float_attributes["sun_elevation_deg"] = static_cast<float>(sun.elevation_deg);
  e.float_attributes["sun_azimuth_deg"] = static_cast<float>(sun.azimuth_deg);
  io::write_exr(exr, e, prov);
  double exposure = 1.0;
  if (!png.empty()) {
    std::vector<float> ys;
    for (std::size_t p = 0; p < img.Y.size(); ++p)
      if (img.valid[p] && img.Y[p] > 0) ys.push_back(img.Y[p]);
    if (!ys.empty()) {
      const std::size_t k = static_cast<std::size_t>(0.95 * (ys.size() - 1));
      std::nth_element(ys.begin(), ys.begin() + static_cast<std::ptrdiff_t>(k), ys.end());
      exposure = ys[k] > 0 ? 2.0 / ys[k] : 1.0;
    }
    io::write_tonemapped_png(png, img.width, img.height, img.R, img.G, img.B, exposure, "reinhard");
    io::write_tone_map_side_file(png, "reinhard v/(1+v) on linear sRGB, then the sRGB transfer curve", exposure,
                                 "2 / (95th percentile of luminance Y in cd/m^2)", exr.filename().string());
  }
  return exposure;
}

std::size_t sky_output_bytes(int width, int height, std::size_t nw, bool spectral) {
  const std::size_t n = mul_bytes(static_cast<std::size_t>(std::max(width, 0)), static_cast<std::size_t>(std::max(height, 0)));
  std::size_t b = atmo::sky_image_bytes(width, height, nw, spectral);
  for (std::size_t x : {io::exr_image_bytes(width, height, 6 + (spectral ? nw : 0)), io::tonemapped_png_bytes(width, height),
                        mul_bytes(n, sizeof(float))})
    b = b > SIZE_MAX - x ? SIZE_MAX : b + x;
  return b;
}

std::size_t scene_output_bytes(const scene::Scene& s, const scene::Output& out, std::array<int, 2> size) {
  const scene::OutputKind* k = scene::find_output_kind(out.kind);
  if (k == nullptr) return 0;
  if (k->image)  // an image of the sky (sky-image)
    return sky_output_bytes(size[0], size[1], atmo::spectrum_wavelengths(s.atmosphere.spectrum).size(), out.spectral);
  if (k->bands) {  // project_sky_sh: a Gauss grid of nlat x 2 nlat, three channels of doubles
    const std::size_t bands = static_cast<std::size_t>(out.bands > 0 ? out.bands : k->default_bands);
    const std::size_t nlat = std::max<std::size_t>(4 * bands, 64);
    return mul_bytes(mul_bytes(nlat, 2 * nlat), 4 * sizeof(double));
  }
  return 0;
}

WorkEstimate sky_rays_work(const scene::Scene& s, const SkySettings& k, double rays) {
  atmo::SkyOptions o = k.sky(s);
  o.scattering = k.scene_for(s).scattering;  // as make_sky_model
  return atmo::sky_rays_work(rays, atmo::spectrum_wavelengths(s.atmosphere.spectrum).size(), o);
}

WorkEstimate scene_output_work(const scene::Scene& s, const scene::Output& out, std::array<int, 2> size, bool quick) {
  const scene::OutputKind* k = scene::find_output_kind(out.kind);
  if (k == nullptr) return {};
  if (k->image) return sky_rays_work(s, SkySettings{}, mul_units(std::max(size[0], 0), std::max(size[1], 0)));
  if (k->bands) {
    const double bands = out.bands > 0 ? out.bands : k->default_bands;
    const double nlat = std::max(4 * bands, 64.0);
    return sky_rays_work(s, SkySettings{}, mul_units(nlat, 2 * nlat));
  }
  if (out.kind == "sun-elevation-study")  // -18..90 deg by 1 (quick: by 12)
    return sky_rays_work(s, SkySettings{}, mul_units(quick ? 10 : 109, kSummaryRays));
  return {};
}

std::array<double, 3> display_colour(const atmo::Rgb& c) {
  const double m = std::max({c.r, c.g, c.b});
  if (!(m > 0)) return {0, 0, 0};
  return {atmo::srgb_encode(std::max(c.r, 0.0) / m), atmo::srgb_encode(std::max(c.g, 0.0) / m),
          atmo::srgb_encode(std::max(c.b, 0.0) / m)};
}

}  // namespace atmosh::studies
