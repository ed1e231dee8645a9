// atmosh sh ... — spherical-harmonic subcommands: project, eval, rotate, irradiance,
// bands, converge; and the SH part of the main job (demo_sh).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/gaunt.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/sh/rotation.hpp"
#include "atmosh/studies/studies_sh.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {

constexpr double kPi = std::numbers::pi;
using sh::Channels;

using CoeffFile = io::ShCoefficients;

// The coefficient file's one reader and writer (atmosh/io/sh_coefficients.hpp).
void write_coeffs(const std::filesystem::path& file, const CoeffFile& cf, const io::Provenance& prov) {
  io::write_sh_coefficients(file, cf, prov);
}
CoeffFile read_coeffs(const std::string& file) { return io::read_sh_coefficients(file); }

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

  // project
  {
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
    c->add_option("--threads", o->threads, "threads for quadrature (0 = all)");
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
      write_coeffs(o->out, cf, prov);
      if (!o->reconstruct.empty()) studies::write_sh_reconstruction(o->reconstruct, cf, o->width, prov);
    });
  }
  // eval
  {
    struct Opt {
      std::string in, dir;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand("eval", "Evaluate a coefficient CSV in a direction");
    c->add_option("coeffs", o->in, "coefficients CSV")->required();
    c->add_option("--dir", o->dir, "direction x,y,z (need not be unit length)")->required();
    c->add_flag("--json", o->json, "print one JSON object");
    c->callback([o] {
      const auto t = parse_triple(o->dir, "--dir");
      const glm::dvec3 d(t[0], t[1], t[2]);
      if (!(glm::dvec3(0) != d)) throw InputError("--dir: '" + o->dir + "' has zero length");
      const glm::dvec3 u = sh::checked_direction(d, "--dir");
      const CoeffFile cf = read_coeffs(o->in);
      nlohmann::json values = nlohmann::json::object();
      for (std::size_t c = 0; c < cf.channels.size(); ++c)
        values[cf.names[c]] = sh::reconstruct(cf.bands, cf.channels[c].data(), u);
      nlohmann::json j = {{"bands", cf.bands}, {"direction", {u.x, u.y, u.z}}, {"values", values}};
      if (o->json) {
        print_json(j);
      } else {
        for (auto& [k, v] : values.items()) std::cout << k << " " << io::format_double(v.get<double>()) << "\n";
      }
    });
  }
  // gaunt
  {
    struct Opt {
      std::vector<int> lm;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand(
        "gaunt", "Gaunt coefficient: integral of Y_l1m1 Y_l2m2 Y_l3m3 over the sphere (real orthonormal SH)");
    c->add_option("lm", o->lm, "L1 M1 L2 M2 L3 M3")->expected(6)->required();
    c->add_flag("--json", o->json, "print one JSON object");
    c->callback([o] {
      const char* names[6] = {"L1", "M1", "L2", "M2", "L3", "M3"};
      for (int k = 0; k < 6; k += 2) {
        const int l = o->lm[k], m = o->lm[k + 1];
        if (l < 0 || l > 100000) throw InputError(std::string(names[k]) + " must be in [0, 100000], got " + std::to_string(l));
        if (std::abs(m) > l)
          throw InputError(std::string(names[k + 1]) + " must satisfy |" + names[k + 1] + "| <= " + names[k] + ", got " +
                           std::to_string(m));
      }
      const double v = sh::gaunt(o->lm[0], o->lm[1], o->lm[2], o->lm[3], o->lm[4], o->lm[5]);
      if (o->json) {
        print_json({{"l1", o->lm[0]}, {"m1", o->lm[1]}, {"l2", o->lm[2]}, {"m2", o->lm[3]}, {"l3", o->lm[4]},
                    {"m3", o->lm[5]}, {"convention", "real orthonormal SH, Condon-Shortley phase"}, {"value", v}});
      } else {
        std::printf("%.17g\n", v);
      }
    });
  }
  // rotate
  {
    struct Opt {
      std::string in, out, euler;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand("rotate", "Rotate coefficients (active rotation f'(r) = f(R^-1 r))");
    c->add_option("coeffs", o->in, "coefficients CSV")->required();
    c->add_option("--euler-zyz", o->euler, "z-y-z Euler angles a,b,c in degrees: R = Rz(a) Ry(b) Rz(c)")->required();
    c->add_option("-o,--output", o->out, "rotated coefficients CSV")->required();
    c->callback([o] {
      const auto e = parse_triple(o->euler, "--euler-zyz");
      CoeffFile cf = read_coeffs(o->in);
      const sh::Rotation R(cf.bands, sh::EulerZYZ{e[0] * kPi / 180, e[1] * kPi / 180, e[2] * kPi / 180});
      for (auto& ch : cf.channels) ch = R.apply(ch);
      write_coeffs(o->out, cf, prov_with({{"input", o->in}, {"euler_zyz_deg", o->euler}}));
    });
  }
  // irradiance
  {
    struct Opt {
      std::string in, out, reconstruct;
      int width = 256;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand("irradiance", "Irradiance (clamped-cosine convolution) of radiance coefficients");
    c->add_option("coeffs", o->in, "radiance coefficients CSV")->required();
    c->add_option("-o,--output", o->out, "irradiance coefficients CSV")->required();
    c->add_option("--reconstruct", o->reconstruct, "also render the irradiance to this equirect EXR");
    c->add_option("--width", o->width, "width of the reconstruction (height = width/2)");
    c->callback([o] {
      if (o->width < 2 || o->width > 16384) throw InputError("--width must be in [2, 16384], got " + std::to_string(o->width));
      CoeffFile cf = read_coeffs(o->in);
      for (auto& ch : cf.channels) ch = sh::irradiance(ch, cf.bands);
      auto prov = prov_with({{"input", o->in}, {"quantity", "irradiance E(n) = integral max(0, n.w) L(w) dOmega"}});
      write_coeffs(o->out, cf, prov);
      if (!o->reconstruct.empty()) studies::write_sh_reconstruction(o->reconstruct, cf, o->width, prov);
    });
  }
  // bands
  {
    struct Opt {
      std::string in, out, plot;
    };
    auto o = std::make_shared<Opt>();
    CLI::App* c = shc->add_subcommand("bands", "Band energy and cumulative energy fraction");
    c->add_option("coeffs", o->in, "coefficients CSV")->required();
    c->add_option("-o,--output", o->out, "band energy CSV")->required();
    c->add_option("--plot", o->plot, "band-energy plot PNG (log axis)");
    c->callback([o] {
      const CoeffFile cf = read_coeffs(o->in);
      studies::write_sh_bands(cf, o->out, o->plot, prov_with({{"input", o->in}}));
    });
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
      for (const auto& p : io::write_study(o->stem, t.spec, t.rows, t.provenance)) std::printf("%s\n", p.c_str());
    });
  };
  add_converge(shc, "converge");
  if (CLI::App* conv = app.get_subcommand("converge")) add_converge(conv, "sh");
}

void demo_sh(DemoContext& ctx) {
  ProgressStep step("demo: spherical harmonics");
  namespace fs = std::filesystem;
  const int W = ctx.quick ? 128 : 512;
  const int bands = ctx.quick ? 8 : 16;
  const io::ExrImage img = studies::synthetic_sky(W);
  io::Provenance prov = io::Provenance::current();
  prov.add("content", "synthetic sky: gradient + vMF sun lobe (kappa 400) at elevation 30 deg, azimuth 40 deg from +x");
  prov.add("value_units", "arbitrary radiance units");
  const fs::path exr = ctx.out_dir / "sh_sky_input.exr";
  io::write_exr(exr, img, prov);
  ctx.written.push_back(exr);

  const studies::ShImage li = load_image(exr.string(), "equirect");
  CoeffFile cf{bands, li.names, sh::project_equirect(li.view(), bands), "arbitrary radiance units"};
  const fs::path coeffs = ctx.out_dir / "sh_coeffs.csv";
  write_coeffs(coeffs, cf, prov);
  ctx.written.push_back(coeffs);
  const fs::path recon = ctx.out_dir / "sh_reconstruct.exr";
  studies::write_sh_reconstruction(recon, cf, W, prov);
  ctx.written.push_back(recon);

  CoeffFile irr = cf;
  for (auto& ch : irr.channels) ch = sh::irradiance(ch, bands);
  const fs::path irr_csv = ctx.out_dir / "sh_irradiance.csv";
  write_coeffs(irr_csv, irr, prov);
  ctx.written.push_back(irr_csv);

  const fs::path bcsv = ctx.out_dir / "sh_bands.csv", bpng = ctx.out_dir / "sh_bands.png";
  studies::write_sh_bands(cf, bcsv, bpng, prov);
  ctx.written.push_back(bcsv);
  ctx.written.push_back(bpng);

  // windows: what each costs in accuracy and the ringing left, on the green channel.
  const fs::path wcsv = ctx.out_dir / "sh_windows.csv";
  io::Provenance wp = prov;
  wp.add("sh_bands", std::to_string(bands));
  studies::write_sh_windows(studies::sh_window_study(cf.channels[1], bands), wcsv, wp);
  ctx.written.push_back(wcsv);

  const studies::StudyTable t = studies::converge_sh(li, bands, ctx.quick, 1, exr.string());
  for (const auto& p : io::write_study(ctx.out_dir / "sh_converge", t.spec, t.rows, t.provenance))
    ctx.written.push_back(p);
}

}  // namespace atmosh::cli
