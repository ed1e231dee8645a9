// bind_studies.cpp — atmosh._atmosh.studies: the studies library (atmosh::studies) as
// tables. Each function returns {"columns": [...], "data": {column: [values]},
// "provenance": [(key, value), ...]} with the columns (names and order) of the CSV the
// CLI writes for the same study; python/atmosh/studies.py makes the pandas.DataFrame.
#include <limits>
#include <optional>
#include <string>
#include <variant>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "atmosh/studies/ms.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "atmosh/studies/studies_sh.hpp"
#include "atmosh/studies/studies_sun.hpp"
#include "common.hpp"

namespace atmosh::python {
namespace {

scene::Scene scene_or_default(const std::optional<std::string>& file) {
  return file ? scene::load_scene(*file) : scene::default_scene();
}

// Columns of cells (double, integer or string) as Python lists, in the table's order.
py::dict table_dict(const io::CsvTable& t, const io::Provenance& p) {
  py::dict data;
  for (std::size_t c = 0; c < t.columns().size(); ++c) {
    py::list col;
    for (const auto& row : t.rows()) std::visit([&](const auto& v) { col.append(v); }, row[c]);
    data[py::str(t.columns()[c])] = col;
  }
  py::list prov;
  for (const auto& [k, v] : p.entries) prov.append(py::make_tuple(k, v));
  py::dict out;
  out["columns"] = t.columns();
  out["data"] = data;
  out["provenance"] = prov;
  return out;
}

// An error-against-run-time table with the columns of io::write_study.
py::dict study_dict(const io::StudySpec& spec, const std::vector<io::StudyRow>& rows, const io::Provenance& p) {
  std::vector<std::string> cols = {"method", "setting", spec.error_max_column, spec.error_rms_column, spec.time_column};
  cols.insert(cols.end(), spec.extra_columns.begin(), spec.extra_columns.end());
  io::CsvTable t(cols);
  for (const auto& r : rows) {
    std::vector<io::CsvCell> row = {r.method, r.setting, r.error_max, r.error_rms, r.time_s};
    for (std::size_t i = 0; i < spec.extra_columns.size(); ++i)
      row.emplace_back(i < r.extras.size() ? r.extras[i] : std::numeric_limits<double>::quiet_NaN());
    t.add_row(std::move(row));
  }
  return table_dict(t, p);
}

studies::SkySettings settings(int shells, int segments, int samples, int threads) {
  studies::SkySettings q;
  if (shells < 2) throw InputError("shells " + std::to_string(shells) + " must be >= 2");
  if (segments < 1) throw InputError("segments " + std::to_string(segments) + " must be >= 1");
  if (samples < 1) throw InputError("samples " + std::to_string(samples) + " must be >= 1");
  if (threads < 0) throw InputError("threads " + std::to_string(threads) + " must be >= 0");
  q.shells = shells, q.segments = segments, q.samples = samples, q.threads = threads;
  return q;
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def(
      "sun_elevation",
      [](const std::optional<std::string>& scene, double from_deg, double to_deg, double step_deg, double azimuth_deg,
         int shells, int segments, int samples, int threads) {
        studies::ElevationStudyOptions o;
        o.from_deg = from_deg, o.to_deg = to_deg, o.step_deg = step_deg, o.azimuth_deg = azimuth_deg;
        o.sky = settings(shells, segments, samples, threads);
        const auto s = scene_or_default(scene);
        studies::ElevationStudy st;
        {
          py::gil_scoped_release release;
          st = studies::sun_elevation_study(s, o);
        }
        std::vector<std::string> cols = {"sun_elevation_deg"};
        cols.insert(cols.end(), studies::sky_summary_columns().begin(), studies::sky_summary_columns().end());
        io::CsvTable t(cols);
        for (std::size_t i = 0; i < st.elevations_deg.size(); ++i) {
          std::vector<io::CsvCell> r = {st.elevations_deg[i]};
          for (double v : studies::sky_summary_values(st.rows[i])) r.emplace_back(v);
          t.add_row(std::move(r));
        }
        return table_dict(t, st.provenance);
      },
      py::arg("scene") = py::none(), py::arg("from_deg") = -18.0, py::arg("to_deg") = 90.0, py::arg("step_deg") = 1.0,
      py::arg("azimuth_deg") = 180.0, py::arg("shells") = 32, py::arg("segments") = 16, py::arg("samples") = 2,
      py::arg("threads") = 0);

  m.def(
      "day",
      [](const std::optional<std::string>& scene, double lat, double lon, double height_m, const std::string& date,
         double step_s, const std::string& step_text, int shells, int segments, int samples, int threads) {
        if (!(lat >= -90 && lat <= 90)) throw InputError("lat " + format_double(lat) + " is outside [-90, 90]");
        if (!(lon >= -180 && lon <= 180)) throw InputError("lon " + format_double(lon) + " is outside [-180, 180]");
        if (!(step_s > 0)) throw InputError("step_s " + format_double(step_s) + " must be > 0");
        if (date.size() != 10) throw InputError("date '" + date + "' is not YYYY-MM-DD");
        studies::DayStudyOptions o;
        o.latitude_deg = lat, o.longitude_deg = lon, o.height_m = height_m, o.date = date;
        o.step_s = step_s, o.step_text = step_text, o.frames = false;
        o.sky = settings(shells, segments, samples, threads);
        const auto s = scene_or_default(scene);
        studies::DayStudy st;
        {
          py::gil_scoped_release release;
          st = studies::day_study(s, o);
        }
        std::vector<std::string> cols = {"time_utc", "sun_elevation_deg", "sun_azimuth_deg",
                                         "apparent_sun_elevation_deg"};
        cols.insert(cols.end(), studies::sky_summary_columns().begin(), studies::sky_summary_columns().end());
        io::CsvTable t(cols);
        for (const auto& r : st.rows) {
          std::vector<io::CsvCell> c = {r.time_utc, r.sun.elevation_deg, r.sun.azimuth_deg,
                                        r.sun.apparent_elevation_deg};
          for (double v : studies::sky_summary_values(r.summary)) c.emplace_back(v);
          t.add_row(std::move(c));
        }
        return table_dict(t, st.provenance);
      },
      py::arg("scene") = py::none(), py::arg("lat"), py::arg("lon"), py::arg("height_m") = 0.0, py::arg("date"),
      py::arg("step_s") = 600.0, py::arg("step_text") = "10min", py::arg("shells") = 32, py::arg("segments") = 16,
      py::arg("samples") = 2, py::arg("threads") = 0);

  m.def(
      "sweep_point",
      [](const std::optional<std::string>& scene, int shells, int segments, int samples, int threads) {
        const auto s = scene_or_default(scene);
        const auto q = settings(shells, segments, samples, threads);
        scene::SweepOutputs out;
        {
          py::gil_scoped_release release;
          out = studies::sweep_point(s, q);
        }
        py::list cols, vals;
        for (const auto& [k, v] : out) cols.append(k), vals.append(v);
        return py::make_tuple(cols, vals);
      },
      py::arg("scene") = py::none(), py::arg("shells") = 32, py::arg("segments") = 16, py::arg("samples") = 2,
      py::arg("threads") = 0);

  m.def(
      "converge_sky",
      [](const std::optional<std::string>& scene, bool quick, int threads) {
        if (threads < 0) throw InputError("threads " + std::to_string(threads) + " must be >= 0");
        const auto s = scene_or_default(scene);
        studies::ConvergeSky c;
        {
          py::gil_scoped_release release;
          c = studies::converge_sky(s, {quick, threads});
        }
        return study_dict(c.spec, c.rows, c.provenance);
      },
      py::arg("scene") = py::none(), py::arg("quick") = false, py::arg("threads") = 0);

  m.def(
      "converge_lut",
      [](const std::optional<std::string>& scene, const std::optional<std::string>& preset, bool quick,
         const std::vector<int>& shells, const std::vector<int>& directions) {
        if (scene && preset) throw InputError("give scene or preset, not both");
        // As the CLI: the scene's atmosphere, else the preset (default earth-graphics).
        atmo::AtmosphereSpec spec = scene ? scene::load_scene(*scene).atmosphere : atmo::preset(preset ? *preset : "earth-graphics");
        studies::LutConvergenceOptions o;
        o.quick = quick;
        if (!shells.empty()) o.shells = shells;
        if (!directions.empty()) o.directions = directions;
        studies::StudyTable t;
        {
          py::gil_scoped_release release;
          t = studies::lut_convergence(spec, o);
        }
        return study_dict(t.spec, t.rows, t.provenance);
      },
      py::arg("scene") = py::none(), py::arg("preset") = py::none(), py::arg("quick") = false,
      py::arg("shells") = std::vector<int>{}, py::arg("directions") = std::vector<int>{});

  m.def(
      "sun_accuracy",
      [](int year, const std::vector<double>& latitudes_deg, long long samples) {
        if (samples < 1) throw InputError("samples " + std::to_string(samples) + " must be >= 1");
        studies::StudyTable t;
        {
          py::gil_scoped_release release;
          t = studies::sun_accuracy_table(year, latitudes_deg, static_cast<std::size_t>(samples));
        }
        return study_dict(t.spec, t.rows, t.provenance);
      },
      py::arg("year") = 2024, py::arg("latitudes_deg") = std::vector<double>{-75, -45, 0, 30, 60, 85},
      py::arg("samples") = 20000);
  m.def(
      "converge_ms",
      [](const std::optional<std::string>& scene, bool quick, long long paths, unsigned long long seed) {
        const auto s = scene_or_default(scene);
        studies::ConvergeMsOptions o;
        o.quick = quick, o.paths = paths, o.seed = seed;
        studies::ConvergeMs c;
        {
          py::gil_scoped_release release;
          c = studies::converge_ms(s, o);
        }
        // The columns of ms_convergence.csv (studies::write_converge_ms).
        io::CsvTable t({"method", "setting", "band", "error_max_rel", "error_rms_rel", "time_s",
                        "reference_rel_stderr_max", "error_max_sigma", "error_max_rel_minus_3sigma", "build_time_s",
                        "eval_time_s", "rows", "rows_skipped"});
        for (const auto& row : c.result.rows)
          t.add_row({row.method, row.setting, row.band, row.error_max_rel, row.error_rms_rel, row.time_s,
                     row.reference_rel_stderr_max, row.error_max_sigma, row.error_max_rel_minus_3sigma,
                     row.build_time_s, row.eval_time_s, std::int64_t{row.rows}, std::int64_t{row.rows_skipped}});
        return table_dict(t, c.provenance);
      },
      py::arg("scene") = py::none(), py::arg("quick") = false, py::arg("paths") = 0, py::arg("seed") = 1);

  m.def(
      "converge_sh",
      [](const std::string& exr, int bands, bool quick, unsigned long long seed, const std::string& layout) {
        if (bands < 1) throw InputError("bands " + std::to_string(bands) + " must be >= 1");
        if (layout != "auto" && layout != "equirect" && layout != "cross")
          throw InputError("layout: '" + layout + "' is not auto, equirect or cross");
        const studies::ShImage image = studies::load_sh_image(exr, layout, std::size_t{4} << 30);
        studies::StudyTable t;
        {
          py::gil_scoped_release release;
          t = studies::converge_sh(image, bands, quick, seed, exr);
        }
        return study_dict(t.spec, t.rows, t.provenance);
      },
      py::arg("exr"), py::arg("bands"), py::arg("quick") = false, py::arg("seed") = 1, py::arg("layout") = "auto");
}

}  // namespace atmosh::python
