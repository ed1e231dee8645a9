// bind_studies.cpp — atmosh._atmosh.studies: the studies library (atmosh::studies) as
// tables. Each function returns {"columns": [...], "data": {column: [values]},
// "provenance": [(key, value), ...]} made from the library's own table of the study
// (elevation_study_table, io::study_table, ...: the table the CLI's CSV is written
// from), so columns (names and order) and values are the CSV's by construction;
// python/atmosh/studies.py makes the pandas.DataFrame.
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <variant>

#include "atmosh/atmo/multiple_scattering.hpp"
#include "atmosh/gi/driver.hpp"
#include "atmosh/atmo/sun_disc.hpp"
#include "atmosh/io/netcdf.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/prt/mesh.hpp"
#include "atmosh/scene/sweep.hpp"
#include "atmosh/studies/studies_prt.hpp"
#include "atmosh/studies/studies_rt.hpp"

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

// An error-against-run-time table (io::study_table: the columns of io::write_study).
py::dict study_dict(const io::StudySpec& spec, const std::vector<io::StudyRow>& rows, const io::Provenance& p) {
  return table_dict(io::study_table(spec, rows), p);
}

// One row of named values (the fields of a CLI command's --json object, in its order).
py::dict row_dict(const std::vector<std::pair<std::string, io::CsvCell>>& fields, const io::Provenance& p) {
  std::vector<std::string> cols;
  std::vector<io::CsvCell> row;
  for (const auto& [k, v] : fields) cols.push_back(k), row.push_back(v);
  io::CsvTable t(cols);
  t.add_row(std::move(row));
  return table_dict(t, p);
}

std::int64_t require_paths(std::int64_t n) {
  if (n < 1 || n > (std::int64_t{1} << 40)) throw InputError("paths " + std::to_string(n) + ": must be in [1, 2^40]");
  return n;
}

double require_in(double v, double lo, double hi, const std::string& what) {
  if (!(std::isfinite(v) && v >= lo && v <= hi))
    throw InputError(what + ": " + format_double(v) + " is out of range [" + format_double(lo) + ", " +
                     format_double(hi) + "]");
  return v;
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
        return table_dict(studies::elevation_study_table(st), st.provenance);
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
        return table_dict(studies::day_study_table(st), st.provenance);
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
        return table_dict(studies::converge_ms_table(c), c.provenance);  // ms_convergence.csv
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

  // ---- the optical-depth zenith sweep (the scene output kind optical-depth) ----------
  m.def(
      "zenith_sweep",
      [](const std::optional<std::string>& scene, const std::optional<std::string>& preset, double altitude_m) {
        if (scene && preset) throw InputError("give scene or preset, not both");
        require_in(altitude_m, 0.0, 1e9, "altitude_m");
        const atmo::AtmosphereSpec spec =
            scene ? scene::load_scene(*scene).atmosphere : atmo::preset(preset ? *preset : "earth-graphics");
        studies::ZenithSweep z;
        {
          py::gil_scoped_release release;
          z = studies::zenith_sweep(spec, altitude_m);
        }
        return py::make_tuple(table_dict(studies::zenith_sweep_table(z), z.provenance), z.lut_name);
      },
      py::arg("scene") = py::none(), py::arg("preset") = py::none(), py::arg("altitude_m") = 1000.0);

  // ---- the SH window study ----------------------------------------------------------
  m.def(
      "sh_windows",
      [](const std::vector<double>& channel, int bands) {
        if (bands < 1 || bands > 64) throw InputError("bands " + std::to_string(bands) + " must be in 1..64");
        if (channel.size() < static_cast<std::size_t>(bands) * static_cast<std::size_t>(bands))
          throw InputError("coefficients: " + std::to_string(channel.size()) + " given, " + std::to_string(bands) +
                           " bands need " + std::to_string(bands * bands));
        io::Provenance p = io::Provenance::current();
        p.add("sh_bands", std::to_string(bands));
        return table_dict(studies::sh_window_table(studies::sh_window_study(channel, bands)), p);
      },
      py::arg("coefficients"), py::arg("bands"));

  // ---- PRT converge ------------------------------------------------------------------
  m.def(
      "prt_converge",
      [](const std::string& builtin, const std::string& mesh_file, int resolution, int bands, const std::string& mode,
         int reference_strata, const std::vector<int>& strata, int threads, int width, int height,
         const std::array<double, 3>& view, const std::string& device, const std::vector<int>& depth_maps) {
        if (builtin.empty() == mesh_file.empty()) throw InputError("give either a mesh file or a built-in scene, not both");
        studies::PrtConvergenceOptions o;
        o.mode = sh::prt::parse_transfer_mode(mode);
        if (o.mode == sh::prt::TransferMode::unshadowed)
          throw InputError("mode: unshadowed transfer is exact (closed form); converge takes shadowed or interreflected");
        if (bands < 1 || bands > 16) throw InputError("bands: must be in 1..16, got " + std::to_string(bands));
        if (reference_strata < 1 || reference_strata > 2000)
          throw InputError("reference_samples: " + std::to_string(reference_strata) + " x itself is outside 1..4000000");
        for (int s : strata)
          if (s < 1 || s > 2000) throw InputError("strata: " + std::to_string(s) + " is not an integer in 1..2000");
        if (strata.empty()) throw InputError("strata: empty list");
        if (width < 1 || height < 1 || width > 4096 || height > 4096)
          throw InputError("pixels: " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1..4096");
        if (view[0] == 0 && view[1] == 0 && view[2] == 0) throw InputError("view: zero vector");
        o.bands = bands, o.reference_strata = reference_strata, o.strata = strata;
        o.threads = resolve_threads(threads);
        o.width = width, o.height = height, o.view = {view[0], view[1], view[2]};
        o.device = device, o.depth_maps = depth_maps;
        o.cpu_only_note = "not run (device cpu)";
        const prt::Mesh mesh = builtin.empty() ? prt::load_mesh(mesh_file) : prt::builtin_scene(builtin, resolution);
        studies::StudyTable t;
        {
          py::gil_scoped_release release;
          t = studies::prt_convergence(mesh, o);
        }
        return study_dict(t.spec, t.rows, t.provenance);
      },
      py::arg("builtin"), py::arg("mesh_file"), py::arg("resolution"), py::arg("bands"), py::arg("mode"),
      py::arg("reference_strata"), py::arg("strata"), py::arg("threads"), py::arg("width"), py::arg("height"),
      py::arg("view"), py::arg("device"), py::arg("depth_maps"));

  // ---- GI converge (atmosh gi converge) ---------------------------------------------------
  m.def(
      "gi_converge",
      [](const std::string& builtin, const std::string& mesh_file, const std::string& light, int width, int height,
         const std::vector<int>& bands, const std::vector<int>& grids, const std::vector<int>& path_samples,
         const std::vector<int>& radiosity_grids, const std::vector<int>& radiosity_bands,
         const std::vector<int>& radiosity_bounces, const std::vector<int>& lpv_grids, int reference_samples,
         int samples, int cube_size, int pixel_samples, unsigned long long seed, int threads, const std::string& dir) {
        gi::SceneRequest req;
        req.builtin = builtin, req.mesh = mesh_file, req.light = light;
        gi::ConvergeOptions c;
        c.method.samples = samples, c.method.cube_size = cube_size, c.method.pixel_samples = pixel_samples;
        c.method.seed = seed, c.method.threads = threads;
        gi::check_render_request(req, c.method);
        if (width < 1 || height < 1 || width > 16384 || height > 16384)
          throw InputError("size: " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1..16384");
        if (reference_samples < 2 || reference_samples > 10000000)
          throw InputError("reference_samples: must be in 2..10000000, got " + std::to_string(reference_samples));
        if (bands.empty() || grids.empty()) throw InputError("bands, grids: give at least one value each");
        c.bands = bands, c.grids = grids, c.path_samples = path_samples, c.reference_samples = reference_samples;
        c.study.radiosity_grids = radiosity_grids, c.study.radiosity_bands = radiosity_bands;
        c.study.radiosity_bounces = radiosity_bounces, c.study.lpv_grids = lpv_grids;
        c.method.threads = resolve_threads(threads);
        const gi::Scene s = gi::scene_from_request(req);
        std::filesystem::create_directories(dir);
        gi::ConvergeStudy st;
        {
          py::gil_scoped_release release;
          st = gi::converge_methods(s, width, height, c, dir);
        }
        return study_dict(st.spec, st.rows, st.provenance);
      },
      py::arg("builtin"), py::arg("mesh_file"), py::arg("light"), py::arg("width"), py::arg("height"),
      py::arg("bands"), py::arg("grids"), py::arg("path_samples"), py::arg("radiosity_grids"),
      py::arg("radiosity_bands"), py::arg("radiosity_bounces"), py::arg("lpv_grids"), py::arg("reference_samples"),
      py::arg("samples"), py::arg("cube_size"), py::arg("pixel_samples"), py::arg("seed"), py::arg("threads"),
      py::arg("dir"));

  // ---- Monte-Carlo radiative transfer (atmosh rt slab | rt sky) ------------------------
  m.def(
      "rt_slab",
      [](double tau, double omega, const std::string& phase, double g, double ground_albedo, double mu0, double mu,
         double phi_deg, int orders, long long paths, unsigned long long seed, int threads) {
        atmo::SlabSpec s;
        if (phase == "isotropic") s.phase = atmo::SlabPhase::Isotropic;
        else if (phase == "hg") s.phase = atmo::SlabPhase::HenyeyGreenstein;
        else if (phase == "rayleigh") s.phase = atmo::SlabPhase::Rayleigh;
        else throw InputError("phase: '" + phase + "' is not isotropic, hg or rayleigh");
        s.tau = require_in(tau, 1e-300, 1e6, "tau");
        s.omega = require_in(omega, 0.0, 1.0, "omega");
        s.g = require_in(g, -0.999999, 0.999999, "g");
        s.ground_albedo = require_in(ground_albedo, 0.0, 1.0, "ground_albedo");
        require_in(mu0, 1e-6, 1.0, "mu0");
        require_in(mu, 1e-6, 1.0, "mu");
        require_in(phi_deg, -360.0, 360.0, "phi_deg");
        if (orders < 0) throw InputError("orders " + std::to_string(orders) + " must be >= 0");
        atmo::RtOptions run;
        run.paths = require_paths(paths);
        run.seed = seed;
        run.threads = resolve_threads(threads);
        run.max_orders = orders;
        atmo::SlabResult r;
        {
          py::gil_scoped_release release;
          r = studies::rt_slab(s, mu0, mu, phi_deg, run);
        }
        // The fields of `atmosh rt slab --json`, in its order.
        return row_dict({{"tau", s.tau}, {"omega", s.omega}, {"phase", phase}, {"g", s.g},
                         {"ground_albedo", s.ground_albedo}, {"mu0", mu0}, {"mu", mu}, {"phi_deg", phi_deg},
                         {"reflection", r.reflection}, {"reflection_stderr", r.reflection_stderr},
                         {"transmission", r.transmission}, {"transmission_stderr", r.transmission_stderr},
                         {"paths", std::int64_t{r.paths}}, {"seed", static_cast<std::int64_t>(run.seed)},
                         {"orders", std::int64_t{run.max_orders}}, {"threads", std::int64_t{run.threads}},
                         {"time_s", r.time_s}},
                        io::Provenance::current());
      },
      py::arg("tau"), py::arg("omega"), py::arg("phase"), py::arg("g"), py::arg("ground_albedo"), py::arg("mu0"),
      py::arg("mu"), py::arg("phi_deg"), py::arg("orders"), py::arg("paths"), py::arg("seed"), py::arg("threads"));

  m.def(
      "rt_sky",
      [](const std::optional<std::string>& scene, double sun_elevation_deg, double sun_azimuth_deg,
         double view_elevation_deg, double view_azimuth_deg, double height_m, double ground_albedo, int orders,
         const std::string& sun_depth, const std::string& line_estimate, long long paths, unsigned long long seed,
         int threads, const std::string& guide) {
        require_in(sun_elevation_deg, -90.0, 90.0, "sun_elevation_deg");
        require_in(view_elevation_deg, -90.0, 90.0, "view_elevation_deg");
        require_in(sun_azimuth_deg, -360.0, 360.0, "sun_azimuth_deg");
        require_in(view_azimuth_deg, -360.0, 360.0, "view_azimuth_deg");
        require_in(height_m, 0.0, 1e9, "height_m");
        if (ground_albedo != -1) require_in(ground_albedo, 0.0, 1.0, "ground_albedo");
        if (orders < 0) throw InputError("orders " + std::to_string(orders) + " must be >= 0");
        atmo::RtSkyOptions so;
        if (sun_depth == "table") so.sun_depth = atmo::RtSunDepth::Table;
        else if (sun_depth == "exact") so.sun_depth = atmo::RtSunDepth::Exact;
        else throw InputError("sun_depth: '" + sun_depth + "' is not table or exact");
        so.line_estimate = studies::rt_switch(line_estimate, "line_estimate");
        so.guide = studies::rt_switch(guide, "guide");
        so.run.paths = require_paths(paths);
        so.run.seed = seed;
        so.run.threads = resolve_threads(threads);
        so.run.max_orders = orders;
        so.ground_albedo = ground_albedo;
        const auto s = scene_or_default(scene);
        atmo::RtSkyResult r;
        {
          py::gil_scoped_release release;
          r = studies::rt_sky_view(s.atmosphere,
                                   {sun_elevation_deg, sun_azimuth_deg, view_elevation_deg, view_azimuth_deg, height_m},
                                   so);
        }
        io::CsvTable t({"wavelength_nm", "radiance_w_m2_sr_nm", "radiance_stderr_w_m2_sr_nm"});
        for (std::size_t i = 0; i < r.wavelengths_nm.size(); ++i)
          t.add_row({r.wavelengths_nm[i], r.radiance[i], r.radiance_stderr[i]});
        py::dict out = table_dict(t, io::Provenance::current());
        // The scalar fields of `atmosh rt sky --json`.
        py::dict sc;
        sc["scene"] = s.source;
        sc["sun_elevation_deg"] = sun_elevation_deg, sc["sun_azimuth_deg"] = sun_azimuth_deg;
        sc["view_elevation_deg"] = view_elevation_deg, sc["view_azimuth_deg"] = view_azimuth_deg;
        sc["observer_height_m"] = height_m;
        sc["ground_albedo"] = ground_albedo >= 0 ? ground_albedo : s.atmosphere.planet.ground_albedo;
        sc["luminance_cd_m2"] = r.luminance, sc["luminance_stderr_cd_m2"] = r.luminance_stderr;
        sc["xyz"] = std::vector<double>{r.xyz.X, r.xyz.Y, r.xyz.Z};
        sc["xyz_stderr"] = std::vector<double>{r.xyz_stderr.X, r.xyz_stderr.Y, r.xyz_stderr.Z};
        sc["paths"] = r.paths, sc["paths_per_wavelength"] = r.paths_per_wavelength, sc["mean_orders"] = r.mean_orders;
        sc["orders"] = so.run.max_orders, sc["seed"] = so.run.seed, sc["threads"] = so.run.threads;
        sc["sun_depth"] = sun_depth, sc["line_estimate"] = line_estimate, sc["guide"] = guide;
        sc["sun_depth_rel_error"] = r.sun_depth_rel_error, sc["time_s"] = r.time_s;
        out["scalars"] = sc;
        return out;
      },
      py::arg("scene"), py::arg("sun_elevation_deg"), py::arg("sun_azimuth_deg"), py::arg("view_elevation_deg"),
      py::arg("view_azimuth_deg"), py::arg("height_m"), py::arg("ground_albedo"), py::arg("orders"),
      py::arg("sun_depth"), py::arg("line_estimate"), py::arg("paths"), py::arg("seed"), py::arg("threads"),
      py::arg("guide"));

  // ---- a whole sweep file (atmosh sweep FILE -o DIR) -----------------------------------
  m.def(
      "sweep_file",
      [](const std::string& file, const std::string& out_dir, int shells, int segments, int samples, int threads,
         bool netcdf) {
        const auto q = settings(shells, segments, samples, threads);
        const auto spec = scene::load_sweep(file);  // InputError for a bad sweep before any work
        scene::SweepOptions o;
        o.out_dir = out_dir;
        o.threads = resolve_threads(threads);
        o.settings = studies::sweep_settings(q);
        scene::SweepResult r;
        {
          py::gil_scoped_release release;
          r = scene::run_sweep(spec, [q](const scene::Scene& s) { return studies::sweep_point(s, q); }, o);
          if (netcdf) {
            std::filesystem::path nc = r.csv;
            io::write_sweep_csv_as_netcdf(r.csv, nc.replace_extension(".nc"), spec.keys);
          }
        }
        // The sweep's table is its result file (the journal's rows in point order).
        io::Provenance p;
        const io::CsvTable t = io::table_from_csv(io::read_csv(r.csv), p);
        py::dict out = table_dict(t, p);
        out["keys"] = spec.keys;
        out["csv"] = r.csv.string();
        return out;
      },
      py::arg("file"), py::arg("out_dir"), py::arg("shells") = 32, py::arg("segments") = 16, py::arg("samples") = 2,
      py::arg("threads") = 0, py::arg("netcdf") = false);
}

}  // namespace atmosh::python
