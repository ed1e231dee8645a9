// The atmosphere's studies (atmosh/studies/studies_atmo.hpp).
#include "atmosh/studies/studies_atmo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/check.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/device.hpp"
#include "atmosh/error.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/parallel.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/sky.hpp"
#endif

namespace atmosh::studies {

using namespace atmosh::atmo;
namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Kinks the tables subtracted from their tabulated densities (LutOptions::subtracted_kinks).
int subtracted_kinks(const OpticalDepthLut& lut) {
  int n = 0;
  for (int c = 0; c < 3; ++c) n += std::max(0, lut.subtracted(c).nodes() - 1);  // p's nodes: 0 and the kinks
  return n;
}
}  // namespace

std::vector<LutRay> lut_study_rays(const Atmosphere& atm) {
  const double R = atm.ground_radius(), top = atm.top_altitude();
  std::vector<LutRay> rays;
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

StudyTable lut_convergence(const AtmosphereSpec& spec, const LutConvergenceOptions& options) {
  // The one device policy (atmosh::resolve_device): "gpu" runs the GPU table pass or
  // fails; "auto" falls back to the CPU rows with a notice. Only "no device"
  // (gpu::Unavailable) and "input not supported" (gpu::Unsupported) fall back.
  const DeviceRequest request = parse_device_request(options.device, "device");
  static const std::string kFallback = "building the tables on the CPU only";
  const auto tell = [&](const DeviceDecision& d) {
    if (options.notice && !d.notice.empty()) options.notice(d.notice);
  };
  Atmosphere atm(spec);
#ifdef ATMOSH_HAVE_GPU
  // With a GPU, every setting gets a second row: the same tables built by the
  // GPU table pass (gpu::build_lut_tables), looked up by the same CPU code.
  std::unique_ptr<gpu::Context> ctx;
  if (request != DeviceRequest::cpu) {
    try {
      ctx = std::make_unique<gpu::Context>();
    } catch (const gpu::Unavailable& e) {
      tell(resolve_device(request, GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}}, kFallback));
    }
  }
#else
  if (request != DeviceRequest::cpu)
    tell(resolve_device(request, GpuUnusable{GpuUnusable::Why::not_built, {}, {}}, kFallback));
#endif
  OpticalDepthReference ref(atm);
  auto rays = lut_study_rays(atm);
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
  StudyTable out;
  io::StudySpec& ss = out.spec;
  ss.title = "Optical depth LUT (Nishita shells) vs exact reference, " + spec.name + ", 550 nm";
  ss.extra_columns = {"shells", "directions", "rays", "build_time_s", "lookup_time_ns", "table_bytes",
                      "flag_mismatches", "error_max_rel_rayleigh_mie", "error_estimate_rel", "subtracted_kinks"};
  std::vector<io::StudyRow>& rows = out.rows;
  rows.push_back({"reference", "adaptive G7-K15 (estimated error)", ref_err, ref_err_rms, ref_time,
                  {0, 0, double(rays.size()), 0.0, 1e9 * ref_time / rays.size(), 0, 0, ref_err, ref_err, 0}});
  std::vector<std::pair<int, int>> settings;
  if (options.quick) {
    settings = {{16, 32}, {40, 64}};  // a coarse table and the default
  } else {
    for (int s : options.shells)
      for (int d : options.directions) settings.push_back({s, d});
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
    volatile double sink = 0.0;  // keeps the timed lookups
    double lookup_s = 0.0;
    for (int pass = 0; pass < 3; ++pass) {
      auto t1 = Clock::now();
      double acc = 0.0;
      for (int rep = 0; rep < reps; ++rep)
        for (const auto& ray : rays) acc += lut.view(ray.r, ray.mu).column[kRayleigh];
      sink = sink + acc;
      const double t = seconds_since(t1) / (double(reps) * rays.size());
      lookup_s = pass == 0 ? t : std::min(lookup_s, t);
    }
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
        tell(resolve_device(request, GpuUnusable{GpuUnusable::Why::unsupported, e.what(), {}}, kFallback));
        ctx.reset();
      }
    }
#endif
  }
  io::Provenance& prov = out.provenance;
  prov = io::Provenance::current();
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
  return out;
}

OpticalDepthAnswer optical_depth_query(const Atmosphere& atm, const OpticalDepthQuery& q) {
  if (!(q.altitude_m >= 0.0)) throw InputError("altitude " + io::format_double(q.altitude_m) + " m: below the ground");
  const double r = atm.ground_radius() + q.altitude_m, mu = std::cos(q.zenith_deg * kDegToRad);
  auto k = atm.coefficients(0);
  glm::dvec3 col, err(0.0);
  bool hits = false;
  double rel_err = 0.0, time_s = 0.0;
  auto t0 = Clock::now();
  if (!q.tables) {
    OpticalDepthReference ref(atm);
    auto c = ref.column(r, mu);
    time_s = seconds_since(t0);
    col = c.column;
    err = c.error;
    hits = c.hits_ground;
  } else {
    LutOptions lo;
    lo.shells = q.shells;
    lo.view_directions = lo.sun_directions = q.directions;
    OpticalDepthLut lut(atm, lo);
    auto c = lut.view(r, mu);
    time_s = seconds_since(t0);  // build + lookup
    col = c.column;
    hits = c.hits_ground;
    // The table's a-posteriori estimate (OpticalDepthLut::estimate_max_rel_error:
    // the largest relative error of the total at this wavelength over samples
    // midway between the table's shells and directions, against fresh integrals);
    // computed after the clock stops, it is not part of the method's cost.
    rel_err = lut.estimate_max_rel_error(atm.wavelengths_nm().at(0));
  }
  const glm::dvec3 tau = k.extinction * col;
  OpticalDepthAnswer a;
  a.rayleigh = tau.x;
  a.mie = tau.y;
  a.ozone = tau.z;
  a.total = tau.x + tau.y + tau.z;
  a.error_estimate = q.tables ? rel_err * a.total : std::abs(glm::dot(k.extinction, err));
  a.time_s = time_s;
  a.hits_ground = hits;
  return a;
}

ZenithSweep zenith_sweep(const AtmosphereSpec& spec, double altitude) {
  Atmosphere atm(spec);
  OpticalDepthReference ref(atm);
  OpticalDepthLut lut(atm);
  auto k = atm.coefficients_at(550.0);
  ZenithSweep out;
  out.lut_name = "LUT " + std::to_string(lut.options().shells) + "x" + std::to_string(lut.options().view_directions);
  for (int i = 0; i <= 360; ++i) {
    double z = 0.5 * i;
    double mu = std::cos(z * kDegToRad);
    double r = atm.ground_radius() + altitude;
    auto a = ref.column(r, mu);
    auto b = lut.view(r, mu);
    double ta = optical_depth(k, a.column), tb = optical_depth(k, b.column);
    out.rows.push_back({z, ta, tb, ta > 0.0 ? std::abs(tb - ta) / ta : 0.0, a.hits_ground});
  }
  out.provenance = io::Provenance::current();
  out.provenance.add("atmosphere", spec.name).add("altitude_m", altitude).add("wavelength_nm", 550.0);
  return out;
}

io::CsvTable zenith_sweep_table(const ZenithSweep& sweep) {
  io::CsvTable t({"zenith_deg", "tau_reference", "tau_lut", "relative_error", "hits_ground"});
  for (const ZenithRow& w : sweep.rows)
    t.add_row({w.zenith_deg, w.tau_reference, w.tau_lut, w.relative_error, std::int64_t(w.hits_ground)});
  return t;
}

std::vector<fs::path> write_zenith_sweep(const ZenithSweep& sweep, const std::string& atmosphere_name,
                                         double altitude, const fs::path& stem) {
  const io::CsvTable t = zenith_sweep_table(sweep);
  io::Series sr{"reference", {}, {}, io::Series::Style::Line}, sl{sweep.lut_name, {}, {}, io::Series::Style::Scatter};
  for (std::size_t i = 0; i < sweep.rows.size(); ++i) {
    const ZenithRow& w = sweep.rows[i];
    sr.x.push_back(w.zenith_deg);
    sr.y.push_back(w.tau_reference);
    if (i % 4 == 0) {
      sl.x.push_back(w.zenith_deg);
      sl.y.push_back(w.tau_lut);
    }
  }
  fs::path csv = stem.string() + ".csv", png = stem.string() + ".png";
  t.write(csv, sweep.provenance);
  io::PlotSpec ps;
  ps.title = "Optical depth at 550 nm against zenith angle (" + atmosphere_name + ", " +
             std::to_string(int(altitude)) + " m)";
  ps.x_label = "zenith angle [deg]";
  ps.y_label = "optical depth (total)";
  ps.log_y = true;
  ps.series = {sr, sl};
  io::write_plot_png(png, ps);
  return {csv, png};
}

void write_stability_csv(const std::vector<StiffCase>& cases, const fs::path& file) {
  io::CsvTable t({"case", "quantity", "value", "reference", "error", "bound", "pass"});
  for (const auto& k : cases)
    t.add_row({k.name, k.quantity, k.value, k.reference, k.error, k.bound, std::int64_t(k.pass)});
  t.write(file, io::Provenance::current());
}

OpticalDepthAnswer optical_depth_at(atmo::AtmosphereSpec spec, double nm, const OpticalDepthQuery& query) {
  require_range(nm, 1.0, 1e5, "--wavelength");
  require_range(query.zenith_deg, 0.0, 180.0, "--zenith");
  require_range(query.altitude_m, -1e3, 1e9, "--altitude");
  spec.spectrum.wavelengths_nm = {nm};
  if (spec.ozone && (nm < 360.0 || nm > 830.0))
    throw InputError("--wavelength " + io::format_double(nm) + ": outside the ozone table (360-830 nm)");
  if (spec.rayleigh && spec.rayleigh->model == atmo::RayleighSpec::Model::Physical &&
      (nm < atmo::kRayleighPhysicalFirstNm || nm > atmo::kRayleighPhysicalLastNm))
    throw InputError("--wavelength " + io::format_double(nm) + ": outside the physical Rayleigh model's range (240-1690 nm)");
  const atmo::Atmosphere atm(spec);
  if (query.altitude_m < 0.0) throw InputError("--altitude " + io::format_double(query.altitude_m) + ": below the ground");
  return optical_depth_query(atm, query);
}

atmo::PhaseSpec phase_spec(const PhaseRequest& o) {
  using M = atmo::PhaseSpec::Model;
  atmo::PhaseSpec s;
  if (o.model == "rayleigh") s.model = M::Rayleigh;
  else if (o.model == "hg") s.model = M::HenyeyGreenstein;
  else if (o.model == "cornette-shanks") s.model = M::CornetteShanks;
  else if (o.model == "double-hg") s.model = M::DoubleHenyeyGreenstein;
  else throw InputError("--model: '" + o.model + "' is not rayleigh, hg, cornette-shanks or double-hg");
  // An option the model does not use is an error, not silently ignored; g has no
  // default (a silent 0.8 would answer a question nobody asked).
  const bool uses_g = s.model != M::Rayleigh, two_lobes = s.model == M::DoubleHenyeyGreenstein;
  if (uses_g && !o.g_given) throw InputError("--g: required for --model " + o.model);
  auto unused = [&](bool given, bool used, const char* name) {
    if (!used && given) throw InputError(std::string(name) + ": not a parameter of --model " + o.model);
  };
  unused(o.g_given, uses_g, "--g");
  unused(o.g2_given, two_lobes, "--g2");
  unused(o.weight_given, two_lobes, "--weight");
  unused(o.depolarization_given, s.model == M::Rayleigh, "--depolarization");
  auto open_unit = [](double v, const char* name) {
    if (!(std::isfinite(v) && std::abs(v) < 1.0))
      throw InputError(std::string(name) + " = " + io::format_double(v) + ": must be in (-1, 1)");
  };
  if (uses_g) open_unit(o.g, "--g");
  if (two_lobes) {
    open_unit(o.g2, "--g2");
    require_range(o.weight, 0.0, 1.0, "--weight");
  }
  if (s.model == M::Rayleigh && !(std::isfinite(o.depolarization) && o.depolarization >= 0.0 && o.depolarization < 0.5))
    throw InputError("--depolarization = " + io::format_double(o.depolarization) + ": must be in [0, 0.5)");
  s.g = o.g;
  s.g2 = o.g2;
  s.weight = o.weight;
  s.depolarization = o.depolarization;
  return s;
}

std::vector<std::filesystem::path> demo_atmo(const std::filesystem::path& dir) {
  // (The default scene's LUT convergence study is one of its outputs, run by run_scene.)
  const auto s = scene::default_scene();
  auto written = write_zenith_sweep(zenith_sweep(s.atmosphere, 1000.0), s.atmosphere.name, 1000.0,
                                    dir / "optical_depth_vs_zenith");
  const auto cases = atmo::run_stiff_cases();  // the stiff and extreme cases, with their bounds
  write_stability_csv(cases, dir / "stability.csv");
  written.push_back(dir / "stability.csv");
  for (const auto& k : cases)
    if (!k.pass) throw std::runtime_error("stiff case '" + k.name + "' fails its bound");
  return written;
}

}  // namespace atmosh::studies
