// Spherical-harmonic studies and steps (atmosh/studies/studies_sh.hpp).
#include "atmosh/studies/studies_sh.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "atmosh/check.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/sh/projection.hpp"
#include "atmosh/io/sh_coefficients.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/gaunt.hpp"

namespace atmosh::studies {

namespace fs = std::filesystem;
using sh::Channels;

namespace {
constexpr double kPi = std::numbers::pi;
}

ShImage load_sh_image(const fs::path& path, const std::string& layout, std::size_t max_bytes) {
  const std::string file = path.string();
  io::ExrImage img = io::read_exr(path, max_bytes);
  ShImage li;
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
                       " is neither 2:1 (equirect) nor a 4:3 / 3:4 cube cross; give the layout");
  } else {
    throw InputError("layout '" + layout + "' is not auto, equirect or cross");
  }
  return li;
}

Channels project_sh_image(const ShImage& li, int bands, const sh::ProjectOptions& opt) {
  if (li.cross) {
    const sh::CubeMap cube = sh::unpack_cross(li.view());
    return sh::project_cube_sampled(cube, bands, opt);
  }
  if (opt.method == sh::Method::quadrature && opt.samples == 0) return sh::project_equirect(li.view(), bands, opt.threads);
  return sh::project_equirect_sampled(li.view(), bands, opt);
}

ShError compare_sh(const Channels& a, const Channels& ref) {
  double emax = 0, scale = 0, se = 0, sr = 0;
  for (std::size_t c = 0; c < ref.size(); ++c)
    for (std::size_t i = 0; i < ref[c].size(); ++i) {
      emax = std::max(emax, std::abs(a[c][i] - ref[c][i]));
      scale = std::max(scale, std::abs(ref[c][i]));
      se += (a[c][i] - ref[c][i]) * (a[c][i] - ref[c][i]);
      sr += ref[c][i] * ref[c][i];
    }
  return {scale > 0 ? emax / scale : emax, sr > 0 ? std::sqrt(se / sr) : std::sqrt(se)};
}

StudyTable converge_sh(const ShImage& li, int bands, bool quick, std::uint64_t seed, const std::string& source) {
  using clock = std::chrono::steady_clock;
  auto timed = [&](auto&& fn, Channels& out) {
    const auto t0 = clock::now();
    out = fn();
    return std::chrono::duration<double>(clock::now() - t0).count();
  };
  Channels ref;
  sh::ProjectOptions q;
  const double tref = timed([&] { return project_sh_image(li, bands, q); }, ref);
  StudyTable out;
  std::vector<io::StudyRow>& rows = out.rows;
  rows.push_back({li.cross ? "cube-texel-integration" : "fejer-quadrature", "all pixels (reference)", 0.0, 0.0, tref,
                  {static_cast<double>(li.width) * li.height}});
  const std::vector<int> strata = quick ? std::vector<int>{8, 16, 45} : std::vector<int>{8, 16, 32, 45, 64, 128, 256};
  const std::vector<int> uni = quick ? std::vector<int>{256, 2025, 8192} : std::vector<int>{256, 1024, 2025, 8192, 32768, 131072};
  for (int n : strata) {
    sh::ProjectOptions o{sh::Method::jittered, n, seed, 1};
    Channels c;
    const double t = timed([&] { return project_sh_image(li, bands, o); }, c);
    const ShError e = compare_sh(c, ref);
    rows.push_back({"jittered", std::to_string(n) + "x" + std::to_string(n), e.max_rel, e.rms_rel, t,
                    {static_cast<double>(n) * n}});
  }
  for (int n : uni) {
    sh::ProjectOptions o{sh::Method::uniform, n, seed, 1};
    Channels c;
    const double t = timed([&] { return project_sh_image(li, bands, o); }, c);
    const ShError e = compare_sh(c, ref);
    rows.push_back({"uniform", std::to_string(n), e.max_rel, e.rms_rel, t, {static_cast<double>(n)}});
  }
  if (!li.cross) {
    const std::vector<int> mult = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4, 8, 16};
    for (int k : mult) {
      sh::ProjectOptions o{sh::Method::quadrature, k * bands, seed, 1};
      if (k == 1) o.samples = bands + 1;  // force the resampling path (nlat = bands + 1)
      Channels c;
      const double t = timed([&] { return project_sh_image(li, bands, o); }, c);
      const ShError e = compare_sh(c, ref);
      rows.push_back({"gauss-grid-bilinear", "nlat=" + std::to_string(o.samples), e.max_rel, e.rms_rel, t,
                      {static_cast<double>(o.samples) * 2.0 * o.samples}});
    }
  }
  io::StudySpec& spec = out.spec;
  // The input file by name: its folder is the run's business (it is in the provenance).
  spec.title = "SH projection of " + fs::path(source).filename().string() + " (" + std::to_string(bands) +
               " bands): error vs run time";
  spec.extra_columns = {"samples"};
  io::Provenance& prov = out.provenance;
  prov = io::Provenance::current();
  prov.add("input", source).add("sh_bands", std::to_string(bands)).add("seed", std::to_string(seed));
  prov.add("reference", li.cross ? "texel-centre values times the exact texel solid angles"
                                 : "Fejer's first rule on the pixel-centre rings (exact for band-limited images)");
  prov.add("error_definition", "max |c - c_ref| / max |c_ref| and ||c - c_ref||_2 / ||c_ref||_2 over all channels");
  return out;
}

void write_sh_bands(const io::ShCoefficients& cf, const fs::path& csv, const fs::path& png,
                    const io::Provenance& prov) {
  std::vector<std::string> cols = {"l"};
  std::vector<std::vector<double>> e, f;
  for (std::size_t c = 0; c < cf.channels.size(); ++c) {
    cols.push_back("energy_" + cf.names[c]);
    e.push_back(sh::band_energy(cf.channels[c], cf.bands));
    f.push_back(sh::cumulative_energy_fraction(e.back()));
  }
  for (std::size_t c = 0; c < cf.channels.size(); ++c) cols.push_back("fraction_" + cf.names[c]);
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

void write_sh_reconstruction(const fs::path& file, const io::ShCoefficients& cf, int width, const io::Provenance& prov) {
  const int w = width, h = std::max(1, width / 2);
  std::vector<std::string> names;
  for (const auto& n : cf.names) {
    std::string u = n;
    if (cf.names.size() == 3 && (n == "r" || n == "g" || n == "b"))
      std::transform(u.begin(), u.end(), u.begin(), [](unsigned char ch) { return std::toupper(ch); });
    names.push_back(u);
  }
  io::ExrImage img(w, h, names);
  for (std::size_t c = 0; c < cf.channels.size(); ++c) img.data[c] = sh::render_equirect(cf.channels[c], cf.bands, w, h);
  img.string_attributes["projection"] = "equirect: row 0 at +z, column 0 at azimuth 0 (+x), azimuth towards +y";
  img.string_attributes["sh_bands"] = std::to_string(cf.bands);
  io::write_exr(file, img, prov);
}

io::ExrImage synthetic_sky(int W) {
  const int H = W / 2;
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
  return img;
}

std::vector<ShWindowRow> sh_window_study(const std::vector<double>& g, int bands) {
  std::vector<ShWindowRow> rows;
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
    rows.push_back({name, sh::windowed_delta_min(w), std::sqrt(d2 / norm), emax / escale});
  }
  return rows;
}

io::CsvTable sh_window_table(const std::vector<ShWindowRow>& rows) {
  io::CsvTable t({"window", "delta_min_rel", "l2_change_rel", "irradiance_max_change_rel"});
  for (const auto& r : rows) t.add_row({r.window, r.delta_min_rel, r.l2_change_rel, r.irradiance_max_change_rel});
  return t;
}

void write_sh_windows(const std::vector<ShWindowRow>& rows, const fs::path& file, const io::Provenance& prov) {
  sh_window_table(rows).write(file, prov);
}

glm::dvec3 sh_eval_direction(const std::string& text) {
  const auto t = parse_triple(text, "--dir");
  const glm::dvec3 d(t[0], t[1], t[2]);
  if (!(glm::dvec3(0) != d)) throw InputError("--dir: '" + text + "' has zero length");
  return sh::checked_direction(d, "--dir");
}

nlohmann::json sh_eval_json(const io::ShCoefficients& cf, const glm::dvec3& u) {
  nlohmann::json values = nlohmann::json::object();
  for (std::size_t c = 0; c < cf.channels.size(); ++c) values[cf.names[c]] = sh::reconstruct(cf.bands, cf.channels[c].data(), u);
  return {{"bands", cf.bands}, {"direction", {u.x, u.y, u.z}}, {"values", values}};
}

nlohmann::json gaunt_json(const std::vector<int>& lm) {
  const char* names[6] = {"L1", "M1", "L2", "M2", "L3", "M3"};
  for (int k = 0; k < 6; k += 2) {
    const int l = lm[k], m = lm[k + 1];
    if (l < 0 || l > 100000) throw InputError(std::string(names[k]) + " must be in [0, 100000], got " + std::to_string(l));
    if (std::abs(m) > l)
      throw InputError(std::string(names[k + 1]) + " must satisfy |" + names[k + 1] + "| <= " + names[k] + ", got " +
                       std::to_string(m));
  }
  return {{"l1", lm[0]}, {"m1", lm[1]}, {"l2", lm[2]}, {"m2", lm[3]}, {"l3", lm[4]}, {"m3", lm[5]},
          {"convention", "real orthonormal SH, Condon-Shortley phase"},
          {"value", sh::gaunt(lm[0], lm[1], lm[2], lm[3], lm[4], lm[5])}};
}

std::vector<std::filesystem::path> demo_sh(const std::filesystem::path& dir, bool quick, std::size_t max_image_bytes) {
  namespace fs = std::filesystem;
  std::vector<fs::path> written;
  const int W = quick ? 128 : 512;
  const int bands = quick ? 8 : 16;
  const io::ExrImage img = synthetic_sky(W);
  io::Provenance prov = io::Provenance::current();
  prov.add("content", "synthetic sky: gradient + vMF sun lobe (kappa 400) at elevation 30 deg, azimuth 40 deg from +x");
  prov.add("value_units", "arbitrary radiance units");
  const fs::path exr = dir / "sh_sky_input.exr";
  io::write_exr(exr, img, prov);
  written.push_back(exr);

  const ShImage li = load_sh_image(exr, "equirect", max_image_bytes);
  io::ShCoefficients cf{bands, li.names, sh::project_equirect(li.view(), bands), "arbitrary radiance units"};
  const fs::path coeffs = dir / "sh_coeffs.csv", recon = dir / "sh_reconstruct.exr";
  io::write_sh_coefficients(coeffs, cf, prov);
  written.push_back(coeffs);
  write_sh_reconstruction(recon, cf, W, prov);
  written.push_back(recon);

  io::ShCoefficients irr = cf;
  for (auto& ch : irr.channels) ch = sh::irradiance(ch, bands);
  const fs::path irr_csv = dir / "sh_irradiance.csv";
  io::write_sh_coefficients(irr_csv, irr, prov);
  written.push_back(irr_csv);

  const fs::path bcsv = dir / "sh_bands.csv", bpng = dir / "sh_bands.png";
  write_sh_bands(cf, bcsv, bpng, prov);
  written.insert(written.end(), {bcsv, bpng});

  // windows: what each costs in accuracy and the ringing left, on the green channel.
  const fs::path wcsv = dir / "sh_windows.csv";
  io::Provenance wp = prov;
  wp.add("sh_bands", std::to_string(bands));
  write_sh_windows(sh_window_study(cf.channels[1], bands), wcsv, wp);
  written.push_back(wcsv);

  const StudyTable t = converge_sh(li, bands, quick, 1, exr.string());
  for (const auto& p : io::write_study(dir / "sh_converge", t.spec, t.rows, t.provenance)) written.push_back(p);
  return written;
}

}  // namespace atmosh::studies
