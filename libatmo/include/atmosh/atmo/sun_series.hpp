// atmosh/atmo/sun_series.hpp — the sun at a place over a range of UTC times, and
// the error-against-run-time study of the fast algorithms against SPA.
//
// Units as in sun_position.hpp (degrees, minutes, AU, UTC Julian days, seconds).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "atmosh/atmo/sun_position.hpp"

namespace atmosh::atmo {

struct SunSample {
  double jd_utc = 0;
  SunPosition position;           // rise/transit/set not filled (see below)
  double east = 0, north = 0, up = 0;  // sun unit direction in ENU (geometric)
};

// Samples at jd_from, jd_from + step, ... while <= jd_to (+1 µs slack). The
// query's time and rise_transit_set fields are ignored (rise/set are per day, ask
// sun_position for them). Throws InputError if jd_to < jd_from, step_s <= 0, or
// more than max_samples rows would result.
std::vector<SunSample> sun_series(const SunQuery& base, double jd_from, double jd_to, double step_s,
                                  std::size_t max_samples = 2000000);

// One row of the accuracy study (CSV columns method, setting, error_max_deg,
// error_rms_deg, time_s).
struct SunAccuracyRow {
  std::string method;    // "spa", "fast", "grena3", "grena1"
  std::string setting;   // "lat=45" or "all"
  double error_max_deg = 0;  // max angular separation from SPA (geometric directions)
  double error_rms_deg = 0;
  double time_s = 0;         // mean wall time per evaluation of the core algorithm
                             // (spa_compute / grena_position, no rise-set), seconds
  std::size_t samples = 0;
};

// Compares every algorithm with SPA over one UTC year (2010..2110 for the Grena
// methods) at the given latitudes: `samples_per_latitude` instants spread over
// the year with hours of day and longitudes varying (deterministic, no RNG:
// instant i at day offset i·365.2425/n, longitude = golden-angle sequence).
// Both sides use the same ΔT (Espenak & Meeus) and UT1−UTC = 0, so the error is
// the algorithm's own. Error = great-circle angle between the geometric
// topocentric directions. Rows: per method, one per latitude then "all".
std::vector<SunAccuracyRow> sun_accuracy_study(int year, const std::vector<double>& latitudes_deg,
                                               std::size_t samples_per_latitude);

}  // namespace atmosh::atmo
