// atmosh/studies/sky.hpp — a sky from a scene: the sun it places, the atmosphere and
// integrator it builds, the provenance of what it computes, sky images on a device and
// their files, and the memory those take.
//
// Units: degrees for angles, metres for heights, astronomical units for the Earth-Sun
// distance, bytes for memory estimates. Nothing here prints; failures are
// atmosh::InputError (bad input) or std::runtime_error (a device that cannot run).
#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "atmosh/memory.hpp"
#include "atmosh/work.hpp"
#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/multiple_scattering.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/scene/sweep.hpp"

namespace atmosh::studies {

// Where the sun is: from a place and a time (NREL SPA) or given directly.
struct SunPlacement {
  double elevation_deg = 0;  // geometric (drives the sky); NaN: varied by a study
  double azimuth_deg = 180;  // from north towards east; NaN: varied by a study
  std::optional<atmo::SunPosition> spa;  // when computed from place and time
  double observer_height_m = 0;
  double distance_au = 1.0;  // NaN: varied with the time (a day study)
  glm::dvec3 direction() const;  // unit vector towards the sun, ENU
  std::string describe() const;
};

// The sun of a scene: [observer] (SPA) or [sun]; InputError if it has neither.
SunPlacement sun_of_scene(const scene::Scene& s);
// SPA at a place and time (ISO 8601 UTC; geometric elevation; apparent reported in spa).
SunPlacement sun_from_place(double lat_deg, double lon_deg, double height_m, const std::string& time_utc);

// The sun a user asks for: a place and a time (lat, lon, time together: SPA), or an
// elevation and azimuth; neither: the scene's sun (sun_of_scene). InputError naming the
// option (--lat, --lon, --time, --height, --sun-elevation, --sun-azimuth) for a value out
// of range or a mix of the two ways.
struct SunRequest {
  std::optional<double> lat_deg, lon_deg, elevation_deg;
  double height_m = 0.0, azimuth_deg = 180.0;
  std::string time_utc;
};
SunPlacement place_sun(const scene::Scene& s, const SunRequest& r);

// One-line notices of a fallback (the CLI prints them on stderr after "atmosh: ").
using Notice = std::function<void(const std::string&)>;

// The settings of the sky integrator that change results (the CLI's quality options,
// parsed). Unset optionals take the scene's value.
struct SkySettings {
  int shells = 32, segments = 16, samples = 2;
  double max_piece_tau = atmo::SkyOptions{}.max_piece_optical_depth;
  std::optional<atmo::SunModel> sun_model;               // else the scene's sun_model
  std::optional<atmo::ScatteringMethod> scattering;      // else the scene's [scattering] method
  std::optional<int> orders;                             // else the scene's orders
  int threads = 0;                                       // worker threads (0 = every CPU this process may use)
  // Where the orders tables are built (use_orders_tables_device: cpu | gpu | auto) and
  // its notices; results the same within the GPU tables' float tolerance (not part of
  // sweep_settings).
  std::string device = "cpu";
  Notice notice;
  // Checked, the messages naming the options as typed (--shells 4..4096, --segments
  // 1..min(shells - 1, the cut spheres), --samples 1..8, --max-piece-tau > 0, --orders
  // 1..64, --threads 0..1024): InputError otherwise. The copy returned has its thread
  // count resolved by atmosh::resolve_threads (0 = the CPUs this process may use).
  SkySettings checked() const;
  // The settings that change results, as recorded in CSVs and hashed into a sweep's
  // identity ("scene" for an override not given).
  scene::SweepSettings sweep_settings() const;
  // The scene with the scattering overrides applied.
  scene::Scene scene_for(scene::Scene s) const;
  // The integrator's options for a scene (its sun model unless overridden).
  atmo::SkyOptions sky(const scene::Scene& s) const;
};

// An atmosphere and its sky integrator for a scene (the scene's [scattering] method).
struct SkyModel {
  scene::Scene scene;
  std::unique_ptr<atmo::Atmosphere> atmosphere;  // outlives `sky`, which refers to it
  std::unique_ptr<atmo::SkyIntegrator> sky;
  double build_time_s = 0;  // wall clock of the table build
  std::string orders_tables_device = "cpu";  // where the orders tables were built (use_orders_tables_device)
};
std::unique_ptr<SkyModel> make_sky_model(const scene::Scene& s, const atmo::SkyOptions& options, double sun_distance_au);
// The sky of scene s with settings k (k.scene_for(s), k.sky(s)), its orders tables built
// where use_orders_tables_device(k.device) says: the studies' and sweeps' skies.
std::unique_ptr<SkyModel> make_sky_model(const scene::Scene& s, const SkySettings& k, double sun_distance_au);

// Provenance of a sky: scene parameters and the sun (NaN fields are recorded as varied).
io::Provenance sky_provenance(const SkyModel& m, const SunPlacement& sun);


// "cpu", "gpu" or "auto"; InputError "--device <name>: must be cpu, gpu or auto" otherwise.
void check_device_name(const std::string& device);

// The sky image on a device: "cpu"; "gpu" (the GPU pass, or std::runtime_error when
// there is no EGL device or the input is unsupported there); "auto" (the GPU pass,
// else the CPU after a one-line notice; with ScatteringMethod::Orders on a software
// renderer the CPU, with a notice: use_orders_tables_device). `used` receives "cpu" or
// "gpu".
// threads: CPU worker threads (0 = all cores).
atmo::SkyImage render_sky_on(const std::string& device, const atmo::SkyIntegrator& sky, atmo::SkyProjection projection,
                             int width, int height, double altitude_m, const glm::dvec3& sun, bool spectral, int threads,
                             std::string& used, const Notice& notice = {});

// Where a sky image on `device` builds the orders tables of scene `s` (the orders method,
// orders >= 2; "cpu" for anything else), the one policy for `atmosh sky` and the scene
// runner's sky images (`atmosh run`): "gpu" sets s.scattering.orders_passes to the GPU's
// passes (gpu/orders.hpp) and returns "gpu" whatever the renderer, or throws
// std::runtime_error as render_sky_on's (no EGL device, more wavelengths than the GPU
// passes hold) before any table is built; "auto" does the same on a hardware GPU and
// otherwise returns "cpu" with a one-line notice why (no EGL device, too many
// wavelengths, or a software renderer: Mesa llvmpipe builds the tables ~11x slower than
// the CPU, docs/gpu.md). The image follows render_sky_on: on the GPU for "gpu" and for
// "auto" on a hardware GPU (the sky pass adds the orders term, the tables uploaded); on
// a software renderer "auto" renders the image with orders on the CPU (llvmpipe is
// slower there too: docs/gpu.md, "The sky image with orders on the GPU").
// keep_on_gpu: the outputs render the image on the GPU and need CPU lookups at most at
// one observer (`atmosh sky`, the scene runner's images): the tables are kept on the
// GPU (gpu::OrdersTables::Resident, nothing read back by the build; the sky pass binds
// them where they are) and read_back_orders_at reads back the part an output's CPU
// lookups need. Otherwise (the studies and sweeps: CPU lookups at every sun) the build
// reads the whole table back (gpu::OrdersTables::ReadBack). The notice says which.
std::string use_orders_tables_device(scene::Scene& s, const std::string& device, const Notice& notice = {},
                                     bool keep_on_gpu = false);

// For a sky whose orders tables are kept on the GPU: reads back the part that the CPU
// lookups of one observer (altitude [m], sun direction) need — summarize_sky,
// sky_irradiance, sky_colour and project_sky_sh at that observer — and nothing else
// (ScatteringOrders::read_back_at). No-op (0 bytes) for tables already on the CPU.
struct OrdersReadBack {
  std::size_t bytes = 0;  // read back now
  double seconds = 0;
};
OrdersReadBack read_back_orders_at(const SkyModel& m, double altitude_m, const glm::dvec3& sun);
// What of the orders tables is on the CPU, for the provenance (`orders_tables_read_back`)
// and notices: "all" (built on the CPU, or read back by the build), "none (kept on the
// GPU)", or "part: B of T bytes (...)"; "" without orders tables.
std::string orders_tables_read_back(const SkyModel& m);

// Writes the EXR (R,G,B,X,Y,Z [+ L_<nm>nm]) and, if png is non-empty, a tone-mapped
// PNG with its operator and exposure in <png>.json. Returns the exposure used.
double write_sky_image(const atmo::SkyImage& img, const std::filesystem::path& exr, const std::filesystem::path& png,
                       const io::Provenance& prov, const std::string& projection, const SunPlacement& sun);

// The sky image as netCDF-CF (io::write_sky_netcdf, atmosh/io/netcdf.hpp): X, Y, Z and,
// where the image keeps it, the spectral radiance cube on elevation x azimuth axes, and
// the sun's zenith and azimuth angles. InputError for a projection other than equirect
// (a fisheye's pixels lie on no elevation x azimuth grid).
void write_sky_netcdf_image(const atmo::SkyImage& img, const std::filesystem::path& file, const io::Provenance& prov,
                            const std::string& projection, const SunPlacement& sun);

// Saturating products for memory estimates: atmosh::mul_bytes (atmosh/memory.hpp).
using atmosh::mul_bytes;
// Memory (bytes) of one sky image of width x height with nw wavelengths, from the
// render to the EXR and PNG written (atmo::sky_image_bytes + io::exr_image_bytes +
// io::tonemapped_png_bytes + the exposure's luminance list).
std::size_t sky_output_bytes(int width, int height, std::size_t nw, bool spectral);
// Memory of one scene output at its image size (sky-image, sh-coefficients; 0 for the
// kinds whose sizes are fixed).
std::size_t scene_output_bytes(const scene::Scene& s, const scene::Output& out, std::array<int, 2> size);
// Work (atmosh/work.hpp) of `rays` view rays through scene s's sky with settings k, as
// make_sky_model builds it (the scene's spectrum and [scattering]): atmo::sky_rays_work.
WorkEstimate sky_rays_work(const scene::Scene& s, const SkySettings& k, double rays);
// One sky summary (atmo::summarize_sky: three view rays on the single-ray path) in rays
// of an image row: kSummaryRays (docs/hostile-input.md, "Work estimates").
inline constexpr double kSummaryRays = 3 * 4.0;
// Work of one scene output at its image size (sky-image: its pixels; sh-coefficients:
// the nlat x 2 nlat grid of project_sky_sh; sun-elevation-study: its rows' summaries;
// 0 for the kinds whose work is small and fixed).
WorkEstimate scene_output_work(const scene::Scene& s, const scene::Output& out, std::array<int, 2> size, bool quick);

// Display colour: linear sRGB scaled so its largest component is 1, then encoded.
std::array<double, 3> display_colour(const atmo::Rgb& c);

}  // namespace atmosh::studies
