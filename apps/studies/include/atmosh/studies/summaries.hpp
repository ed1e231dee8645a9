// atmosh/studies/summaries.hpp — the JSON summaries of the toolkit's one-shot results
// (what `atmosh ... --json` prints) and their text forms (what it prints without
// --json), as library calls that the Python module can reuse.
// Keys and units are those of docs/cli.md; every number is a double or an integer,
// printed in full precision by nlohmann::json::dump (shortest round-trip form).
// Nothing here prints.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/atmo/stiff_cases.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/prt/bake.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "atmosh/studies/studies_rt.hpp"

namespace atmosh::studies {

// A sky image and its sky (`atmosh sky --json`): the sun, the zenith and horizon colours
// and luminances, the irradiance (direct and diffuse, spectral and in lux) at the
// observer's height (>= 0), the run times, the files (empty: null).
struct SkyFiles {
  std::string exr, png, netcdf;
};
nlohmann::json sky_json(const SkyModel& model, const SunPlacement& sun, const atmo::SkyImage& image, double exposure,
                        const std::string& device, const SkyFiles& files);

// The sun's position for one query (`atmosh sun --json`): angles in degrees, rise,
// transit and set in ISO 8601 UTC (null when none), the ENU direction towards the sun.
nlohmann::json sun_position_json(const atmo::SunQuery& query, const atmo::SunPosition& position);

// One optical-depth answer (`atmosh optical-depth --json`).
nlohmann::json optical_depth_json(const OpticalDepthAnswer& answer, const std::string& method, double wavelength_nm,
                                  const std::string& atmosphere);

// A phase function's value [1/sr] at cos_theta and its mean cosine (`atmosh phase --json`).
nlohmann::json phase_json(const atmo::PhaseFunction& phase, const std::string& model, double cos_theta);

// The stiff/extreme-case table (`atmosh stability --json`): cases and all_pass.
nlohmann::json stability_json(const std::vector<atmo::StiffCase>& cases);

// The Monte-Carlo slab (`atmosh rt slab --json`) and sky view (`atmosh rt sky --json`):
// inputs as given, results with standard errors, threads resolved.
nlohmann::json rt_slab_json(const RtSlabRequest& request, const atmo::SlabResult& result);
nlohmann::json rt_sky_json(const RtSkyRequest& request, const scene::Scene& scene, const atmo::RtSkyResult& result);

// A per-vertex (.ply) and a per-pixel (.exr) transfer bake (`atmosh prt bake --json`);
// time_s: wall clock of the bake.
nlohmann::json prt_bake_json(const prt::Transfer& transfer, const std::string& file, double time_s);
nlohmann::json prt_pixel_bake_json(const prt::PixelTransfer& transfer, sh::prt::TransferMode mode,
                                   const std::string& file, double time_s);

// The passes of a scene and the estimates `run` checks against its budgets (peak memory,
// computing: atmosh/budget.hpp) (`atmosh plan --json`), and the same as text (`atmosh plan`).
nlohmann::json plan_json(const scene::Scene& scene, const std::vector<scene::Pass>& passes);
std::string plan_text(const scene::Scene& scene, const std::vector<scene::Pass>& passes);

// ---- the text forms (one line each, ending in a newline) ----------------------------
// The sun's position, one quantity a line (8 significant digits), rise/transit/set.
std::string sun_position_text(const atmo::SunQuery& query, const atmo::SunPosition& position);
// Optical depth per constituent and in total (12 significant digits), its error and time.
std::string optical_depth_text(const OpticalDepthAnswer& answer, const std::string& method, double wavelength_nm,
                               double altitude_m, double zenith_deg, const std::string& atmosphere);
// The stiff/extreme-case table: a row per case, PASS/FAIL, and the verdict.
std::string stability_text(const std::vector<atmo::StiffCase>& cases);
// R and T with standard errors; the luminance and the spectral radiance with theirs.
std::string rt_slab_text(const atmo::SlabResult& result);
std::string rt_sky_text(const atmo::RtSkyResult& result);
// The summary of a transfer bake written to `file`.
std::string prt_bake_text(const nlohmann::json& summary);

}  // namespace atmosh::studies
