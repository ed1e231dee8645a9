// atmosh sh ... — spherical-harmonic subcommands: project, eval, gaunt, rotate,
// irradiance, bands, converge.
#include <cmath>
#include <numbers>

#include "atmosh/error.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/studies/studies_sh.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {

constexpr double kPi = std::numbers::pi;
using CoeffFile = io::ShCoefficients;

// An input image: the library reads it within half the memory budget (the image and
// its planar copy); its messages speak of "the layout", the option is --layout.
studies::ShImage load_image(const std::string& file, const std::string& layout) {
  if (layout != "auto" && layout != "equirect" && layout != "cross")
    throw InputError("--layout: '" + layout + "' is not auto, equirect or cross");
  return studies::load_sh_image(file, layout, memory_budget() / 2);
}

io::Provenance prov_with(const std::vector<std::pair<std::string, std::string>>& kv) {
  io::Provenance p = io::Provenance::current();
  for (const auto& [k, v] : kv) p.add(k, v);
  return p;
}

int require_bands(int bands) {
  if (bands < 1 || bands > 4096) throw InputError("--bands must be in [1, 4096], got " + std::to_string(bands));
  return bands;
}

}  // namespace

void register_sh_commands(CLI::App& app) {
  CLI::App* shc = app.add_subcommand("sh", "Spherical harmonics: project, eval, gaunt, rotate, irradiance, bands, converge");
  shc->require_subcommand(1);

  {  // project
    struct Opt {
      std::string in, out, method = "quadrature", reconstruct, layout = "auto";
      int bands = 0, samples = 0, threads = 1, width = 512;
      std::uint64_t seed = 1;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand("project", "Project an equirect (2:1) or cube-cross EXR onto SH");
    c->add_option("input", o->in, "input EXR")->required();
    c->add_option("--bands", o->bands, "number of bands L (l = 0..L-1)")->required();
    c->add_option("--method", o->method, "quadrature (equirect: Fejer's first rule, exact for band-limited images; cube: texel solid angle) | "
                  "solid-angle | pixel-integrated | jittered | uniform");
    c->add_option("--samples", o->samples, "jittered: strata per side (default 45); uniform: samples (default 2025)");
    c->add_option("--seed", o->seed, "random seed (default 1)");
    c->add_option("--layout", o->layout, "auto | equirect | cross");
    add_threads_option(c, o->threads);
    c->add_option("-o,--output", o->out, "coefficients CSV")->required();
    c->add_option("--reconstruct", o->reconstruct, "also render the coefficients to this equirect EXR");
    c->add_option("--width", o->width, "width of the reconstruction (height = width/2)");
    c->callback([o] {
      require_bands(o->bands);
      sh::ProjectOptions po{sh::parse_method(o->method), o->samples, o->seed, threads_option(o->threads)};
      if (o->samples < 0) throw InputError("--samples must be >= 0, got " + std::to_string(o->samples));
      if (o->width < 2 || o->width > 16384) throw InputError("--width must be in [2, 16384], got " + std::to_string(o->width));
      if (po.method == sh::Method::quadrature) po.samples = 0;
      check_output_file(o->out, {".csv"}, "-o");
      if (!o->reconstruct.empty()) check_output_file(o->reconstruct, {".exr"}, "--reconstruct");
      check_memory(sh::sampler_bytes(po, 3), "--method " + o->method + " --samples " + std::to_string(o->samples));
      check_time(sh::sampler_work(po, o->bands, 3), 1, "--method " + o->method + " --samples " + std::to_string(o->samples));
      const studies::ShImage li = load_image(o->in, o->layout);
      CoeffFile cf{o->bands, li.names, studies::project_sh_image(li, o->bands, po), li.value_units};
      auto prov = prov_with({{"input", o->in}, {"method", o->method}, {"seed", std::to_string(o->seed)},
                             {"samples", std::to_string(o->samples)}, {"layout", li.cross ? "cube cross" : "equirect"}});
      if (!li.value_units.empty()) prov.add("value_units", li.value_units);  // of the projected values
      io::write_sh_coefficients(o->out, cf, prov);
      if (!o->reconstruct.empty()) studies::write_sh_reconstruction(o->reconstruct, cf, o->width, prov);
    });
  }
  {  // eval
    static std::string in, dir;
    static bool json = false;
    CLI::App* c = shc->add_subcommand("eval", "Evaluate a coefficient CSV in a direction");
    c->add_option("coeffs", in, "coefficients CSV")->required();
    c->add_option("--dir", dir, "direction x,y,z (need not be unit length)")->required();
    add_json_flag(c, json);
    c->callback([] {
      const glm::dvec3 u = studies::sh_eval_direction(dir);
      const nlohmann::json j = studies::sh_eval_json(io::read_sh_coefficients(in), u);
      if (json) return print_json(j);
      for (auto& [k, v] : j["values"].items()) std::cout << k << " " << io::format_double(v.get<double>()) << "\n";
    });
  }
  {  // gaunt
    static std::vector<int> lm;
    static bool json = false;
    CLI::App* c = shc->add_subcommand(
        "gaunt", "Gaunt coefficient: integral of Y_l1m1 Y_l2m2 Y_l3m3 over the sphere (real orthonormal SH)");
    c->add_option("lm", lm, "L1 M1 L2 M2 L3 M3")->expected(6)->required();
    add_json_flag(c, json);
    c->callback([] {
      const nlohmann::json j = studies::gaunt_json(lm);
      if (json) return print_json(j);
      std::printf("%.17g\n", j["value"].get<double>());
    });
  }
  {  // rotate
    static std::string in, out, euler;
    CLI::App* c = shc->add_subcommand("rotate", "Rotate coefficients (active rotation f'(r) = f(R^-1 r))");
    c->add_option("coeffs", in, "coefficients CSV")->required();
    c->add_option("--euler-zyz", euler, "z-y-z Euler angles a,b,c in degrees: R = Rz(a) Ry(b) Rz(c)")->required();
    c->add_option("-o,--output", out, "rotated coefficients CSV")->required();
    c->callback([] {
      const auto e = parse_triple(euler, "--euler-zyz");
      CoeffFile cf = io::read_sh_coefficients(in);
      const sh::Rotation R(cf.bands, sh::EulerZYZ{e[0] * kPi / 180, e[1] * kPi / 180, e[2] * kPi / 180});
      for (auto& ch : cf.channels) ch = R.apply(ch);
      io::write_sh_coefficients(out, cf, prov_with({{"input", in}, {"euler_zyz_deg", euler}}));
    });
  }
  {  // irradiance
    static std::string in, out, reconstruct;
    static int width = 256;
    CLI::App* c = shc->add_subcommand("irradiance", "Irradiance (clamped-cosine convolution) of radiance coefficients");
    c->add_option("coeffs", in, "radiance coefficients CSV")->required();
    c->add_option("-o,--output", out, "irradiance coefficients CSV")->required();
    c->add_option("--reconstruct", reconstruct, "also render the irradiance to this equirect EXR");
    c->add_option("--width", width, "width of the reconstruction (height = width/2)");
    c->callback([] {
      if (width < 2 || width > 16384) throw InputError("--width must be in [2, 16384], got " + std::to_string(width));
      CoeffFile cf = io::read_sh_coefficients(in);
      for (auto& ch : cf.channels) ch = sh::irradiance(ch, cf.bands);
      auto prov = prov_with({{"input", in}, {"quantity", "irradiance E(n) = integral max(0, n.w) L(w) dOmega"}});
      io::write_sh_coefficients(out, cf, prov);
      if (!reconstruct.empty()) studies::write_sh_reconstruction(reconstruct, cf, width, prov);
    });
  }
  {  // bands
    static std::string in, out, plot;
    CLI::App* c = shc->add_subcommand("bands", "Band energy and cumulative energy fraction");
    c->add_option("coeffs", in, "coefficients CSV")->required();
    c->add_option("-o,--output", out, "band energy CSV")->required();
    c->add_option("--plot", plot, "band-energy plot PNG (log axis)");
    c->callback([] { studies::write_sh_bands(io::read_sh_coefficients(in), out, plot, prov_with({{"input", in}})); });
  }
  // converge (also as `atmosh converge sh`)
  auto add_converge = [](CLI::App* parent, const std::string& name) {
    struct Opt {
      std::string in, stem = "sh_converge", layout = "auto";
      int bands = 0;
      bool quick = false;
      std::uint64_t seed = 1;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = parent->add_subcommand(name, "SH projection: error against run time of each method and sample count");
    c->add_option("input", o->in, "input EXR (equirect or cube cross)")->required();
    c->add_option("--bands", o->bands, "number of bands L")->required();
    c->add_option("-o,--output", o->stem, "output stem: STEM.csv and STEM.png");
    c->add_option("--seed", o->seed, "random seed");
    c->add_option("--layout", o->layout, "auto | equirect | cross");
    c->add_flag("--quick", o->quick, "fewer sample counts");
    add_format_option(c, o->stem);
    c->callback([o] {
      require_bands(o->bands);
      check_study_stem(o->stem, "-o");
      const studies::ShImage li = load_image(o->in, o->layout);
      ProgressStep step("converge sh");
      const studies::StudyTable t = studies::converge_sh(li, o->bands, o->quick, o->seed, o->in);
      print_files(io::write_study(o->stem, t.spec, t.rows, t.provenance));
    });
  };
  add_converge(shc, "converge");
  if (CLI::App* conv = app.get_subcommand("converge")) add_converge(conv, "sh");
}

}  // namespace atmosh::cli
