// atmosh optical-depth, phase, stability, converge lut; and the atmosphere part
// of the main job (demo_atmo).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/atmo/stiff_cases.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;
namespace fs = std::filesystem;


AtmosphereSpec load_atmosphere(const std::string& scene_file, const std::string& preset_name) {
  if (!scene_file.empty() && !preset_name.empty()) throw InputError("--scene and --preset: give only one");
  if (!scene_file.empty()) return scene::load_scene(scene_file).atmosphere;
  return preset(preset_name.empty() ? "earth-graphics" : preset_name);
}


// ---- converge lut --------------------------------------------------------------

std::vector<fs::path> run_converge_lut(const AtmosphereSpec& spec, const std::vector<int>& shells,
                                       const std::vector<int>& directions, bool quick, const fs::path& stem,
                                       const std::string& device = "cpu") {
  check_device(device);
  studies::LutConvergenceOptions o;
  o.shells = shells;
  o.directions = directions;
  o.quick = quick;
  o.device = device;
  o.notice = [](const std::string& m) { std::cerr << "atmosh: " << m << "\n"; };
  const studies::StudyTable t = studies::lut_convergence(spec, o);  // "--device gpu: <why>" without a GPU
  return io::write_study(stem, t.spec, t.rows, t.provenance);
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
  return studies::write_zenith_sweep(studies::zenith_sweep(spec, altitude), spec.name, altitude, stem);
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
        check_time(OpticalDepthLut::estimate_build_work(lo), 0,
                   "--method lut --shells " + std::to_string(o->shells) + " --directions " + std::to_string(o->directions));
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
      const studies::OpticalDepthAnswer q =
          studies::optical_depth_query(atm, {alt, zen, o->method == "lut", o->shells, o->directions});
      const glm::dvec3 tau(q.rayleigh, q.mie, q.ozone);
      const double total = q.total, error_estimate = q.error_estimate, time_s = q.time_s;
      const bool hits = q.hits_ground;
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
      if (!o->output.empty()) studies::write_stability_csv(cases, o->output);
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
    add_format_option(c, o->stem);
    c->callback([o, os, od] {
      check_device(o->device);
      check_study_stem(o->stem, "-o");
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

void demo_atmo(DemoContext& ctx) {
  ProgressStep step("demo: optical depth and its tables");
  // (The default scene's LUT convergence study is one of its outputs, run by run_scene.)
  const auto s = scene::default_scene();
  for (const auto& p : write_zenith_sweep(s.atmosphere, 1000.0, ctx.out_dir / "optical_depth_vs_zenith"))
    ctx.written.push_back(p);
  // The stiff and extreme cases, with their bounds.
  const auto cases = run_stiff_cases();
  studies::write_stability_csv(cases, ctx.out_dir / "stability.csv");
  ctx.written.push_back(ctx.out_dir / "stability.csv");
  for (const auto& k : cases)
    if (!k.pass) throw std::runtime_error("stiff case '" + k.name + "' fails its bound");
}

}  // namespace atmosh::cli
