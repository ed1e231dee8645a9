// atmosh sun — solar position at a place and a UTC time, time series, and the
// accuracy study of the fast algorithms against NREL SPA.
#include <iostream>
#include <memory>

#include "atmosh/atmo/sun_series.hpp"
#include "atmosh/atmo/time_utc.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/studies/studies_sun.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;

struct SunOptions {
  studies::SunPlaceRequest place;
  std::string time, from, to, step = "10min", output, format = "csv";
  bool json = false;
};

void run_sun(const SunOptions& o) {
  if (o.format != "csv" && o.format != "netcdf") throw InputError("--format: '" + o.format + "' is not csv or netcdf");
  const SunQuery base = studies::sun_query(o.place);
  if (!o.from.empty() || !o.to.empty()) {  // a range
    if (o.from.empty() || o.to.empty()) throw InputError("a time range needs both --from and --to");
    if (!o.time.empty()) throw InputError("--time cannot be combined with --from/--to");
    const double from = parse_iso8601(o.from).jd_utc, to = parse_iso8601(o.to).jd_utc;
    const double step = parse_duration_s(o.step);
    if (!o.output.empty() && o.output != "-") check_output_file(o.output, {o.format == "netcdf" ? ".nc" : ".csv", ".nc"}, "-o");
    const auto samples = sun_series(base, from, to, step);
    io::Provenance prov = studies::sun_place_provenance(base);
    const int decimals = studies::sun_time_decimals(step, o.from);
    prov.add("from_utc", format_iso8601_utc(from, decimals)).add("to_utc", format_iso8601_utc(to, decimals)).add("step_s", step);
    const io::CsvTable table = studies::sun_series_table(samples, decimals);
    if (o.output.empty() || o.output == "-") {
      if (o.format == "netcdf") throw InputError("--format netcdf: needs -o FILE.nc");
      std::cout << table.to_string(prov);
      return;
    }
    if (o.format == "netcdf" || std::filesystem::path(o.output).extension() == ".nc") {  // CF time from jd_utc
      auto nc = io::sun_track_netcdf_options();
      nc.scalars["latitude"] = {base.latitude_deg, "degrees_north", "latitude"};
      nc.scalars["longitude"] = {base.longitude_deg, "degrees_east", "longitude"};
      io::write_table_netcdf(o.output, table, prov, nc);
    } else {
      table.write(o.output, prov);
    }
    std::cerr << "wrote " << o.output << " (" << samples.size() << " rows)\n";
    return;
  }
  if (o.time.empty()) throw InputError("--time is required (or --from/--to for a range)");
  const ParsedTime t = parse_iso8601(o.time);
  SunQuery q = base;
  q.jd_utc = t.jd_utc;
  q.day_offset_minutes = t.offset_minutes;
  const SunPosition s = sun_position(q);
  if (o.json) return print_json(studies::sun_position_json(q, s));
  std::cout << studies::sun_position_text(q, s);
}

}  // namespace

void register_sun_commands(CLI::App& app) {
  auto opt = std::make_shared<SunOptions>();
  CLI::App* sun = app.add_subcommand(
      "sun",
      "Sun position from latitude, longitude, height and a UTC time (NREL SPA, or the fast Grena 2012 "
      "algorithm), a time series (--from/--to/--step), or `sun accuracy`");
  studies::SunPlaceRequest& p = opt->place;
  sun->add_option("--lat", p.lat_deg, "geodetic latitude [deg], north positive");
  sun->add_option("--lon", p.lon_deg, "longitude [deg], east positive");
  sun->add_option("--height", p.height_m, "height above the WGS84 ellipsoid [m] (default 0)");
  sun->add_option("--time", opt->time, "UTC instant, ISO 8601, offsets accepted (2003-10-17T12:30:30-07:00)");
  sun->add_option("--pressure", p.pressure_hpa, "air pressure for refraction [hPa] (default 1013.25)");
  sun->add_option("--temperature", p.temperature_c, "air temperature for refraction [C] (default 15)");
  sun->add_option("--delta-t", p.delta_t_s, "TT - UT1 [s] (default: Espenak & Meeus model for the year)");
  sun->add_option("--delta-ut1", p.delta_ut1_s, "UT1 - UTC [s] (default 0; needed with --delta-t for 0.0003 deg)");
  sun->add_option("--algorithm", p.algorithm, "spa (default, years -2000..6000) | fast (Grena 2012 #5, 2010..2110)");
  add_json_flag(sun, opt->json);
  sun->add_option("--from", opt->from, "start of a time range (ISO 8601)");
  sun->add_option("--to", opt->to, "end of a time range (ISO 8601, inclusive)");
  sun->add_option("--step", opt->step, "step of the range: 90s, 10min, 1h, 1d (default 10min)");
  sun->add_option("-o,--output", opt->output, "CSV file for a range (default: standard output); a name ending in .nc "
                                              "writes netCDF-CF");
  sun->add_option("--format", opt->format, "csv (default) | netcdf: the range's file format (netCDF-CF, time "
                                           "coordinate from jd_utc)");

  static int year = 2024;
  static std::string latitudes = "-75,-45,0,30,60,85", output = "sun_accuracy";
  static std::size_t samples = 20000;
  CLI::App* accuracy = sun->add_subcommand(
      "accuracy", "Error of the fast algorithms against SPA over a year at several latitudes, against run time "
                  "(CSV method,setting,error_max_deg,error_rms_deg,time_s + log-log PNG)");
  accuracy->add_option("--year", year, "UTC year (2010..2110 for the fast algorithms; default 2024)");
  accuracy->add_option("--latitudes", latitudes, "comma-separated latitudes [deg]");
  accuracy->add_option("--samples", samples, "instants per latitude (default 20000)");
  accuracy->add_option("-o,--output", output, "output stem: writes STEM.csv and STEM.png");
  accuracy->callback([] {
    const std::vector<double> lats = parse_list(latitudes, "--latitudes");
    for (double l : lats) require_range(l, -90.0, 90.0, "--latitudes");
    if (year < 2010 || year > 2110)
      throw InputError("--year " + std::to_string(year) + " is outside 2010..2110, the fast algorithms' range");
    if (samples < 1 || samples > 10000000)
      throw InputError("--samples " + std::to_string(samples) + " is outside 1..10000000");
    check_study_stem(output, "-o");
    ProgressStep step("sun accuracy");
    for (const auto& f : studies::write_sun_accuracy(output, year, lats, samples)) std::cerr << "wrote " << f.string() << "\n";
  });
  sun->callback([sun, opt]() {
    if (!sun->got_subcommand("accuracy")) run_sun(*opt);
  });
}

}  // namespace atmosh::cli
