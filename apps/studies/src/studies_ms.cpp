// The multiple-scattering convergence driver (see atmosh/studies/ms.hpp).
#include "atmosh/studies/ms.hpp"

#include <string>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/sky_image.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/study.hpp"

namespace atmosh::studies {

namespace fs = std::filesystem;
using namespace atmosh::atmo;

ConvergeMs converge_ms(const scene::Scene& s, const ConvergeMsOptions& o) {
  const std::int64_t paths = o.paths != 0 ? o.paths : (o.quick ? 16000 : 128000);
  if (paths < 1 || paths > (std::int64_t{1} << 40))
    throw InputError("--paths " + std::to_string(paths) + ": must be in [1, 2^40]");
  const Atmosphere atm(s.atmosphere);
  const SolarSpectrum solar = solar_spectrum_for_bins(s.atmosphere.spectrum);
  ConvergeMs c;
  c.paths = paths;
  MsStudyOptions& so = c.options;
  so.reference_run.paths = paths;
  so.reference_run.seed = o.seed;
  so.settings = ms_study_default_settings(o.quick);
  if (o.quick) {
    // A few seconds: the zenith and the horizon away from the sun, the sun above the horizon.
    so.views = {{90, 0}, {5, 180}};
    so.sun_elevations_deg = {30, 10};
    so.timing_repetitions = 1;
  }
  c.result = ms_convergence_study(atm, solar, so);
  const MsStudyResult& r = c.result;
  auto& prov = c.provenance;
  prov = io::Provenance::current();
  prov.add("scene", s.source);
  prov.add("reference", "Monte-Carlo radiative transfer (atmosh rt sky: every order, ground albedo of the scene), " +
                            std::to_string(paths) + " paths per row, seed " + std::to_string(o.seed));
  prov.add("reference_time_s", r.reference_time_s);
  prov.add("rows", static_cast<double>(r.points.size()));
  prov.add("views", "elevation/azimuth from the sun [deg]: see ms_convergence_points.csv");
  prov.add("bands", "all; day = sun >= 0 deg; civil = -6 <= sun < 0 deg; night = sun < -6 deg");
  prov.add("error", "relative error of the luminance (CIE Y) against the reference's mean; "
                    "error_max_sigma = max |L - L_mc| / stderr_mc; error_max_rel_minus_3sigma = max (e - 3 rel stderr)");
  prov.add("time_s", "table build + evaluation of every row (wall clock, all threads; fastest of " +
                         std::to_string(so.timing_repetitions) + " runs, one run for settings over 2 s)");
  return c;
}

io::CsvTable converge_ms_table(const ConvergeMs& c) {
  io::CsvTable csv({"method", "setting", "band", "error_max_rel", "error_rms_rel", "time_s",
                    "reference_rel_stderr_max", "error_max_sigma", "error_max_rel_minus_3sigma", "build_time_s",
                    "eval_time_s", "rows", "rows_skipped"});
  for (const auto& row : c.result.rows)
    csv.add_row({row.method, row.setting, row.band, row.error_max_rel, row.error_rms_rel, row.time_s,
                 row.reference_rel_stderr_max, row.error_max_sigma, row.error_max_rel_minus_3sigma,
                 row.build_time_s, row.eval_time_s, std::int64_t{row.rows}, std::int64_t{row.rows_skipped}});
  return csv;
}

std::vector<fs::path> write_converge_ms(const ConvergeMs& c, const fs::path& dir, bool netcdf) {
  const MsStudyResult& r = c.result;
  const auto& prov = c.provenance;
  const fs::path stem = dir / "ms_convergence";
  std::vector<io::StudyRow> plot_rows;
  for (const auto& row : r.rows) {
    // The plot: day and civil twilight (night rows, reference stderr 3-25 %, are in the CSV).
    if (row.band == "day" || row.band == "civil")
      plot_rows.push_back({row.method + " (" + row.band + ")", row.setting, row.error_max_rel, row.error_rms_rel,
                           row.time_s, {}});
  }
  fs::path csv_file = stem;
  csv_file += ".csv";
  io::NetcdfTableOptions nc;
  nc.title = "atmosh converge ms: the sky's scattering methods against the Monte-Carlo reference";
  std::vector<fs::path> written = io::write_table_files(csv_file, converge_ms_table(c), prov, netcdf, nc);

  io::StudySpec spec;
  spec.title = "Sky scattering methods against Monte-Carlo RT: luminance error vs run time (sun >= -6 deg)";
  spec.error_axis_label = "max relative error of luminance";
  spec.time_axis_label = "table build + evaluation [s]";
  fs::path png = stem;
  png += ".png";
  io::write_plot_png(png, io::study_plot_spec(spec, plot_rows));
  written.push_back(png);

  std::vector<std::string> cols = {"sun_elevation_deg", "view_elevation_deg", "view_relative_azimuth_deg",
                                   "reference_luminance_cd_m2", "reference_luminance_stderr_cd_m2"};
  for (const auto& st : c.options.settings) cols.push_back(st.method + " " + st.setting);
  io::CsvTable pts(cols);
  for (const auto& p : r.points) {
    std::vector<io::CsvCell> row = {p.sun_elevation_deg, p.view_elevation_deg, p.view_relative_azimuth_deg,
                                    p.reference_luminance, p.reference_luminance_stderr};
    for (double l : p.luminance) row.push_back(l);
    pts.add_row(row);
  }
  const fs::path pts_file = dir / "ms_convergence_points.csv";
  pts.write(pts_file, prov);
  written.push_back(pts_file);
  return written;
}

std::vector<fs::path> demo_ms(const fs::path& dir) {
  ConvergeMsOptions o;
  o.quick = true;  // the full study takes minutes (docs/radiative-transfer.md): `atmosh converge ms`
  return write_converge_ms(converge_ms(scene::default_scene(), o), dir);
}

}  // namespace atmosh::studies
