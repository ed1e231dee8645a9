// atmosh sun — solar position at a place and a UTC time, time series, and the
// accuracy study of the fast algorithms against NREL SPA.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "atmosh/atmo/observer.hpp"
#include "atmosh/atmo/sun_position.hpp"
#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "cli_common.hpp"
#include "atmosh/studies/studies_sun.hpp"
#include "progress.hpp"

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;

struct SunOptions {
  std::optional<double> lat, lon;
  double height = 0.0;
  std::string time, from, to, step = "10min", output;
  double pressure = 1013.25, temperature = 15.0;
  std::optional<double> delta_t;
  double delta_ut1 = 0.0;
  std::string algorithm = "spa";
  std::string format = "csv";
  bool json = false;
};

struct AccuracyOptions {
  int year = 2024;
  std::string latitudes = "-75,-45,0,30,60,85";
  std::size_t samples = 20000;
  std::string output = "sun_accuracy";
};

nlohmann::json jd_or_null(const std::optional<double>& jd) {
  return jd ? nlohmann::json(format_iso8601_utc(*jd)) : nlohmann::json(nullptr);
}

std::string fs_ext(const std::string& file) { return std::filesystem::path(file).extension().string(); }

SunQuery base_query(const SunOptions& o) {
  if (o.format != "csv" && o.format != "netcdf") throw InputError("--format: '" + o.format + "' is not csv or netcdf");
  if (!o.lat) throw InputError("--lat is required");
  if (!o.lon) throw InputError("--lon is required");
  SunQuery q;
  q.latitude_deg = require_range(*o.lat, -90.0, 90.0, "--lat");
  q.longitude_deg = require_range(*o.lon, -180.0, 180.0, "--lon");
  q.height_m = require_range(o.height, -12000.0, 1e8, "--height");
  q.pressure_hpa = require_range(o.pressure, 0.0, 5000.0, "--pressure");
  q.temperature_c = require_range(o.temperature, -272.999, 6000.0, "--temperature");
  if (o.delta_t) q.delta_t_s = require_range(*o.delta_t, -1e6, 1e6, "--delta-t");
  q.delta_ut1_s = require_range(o.delta_ut1, -1.0, 1.0, "--delta-ut1");
  q.algorithm = parse_sun_algorithm(o.algorithm);
  return q;
}

io::Provenance place_provenance(const SunQuery& q) { return studies::sun_place_provenance(q); }

std::vector<std::filesystem::path> write_accuracy(const std::filesystem::path& stem, int year,
                                                  const std::vector<double>& lats, std::size_t samples) {
  const studies::StudyTable t = studies::sun_accuracy_table(year, lats, samples);
  return io::write_study(stem, t.spec, t.rows, t.provenance);
}

void run_sun(const SunOptions& o) {
  const SunQuery base = base_query(o);
  const bool range = !o.from.empty() || !o.to.empty();
  if (range) {
    if (o.from.empty() || o.to.empty()) throw InputError("a time range needs both --from and --to");
    if (!o.time.empty()) throw InputError("--time cannot be combined with --from/--to");
    const double from = parse_iso8601(o.from).jd_utc, to = parse_iso8601(o.to).jd_utc;
    const double step = parse_duration_s(o.step);
    if (!o.output.empty() && o.output != "-") check_output_file(o.output, {o.format == "netcdf" ? ".nc" : ".csv", ".nc"}, "-o");
    const auto samples = sun_series(base, from, to, step);
    io::Provenance prov = place_provenance(base);
    const int decimals = studies::sun_time_decimals(step, o.from);
    prov.add("from_utc", format_iso8601_utc(from, decimals)).add("to_utc", format_iso8601_utc(to, decimals)).add("step_s", step);
    const io::CsvTable table = studies::sun_series_table(samples, decimals);
    if (o.output.empty() || o.output == "-") {
      if (o.format == "netcdf") throw InputError("--format netcdf: needs -o FILE.nc");
      std::cout << table.to_string(prov);
    } else if (o.format == "netcdf" || fs_ext(o.output) == ".nc") {  // CF time coordinate from jd_utc
      auto nc = io::sun_track_netcdf_options();
      nc.scalars["latitude"] = {base.latitude_deg, "degrees_north", "latitude"};
      nc.scalars["longitude"] = {base.longitude_deg, "degrees_east", "longitude"};
      io::write_table_netcdf(o.output, table, prov, nc);
      std::cerr << "wrote " << o.output << " (" << samples.size() << " rows)\n";
    } else {
      table.write(o.output, prov);
      std::cerr << "wrote " << o.output << " (" << samples.size() << " rows)\n";
    }
    return;
  }
  if (o.time.empty()) throw InputError("--time is required (or --from/--to for a range)");
  const ParsedTime t = parse_iso8601(o.time);
  SunQuery q = base;
  q.jd_utc = t.jd_utc;
  q.day_offset_minutes = t.offset_minutes;
  const SunPosition s = sun_position(q);
  const glm::dvec3 d = enu_direction_from_zenith(s.zenith_deg, s.azimuth_deg);
  if (o.json) {
    nlohmann::json j;
    j["zenith_deg"] = s.zenith_deg;
    j["azimuth_deg"] = s.azimuth_deg;
    j["elevation_deg"] = s.elevation_deg;
    j["apparent_zenith_deg"] = s.apparent_zenith_deg;
    j["apparent_elevation_deg"] = s.apparent_elevation_deg;
    j["declination_deg"] = s.declination_deg;
    j["hour_angle_deg"] = s.hour_angle_deg;
    j["equation_of_time_min"] = s.equation_of_time_min;
    j["earth_sun_distance_au"] = s.earth_sun_distance_au;
    j["sunrise_utc"] = jd_or_null(s.sunrise_jd_utc);
    j["transit_utc"] = jd_or_null(s.transit_jd_utc);
    j["sunset_utc"] = jd_or_null(s.sunset_jd_utc);
    j["polar"] = s.polar == Polar::None ? nlohmann::json(nullptr) : nlohmann::json(polar_name(s.polar));
    j["time_utc"] = format_iso8601_utc(t.jd_utc, 3);
    j["delta_t_s"] = s.delta_t_s;
    j["delta_ut1_s"] = q.delta_ut1_s;
    j["algorithm"] = sun_algorithm_name(q.algorithm);
    j["sun_direction_enu"] = {d.x, d.y, d.z};
    print_json(j);
    return;
  }
  std::cout.precision(8);
  std::cout << "time (UTC)            " << format_iso8601_utc(t.jd_utc, 3) << "\n"
            << "algorithm             " << sun_algorithm_name(q.algorithm) << " (delta T " << s.delta_t_s
            << " s, UT1-UTC " << q.delta_ut1_s << " s)\n"
            << "zenith                " << s.zenith_deg << " deg (geometric; apparent " << s.apparent_zenith_deg
            << ")\n"
            << "elevation             " << s.elevation_deg << " deg (geometric; apparent "
            << s.apparent_elevation_deg << ")\n"
            << "azimuth               " << s.azimuth_deg << " deg (from north, eastward)\n"
            << "declination           " << s.declination_deg << " deg\n"
            << "hour angle            " << s.hour_angle_deg << " deg\n"
            << "equation of time      " << s.equation_of_time_min << " min\n"
            << "Earth-Sun distance    " << s.earth_sun_distance_au << " AU\n"
            << "sun direction (ENU)   " << d.x << ", " << d.y << ", " << d.z << "\n";
  auto line = [](const char* name, const std::optional<double>& jd) {
    std::cout << name << (jd ? format_iso8601_utc(*jd) : std::string("none")) << "\n";
  };
  line("sunrise               ", s.sunrise_jd_utc);
  line("transit               ", s.transit_jd_utc);
  line("sunset                ", s.sunset_jd_utc);
  if (s.polar != Polar::None) std::cout << "polar                 " << polar_name(s.polar) << "\n";
}

}  // namespace

void register_sun_commands(CLI::App& app) {
  auto opt = std::make_shared<SunOptions>();
  auto acc = std::make_shared<AccuracyOptions>();
  CLI::App* sun = app.add_subcommand(
      "sun",
      "Sun position from latitude, longitude, height and a UTC time (NREL SPA, or the fast Grena 2012 "
      "algorithm), a time series (--from/--to/--step), or `sun accuracy`");
  sun->add_option("--lat", opt->lat, "geodetic latitude [deg], north positive");
  sun->add_option("--lon", opt->lon, "longitude [deg], east positive");
  sun->add_option("--height", opt->height, "height above the WGS84 ellipsoid [m] (default 0)");
  sun->add_option("--time", opt->time, "UTC instant, ISO 8601, offsets accepted (2003-10-17T12:30:30-07:00)");
  sun->add_option("--pressure", opt->pressure, "air pressure for refraction [hPa] (default 1013.25)");
  sun->add_option("--temperature", opt->temperature, "air temperature for refraction [C] (default 15)");
  sun->add_option("--delta-t", opt->delta_t, "TT - UT1 [s] (default: Espenak & Meeus model for the year)");
  sun->add_option("--delta-ut1", opt->delta_ut1, "UT1 - UTC [s] (default 0; needed with --delta-t for 0.0003 deg)");
  sun->add_option("--algorithm", opt->algorithm, "spa (default, years -2000..6000) | fast (Grena 2012 #5, 2010..2110)");
  sun->add_flag("--json", opt->json, "print one JSON object");
  sun->add_option("--from", opt->from, "start of a time range (ISO 8601)");
  sun->add_option("--to", opt->to, "end of a time range (ISO 8601, inclusive)");
  sun->add_option("--step", opt->step, "step of the range: 90s, 10min, 1h, 1d (default 10min)");
  sun->add_option("-o,--output", opt->output, "CSV file for a range (default: standard output); a name ending in .nc "
                                              "writes netCDF-CF");
  sun->add_option("--format", opt->format, "csv (default) | netcdf: the range's file format (netCDF-CF, time "
                                           "coordinate from jd_utc)");

  CLI::App* accuracy = sun->add_subcommand(
      "accuracy", "Error of the fast algorithms against SPA over a year at several latitudes, against run time "
                  "(CSV method,setting,error_max_deg,error_rms_deg,time_s + log-log PNG)");
  accuracy->add_option("--year", acc->year, "UTC year (2010..2110 for the fast algorithms; default 2024)");
  accuracy->add_option("--latitudes", acc->latitudes, "comma-separated latitudes [deg]");
  accuracy->add_option("--samples", acc->samples, "instants per latitude (default 20000)");
  accuracy->add_option("-o,--output", acc->output, "output stem: writes STEM.csv and STEM.png");
  accuracy->callback([acc]() {
    const std::vector<double> lats = parse_list(acc->latitudes, "--latitudes");
    for (double l : lats) require_range(l, -90.0, 90.0, "--latitudes");
    if (acc->year < 2010 || acc->year > 2110)
      throw InputError("--year " + std::to_string(acc->year) + " is outside 2010..2110, the fast algorithms' range");
    if (acc->samples < 1 || acc->samples > 10000000)
      throw InputError("--samples " + std::to_string(acc->samples) + " is outside 1..10000000");
    check_study_stem(acc->output, "-o");
    ProgressStep step("sun accuracy");
    for (const auto& p : write_accuracy(acc->output, acc->year, lats, acc->samples)) std::cerr << "wrote " << p.string() << "\n";
  });
  sun->callback([sun, opt]() {
    if (sun->got_subcommand("accuracy")) return;
    run_sun(*opt);
  });
}

void demo_sun(DemoContext& ctx) {
  ProgressStep step("demo: sun positions");
  // (The sun track of the default scene is one of its outputs, written by run_scene.)
  const std::vector<double> lats = {-75.0, -45.0, 0.0, 30.0, 60.0, 85.0};
  for (const auto& p : write_accuracy(ctx.out_dir / "sun_accuracy", 2026, lats, ctx.quick ? 500 : 20000))
    ctx.written.push_back(p);
}

}  // namespace atmosh::cli
