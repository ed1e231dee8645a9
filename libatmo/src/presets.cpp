#include "atmosh/atmo/presets.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "atmosh/atmo/density.hpp"
#include "atmosh/atmo/ozone.hpp"
#include "atmosh/atmo/rayleigh.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace atmosh::atmo {

namespace {

std::string num(double v) { return atmosh::format_double(v); }

void require(bool ok, const std::string& key, double value, const std::string& what) {
  if (!ok) throw InputError(key + " = " + num(value) + ": " + what);
}

DensityProfileSpec exponential_profile(double H) {
  DensityProfileSpec p;
  p.kind = DensityProfileSpec::Kind::Exponential;
  p.scale_height_m = H;
  return p;
}

DensityProfileSpec tent_profile(double bottom, double peak, double top) {
  DensityProfileSpec p;
  p.kind = DensityProfileSpec::Kind::Tent;
  p.bottom_m = bottom;
  p.peak_m = peak;
  p.top_m = top;
  return p;
}

void validate_phase(const PhaseSpec& p, const std::string& key) {
  using M = PhaseSpec::Model;
  switch (p.model) {
    case M::Rayleigh:
      require(std::isfinite(p.depolarization) && p.depolarization >= 0.0 && p.depolarization < 0.5,
              key + ".depolarization", p.depolarization, "must be in [0, 0.5)");
      break;
    case M::HenyeyGreenstein:
    case M::CornetteShanks:
      require(std::isfinite(p.g) && std::abs(p.g) < 1.0, key + ".g", p.g, "must be in (-1, 1)");
      break;
    case M::DoubleHenyeyGreenstein:
      require(std::isfinite(p.g) && std::abs(p.g) < 1.0, key + ".g", p.g, "must be in (-1, 1)");
      require(std::isfinite(p.g2) && std::abs(p.g2) < 1.0, key + ".g2", p.g2, "must be in (-1, 1)");
      require(std::isfinite(p.weight) && p.weight >= 0.0 && p.weight <= 1.0, key + ".weight", p.weight,
              "must be in [0, 1]");
      break;
    case M::Tabulated:
      if (p.cos_theta.size() < 2 || p.cos_theta.size() != p.value.size())
        throw InputError(key + ": tabulated phase needs >= 2 (cos_theta, value) pairs of equal length");
      for (std::size_t i = 0; i < p.cos_theta.size(); ++i) {
        require(std::isfinite(p.cos_theta[i]) && p.cos_theta[i] >= -1.0 && p.cos_theta[i] <= 1.0 &&
                    (i == 0 || p.cos_theta[i] > p.cos_theta[i - 1]),
                key + ".cos_theta[" + std::to_string(i) + "]", p.cos_theta[i], "must increase within [-1, 1]");
        require(std::isfinite(p.value[i]) && p.value[i] >= 0.0, key + ".value[" + std::to_string(i) + "]",
                p.value[i], "must be finite and >= 0");
      }
      break;
  }
}

}  // namespace

std::vector<double> spectrum_wavelengths(const SpectrumSpec& s) {
  if (!s.wavelengths_nm.empty()) return s.wavelengths_nm;
  std::vector<double> w(static_cast<std::size_t>(std::max(s.count, 0)));
  for (int i = 0; i < s.count; ++i) w[i] = s.from_nm + (i + 0.5) * (s.to_nm - s.from_nm) / s.count;
  return w;
}

namespace {
// A profile valid on its own (DensityProfile) whose nodes also lie above the planet's
// centre: a node radius <= 0 breaks the ray geometry of the closed-form columns.
void check_profile(const DensityProfileSpec& p, const std::string& key, double radius_m) {
  DensityProfile(p, key);
  if (p.kind == DensityProfileSpec::Kind::Tent)
    require(p.bottom_m > -radius_m, key + ".bottom_m", p.bottom_m, "must lie above the planet's centre (> -radius_m)");
  if (p.kind == DensityProfileSpec::Kind::Tabulated && !p.altitude_m.empty())
    require(p.altitude_m.front() > -radius_m, key + ".altitude_m[0]", p.altitude_m.front(),
            "must lie above the planet's centre (> -radius_m)");
}
}  // namespace

void validate(const AtmosphereSpec& s) {
  // Upper bounds well beyond any planet (the Sun's radius is 7e8 m) keep every derived
  // quantity finite.
  require(std::isfinite(s.planet.radius_m) && s.planet.radius_m > 0.0 && s.planet.radius_m <= 1e9, "planet.radius_m",
          s.planet.radius_m, "must be in (0, 1e9] m");
  require(std::isfinite(s.planet.atmosphere_top_m) && s.planet.atmosphere_top_m >= 1.0 &&
              s.planet.atmosphere_top_m <= 1e8,
          "planet.atmosphere_top_m", s.planet.atmosphere_top_m,
          "must be in [1, 1e8] m (the top must lie above the ground)");
  require(std::isfinite(s.planet.ground_albedo) && s.planet.ground_albedo >= 0.0 && s.planet.ground_albedo <= 1.0,
          "planet.ground_albedo", s.planet.ground_albedo, "must be in [0, 1]");
  if (s.rayleigh) {
    const auto& r = *s.rayleigh;
    if (r.model == RayleighSpec::Model::Physical) {
      // Bounds keep the number density p / (k T) finite (Venus: 9.2e6 Pa, 737 K).
      require(std::isfinite(r.pressure_pa) && r.pressure_pa > 0.0 && r.pressure_pa <= 1e9, "rayleigh.pressure_pa",
              r.pressure_pa, "must be in (0, 1e9] Pa");
      require(std::isfinite(r.temperature_k) && r.temperature_k >= 1.0 && r.temperature_k <= 1e5,
              "rayleigh.temperature_k", r.temperature_k, "must be in [1, 1e5] K");
      require(std::isfinite(r.co2_ppm) && r.co2_ppm >= 0.0 && r.co2_ppm < 1e6, "rayleigh.co2_ppm", r.co2_ppm,
              "must be in [0, 1e6)");
    } else {
      require(std::isfinite(r.scattering_per_m) && r.scattering_per_m >= 0.0 && r.scattering_per_m <= 1e3,
              "rayleigh.scattering_per_m", r.scattering_per_m,
              "must be in [0, 1e3] per metre (a density or coefficient cannot be negative)");
      require(std::isfinite(r.reference_nm) && r.reference_nm >= 1.0 && r.reference_nm <= 1e6,
              "rayleigh.reference_nm", r.reference_nm, "must be in [1, 1e6] nm");
    }
    check_profile(r.profile, "rayleigh.profile", s.planet.radius_m);
    validate_phase(r.phase, "rayleigh.phase");
  }
  if (s.mie) {
    const auto& m = *s.mie;
    require(std::isfinite(m.scattering_per_m) && m.scattering_per_m >= 0.0 && m.scattering_per_m <= 1e3,
            "mie.scattering_per_m", m.scattering_per_m,
            "must be in [0, 1e3] per metre (a density or coefficient cannot be negative)");
    require(std::isfinite(m.reference_nm) && m.reference_nm >= 1.0 && m.reference_nm <= 1e6, "mie.reference_nm",
            m.reference_nm, "must be in [1, 1e6] nm");
    require(std::isfinite(m.angstrom) && std::abs(m.angstrom) <= 10.0, "mie.angstrom", m.angstrom,
            "must be finite, |a| <= 10");
    require(std::isfinite(m.single_scattering_albedo) && m.single_scattering_albedo > 0.0 &&
                m.single_scattering_albedo <= 1.0,
            "mie.single_scattering_albedo", m.single_scattering_albedo, "must be in (0, 1]");
    check_profile(m.profile, "mie.profile", s.planet.radius_m);
    validate_phase(m.phase, "mie.phase");
  }
  if (s.ozone) {
    require(std::isfinite(s.ozone->column_du) && s.ozone->column_du >= 0.0 && s.ozone->column_du <= 1e6,
            "ozone.column_du", s.ozone->column_du, "must be in [0, 1e6] DU");
    check_profile(s.ozone->profile, "ozone.profile", s.planet.radius_m);
    DensityProfile p(s.ozone->profile, "ozone.profile");
    const double col = p.vertical_column(0.0, s.planet.atmosphere_top_m);
    if (s.ozone->column_du > 0.0 && !(col > 0.0))
      throw InputError("ozone.profile: zero column below planet.atmosphere_top_m, cannot hold " +
                       num(s.ozone->column_du) + " DU");
    if (s.ozone->column_du > 0.0 && !std::isfinite(s.ozone->column_du * kDobsonUnitPerM2 / col))
      throw InputError("ozone.profile: column " + num(col) + " m below the top is too thin to hold " +
                       num(s.ozone->column_du) + " DU (the number density overflows)");
  }
  const auto& sp = s.spectrum;
  if (sp.wavelengths_nm.empty()) {
    require(std::isfinite(sp.from_nm) && sp.from_nm > 0.0, "spectrum.from_nm", sp.from_nm, "must be > 0");
    require(std::isfinite(sp.to_nm) && sp.to_nm > sp.from_nm, "spectrum.to_nm", sp.to_nm,
            "must be > spectrum.from_nm");
    require(sp.count >= 1 && sp.count <= 100000, "spectrum.count", sp.count, "must be in [1, 100000]");
  }
  auto w = spectrum_wavelengths(sp);
  // A generated grid is named by the key the user wrote (from_nm / to_nm) and the bin
  // centre that falls outside; an explicit list by its element.
  auto where = [&](std::size_t i, bool below) {
    return sp.wavelengths_nm.empty() ? (below ? "spectrum.from_nm" : "spectrum.to_nm")
                                     : "spectrum.wavelengths_nm[" + std::to_string(i) + "]";
  };
  auto value_of = [&](std::size_t i, bool below) {
    return sp.wavelengths_nm.empty() ? (below ? sp.from_nm : sp.to_nm) : w[i];
  };
  auto range = [&](std::size_t i, double lo, double hi, const std::string& why) {
    if (w[i] >= lo && w[i] <= hi) return;
    const bool below = w[i] < lo;
    require(false, where(i, below), value_of(i, below),
            (sp.wavelengths_nm.empty() ? "its bin centre " + num(w[i]) + " nm lies " : std::string()) + "outside " +
                num(lo) + "-" + num(hi) + " nm, " + why);
  };
  for (std::size_t i = 0; i < w.size(); ++i) {
    require(std::isfinite(w[i]) && w[i] > 0.0, "spectrum.wavelengths_nm[" + std::to_string(i) + "]", w[i],
            "must be > 0");
    // The bins (solar spectrum, CIE weights) lie between neighbouring wavelengths.
    if (i > 0)
      require(w[i] > w[i - 1], "spectrum.wavelengths_nm[" + std::to_string(i) + "]", w[i],
              "must be greater than the wavelength before it (" + num(w[i - 1]) + " nm): the list is increasing");
    if (s.ozone) range(i, kOzoneTableFirstNm, kOzoneTableLastNm, "the ozone cross-section table");
    if (s.rayleigh && s.rayleigh->model == RayleighSpec::Model::Physical)
      range(i, kRayleighPhysicalFirstNm, kRayleighPhysicalLastNm,
            "the measurements behind the physical Rayleigh model's refractivity (Peck & Reeder 1972)");
  }
}

DensityProfileSpec us_standard_1976_profile(double top_m, double step_m) {
  // U.S. Standard Atmosphere 1976 (NOAA/NASA/USAF), defining constants: g0 =
  // 9.80665 m/s^2, M0 = 28.9644 kg/kmol, R* = 8314.32 J/(kmol K), r0 = 6356766 m,
  // base geopotential heights [km'] and lapse rates [K/km'] of its seven layers.
  constexpr double g0 = 9.80665, M0 = 28.9644, Rs = 8314.32, r0 = 6356766.0;
  constexpr double Hb[8] = {0, 11e3, 20e3, 32e3, 47e3, 51e3, 71e3, 84852.0};
  constexpr double Lb[8] = {-6.5e-3, 0, 1.0e-3, 2.8e-3, 0, -2.8e-3, -2.0e-3, 0};  // last: isothermal continuation
  double Tb[8], Pb[8];
  Tb[0] = 288.15;
  Pb[0] = 101325.0;
  auto layer = [&](int i, double H, double& T, double& P) {
    double dH = H - Hb[i];
    T = Tb[i] + Lb[i] * dH;
    P = Lb[i] == 0.0 ? Pb[i] * std::exp(-g0 * M0 * dH / (Rs * Tb[i]))
                     : Pb[i] * std::pow(Tb[i] / T, g0 * M0 / (Rs * Lb[i]));
  };
  for (int i = 1; i < 8; ++i) layer(i - 1, Hb[i], Tb[i], Pb[i]);
  const double rho0 = Pb[0] * M0 / (Rs * Tb[0]);
  DensityProfileSpec p;
  p.kind = DensityProfileSpec::Kind::Tabulated;
  // Nodes every step_m and at the layer boundaries (their geometric altitudes
  // z = r0 H / (r0 - H)): the kinks of the standard's density fall on nodes.
  std::vector<double> zs;
  int n = static_cast<int>(std::ceil(top_m / step_m));
  for (int k = 0; k <= n; ++k) zs.push_back(std::min(k * step_m, top_m));
  for (int i = 1; i < 8; ++i) {
    const double zb = r0 * Hb[i] / (r0 - Hb[i]);
    if (!(zb < top_m)) continue;
    // A grid node within step / 10 moves onto the boundary (no sliver pieces).
    auto near = std::min_element(zs.begin(), zs.end(), [&](double a, double b) { return std::abs(a - zb) < std::abs(b - zb); });
    if (std::abs(*near - zb) < 0.1 * step_m && *near > 0.0 && *near < top_m)
      *near = zb;
    else
      zs.insert(std::upper_bound(zs.begin(), zs.end(), zb), zb);
  }
  for (double z : zs) {
    double H = r0 * z / (r0 + z);  // geopotential height
    int i = 7;
    while (i > 0 && H < Hb[i]) --i;
    double T, P;
    layer(i, H, T, P);
    p.altitude_m.push_back(z);
    p.value.push_back(P * M0 / (Rs * T) / rho0);
  }
  return p;
}

std::vector<std::string> preset_names() { return {"earth-physical", "earth-graphics", "test-planet"}; }

namespace {
// A Mie constituent: scattering coefficient [1/m] at reference_nm, Angstrom exponent,
// single-scattering albedo, exponential profile of scale height [m], phase model with g.
MieSpec aerosol(double scattering_per_m, double reference_nm, double angstrom, double albedo, double scale_height_m,
                PhaseSpec::Model phase, double g) {
  MieSpec m;
  m.scattering_per_m = scattering_per_m;
  m.reference_nm = reference_nm;
  m.angstrom = angstrom;
  m.single_scattering_albedo = albedo;
  m.profile = exponential_profile(scale_height_m);
  m.phase = PhaseSpec{};
  m.phase.model = phase;
  m.phase.g = g;
  return m;
}
}  // namespace

AtmosphereSpec preset(std::string_view name) {
  AtmosphereSpec s;
  s.name = std::string(name);
  if (name == "earth-physical") {
    s.planet = {6371e3, 100e3, 0.1};
    RayleighSpec r;
    r.model = RayleighSpec::Model::Physical;
    r.pressure_pa = 101325.0;
    r.temperature_k = 288.15;
    r.co2_ppm = 360.0;
    r.profile = us_standard_1976_profile(100e3);
    r.phase = PhaseSpec{};
    r.phase.model = PhaseSpec::Model::Rayleigh;
    r.phase.depolarization = depolarization_from_king(king_factor_air(550.0, 360.0));
    s.rayleigh = r;
    // aerosol optical depth 0.1 at 550 nm
    s.mie = aerosol(0.9 * 0.1 / 1200.0, 550.0, 1.3, 0.9, 1200.0, PhaseSpec::Model::CornetteShanks, 0.8);
    s.ozone = OzoneSpec{};
    return s;
  }
  if (name == "earth-graphics") {
    s.planet = {6360e3, 60e3, 0.1};
    RayleighSpec r;
    r.model = RayleighSpec::Model::Coefficients;
    r.scattering_per_m = 1.24062e-6;
    r.reference_nm = 1000.0;
    r.profile = exponential_profile(8000.0);
    r.phase = PhaseSpec{};
    r.phase.model = PhaseSpec::Model::Rayleigh;
    r.phase.depolarization = 0.0;
    s.rayleigh = r;
    s.mie = aerosol(5.328e-3 / 1200.0 * 0.9, 550.0, 0.0, 0.9, 1200.0, PhaseSpec::Model::CornetteShanks, 0.8);
    s.ozone = OzoneSpec{};
    return s;
  }
  if (name == "test-planet") {
    s.planet = {200e3, 20e3, 0.2};
    RayleighSpec r;
    r.model = RayleighSpec::Model::Coefficients;
    r.scattering_per_m = 2.0e-5;
    r.reference_nm = 550.0;
    r.profile = exponential_profile(2000.0);
    r.phase = PhaseSpec{};
    r.phase.model = PhaseSpec::Model::Rayleigh;
    s.rayleigh = r;
    s.mie = aerosol(1.0e-5, 550.0, 1.0, 0.95, 500.0, PhaseSpec::Model::HenyeyGreenstein, 0.7);
    OzoneSpec o;
    o.column_du = 100.0;
    o.profile = tent_profile(4e3, 8e3, 12e3);
    s.ozone = o;
    s.spectrum.count = 8;
    return s;
  }
  std::string list;
  for (const auto& n : preset_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("preset '" + std::string(name) + "': unknown (valid: " + list + ")");
}

}  // namespace atmosh::atmo
