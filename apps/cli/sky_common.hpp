// sky_common.hpp — building a sky from a scene and writing sky images (apps/ only).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "atmosh/atmo/sky.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::cli {

// Where the sun is: from a place and a time (NREL SPA) or given directly.
struct SunPlacement {
  double elevation_deg = 0;  // geometric (drives the sky)
  double azimuth_deg = 180;
  std::optional<atmo::SunPosition> spa;  // when computed from place and time
  double observer_height_m = 0;
  double distance_au = 1.0;
  glm::dvec3 direction() const;
  std::string describe() const;
};

// The sun of a scene: [observer] (SPA) or [sun]; InputError if it has neither.
SunPlacement sun_of_scene(const scene::Scene& s);
// SPA at a place and time (geometric elevation; apparent reported separately).
SunPlacement sun_from_place(double lat, double lon, double height_m, const std::string& time_utc);

// An atmosphere and its sky integrator for a scene (the scene's [scattering] method).
struct SkyModel {
  scene::Scene scene;
  std::unique_ptr<atmo::Atmosphere> atmosphere;
  std::unique_ptr<atmo::SkyIntegrator> sky;
  double build_time_s = 0;
};
std::unique_ptr<SkyModel> make_sky_model(const scene::Scene& s, const atmo::SkyOptions& options, double sun_distance_au);

// Provenance of a sky: scene parameters and the sun.
io::Provenance sky_provenance(const SkyModel& m, const SunPlacement& sun);

// Writes the EXR (R,G,B,X,Y,Z [+ L_<nm>nm]) and, if png is non-empty, a tone-mapped
// PNG with its operator and exposure in <png>.json. Returns the exposure used.
double write_sky_image(const atmo::SkyImage& img, const std::filesystem::path& exr, const std::filesystem::path& png,
                       const io::Provenance& prov, const std::string& projection, const SunPlacement& sun);

// The sky image on a device: "cpu"; "gpu" (the GPU pass, or std::runtime_error when
// there is no EGL device or the atmosphere is unsupported there); "auto" (the GPU pass,
// else the CPU after a one-line notice on stderr). InputError for another name. `used`
// receives "cpu" or "gpu". threads: CPU worker threads (0 = all cores).
atmo::SkyImage render_sky_on(const std::string& device, const atmo::SkyIntegrator& sky, atmo::SkyProjection projection,
                             int width, int height, double altitude_m, const glm::dvec3& sun, bool spectral, int threads,
                             std::string& used);

// Display colour: linear sRGB scaled so its largest component is 1, then encoded.
std::array<double, 3> display_colour(const atmo::Rgb& c);

}  // namespace atmosh::cli
