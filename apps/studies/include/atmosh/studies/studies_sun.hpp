// atmosh/studies/studies_sun.hpp — the sun's tables as library calls: a series of
// positions as a CSV table with the place in its provenance, the sun's track over a UTC
// day (table and plot), and the accuracy study of the fast algorithms against NREL SPA
// (atmo::sun_accuracy_study) as a study table. Angles in degrees, times UTC (ISO 8601).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/studies/study_table.hpp"

namespace atmosh::studies {

// The place and the models of `atmosh sun` as its options give them; sun_query checks
// them, InputError naming the option as typed (--lat, --lon required; --height,
// --pressure, --temperature, --delta-t, --delta-ut1 in range; --algorithm spa | fast).
struct SunPlaceRequest {
  std::optional<double> lat_deg, lon_deg, delta_t_s;
  double height_m = 0.0, pressure_hpa = 1013.25, temperature_c = 15.0, delta_ut1_s = 0.0;
  std::string algorithm = "spa";
};
atmo::SunQuery sun_query(const SunPlaceRequest& request);

// The place and the models of a query: latitude, longitude, height, pressure,
// temperature, delta T (or the model's), UT1 - UTC, algorithm and frame.
io::Provenance sun_place_provenance(const atmo::SunQuery& query);

// Decimals of the seconds in time_utc: as many as the step and the start need
// (0.5 s -> 1, 0.25 s -> 2; whole seconds -> 0; digits after a decimal point in the
// seconds of from_text), at most 6.
int sun_time_decimals(double step_s, const std::string& from_text);

// One row per sample: time_utc, jd_utc, zenith, azimuth, elevation (geometric and
// apparent), declination, hour angle, equation of time, distance, ENU direction.
io::CsvTable sun_series_table(const std::vector<atmo::SunSample>& samples, int decimals = 0);

// The sun over the whole UTC day that contains time_utc, every step_s seconds, by SPA.
struct SunDayTrack {
  std::vector<atmo::SunSample> samples;
  double from_jd = 0.0, to_jd = 0.0;  // the day's start and end (UTC Julian days)
  io::Provenance provenance;
};
// InputError for a latitude outside [-90, 90] or a longitude outside [-180, 180].
SunDayTrack sun_day_track(double latitude_deg, double longitude_deg, double height_m, const std::string& time_utc,
                          double step_s);
// STEM.csv (sun_series_table) and STEM.png (elevations and azimuth against hours).
std::vector<std::filesystem::path> write_sun_day_track(const SunDayTrack& track, double latitude_deg,
                                                       double longitude_deg, const std::filesystem::path& stem);

// The fast algorithms' error against SPA over a year at the given latitudes, as a study
// table (error_max_deg, error_rms_deg, time per evaluation, samples).
StudyTable sun_accuracy_table(int year, const std::vector<double>& latitudes_deg, std::size_t samples);
// The table as STEM.csv and STEM.png (io::write_study); returns the files.
std::vector<std::filesystem::path> write_sun_accuracy(const std::filesystem::path& stem, int year,
                                                      const std::vector<double>& latitudes_deg, std::size_t samples);

}  // namespace atmosh::studies
