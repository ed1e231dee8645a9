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
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {

constexpr double kPi = std::numbers::pi;
using sh::Channels;

// ---- coefficient files ----------------------------------------------------------
struct CoeffFile {
  int bands = 0;
  std::vector<std::string> names;  // channel column names
  Channels ch;
  std::string value_units;  // units of the projected values (provenance value_units), if stated
};

void write_coeffs(const std::filesystem::path& file, const CoeffFile& cf, io::Provenance prov) {
  std::vector<std::string> cols = {"l", "m", "index"};
  for (const auto& n : cf.names) cols.push_back(n);
  io::CsvTable t(cols);
  for (int l = 0; l < cf.bands; ++l)
    for (int m = -l; m <= l; ++m) {
      std::vector<io::CsvCell> row = {std::int64_t{l}, std::int64_t{m}, std::int64_t{sh::sh_index(l, m)}};
      for (const auto& c : cf.ch) row.emplace_back(c[sh::sh_index(l, m)]);
      t.add_row(std::move(row));
    }
  prov.add("sh_convention", "real orthonormal, Condon-Shortley phase, index l(l+1)+m, t from +z, p from +x to +y");
  prov.add("sh_bands", std::to_string(cf.bands));
  t.write(file, prov);
}

CoeffFile read_coeffs(const std::string& file) {
  io::ShCoefficients c = io::read_sh_coefficients(file);
  return {c.bands, std::move(c.names), std::move(c.channels), std::move(c.value_units)};
}

// ---- images -----------------------------------------------------------------------
struct LoadedImage {
  int width = 0, height = 0;
  std::vector<std::string> names;
  std::vector<float> planar;  // channel-major
  bool cross = false;
  std::string value_units;  // units of the pixel values, when the EXR states them (attribute value_units)
  sh::ImageView view() const {
    return {width, height, static_cast<int>(names.size()), planar.data()};
  }
};

LoadedImage load_image(const std::string& file, const std::string& layout) {
  io::ExrImage img = io::read_exr(file, memory_budget() / 2);  // the image and its planar copy
  LoadedImage li;
  li.width = img.width;
  li.height = img.height;
  std::vector<int> use;
  const int r = img.find_channel("R"), g = img.find_channel("G"), b = img.find_channel("B");
  if (r >= 0 && g >= 0 && b >= 0) {
    use = {r, g, b};
    li.names = {"r", "g", "b"};
  } else {
    for (std::size_t c = 0; c < img.channels.size(); ++c) {
      use.push_back(static_cast<int>(c));
      std::string n = img.channels[c];
      std::transform(n.begin(), n.end(), n.begin(), [](unsigned char ch) { return std::tolower(ch); });
      li.names.push_back(n);
    }
  }
  if (use.empty()) throw InputError(file + ": EXR has no channels");
  if (auto u = img.string_attributes.find("value_units"); u != img.string_attributes.end()) li.value_units = u->second;
  li.planar.reserve(use.size() * img.width * img.height);
  for (int c : use) li.planar.insert(li.planar.end(), img.data[c].begin(), img.data[c].end());
  for (float v : li.planar)
    if (!std::isfinite(v)) throw InputError(file + ": EXR contains a NaN or infinite pixel");
  if (layout == "equirect") {
    li.cross = false;
  } else if (layout == "cross") {
    li.cross = true;
  } else if (layout == "auto") {
    if (li.width == 2 * li.height)
      li.cross = false;
    else if (li.width * 3 == li.height * 4 || li.width * 4 == li.height * 3)
      li.cross = true;
    else
      throw InputError(file + ": " + std::to_string(li.width) + " x " + std::to_string(li.height) +
                       " is neither 2:1 (equirect) nor a 4:3 / 3:4 cube cross; pass --layout");
  } else {
    throw InputError("--layout: '" + layout + "' is not auto, equirect or cross");
  }
  return li;
}

Channels project_image(const LoadedImage& li, int bands, const sh::ProjectOptions& opt) {
  if (li.cross) {
    const sh::CubeMap cube = sh::unpack_cross(li.view());
    return sh::project_cube_sampled(cube, bands, opt);
  }
  if (opt.method == sh::Method::quadrature && opt.samples == 0) return sh::project_equirect(li.view(), bands, opt.threads);
  return sh::project_equirect_sampled(li.view(), bands, opt);
}

void render_exr(const std::filesystem::path& file, const CoeffFile& cf, int width, io::Provenance prov) {
  const int w = width, h = std::max(1, width / 2);
  std::vector<std::string> names;
  for (const auto& n : cf.names) {
    std::string u = n;
    if (cf.names.size() == 3 && (n == "r" || n == "g" || n == "b")) std::transform(u.begin(), u.end(), u.begin(), ::toupper);
    names.push_back(u);
  }
  io::ExrImage img(w, h, names);
  for (std::size_t c = 0; c < cf.ch.size(); ++c) img.data[c] = sh::render_equirect(cf.ch[c], cf.bands, w, h);
  img.string_attributes["projection"] = "equirect: row 0 at +z, column 0 at azimuth 0 (+x), azimuth towards +y";
  img.string_attributes["sh_bands"] = std::to_string(cf.bands);
  write_exr(file, img, prov);
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

// ---- convergence study --------------------------------------------------------------
struct ErrorPair {
  double max_rel, rms_rel;
};
ErrorPair compare(const Channels& a, const Channels& ref) {
  double emax = 0, scale = 0, se = 0, sr = 0;
  std::size_t n = 0;
  for (std::size_t c = 0; c < ref.size(); ++c)
    for (std::size_t i = 0; i < ref[c].size(); ++i) {
      emax = std::max(emax, std::abs(a[c][i] - ref[c][i]));
      scale = std::max(scale, std::abs(ref[c][i]));
      se += (a[c][i] - ref[c][i]) * (a[c][i] - ref[c][i]);
      sr += ref[c][i] * ref[c][i];
      ++n;
    }
  (void)n;
  return {scale > 0 ? emax / scale : emax, sr > 0 ? std::sqrt(se / sr) : std::sqrt(se)};
}

std::vector<std::filesystem::path> run_converge(const LoadedImage& li, int bands, bool quick, std::uint64_t seed,
                                                const std::filesystem::path& stem, const std::string& source) {
  using clock = std::chrono::steady_clock;
  auto timed = [&](auto&& fn, Channels& out) {
    const auto t0 = clock::now();
    out = fn();
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  Channels ref;
  sh::ProjectOptions q;
  const double tref = timed([&] { return project_image(li, bands, q); }, ref);
  std::vector<io::StudyRow> rows;
  rows.push_back({li.cross ? "cube-texel-integration" : "fejer-quadrature", "all pixels (reference)", 0.0, 0.0, tref,
                  {static_cast<double>(li.width) * li.height}});
  const std::vector<int> strata = quick ? std::vector<int>{8, 16, 45} : std::vector<int>{8, 16, 32, 45, 64, 128, 256};
  const std::vector<int> uni = quick ? std::vector<int>{256, 2025, 8192} : std::vector<int>{256, 1024, 2025, 8192, 32768, 131072};
  for (int n : strata) {
    sh::ProjectOptions o{sh::Method::jittered, n, seed, 1};
    Channels c;
    const double t = timed([&] { return project_image(li, bands, o); }, c);
    const ErrorPair e = compare(c, ref);
    rows.push_back({"jittered", std::to_string(n) + "x" + std::to_string(n), e.max_rel, e.rms_rel, t,
                    {static_cast<double>(n) * n}});
  }
  for (int n : uni) {
    sh::ProjectOptions o{sh::Method::uniform, n, seed, 1};
    Channels c;
    const double t = timed([&] { return project_image(li, bands, o); }, c);
    const ErrorPair e = compare(c, ref);
    rows.push_back({"uniform", std::to_string(n), e.max_rel, e.rms_rel, t, {static_cast<double>(n)}});
  }
  if (!li.cross) {
    const std::vector<int> mult = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4, 8, 16};
    for (int k : mult) {
      sh::ProjectOptions o{sh::Method::quadrature, k * bands, seed, 1};
      if (k == 1) o.samples = bands + 1;  // force the resampling path (nlat = bands + 1)
      Channels c;
      const double t = timed([&] { return project_image(li, bands, o); }, c);
      const ErrorPair e = compare(c, ref);
      rows.push_back({"gauss-grid-bilinear", "nlat=" + std::to_string(o.samples), e.max_rel, e.rms_rel, t,
                      {static_cast<double>(o.samples) * 2.0 * o.samples}});
    }
  }
  io::StudySpec spec;
  // The input file by name: its folder is the run's business (it is in the provenance).
  spec.title = "SH projection of " + std::filesystem::path(source).filename().string() + " (" + std::to_string(bands) + " bands): error vs run time";
  spec.extra_columns = {"samples"};
  io::Provenance prov = io::Provenance::current();
  prov.add("input", source).add("sh_bands", std::to_string(bands)).add("seed", std::to_string(seed));
  prov.add("reference", li.cross ? "texel-centre values times the exact texel solid angles"
                                 : "Fejer's first rule on the pixel-centre rings (exact for band-limited images)");
  prov.add("error_definition", "max |c - c_ref| / max |c_ref| and ||c - c_ref||_2 / ||c_ref||_2 over all channels");
  return io::write_study(stem, spec, rows, prov);
}

void write_band_files(const CoeffFile& cf, const std::filesystem::path& csv, const std::filesystem::path& png,
                      const io::Provenance& prov) {
  std::vector<std::string> cols = {"l"};
  std::vector<std::vector<double>> e, f;
  for (std::size_t c = 0; c < cf.ch.size(); ++c) {
    cols.push_back("energy_" + cf.names[c]);
    e.push_back(sh::band_energy(cf.ch[c], cf.bands));
    f.push_back(sh::cumulative_energy_fraction(e.back()));
  }
  for (std::size_t c = 0; c < cf.ch.size(); ++c) cols.push_back("fraction_" + cf.names[c]);
  io::CsvTable t(cols);
  for (int l = 0; l < cf.bands; ++l) {
    std::vector<io::CsvCell> row = {std::int64_t{l}};
    for (auto& v : e) row.emplace_back(v[l]);
    for (auto& v : f) row.emplace_back(v[l]);
    t.add_row(std::move(row));
  }
  t.write(csv, prov);
  if (!png.empty()) {
    // The coefficients carry the input's units times sr; the input's units are those
    // the coefficient file states (provenance value_units), else unnamed.
    const std::string units = cf.value_units.empty() ? "input units" : cf.value_units;
    const io::PlotSpec spec =
        io::band_energy_plot_spec("SH band energy (power per band, rotation invariant)", cf.names, e, units);
    io::write_plot_png(png, spec);
  }
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
      const LoadedImage li = load_image(o->in, o->layout);
      CoeffFile cf{o->bands, li.names, project_image(li, o->bands, po), li.value_units};
      auto prov = prov_with({{"input", o->in}, {"method", o->method}, {"seed", std::to_string(o->seed)},
                             {"samples", std::to_string(o->samples)}, {"layout", li.cross ? "cube cross" : "equirect"}});
      if (!li.value_units.empty()) prov.add("value_units", li.value_units);  // of the projected values
      write_coeffs(o->out, cf, prov);
      if (!o->reconstruct.empty()) render_exr(o->reconstruct, cf, o->width, prov);
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
      for (std::size_t c = 0; c < cf.ch.size(); ++c) values[cf.names[c]] = sh::reconstruct(cf.bands, cf.ch[c].data(), u);
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
      for (auto& ch : cf.ch) ch = R.apply(ch);
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
      for (auto& ch : cf.ch) ch = sh::irradiance(ch, cf.bands);
      auto prov = prov_with({{"input", o->in}, {"quantity", "irradiance E(n) = integral max(0, n.w) L(w) dOmega"}});
      write_coeffs(o->out, cf, prov);
      if (!o->reconstruct.empty()) render_exr(o->reconstruct, cf, o->width, prov);
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
      write_band_files(cf, o->out, o->plot, prov_with({{"input", o->in}}));
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
    c->callback([o] {
      require_bands(o->bands);
      const LoadedImage li = load_image(o->in, o->layout);
      ProgressStep step("converge sh");
      for (const auto& p : run_converge(li, o->bands, o->quick, o->seed, o->stem, o->in)) std::printf("%s\n", p.c_str());
    });
  };
  add_converge(shc, "converge");
  if (CLI::App* conv = app.get_subcommand("converge")) add_converge(conv, "sh");
}

void demo_sh(DemoContext& ctx) {
  ProgressStep step("demo: spherical harmonics");
  namespace fs = std::filesystem;
  const int W = ctx.quick ? 128 : 512, H = W / 2;
  const int bands = ctx.quick ? 8 : 16;
  // Synthetic sky-like radiance: a gradient from horizon to zenith, a dark ground,
  // and a sun lobe (normalised von Mises–Fisher, kappa 400) at elevation 30 deg.
  const glm::dvec3 sun = sh::direction_from_angles(60.0 * kPi / 180, 40.0 * kPi / 180);
  const double colour[3] = {0.6, 0.8, 1.2};
  io::ExrImage img(W, H, {"R", "G", "B"});
  for (int r = 0; r < H; ++r)
    for (int q = 0; q < W; ++q) {
      const glm::dvec3 d = sh::direction_from_angles(kPi * (r + 0.5) / H, 2 * kPi * (q + 0.5) / W);
      const double cosg = d.x * sun.x + d.y * sun.y + d.z * sun.z;
      const double lobe = 400.0 / (2 * kPi * (1 - std::exp(-800.0))) * std::exp(400.0 * (cosg - 1.0));
      for (int c = 0; c < 3; ++c) {
        const double sky = d.z > 0 ? colour[c] * (0.3 + 0.7 * (1 - d.z)) : 0.05 * colour[c];
        img.data[c][static_cast<std::size_t>(r) * W + q] = static_cast<float>(sky + 0.02 * lobe);
      }
    }
  io::Provenance prov = io::Provenance::current();
  prov.add("content", "synthetic sky: gradient + vMF sun lobe (kappa 400) at elevation 30 deg, azimuth 40 deg from +x");
  prov.add("value_units", "arbitrary radiance units");
  const fs::path exr = ctx.out_dir / "sh_sky_input.exr";
  io::write_exr(exr, img, prov);
  ctx.written.push_back(exr);

  const LoadedImage li = load_image(exr.string(), "equirect");
  CoeffFile cf{bands, li.names, sh::project_equirect(li.view(), bands), "arbitrary radiance units"};
  const fs::path coeffs = ctx.out_dir / "sh_coeffs.csv";
  write_coeffs(coeffs, cf, prov);
  ctx.written.push_back(coeffs);
  const fs::path recon = ctx.out_dir / "sh_reconstruct.exr";
  render_exr(recon, cf, W, prov);
  ctx.written.push_back(recon);

  CoeffFile irr = cf;
  for (auto& ch : irr.ch) ch = sh::irradiance(ch, bands);
  const fs::path irr_csv = ctx.out_dir / "sh_irradiance.csv";
  write_coeffs(irr_csv, irr, prov);
  ctx.written.push_back(irr_csv);

  const fs::path bcsv = ctx.out_dir / "sh_bands.csv", bpng = ctx.out_dir / "sh_bands.png";
  write_band_files(cf, bcsv, bpng, prov);
  ctx.written.push_back(bcsv);
  ctx.written.push_back(bpng);

  // windows: what each costs in accuracy (L2 error of the windowed green channel against
  // the unwindowed band-limited one) and the ringing left (min of the windowed delta).
  {
    io::CsvTable t({"window", "delta_min_rel", "l2_change_rel", "irradiance_max_change_rel"});
    const std::vector<double>& g = cf.ch[1];
    double norm = 0;
    for (double v : g) norm += v * v;
    const std::vector<double> eg = sh::irradiance(g, bands);
    for (const char* name : {"none", "hanning", "lanczos", "nonnegative"}) {
      const auto w = sh::window_weights(sh::parse_window(name), bands);
      std::vector<double> gw = g;
      sh::convolve_zonal(gw, bands, w);
      double d2 = 0;
      for (std::size_t i = 0; i < g.size(); ++i) d2 += (gw[i] - g[i]) * (gw[i] - g[i]);
      const std::vector<double> ew = sh::irradiance(gw, bands);
      double emax = 0, escale = 0;
      for (int r = 0; r < 32; ++r)
        for (int q = 0; q < 64; ++q) {
          const glm::dvec3 d = sh::direction_from_angles(kPi * (r + 0.5) / 32, 2 * kPi * (q + 0.5) / 64);
          const double a = sh::reconstruct(bands, ew.data(), d), b = sh::reconstruct(bands, eg.data(), d);
          emax = std::max(emax, std::abs(a - b));
          escale = std::max(escale, std::abs(b));
        }
      t.add_row({std::string(name), sh::windowed_delta_min(w), std::sqrt(d2 / norm), emax / escale});
    }
    const fs::path wcsv = ctx.out_dir / "sh_windows.csv";
    io::Provenance wp = prov;
    wp.add("sh_bands", std::to_string(bands));
    t.write(wcsv, wp);
    ctx.written.push_back(wcsv);
  }
  for (const auto& p : run_converge(li, bands, ctx.quick, 1, ctx.out_dir / "sh_converge", exr.string()))
    ctx.written.push_back(p);
}

}  // namespace atmosh::cli
