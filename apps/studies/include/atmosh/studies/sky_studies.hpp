// atmosh/studies/sky_studies.hpp — the studies of the single-scattering sky: colour
// against sun elevation, through a day at a place, one sweep point, the integrator's
// error against run time (converge sky), and the sky's spherical harmonics.
//
// Each study takes a scene (or a sky model) and options and returns typed rows with
// their provenance; the write_* functions put them into the files their caller names.
// Nothing here prints or reads the command line. Units: degrees, metres, seconds;
// luminance in cd/m^2, radiance in W m^-2 sr^-1 nm^-1; sRGB linear (D65) scaled so Y is
// luminance.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/progress.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/scene/sweep.hpp"
#include "atmosh/studies/sky.hpp"

namespace atmosh::studies {

// The columns of a sky summary, as the studies' CSVs and the sweeps report them.
const std::vector<std::string>& sky_summary_columns();
// The values of those columns (chromaticities NaN where a colour is black).
std::vector<double> sky_summary_values(const atmo::SkySummary& m);

// ----------------------------------------------------- sun-elevation study
struct ElevationStudyOptions {
  double from_deg = -18, to_deg = 90, step_deg = 1, azimuth_deg = 180;
  SkySettings sky;
};
struct ElevationStudy {
  double azimuth_deg = 180;               // of the sun, fixed
  std::vector<double> elevations_deg;     // from, from + step, ... <= to
  std::vector<atmo::SkySummary> rows;     // one per elevation, at the scene's observer height (>= 0)
  io::Provenance provenance;
};
// Rows from `from_deg` while <= to_deg (+1e-9). InputError for a range outside
// [-90, 90], step <= 0 or to < from. progress: fractions done (may be empty).
ElevationStudy sun_elevation_study(const scene::Scene& s, const ElevationStudyOptions& o,
                                   const ProgressCallback& progress = {});
// Memory of the study (saturates for a hostile step).
std::size_t elevation_study_bytes(const ElevationStudyOptions& o);
// Work of the study on scene s (atmosh/work.hpp): its rows' sky summaries.
WorkEstimate elevation_study_work(const scene::Scene& s, const ElevationStudyOptions& o);
// The study's table (sun_elevation.csv): sun_elevation_deg, then sky_summary_columns().
// The one place its columns are made (CSV, netCDF, the Python module's DataFrame).
io::CsvTable elevation_study_table(const ElevationStudy& st);
// Its netCDF-CF layout: dimension and coordinate sun_elevation_deg (standard name
// solar_elevation_angle, degree), the sun's fixed azimuth as the scalar
// solar_azimuth_angle.
io::NetcdfTableOptions elevation_study_netcdf_options(const ElevationStudy& st);
// dir/sun_elevation.csv (with netcdf also dir/sun_elevation.nc, netCDF-CF) and the
// plots (horizon_colour.png, zenith_colour.png, luminance.png, chromaticity.png);
// returns the files written.
std::vector<std::filesystem::path> write_elevation_study(const ElevationStudy& st, const std::filesystem::path& dir,
                                                         bool netcdf = false);

// ------------------------------------------------------------- day study
struct DayStudyOptions {
  double latitude_deg = 0, longitude_deg = 0, height_m = 0;
  std::string date;        // UTC date YYYY-MM-DD
  double step_s = 600;     // time step
  std::string step_text;   // the step as given (provenance), e.g. "10min"
  bool frames = true;      // render one equirect frame per row
  int frame_width = 128, frame_height = 64;
  SkySettings sky;
};
struct DayRow {
  std::string time_utc;            // ISO 8601
  double hours = 0;                // since 00:00 UTC of the date
  atmo::SunPosition sun;           // NREL SPA at the place and time
  atmo::SkySummary summary;        // at the day's Earth-Sun distance
};
struct DayFrame {
  std::string time_utc;
  atmo::SkyImage image;      // equirect, radiances at the day's Earth-Sun distance
  SunPlacement sun;
  io::Provenance provenance;
};
struct DayStudy {
  std::string date;
  double latitude_deg = 0, longitude_deg = 0, height_m = 0;  // the place
  std::vector<DayRow> rows;
  io::Provenance provenance;
};
// The sky every step over the UTC day (00:00 <= t < 24:00); each frame (when asked) is
// handed to on_frame as it is rendered, so at most one frame is held.
// Work of the study on scene s (atmosh/work.hpp): per time step a sky summary and, with
// frames, an image of frame_width x frame_height.
WorkEstimate day_study_work(const scene::Scene& s, const DayStudyOptions& o);
DayStudy day_study(const scene::Scene& s, const DayStudyOptions& o, const std::function<void(DayFrame&&)>& on_frame = {},
                   const ProgressCallback& progress = {});
// The study's table (day.csv): time_utc, sun_elevation_deg, sun_azimuth_deg,
// apparent_sun_elevation_deg, then sky_summary_columns(). The one place its columns
// are made.
io::CsvTable day_study_table(const DayStudy& st);
// Its netCDF-CF layout: dimension `time` with a CF time coordinate (seconds since
// 1970-01-01 00:00:00 UTC, from time_utc), solar_elevation_angle / solar_azimuth_angle
// standard names, the place as the scalars latitude [degree_north], longitude
// [degree_east] and height [m].
io::NetcdfTableOptions day_study_netcdf_options(const DayStudy& st);
// dir/day.csv (with netcdf also dir/day.nc) and the plots; returns the files written.
std::vector<std::filesystem::path> write_day_study(const DayStudy& st, const std::filesystem::path& dir,
                                                   bool netcdf = false);
// An EXR frame (no PNG) at dir/frames/sky_HHMMZ.exr; returns its path.
std::filesystem::path write_day_frame(const DayFrame& f, const std::filesystem::path& dir);

// ------------------------------------------------------------------ sweep
// One point of a sweep: the sky summary of a scene (sun from the scene), its sun, and
// the table build time.
scene::SweepOutputs sweep_point(const scene::Scene& s, const SkySettings& q);
// The settings that change a sky sweep's results, as its CSVs record them and its
// identity hashes them (scene::sweep_identity): lut_shells, view_segments,
// samples_per_segment, max_piece_optical_depth, sun_model, scattering, orders ("scene"
// where the scene's own applies).
scene::SweepSettings sweep_settings(const SkySettings& q);

// --------------------------------------------------------- converge sky
struct ConvergeSkyOptions {
  bool quick = false;
  int threads = 0;  // for the reference (0 = every CPU this process may use)
};
struct ConvergeSky {
  io::StudySpec spec;
  std::vector<io::StudyRow> rows;  // per setting: day and twilight
  io::Provenance provenance;
};
// The fast integrator's error against the exact reference (adaptive Gauss-Kronrod,
// rel tol 1e-6) and its run time, for a grid of table/quadrature settings.
ConvergeSky converge_sky(const scene::Scene& s, const ConvergeSkyOptions& o);
// <stem>.csv (with netcdf, or a stem ending in .nc, also <stem>.nc) and <stem>.png
// (io::write_study).
std::vector<std::filesystem::path> write_converge_sky(const ConvergeSky& c, const std::filesystem::path& stem,
                                                      bool netcdf = false);

// ---------------------------------------------------- the sky's SH (sky -> SH)
struct SkySh {
  int bands = 0;
  int nlat = 0, nphi = 0;                     // the Gauss-Legendre grid
  std::array<std::vector<double>, 3> coeffs;  // linear sRGB r, g, b; index l(l+1)+m
  io::Provenance provenance;
};
// Samples the sky on a Gauss-Legendre grid of max(4 bands, 64) x 2 that and analyses
// each linear-sRGB channel (real orthonormal SH, Condon-Shortley phase, frame x = east,
// y = north, z = up). InputError for bands < 1.
SkySh project_sky_sh(const SkyModel& model, const SunPlacement& sun, int bands);
// The coefficient CSV at `csv`, and <stem>_bands.csv / <stem>_bands.png (band energy);
// returns the files written.
std::vector<std::filesystem::path> write_sky_sh(const SkySh& sh, const std::filesystem::path& csv);

// ------------------------------------------------- the demo's sky step
// converge sky (quick or full) on the default scene into dir/sky_convergence.{csv,png}.
std::vector<std::filesystem::path> demo_sky(const std::filesystem::path& dir, bool quick);

}  // namespace atmosh::studies
