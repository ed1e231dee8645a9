// atmosh/atmo/ms_convergence.hpp — error against run time of the sky's scattering
// methods (single scattering, the all-orders approximation, successive orders and
// their table sizes) against the Monte-Carlo radiative-transfer reference
// (radiative_transfer.hpp), the study behind `atmosh converge ms`.
//
// Over a fixed set of views x sun elevations (rt_reference_view_set() x
// rt_reference_sun_elevations() by default: 60 deg down to -15 deg), observer at
// `altitude_m`:
//   * the reference: MonteCarloSky luminance L_mc [cd m^-2] per row, with its standard
//     error s_mc (every order of scattering, the scene's ground albedo);
//   * per setting: a SkyIntegrator with that MultipleScatteringOptions is built (its
//     tables: the sun table, and the multiple-scattering table of the method) and
//     evaluated on every row; e = |L - L_mc| / L_mc per row.
// Rows are reported per sun-elevation band ("all", "day": sun >= 0, "civil":
// -6 <= sun < 0, "night": sun < -6; empty bands are left out), since the targets
// differ by band. Errors are luminance errors (the CIE Y of the spectral radiance at
// the atmosphere's wavelengths). Rows whose reference luminance is not positive are
// skipped (counted in `rows_skipped`).
//
// Times are wall clock on the calling machine: time_s = the fastest of
// `timing_repetitions` (table build + evaluation of every row of the study; one run
// when it takes over 2 s), the table builds on the threads the scattering options
// say (0: every core). The reference's time is reported apart. Errors measured on the
// default scene, and what they mean per band: docs/radiative-transfer.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/atmo/sky.hpp"

namespace atmosh::atmo {

struct MsStudySetting {
  std::string method;   // "single", "approximate", "orders" (scattering_method_name)
  std::string setting;  // the sizes, human readable ("altitudes=32 sun=64", ...)
  MultipleScatteringOptions scattering;
};

// The settings the study runs: single scattering; the approximation at table sizes
// (altitudes x sun directions) 8x16 (8 zenith x 4 azimuth directions, 16 steps per
// entry), 16x32, 32x64 (the default), 64x128 and the default with twice the
// directions and steps per entry; orders N = 2, 3, 4, 5, 6, 8 at the default table
// sizes, the default N at half of them (radii, view, sun, azimuths) and with each of
// the radii, view, sun axes and the ray steps doubled alone. quick: single + the
// approximation at 8x16 (coarse entries) and 16x32 (orders' tables take seconds).
std::vector<MsStudySetting> ms_study_default_settings(bool quick);

struct MsStudyOptions {
  std::vector<RtViewDirection> views = rt_reference_view_set();
  std::vector<double> sun_elevations_deg = rt_reference_sun_elevations();
  double altitude_m = 0.0;
  RtOptions reference_run{.paths = 128000};  // per row (paths over all wavelengths), seed
  RtSkyOptions reference;                    // the Monte-Carlo sky's own options (run is replaced)
  SkyOptions sky;                            // integrator options; `scattering` replaced per setting
  std::vector<MsStudySetting> settings = ms_study_default_settings(false);
  int timing_repetitions = 3;                // >= 1; a setting whose run takes > 2 s runs once
};

// One view x sun elevation: the reference and every setting's luminance.
struct MsStudyPoint {
  double sun_elevation_deg = 0, view_elevation_deg = 0, view_relative_azimuth_deg = 0;
  double reference_luminance = 0, reference_luminance_stderr = 0;  // cd m^-2
  std::vector<double> luminance;  // per setting, cd m^-2
};

struct MsStudyRow {
  std::string method, setting, band;
  double error_max_rel = 0, error_rms_rel = 0;
  double time_s = 0;                 // build + evaluation of every row of the study
  double build_time_s = 0, eval_time_s = 0;
  double reference_rel_stderr_max = 0;  // largest s_mc / L_mc over the band's rows
  // Largest |L - L_mc| / s_mc over the band: errors well above 3 are the method's, not
  // the reference's noise.
  double error_max_sigma = 0;
  // The largest error with the reference's 3-sigma taken off (>= 0): a lower bound of
  // the method's true error at the worst row.
  double error_max_rel_minus_3sigma = 0;
  int rows = 0, rows_skipped = 0;
};

struct MsStudyResult {
  std::vector<MsStudyPoint> points;
  std::vector<MsStudyRow> rows;  // per setting, per band (all, day, civil, night)
  double reference_time_s = 0;   // wall clock of every reference row
  std::int64_t reference_paths_per_row = 0;
};

// InputError for an empty view / sun set, no settings, timing_repetitions < 1, paths < 1
// or invalid scattering options (named as validate() names them).
MsStudyResult ms_convergence_study(const Atmosphere& atmosphere, const SolarSpectrum& solar,
                                   const MsStudyOptions& options);

// The band of a sun elevation: "day" (>= 0), "civil" ([-6, 0)), "night" (< -6).
const char* ms_study_band(double sun_elevation_deg);

}  // namespace atmosh::atmo
