// atmosh optical-depth, phase, stability, converge lut.
#include <cstdio>
#include <memory>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;

AtmosphereSpec load_atmosphere(const std::string& scene_file, const std::string& preset_name) {
  if (!scene_file.empty() && !preset_name.empty()) throw InputError("--scene and --preset: give only one");
  if (!scene_file.empty()) return scene::load_scene(scene_file).atmosphere;
  return preset(preset_name.empty() ? "earth-graphics" : preset_name);
}

}  // namespace

void register_atmo_commands(CLI::App& app) {
  {  // optical-depth
    struct Opt {
      std::string scene, preset, method = "reference";
      double wavelength = 550.0;
      studies::OpticalDepthQuery q{0.0, 0.0, false, LutOptions{}.shells, LutOptions{}.view_directions};
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = app.add_subcommand("optical-depth", "Optical depth along a ray from an altitude at a zenith angle");
    c->add_option("--scene", o->scene, "scene TOML file (its atmosphere)");
    c->add_option("--preset", o->preset, "earth-physical | earth-graphics (default) | test-planet");
    c->add_option("--wavelength", o->wavelength, "wavelength [nm]")->required();
    c->add_option("--altitude", o->q.altitude_m, "altitude of the ray origin above the ground [m]")->required();
    c->add_option("--zenith", o->q.zenith_deg, "zenith angle of the ray [deg] (90 = horizontal, > 90 looks down)")->required();
    c->add_option("--method", o->method, "reference | lut");
    CLI::Option* osh = c->add_option("--shells", o->q.shells, "lut: shell count (default 40)");
    CLI::Option* odi = c->add_option("--directions", o->q.directions, "lut: directions per table branch (default 64)");
    add_json_flag(c, o->json);
    c->callback([o, osh, odi] {
      if (o->method != "reference" && o->method != "lut")
        throw InputError("--method: '" + o->method + "' is not reference or lut");
      for (CLI::Option* opt : {osh, odi})
        if (opt->count() > 0 && o->method != "lut") throw InputError(opt->get_name() + ": only with --method lut");
      require_range(o->q.shells, 4, 4096, "--shells");
      require_range(o->q.directions, 4, 65536, "--directions");
      studies::OpticalDepthQuery q = o->q;
      q.tables = o->method == "lut";
      if (q.tables) {
        LutOptions lo;
        lo.shells = q.shells;
        lo.view_directions = lo.sun_directions = q.directions;
        check_memory(OpticalDepthLut::estimate_table_bytes(lo), "--method lut --shells " + std::to_string(q.shells) +
                                                                    " --directions " + std::to_string(q.directions));
        check_time(OpticalDepthLut::estimate_build_work(lo), 0,
                   "--method lut --shells " + std::to_string(q.shells) + " --directions " + std::to_string(q.directions));
      }
      const AtmosphereSpec spec = load_atmosphere(o->scene, o->preset);
      const double nm = o->wavelength, alt = q.altitude_m, zen = q.zenith_deg;
      const studies::OpticalDepthAnswer a = studies::optical_depth_at(spec, nm, q);
      if (o->json) return print_json(studies::optical_depth_json(a, o->method, nm, spec.name));
      std::fputs(studies::optical_depth_text(a, o->method, nm, alt, zen, spec.name).c_str(), stdout);
    });
  }
  {  // phase
    static studies::PhaseRequest r;
    static double mu = 1.0;
    static bool json = false;
    CLI::App* c = app.add_subcommand("phase", "Phase function value [1/sr] and mean cosine");
    c->add_option("--model", r.model, "rayleigh | hg | cornette-shanks | double-hg")->required();
    CLI::Option* og = c->add_option("--g", r.g, "asymmetry parameter (first lobe for double-hg); required for hg, cornette-shanks, double-hg");
    CLI::Option* og2 = c->add_option("--g2", r.g2, "double-hg: second lobe (default -0.3)");
    CLI::Option* ow = c->add_option("--weight", r.weight, "double-hg: weight of the first lobe (default 0.9)");
    CLI::Option* od = c->add_option("--depolarization", r.depolarization, "rayleigh: depolarisation factor (default 0.0279)");
    c->add_option("--cos-theta", mu, "cosine of the scattering angle (1 = forward)")->required();
    add_json_flag(c, json);
    c->callback([og, og2, ow, od] {
      r.g_given = og->count() > 0, r.g2_given = og2->count() > 0, r.weight_given = ow->count() > 0;
      r.depolarization_given = od->count() > 0;
      const PhaseSpec spec = studies::phase_spec(r);
      require_range(mu, -1.0, 1.0, "--cos-theta");
      const PhaseFunction p(spec, "phase");
      if (json) return print_json(studies::phase_json(p, r.model, mu));
      std::printf("%s phase at cos(theta) = %g: %.15g /sr, mean cosine %.15g\n", r.model.c_str(), mu, p.value(mu),
                  p.mean_cosine());
    });
  }
  {  // stability
    static bool json = false;
    static std::string output;
    CLI::App* c = app.add_subcommand("stability", "Run the stiff/extreme-case suite; exit 1 if any case fails");
    add_json_flag(c, json);
    c->add_option("-o,--output", output, "also write the table as CSV");
    c->callback([] {
      const auto cases = run_stiff_cases();
      if (!output.empty()) studies::write_stability_csv(cases, output);
      const nlohmann::json j = studies::stability_json(cases);
      if (json)
        print_json(j);
      else
        std::fputs(studies::stability_text(cases).c_str(), stdout);
      if (!j["all_pass"].get<bool>()) throw CLI::RuntimeError(1);
    });
  }
  if (CLI::App* conv = app.get_subcommand("converge")) {  // converge lut
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
    add_format_option(c, o->stem);
    CLI::Option* os = c->add_option("--shells", o->shells, "comma-separated shell counts");
    CLI::Option* od = c->add_option("--directions", o->directions, "comma-separated direction counts (per table branch)");
    c->add_flag("--quick", o->quick, "two settings only (16 x 32 and the default 40 x 64); not with --shells/--directions");
    add_device_option(c, o->device, "with a GPU, each setting also gets a lut_gpu row (tables built on the GPU)");
    c->callback([o, os, od] {
      check_device(o->device);
      check_study_stem(o->stem, "-o");
      ProgressStep step("converge lut");
      if (o->quick && (os->count() > 0 || od->count() > 0))
        throw InputError("--quick: sweeps its own two settings; drop --shells/--directions or --quick");
      studies::LutConvergenceOptions lo;
      lo.shells = parse_int_list(o->shells, "--shells", 4, 4096);
      lo.directions = parse_int_list(o->directions, "--directions", 4, 4096);
      lo.quick = o->quick;
      lo.device = o->device;
      lo.notice = notice;
      const studies::StudyTable t = studies::lut_convergence(load_atmosphere(o->scene, o->preset), lo);  // "--device gpu: <why>" without a GPU
      print_files(io::write_study(o->stem, t.spec, t.rows, t.provenance));
    });
  }
}

}  // namespace atmosh::cli
