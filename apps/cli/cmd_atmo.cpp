// atmosh optical-depth, phase, stability, converge lut; and the atmosphere part
// of the main job (demo_atmo).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/stiff_cases.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/scene/scene.hpp"
#include "cli_common.hpp"
#include "progress.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/sky.hpp"
#endif

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

AtmosphereSpec load_atmosphere(const std::string& scene_file, const std::string& preset_name) {
  if (!scene_file.empty() && !preset_name.empty()) throw InputError("--scene and --preset: give only one");
  if (!scene_file.empty()) return scene::load_scene(scene_file).atmosphere;
  return preset(preset_name.empty() ? "earth-graphics" : preset_name);
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ---- converge lut --------------------------------------------------------------

struct Ray {
  double r, mu;
};

// Rays for the study: altitudes from the ground to the top (including just
// above the ground and just below the top), directions on a uniform grid in mu
// plus grazing rays at 1e-9..3e-2 either side of the horizon and of mu = 0, and
// rays whose tangent point lies 1 mm..1 km above the ground. Then, at every kink
// of a present profile among its 32 strongest (tent corners, outstanding table nodes: where a column's derivative in
// the ray's direction jumps and table interpolation is worst), near-horizontal rays
// from 100 m below and above it and rays from just below the top whose tangent point
// lies 1 m and 100 m either side of it (kink_probe_rays); and 1000 seeded random rays.
std::vector<Ray> study_rays(const Atmosphere& atm) {
  const double R = atm.ground_radius(), top = atm.top_altitude();
  std::vector<Ray> rays;
  std::vector<double> hs = {0.0, 1.0, 10.0, 100.0, 500.0, 1000.0, 2000.0, 5000.0, 10e3, 20e3, 35e3};
  for (auto& f : {0.5, 0.8, 0.99, 0.99999}) hs.push_back(f * top);
  for (double h : hs) {
    if (h > top) continue;
    double r = R + h, muh = shared::mu_horizon(r, R);
    std::vector<double> mus;
    for (int i = 0; i <= 40; ++i) mus.push_back(-1.0 + 2.0 * i / 40.0);
    for (double e : {1e-9, 1e-7, 1e-5, 1e-3, 1e-2, 3e-2}) {
      mus.insert(mus.end(), {muh + e, muh - e, e, -e});
    }
    for (double th : {1e-3, 1.0, 100.0, 1000.0})
      if (r > R + th) mus.push_back(-std::sqrt(1.0 - std::pow((R + th) / r, 2.0)));
    for (double mu : mus)
      if (mu >= -1.0 && mu <= 1.0) rays.push_back({r, mu});
  }
  for (const ProbeRay& p : kink_probe_rays(atm)) rays.push_back({p.r, p.mu});
  // And 1000 random rays (fixed seed; uniform doubles from the top 53 bits, so the
  // set is the same on every platform): altitudes uniform in [0, top) for half of
  // them, top u^3 (crowded near the ground) for the other half; mu uniform in
  // [-1, 1], every third within 0.025 of the horizontal. The fixed altitudes above
  // missed rays such as those looking up from 97 km (the default scene's worst).
  std::mt19937_64 rng(20261122);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
  for (int i = 0; i < 1000; ++i) {
    const double u = uniform(), v = uniform();
    const double h = (i % 2 != 0) ? u * top : top * u * u * u;
    const double mu = (i % 3 == 0) ? 0.05 * (v - 0.5) : 2.0 * v - 1.0;
    rays.push_back({R + h, mu});
  }
  return rays;
}

// Kinks the tables subtracted from their tabulated densities (LutOptions::subtracted_kinks).
int subtracted_kinks(const OpticalDepthLut& lut) {
  int n = 0;
  for (int c = 0; c < 3; ++c) n += std::max(0, lut.subtracted(c).nodes() - 1);  // p's nodes: 0 and the kinks
  return n;
}

std::vector<fs::path> run_converge_lut(const AtmosphereSpec& spec, const std::vector<int>& shells,
                                       const std::vector<int>& directions, bool quick, const fs::path& stem,
                                       const std::string& device = "cpu") {
  const DeviceRequest request = check_device(device);
  Atmosphere atm(spec);
  std::optional<GpuUnusable> unusable;
#ifdef ATMOSH_HAVE_GPU
  // With a GPU, every setting gets a second row: the same tables built by the
  // GPU table pass (gpu::build_lut_tables), looked up by the same CPU code.
  std::unique_ptr<gpu::Context> ctx;
  if (request != DeviceRequest::cpu) {
    try {
      ctx = std::make_unique<gpu::Context>();
    } catch (const gpu::Unavailable& e) {
      unusable = GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}};
    }
  }
#else
  unusable = GpuUnusable{GpuUnusable::Why::not_built, {}, {}};
#endif
  device_notice(resolve_device(request, unusable, "building the tables on the CPU only"));
  OpticalDepthReference ref(atm);
  auto rays = study_rays(atm);
  auto k = atm.coefficients_at(550.0);
  Coefficients ks = k;  // Rayleigh + Mie only (smooth profiles)
  ks.extinction[kOzone] = 0.0;
  std::vector<double> exact(rays.size()), exact_smooth(rays.size());
  std::vector<bool> ground(rays.size());
  double ref_err = 0.0, ref_err_sq = 0.0;
  int ref_n = 0;
  auto t0 = Clock::now();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    auto c = ref.column(rays[i].r, rays[i].mu);
    exact[i] = optical_depth(k, c.column);
    exact_smooth[i] = optical_depth(ks, c.column);
    ground[i] = c.hits_ground;
    if (exact[i] > 0.0) {
      const double e = optical_depth(k, c.error) / exact[i];
      ref_err = std::max(ref_err, e);
      ref_err_sq += e * e;
      ++ref_n;
    }
  }
  const double ref_err_rms = ref_n > 0 ? std::sqrt(ref_err_sq / ref_n) : 0.0;
  double ref_time = seconds_since(t0);
  io::StudySpec ss;
  ss.title = "Optical depth LUT (Nishita shells) vs exact reference, " + spec.name + ", 550 nm";
  ss.extra_columns = {"shells", "directions", "rays", "build_time_s", "lookup_time_ns", "table_bytes",
                      "flag_mismatches", "error_max_rel_rayleigh_mie", "error_estimate_rel", "subtracted_kinks"};
  std::vector<io::StudyRow> rows;
  rows.push_back({"reference", "adaptive G7-K15 (estimated error)", ref_err, ref_err_rms, ref_time,
                  {0, 0, double(rays.size()), 0.0, 1e9 * ref_time / rays.size(), 0, 0, ref_err, ref_err, 0}});
  std::vector<std::pair<int, int>> settings;
  if (quick) {
    settings = {{16, 32}, {40, 64}};  // a coarse table and the default
  } else {
    for (int s : shells)
      for (int d : directions) settings.push_back({s, d});
  }
  // Error of one table set over all rays, and its per-lookup time.
  auto evaluate = [&](const OpticalDepthLut& lut, const std::string& method, int s, int d, double build_s) {
    double emax = 0.0, esum = 0.0, emax_smooth = 0.0;
    int n = 0, mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      auto c = lut.view(rays[i].r, rays[i].mu);
      mismatches += c.hits_ground != ground[i];
      if (exact_smooth[i] > 0.0)
        emax_smooth = std::max(emax_smooth, std::abs(optical_depth(ks, c.column) - exact_smooth[i]) / exact_smooth[i]);
      if (!(exact[i] > 0.0)) continue;
      double e = std::abs(optical_depth(k, c.column) - exact[i]) / exact[i];
      emax = std::max(emax, e);
      esum += e * e;
      ++n;
    }
    // Lookup timing: all rays, repeated to at least ~20 ms; the fastest of 3 such
    // passes (the wall clock of a shared machine stalls at random).
    int reps = std::max(1, static_cast<int>(2e6 / rays.size()));
    double sink = 0.0, lookup_s = 0.0;
    for (int pass = 0; pass < 3; ++pass) {
      auto t1 = Clock::now();
      for (int rep = 0; rep < reps; ++rep)
        for (const auto& ray : rays) sink += lut.view(ray.r, ray.mu).column[kRayleigh];
      const double t = seconds_since(t1) / (double(reps) * rays.size());
      lookup_s = pass == 0 ? t : std::min(lookup_s, t);
    }
    if (sink == -1.0) std::printf(" ");
    rows.push_back({method, std::to_string(s) + "x" + std::to_string(d), emax, std::sqrt(esum / std::max(n, 1)),
                    build_s + lookup_s * rays.size(),
                    {double(s), double(d), double(rays.size()), build_s, 1e9 * lookup_s, double(lut.table_bytes()),
                     double(mismatches), emax_smooth, lut.estimate_max_rel_error(550.0), double(subtracted_kinks(lut))}});
  };
  // Build time: the fastest of up to 3 builds (the tables are the same each time),
  // fewer once the builds so far took 0.5 s.
  auto fastest_build = [&](const LutOptions& o) {
    OpticalDepthLut lut(atm, o);
    double best = lut.build_time_s(), spent = best;
    for (int i = 1; i < 3 && spent < 0.5; ++i) {
      const OpticalDepthLut again(atm, o);
      best = std::min(best, again.build_time_s());
      spent += again.build_time_s();
    }
    return std::pair<OpticalDepthLut, double>(std::move(lut), best);
  };
  std::string used = "cpu";
  for (auto [s, d] : settings) {
    LutOptions o;
    o.shells = s;
    o.view_directions = d;
    o.sun_directions = d;
    const auto [lut, build_s] = fastest_build(o);
    evaluate(lut, "lut", s, d, build_s);
    if (subtracted_kinks(lut) > 0) {  // the same tables interpolated across those kinks
      LutOptions plain = o;
      plain.subtracted_kinks = 0;
      const auto [across, across_s] = fastest_build(plain);
      evaluate(across, "lut_plain", s, d, across_s);
    }
#ifdef ATMOSH_HAVE_GPU
    if (ctx) {
      try {
        int off_ground = 0, off_sun = 0;
        double gpu_s = 0.0;
        const std::vector<float> tables = gpu::build_lut_tables(*ctx, lut, atm, off_ground, off_sun, &gpu_s);
        OpticalDepthLut from_gpu = lut;
        from_gpu.replace_log_tables(tables, off_ground, off_sun);
        evaluate(from_gpu, "lut_gpu", s, d, gpu_s);
        used = "gpu";
      } catch (const gpu::Unsupported& e) {
        device_notice(resolve_device(request, GpuUnusable{GpuUnusable::Why::unsupported, e.what(), {}},
                                     "building the tables on the CPU only"));
        ctx.reset();
      }
    }
#endif
  }
  io::Provenance prov = io::Provenance::current();
  prov.add("atmosphere", spec.name).add("wavelength_nm", 550.0);
  prov.add("device", used);
  prov.add("time_s", "lut: build time + per-lookup time x rays; lut_gpu: the same with the GPU table pass's wall "
                     "time (shader compilation, upload, dispatch, read-back) as build time; reference: time of all rays");
  prov.add("error", "relative error of the total optical depth at 550 nm over all rays (view table; lut_gpu: "
                    "tables built on the GPU, looked up on the CPU; lut_plain: the same tables without the kinks "
                    "subtracted from long tabulated profiles, subtracted_kinks of them in the lut rows); "
                    "error_max_rel_rayleigh_mie: the same without ozone; "
                    "error_estimate_rel: the tables' own a-posteriori estimate at 550 nm "
                    "(OpticalDepthLut::estimate_max_rel_error; reference: its quadrature error estimate)");
  prov.add("build_threads", static_cast<double>(resolve_threads(LutOptions{}.threads)));  // CPU builds: one shell each
  prov.add("timing", "build_time_s: the fastest of up to 3 CPU builds (fewer once they took 0.5 s); "
                     "lookup_time_ns: the fastest of 3 passes over all rays");
  prov.add("machine_note", "timings depend on the machine and its load");
  return io::write_study(stem, ss, rows, prov);
}

void write_stability_csv(const std::vector<StiffCase>& cases, const fs::path& file) {
  io::CsvTable t({"case", "quantity", "value", "reference", "error", "bound", "pass"});
  for (const auto& k : cases)
    t.add_row({k.name, k.quantity, k.value, k.reference, k.error, k.bound, std::int64_t(k.pass)});
  t.write(file, io::Provenance::current());
}

std::vector<int> parse_int_list(const std::string& text, const std::string& what) {
  std::vector<int> v;
  for (double d : parse_list(text, what)) {
    if (d != std::floor(d) || d < 4 || d > 4096) throw InputError(what + ": '" + text + "' must be integers in [4, 4096]");
    v.push_back(static_cast<int>(d));
  }
  return v;
}

// ---- optical depth vs zenith (demo) -------------------------------------------------

std::vector<fs::path> write_zenith_sweep(const AtmosphereSpec& spec, double altitude, const fs::path& stem) {
  Atmosphere atm(spec);
  OpticalDepthReference ref(atm);
  OpticalDepthLut lut(atm);
  auto k = atm.coefficients_at(550.0);
  io::CsvTable t({"zenith_deg", "tau_reference", "tau_lut", "relative_error", "hits_ground"});
  const std::string lut_name = "LUT " + std::to_string(lut.options().shells) + "x" +
                               std::to_string(lut.options().view_directions);
  io::Series sr{"reference", {}, {}, io::Series::Style::Line}, sl{lut_name, {}, {}, io::Series::Style::Scatter};
  for (int i = 0; i <= 360; ++i) {
    double z = 0.5 * i;
    double mu = std::cos(z * kDegToRad);
    double r = atm.ground_radius() + altitude;
    auto a = ref.column(r, mu);
    auto b = lut.view(r, mu);
    double ta = optical_depth(k, a.column), tb = optical_depth(k, b.column);
    t.add_row({z, ta, tb, ta > 0.0 ? std::abs(tb - ta) / ta : 0.0, std::int64_t(a.hits_ground)});
    sr.x.push_back(z);
    sr.y.push_back(ta);
    if (i % 4 == 0) {
      sl.x.push_back(z);
      sl.y.push_back(tb);
    }
  }
  io::Provenance prov = io::Provenance::current();
  prov.add("atmosphere", spec.name).add("altitude_m", altitude).add("wavelength_nm", 550.0);
  fs::path csv = stem.string() + ".csv", png = stem.string() + ".png";
  t.write(csv, prov);
  io::PlotSpec ps;
  ps.title = "Optical depth at 550 nm against zenith angle (" + spec.name + ", " + std::to_string(int(altitude)) + " m)";
  ps.x_label = "zenith angle [deg]";
  ps.y_label = "optical depth (total)";
  ps.log_y = true;
  ps.series = {sr, sl};
  io::write_plot_png(png, ps);
  return {csv, png};
}

}  // namespace

void register_atmo_commands(CLI::App& app) {
  // optical-depth
  {
    struct Opt {
      std::string scene, preset, method = "reference";
      double wavelength = 550.0, altitude = 0.0, zenith = 0.0;
      int shells = LutOptions{}.shells, directions = LutOptions{}.view_directions;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = app.add_subcommand("optical-depth", "Optical depth along a ray from an altitude at a zenith angle");
    c->add_option("--scene", o->scene, "scene TOML file (its atmosphere)");
    c->add_option("--preset", o->preset, "earth-physical | earth-graphics (default) | test-planet");
    c->add_option("--wavelength", o->wavelength, "wavelength [nm]")->required();
    c->add_option("--altitude", o->altitude, "altitude of the ray origin above the ground [m]")->required();
    c->add_option("--zenith", o->zenith, "zenith angle of the ray [deg] (90 = horizontal, > 90 looks down)")->required();
    c->add_option("--method", o->method, "reference | lut");
    CLI::Option* osh = c->add_option("--shells", o->shells, "lut: shell count (default 40)");
    CLI::Option* odi = c->add_option("--directions", o->directions, "lut: directions per table branch (default 64)");
    c->add_flag("--json", o->json, "print one JSON object");
    c->callback([o, osh, odi] {
      if (o->method != "reference" && o->method != "lut")
        throw InputError("--method: '" + o->method + "' is not reference or lut");
      for (CLI::Option* opt : {osh, odi})
        if (opt->count() > 0 && o->method != "lut")
          throw InputError(opt->get_name() + ": only with --method lut");
      require_range(o->shells, 4, 4096, "--shells");
      require_range(o->directions, 4, 65536, "--directions");
      if (o->method == "lut") {
        LutOptions lo;
        lo.shells = o->shells;
        lo.view_directions = lo.sun_directions = o->directions;
        check_memory(OpticalDepthLut::estimate_table_bytes(lo), "--method lut --shells " + std::to_string(o->shells) +
                                                                    " --directions " + std::to_string(o->directions));
      }
      double nm = require_range(o->wavelength, 1.0, 1e5, "--wavelength");
      double zen = require_range(o->zenith, 0.0, 180.0, "--zenith");
      double alt = require_range(o->altitude, -1e3, 1e9, "--altitude");
      AtmosphereSpec spec = load_atmosphere(o->scene, o->preset);
      spec.spectrum.wavelengths_nm = {nm};
      if (spec.ozone && (nm < 360.0 || nm > 830.0))
        throw InputError("--wavelength " + io::format_double(nm) + ": outside the ozone table (360-830 nm)");
      if (spec.rayleigh && spec.rayleigh->model == RayleighSpec::Model::Physical &&
          (nm < kRayleighPhysicalFirstNm || nm > kRayleighPhysicalLastNm))
        throw InputError("--wavelength " + io::format_double(nm) +
                         ": outside the physical Rayleigh model's range (240-1690 nm)");
      Atmosphere atm(spec);
      if (alt < 0.0) throw InputError("--altitude " + io::format_double(alt) + ": below the ground");
      const double r = atm.ground_radius() + alt, mu = std::cos(zen * kDegToRad);
      auto k = atm.coefficients(0);
      glm::dvec3 col, err(0.0);
      bool hits = false;
      double rel_err = 0.0, time_s = 0.0;
      auto t0 = Clock::now();
      if (o->method == "reference") {
        OpticalDepthReference ref(atm);
        auto c = ref.column(r, mu);
        time_s = seconds_since(t0);
        col = c.column;
        err = c.error;
        hits = c.hits_ground;
      } else {
        LutOptions lo;
        lo.shells = o->shells;
        lo.view_directions = lo.sun_directions = o->directions;
        OpticalDepthLut lut(atm, lo);
        auto c = lut.view(r, mu);
        time_s = seconds_since(t0);  // build + lookup
        col = c.column;
        hits = c.hits_ground;
        // The table's a-posteriori estimate (OpticalDepthLut::estimate_max_rel_error:
        // the largest relative error of the total at this wavelength over samples
        // midway between the table's shells and directions, against fresh integrals);
        // computed after the clock stops, it is not part of the method's cost.
        rel_err = lut.estimate_max_rel_error(nm);
      }
      glm::dvec3 tau = k.extinction * col;
      double total = tau.x + tau.y + tau.z;
      double error_estimate = std::abs(glm::dot(k.extinction, err));
      if (o->method == "lut") error_estimate = rel_err * total;
      if (o->json) {
        print_json({{"rayleigh", tau.x}, {"mie", tau.y}, {"ozone", tau.z}, {"total", total},
                    {"transmittance", transmittance(total)}, {"method", o->method},
                    {"error_estimate", error_estimate}, {"time_s", time_s}, {"hits_ground", hits},
                    {"wavelength_nm", nm}, {"atmosphere", spec.name}});
      } else {
        std::printf("optical depth at %g nm, altitude %g m, zenith %g deg (%s, %s)%s\n", nm, alt, zen,
                    spec.name.c_str(), o->method.c_str(), hits ? ", ray hits the ground" : "");
        std::printf("  rayleigh %.12g\n  mie      %.12g\n  ozone    %.12g\n  total    %.12g (+- %.3g)\n"
                    "  transmittance %.12g\n  time %.3g s\n",
                    tau.x, tau.y, tau.z, total, error_estimate, transmittance(total), time_s);
      }
    });
  }
  // phase
  {
    struct Opt {
      std::string model;
      double g = 0.8, g2 = -0.3, weight = 0.9, depolarization = 0.0279, mu = 1.0;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = app.add_subcommand("phase", "Phase function value [1/sr] and mean cosine");
    c->add_option("--model", o->model, "rayleigh | hg | cornette-shanks | double-hg")->required();
    CLI::Option* og = c->add_option("--g", o->g, "asymmetry parameter (first lobe for double-hg); required for hg, cornette-shanks, double-hg");
    CLI::Option* og2 = c->add_option("--g2", o->g2, "double-hg: second lobe (default -0.3)");
    CLI::Option* ow = c->add_option("--weight", o->weight, "double-hg: weight of the first lobe (default 0.9)");
    CLI::Option* od = c->add_option("--depolarization", o->depolarization, "rayleigh: depolarisation factor (default 0.0279)");
    c->add_option("--cos-theta", o->mu, "cosine of the scattering angle (1 = forward)")->required();
    c->add_flag("--json", o->json, "print one JSON object");
    c->callback([o, og, og2, ow, od] {
      PhaseSpec s;
      if (o->model == "rayleigh") s.model = PhaseSpec::Model::Rayleigh;
      else if (o->model == "hg") s.model = PhaseSpec::Model::HenyeyGreenstein;
      else if (o->model == "cornette-shanks") s.model = PhaseSpec::Model::CornetteShanks;
      else if (o->model == "double-hg") s.model = PhaseSpec::Model::DoubleHenyeyGreenstein;
      else throw InputError("--model: '" + o->model + "' is not rayleigh, hg, cornette-shanks or double-hg");
      // An option the model does not use is an error, not silently ignored; g has no
      // default (a silent 0.8 would answer a question nobody asked).
      const bool uses_g = s.model != PhaseSpec::Model::Rayleigh;
      const bool two_lobes = s.model == PhaseSpec::Model::DoubleHenyeyGreenstein;
      if (uses_g && og->count() == 0) throw InputError("--g: required for --model " + o->model);
      auto unused = [&](const CLI::Option* opt, bool used, const char* name) {
        if (!used && opt->count() > 0) throw InputError(std::string(name) + ": not a parameter of --model " + o->model);
      };
      unused(og, uses_g, "--g");
      unused(og2, two_lobes, "--g2");
      unused(ow, two_lobes, "--weight");
      unused(od, s.model == PhaseSpec::Model::Rayleigh, "--depolarization");
      auto open_unit = [](double v, const char* name) {
        if (!(std::isfinite(v) && std::abs(v) < 1.0)) throw InputError(std::string(name) + " = " + io::format_double(v) + ": must be in (-1, 1)");
      };
      if (uses_g) open_unit(o->g, "--g");
      if (two_lobes) {
        open_unit(o->g2, "--g2");
        require_range(o->weight, 0.0, 1.0, "--weight");
      }
      if (s.model == PhaseSpec::Model::Rayleigh && !(std::isfinite(o->depolarization) && o->depolarization >= 0.0 &&
                                                     o->depolarization < 0.5))
        throw InputError("--depolarization = " + io::format_double(o->depolarization) + ": must be in [0, 0.5)");
      s.g = o->g;
      s.g2 = o->g2;
      s.weight = o->weight;
      s.depolarization = o->depolarization;
      double mu = require_range(o->mu, -1.0, 1.0, "--cos-theta");
      PhaseFunction p(s, "phase");
      if (o->json) {
        print_json({{"value", p.value(mu)}, {"mean_cosine", p.mean_cosine()}, {"model", o->model}, {"cos_theta", mu}});
      } else {
        std::printf("%s phase at cos(theta) = %g: %.15g /sr, mean cosine %.15g\n", o->model.c_str(), mu, p.value(mu),
                    p.mean_cosine());
      }
    });
  }
  // stability
  {
    struct Opt {
      bool json = false;
      std::string output;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = app.add_subcommand("stability", "Run the stiff/extreme-case suite; exit 1 if any case fails");
    c->add_flag("--json", o->json, "print one JSON object");
    c->add_option("-o,--output", o->output, "also write the table as CSV");
    c->callback([o] {
      auto cases = run_stiff_cases();
      bool all = true;
      for (const auto& k : cases) all = all && k.pass;
      if (!o->output.empty()) write_stability_csv(cases, o->output);
      if (o->json) {
        nlohmann::json arr = nlohmann::json::array();
        for (const auto& k : cases)
          arr.push_back({{"case", k.name}, {"quantity", k.quantity}, {"value", k.value}, {"reference", k.reference},
                         {"error", k.error}, {"bound", k.bound}, {"pass", k.pass}});
        print_json({{"cases", arr}, {"all_pass", all}});
      } else {
        std::printf("%-44s %22s %22s %10s %8s  %s\n", "case", "value", "reference", "error", "bound", "result");
        for (const auto& k : cases)
          std::printf("%-44s %22.15g %22.15g %10.2e %8.1e  %s\n", k.name.c_str(), k.value, k.reference, k.error,
                      k.bound, k.pass ? "PASS" : "FAIL");
        std::printf("%s\n", all ? "all cases pass" : "SOME CASES FAIL");
      }
      if (!all) throw CLI::RuntimeError(1);
    });
  }
  // converge lut
  if (CLI::App* conv = app.get_subcommand("converge")) {
    struct Opt {
      std::string scene, preset, stem = "lut_convergence", shells = "8,16,32,40,48,64", directions = "16,32,64,128";
      std::string device = "cpu";
      bool quick = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = conv->add_subcommand("lut", "Optical-depth LUT: error against build + lookup time, sweeping shells and directions");
    c->add_option("--scene", o->scene, "scene TOML file (its atmosphere)");
    c->add_option("--preset", o->preset, "atmosphere preset (default earth-graphics)");
    c->add_option("-o,--output", o->stem, "output stem: STEM.csv and STEM.png");
    CLI::Option* os = c->add_option("--shells", o->shells, "comma-separated shell counts");
    CLI::Option* od = c->add_option("--directions", o->directions, "comma-separated direction counts (per table branch)");
    c->add_flag("--quick", o->quick, "two settings only (16 x 32 and the default 40 x 64); not with --shells/--directions");
    c->add_option("--device", o->device,
                  "cpu, gpu or auto: with a GPU, each setting also gets a lut_gpu row (tables built on the GPU); "
                  "auto uses the GPU if a headless EGL device exists, else the CPU only");
    c->callback([o, os, od] {
      check_device(o->device);
      ProgressStep step("converge lut");
      if (o->quick && (os->count() > 0 || od->count() > 0))
        throw InputError("--quick: sweeps its own two settings; drop --shells/--directions or --quick");
      auto s = parse_int_list(o->shells, "--shells");
      auto d = parse_int_list(o->directions, "--directions");
      for (const auto& p :
           run_converge_lut(load_atmosphere(o->scene, o->preset), s, d, o->quick, o->stem, o->device))
        std::printf("%s\n", p.c_str());
    });
  }
}

std::vector<fs::path> write_lut_convergence(const AtmosphereSpec& spec, const fs::path& stem, bool quick) {
  return run_converge_lut(spec, {16, 32, 40, 48, 64}, {32, 64, 128}, quick, stem);
}

std::vector<fs::path> write_optical_depth_table(const AtmosphereSpec& spec, const fs::path& stem) {
  return write_zenith_sweep(spec, 1000.0, stem);
}

void demo_atmo(DemoContext& ctx) {
  ProgressStep step("demo: optical depth and its tables");
  // (The default scene's LUT convergence study is one of its outputs, run by run_scene.)
  const auto s = scene::default_scene();
  for (const auto& p : write_zenith_sweep(s.atmosphere, 1000.0, ctx.out_dir / "optical_depth_vs_zenith"))
    ctx.written.push_back(p);
  // The stiff and extreme cases, with their bounds.
  const auto cases = run_stiff_cases();
  write_stability_csv(cases, ctx.out_dir / "stability.csv");
  ctx.written.push_back(ctx.out_dir / "stability.csv");
  for (const auto& k : cases)
    if (!k.pass) throw std::runtime_error("stiff case '" + k.name + "' fails its bound");
}

}  // namespace atmosh::cli
