// atmosh/scene/scene.hpp — scene files (TOML, version 1) and the pass plan.
//
// A scene names an atmosphere (tables [planet], [rayleigh], [mie], [ozone],
// [spectrum] — a constituent whose table is absent is left out), where the sun is
// (an [observer] with place and UTC time, or a [sun] with elevation/azimuth in
// degrees), and its outputs ([[output]] entries). The full schema with units and
// ranges is in docs/scene-format.md.
//
// Validation is strict: an unknown key, a wrong type or an out-of-range value
// throws atmosh::InputError whose message starts with the key's path, e.g.
//   "scene.toml: mie.scale_height_m = -5: must be > 0".
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <cstdint>
#include <variant>
#include <vector>

#include "atmosh/atmo/multiple_scattering.hpp"
#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/spec.hpp"

namespace atmosh::scene {

// [observer]: a place (atmo::Observer: latitude_deg, longitude_deg, height_m, with
// its one validation, atmo::validate_observer) and a time.
struct Observer : atmo::Observer {
  std::string time_utc;         // ISO 8601 (offsets accepted)
};

struct SunOverride {
  double elevation_deg = 30.0;  // geometric elevation, [-90, 90]
  double azimuth_deg = 180.0;   // from north towards east, [0, 360)
};

struct Output {
  std::string kind;             // "sky-image", "sun-track", "optical-depth", "sh-coefficients", ...
  std::string file;
  std::string projection = "equirect";   // sky-image: equirect | fisheye
  std::array<int, 2> size{256, 128};     // sky-image: width, height in pixels
  int bands = 0;                         // sh-coefficients: number of SH bands (0 = not used)
  bool spectral = false;                 // sky-image: write per-wavelength channels
};

struct Scene {
  int version = 1;
  std::string source = "<built-in>";  // file name, for messages
  atmo::AtmosphereSpec atmosphere;
  std::optional<Observer> observer;
  std::optional<SunOverride> sun;
  std::string sun_model = "disc";  // "disc" (limb-darkened solar disc) or "point"
  std::vector<Output> outputs;
  // [scattering]: how the sky treats light scattered more than once (method, orders,
  // table sizes). A scene without the table keeps single scattering; the built-in
  // default scene uses multiple scattering (docs/scene-format.md).
  atmo::MultipleScatteringOptions scattering;
};

// One scene parameter set by its dotted key path, e.g. {"mie.scattering_per_m",
// 8e-6} or {"spectrum.count", int64_t{32}}. Missing tables are created (so
// "mie.angstrom" adds a default [mie] when the scene has none). Setting a "sun.*"
// key removes an [observer] table and vice versa, so that a sweep over sun
// elevation works on a scene that places the sun by time.
struct Override {
  std::string key;
  std::variant<double, std::int64_t, std::string> value;
};
std::string override_value_string(const Override& o);


// Outputs stay inside the output folder and never overwrite each other: every
// `file` is a relative path without ".." (InputError naming output[i].file
// otherwise), and no two outputs write the same file, side files included
// (InputError naming both outputs). parse_scene calls it, so `scene check`,
// `plan` and `run` refuse such a scene before any work.
void check_output_files(const Scene& scene);

// Parses and validates TOML text; source_name prefixes error messages. Overrides
// are applied before validation, so a bad override is reported by its key.
Scene parse_scene(std::string_view toml_text, const std::string& source_name,
                  const std::vector<Override>& overrides = {});
// Reads and parses a file; InputError if it cannot be read. Whether the scene meets
// what its outputs need is check_outputs (outputs.hpp), called by `scene check`, `plan`
// and `run` — not here: `sky --scene` or a sweep point uses the atmosphere, not the outputs.
Scene load_scene(const std::filesystem::path& file);
// The built-in default scene (TOML text embedded in the binary).
std::string_view default_scene_toml();
Scene default_scene();
// Writes a scene back as TOML in the same schema (parse(to_toml(s)) == s).
std::string to_toml(const Scene& scene);

// One step of work a scene may need, and whether this scene needs it.
struct Pass {
  std::string name;     // e.g. "optical-depth-lut:mie"
  bool needed = false;
  std::string reason;   // why it runs, or why it is left out
};
// The passes derived from the scene's outputs: constituents, tables, wavelengths,
// SH bands, sun position. Passes not needed are listed with the reason.
std::vector<Pass> plan(const Scene& scene);

}  // namespace atmosh::scene
