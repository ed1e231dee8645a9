// The sun's tables (atmosh/studies/studies_sun.hpp).
#include "atmosh/studies/studies_sun.hpp"

#include "atmosh/io/study.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/plot.hpp"

namespace atmosh::studies {

using namespace atmosh::atmo;
namespace fs = std::filesystem;

io::Provenance sun_place_provenance(const SunQuery& q) {
  io::Provenance p = io::Provenance::current();
  p.add("latitude_deg", q.latitude_deg).add("longitude_deg", q.longitude_deg).add("height_m", q.height_m);
  p.add("pressure_hpa", q.pressure_hpa).add("temperature_c", q.temperature_c);
  p.add("delta_t_s", q.delta_t_s ? io::format_double(*q.delta_t_s) : std::string("Espenak & Meeus model per instant"));
  p.add("delta_ut1_s", q.delta_ut1_s);
  p.add("algorithm", sun_algorithm_name(q.algorithm));
  p.add("frame", "azimuth from north towards east; ENU x east, y north, z up; elevations in degrees");
  return p;
}

int sun_time_decimals(double step_s, const std::string& from_text) {
  int d = 0;
  while (d < 6) {
    const double scaled = step_s * std::pow(10.0, d);
    if (std::fabs(scaled - std::round(scaled)) <= 1e-6 * std::max(1.0, scaled)) break;
    ++d;
  }
  // Digits after a decimal point in the seconds of the start (e.g. 12:00:00.25Z -> 2).
  if (const auto t = from_text.find('T'); t != std::string::npos)
    if (const auto dot = from_text.find('.', t); dot != std::string::npos) {
      int n = 0;
      for (std::size_t i = dot + 1; i < from_text.size() && std::isdigit(static_cast<unsigned char>(from_text[i])); ++i) ++n;
      d = std::max(d, std::min(n, 6));
    }
  return d;
}

io::CsvTable sun_series_table(const std::vector<SunSample>& samples, int decimals) {
  io::CsvTable t({"time_utc", "jd_utc", "zenith_deg", "azimuth_deg", "elevation_deg", "apparent_zenith_deg",
                  "apparent_elevation_deg", "declination_deg", "hour_angle_deg", "equation_of_time_min",
                  "earth_sun_distance_au", "sun_east", "sun_north", "sun_up"});
  for (const SunSample& s : samples) {
    const SunPosition& p = s.position;
    t.add_row({format_iso8601_utc(s.jd_utc, decimals), s.jd_utc, p.zenith_deg, p.azimuth_deg, p.elevation_deg,
               p.apparent_zenith_deg, p.apparent_elevation_deg, p.declination_deg, p.hour_angle_deg,
               p.equation_of_time_min, p.earth_sun_distance_au, s.east, s.north, s.up});
  }
  return t;
}

namespace {
void write_track_plot(const fs::path& png, const std::vector<SunSample>& samples, const std::string& title) {
  io::PlotSpec spec;
  spec.title = title;
  spec.x_label = "time since start [h]";
  spec.y_label = "angle [deg]";
  io::Series el{"elevation (geometric)", {}, {}, io::Series::Style::Line};
  io::Series app{"apparent elevation", {}, {}, io::Series::Style::Line};
  io::Series az{"azimuth (from north, eastward)", {}, {}, io::Series::Style::Line};
  const double t0 = samples.empty() ? 0.0 : samples.front().jd_utc;
  for (const SunSample& s : samples) {
    const double h = (s.jd_utc - t0) * 24.0;
    el.x.push_back(h);
    el.y.push_back(s.position.elevation_deg);
    app.x.push_back(h);
    app.y.push_back(s.position.apparent_elevation_deg);
    if (!az.y.empty() && std::fabs(s.position.azimuth_deg - az.y.back()) > 180.0) {
      az.x.push_back(h);  // break the line where the azimuth wraps through north
      az.y.push_back(std::nan(""));
    }
    az.x.push_back(h);
    az.y.push_back(s.position.azimuth_deg);
  }
  spec.series = {el, app, az};
  io::write_plot_png(png, spec);
}

double in_range(double v, double lo, double hi, const std::string& what) {
  if (!(std::isfinite(v) && v >= lo && v <= hi))
    throw InputError(what + ": " + io::format_double(v) + " is out of range [" + io::format_double(lo) + ", " +
                     io::format_double(hi) + "]");
  return v;
}
}  // namespace

SunQuery sun_query(const SunPlaceRequest& o) {
  if (!o.lat_deg) throw InputError("--lat is required");
  if (!o.lon_deg) throw InputError("--lon is required");
  SunQuery q;
  q.latitude_deg = in_range(*o.lat_deg, -90.0, 90.0, "--lat");
  q.longitude_deg = in_range(*o.lon_deg, -180.0, 180.0, "--lon");
  q.height_m = in_range(o.height_m, -12000.0, 1e8, "--height");
  q.pressure_hpa = in_range(o.pressure_hpa, 0.0, 5000.0, "--pressure");
  q.temperature_c = in_range(o.temperature_c, -272.999, 6000.0, "--temperature");
  if (o.delta_t_s) q.delta_t_s = in_range(*o.delta_t_s, -1e6, 1e6, "--delta-t");
  q.delta_ut1_s = in_range(o.delta_ut1_s, -1.0, 1.0, "--delta-ut1");
  q.algorithm = atmo::parse_sun_algorithm(o.algorithm);
  return q;
}

SunDayTrack sun_day_track(double latitude_deg, double longitude_deg, double height_m, const std::string& time_utc,
                          double step_s) {
  SunQuery q;
  q.latitude_deg = in_range(latitude_deg, -90.0, 90.0, "latitude_deg");
  q.longitude_deg = in_range(longitude_deg, -180.0, 180.0, "longitude_deg");
  q.height_m = height_m;
  // The whole UTC day that contains the given time.
  const double jd = parse_iso8601(time_utc).jd_utc;
  SunDayTrack t;
  t.from_jd = std::floor(jd - 0.5) + 0.5;
  t.to_jd = t.from_jd + 1.0;
  t.samples = sun_series(q, t.from_jd, t.to_jd, step_s);
  t.provenance = sun_place_provenance(q);
  t.provenance.add("from_utc", format_iso8601_utc(t.from_jd))
      .add("to_utc", format_iso8601_utc(t.to_jd))
      .add("step_s", step_s);
  return t;
}

std::vector<fs::path> write_sun_day_track(const SunDayTrack& t, double latitude_deg, double longitude_deg,
                                          const fs::path& stem) {
  fs::path csv = stem, png = stem;
  csv += ".csv";
  png += ".png";
  sun_series_table(t.samples).write(csv, t.provenance);
  std::ostringstream title;
  title.precision(8);
  title << "Sun at " << latitude_deg << " deg, " << longitude_deg << " deg on "
        << format_iso8601_utc(t.from_jd).substr(0, 10) << " (UTC), NREL SPA";
  write_track_plot(png, t.samples, title.str());
  return {csv, png};
}

StudyTable sun_accuracy_table(int year, const std::vector<double>& lats, std::size_t samples) {
  const std::vector<SunAccuracyRow> rows = sun_accuracy_study(year, lats, samples);
  StudyTable out;
  for (const SunAccuracyRow& r : rows) {
    io::StudyRow s;
    s.method = r.method;
    s.setting = r.setting;
    s.error_max = r.error_max_deg;
    s.error_rms = r.error_rms_deg;
    s.time_s = r.time_s;
    s.extras = {static_cast<double>(r.samples)};
    out.rows.push_back(s);
  }
  io::StudySpec& spec = out.spec;
  spec.title = "Sun position: error against SPA vs time per evaluation (" + std::to_string(year) + ")";
  spec.error_max_column = "error_max_deg";
  spec.error_rms_column = "error_rms_deg";
  spec.error_axis_label = "max angular error vs SPA [deg]";
  spec.time_axis_label = "time per evaluation [s]";
  spec.extra_columns = {"samples"};
  io::Provenance& prov = out.provenance;
  prov = io::Provenance::current();
  prov.add("year", static_cast<double>(year));
  std::string l;
  for (double v : lats) {  // appended piecewise: GCC 12 warns falsely (-Wrestrict, its bug 105329) on "," + string
    if (!l.empty()) l += ',';
    l += io::format_double(v);
  }
  prov.add("latitudes_deg", l);
  prov.add("reference", "NREL SPA (Reda & Andreas 2008), same delta T (Espenak & Meeus), UT1-UTC = 0");
  prov.add("error", "great-circle angle between geometric topocentric directions, degrees");
  prov.add("time_s", "mean wall time per evaluation of the core algorithm (one thread)");
  prov.add("methods", "fast = Grena 2012 algorithm 5; grena3, grena1 = Grena 2012 algorithms 3 and 1");
  return out;
}

std::vector<std::filesystem::path> write_sun_accuracy(const std::filesystem::path& stem, int year,
                                                      const std::vector<double>& lats, std::size_t samples) {
  const StudyTable t = sun_accuracy_table(year, lats, samples);
  return io::write_study(stem, t.spec, t.rows, t.provenance);
}

}  // namespace atmosh::studies
