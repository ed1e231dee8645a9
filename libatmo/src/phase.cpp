#include "atmosh/atmo/phase.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/sh/zonal.hpp"

namespace atmosh::atmo {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kCsNodes = 2049;    // uniform in the HG-CDF variable
constexpr int kCsMuNodes = 512;   // and uniform in mu

std::string num(double v) { return atmosh::format_double(v); }
}  // namespace

double sample_hg(double g, double u) {
  u = std::clamp(u, 0.0, 1.0);
  if (std::abs(g) < 1e-8) return 2.0 * u - 1.0;
  if (g < 0.0) return -sample_hg(-g, 1.0 - u);
  // 1 - mu = (1 - g)(1 - u)(s + 1 - g) / (1 - g + 2 g u), s = (1 - g^2)/(1 - g + 2 g u):
  // no cancellation near the forward peak.
  double den = 1.0 - g + 2.0 * g * u;
  double s = (1.0 - g) * (1.0 + g) / den;
  double one_minus_mu = (1.0 - g) * (1.0 - u) * (s + 1.0 - g) / den;
  return std::clamp(1.0 - one_minus_mu, -1.0, 1.0);
}

PhaseFunction::PhaseFunction(const PhaseSpec& spec, const std::string& key) : spec_(spec) {
  using M = PhaseSpec::Model;
  auto check_g = [&](double g, const std::string& k) {
    if (!std::isfinite(g) || std::abs(g) >= 1.0) throw InputError(key + "." + k + " = " + num(g) + ": must be in (-1, 1)");
  };
  switch (spec_.model) {
    case M::Rayleigh:
      if (!std::isfinite(spec_.depolarization) || spec_.depolarization < 0.0 || spec_.depolarization >= 0.5)
        throw InputError(key + ".depolarization = " + num(spec_.depolarization) + ": must be in [0, 0.5)");
      mean_cos_ = 0.0;
      break;
    case M::HenyeyGreenstein:
      check_g(spec_.g, "g");
      mean_cos_ = spec_.g;
      break;
    case M::CornetteShanks: {
      check_g(spec_.g, "g");
      double g = spec_.g;
      mean_cos_ = 3.0 * g * (4.0 + g * g) / (5.0 * (2.0 + g * g));
      // CDF in the HG-CDF variable v: dG/dv = p_CS / p_HG = 1.5 (1 + mu(v)^2) / (2 + g^2).
      // Nodes: uniform in v, plus the v of mu uniform in [-1, 1] (v = the HG CDF of mu),
      // so that no cell spans a wide range of mu: for g -> 1 the whole backward
      // hemisphere lies within v < ~1e-4, one cell of the uniform grid.
      cs_v_.clear();
      for (int i = 0; i < kCsNodes; ++i) cs_v_.push_back(static_cast<double>(i) / (kCsNodes - 1));
      if (std::abs(g) > 1e-3)
        for (int j = 1; j < kCsMuNodes; ++j) {
          const double mu = -1.0 + 2.0 * j / kCsMuNodes;
          const double v = (1.0 - g) * (1.0 + g) / (2.0 * g) *
                           (1.0 / std::sqrt(shared::hg_denominator(mu, g)) - 1.0 / (1.0 + g));
          if (v > 0.0 && v < 1.0) cs_v_.push_back(v);
        }
      std::sort(cs_v_.begin(), cs_v_.end());
      cs_v_.erase(std::unique(cs_v_.begin(), cs_v_.end(), [](double a, double b) { return b - a < 1e-13; }),
                  cs_v_.end());
      cs_v_.back() = 1.0;
      cs_cdf_.assign(cs_v_.size(), 0.0);
      auto dens = [&](double v) {
        double mu = sample_hg(g, v);
        return 1.5 * (1.0 + mu * mu) / (2.0 + g * g);
      };
      // 4-point Gauss-Legendre per cell (nodes on [0,1]).
      const double gx[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
      const double gw[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269};
      for (std::size_t i = 1; i < cs_v_.size(); ++i) {
        double a = cs_v_[i - 1], h = cs_v_[i] - a, s = 0.0;
        for (int q = 0; q < 4; ++q) s += gw[q] * dens(a + gx[q] * h);
        cs_cdf_[i] = cs_cdf_[i - 1] + s * h;
      }
      double total = cs_cdf_.back();
      for (double& c : cs_cdf_) c /= total;
      break;
    }
    case M::DoubleHenyeyGreenstein:
      check_g(spec_.g, "g");
      check_g(spec_.g2, "g2");
      if (!std::isfinite(spec_.weight) || spec_.weight < 0.0 || spec_.weight > 1.0)
        throw InputError(key + ".weight = " + num(spec_.weight) + ": must be in [0, 1]");
      mean_cos_ = spec_.weight * spec_.g + (1.0 - spec_.weight) * spec_.g2;
      break;
    case M::Tabulated: {
      const auto& c = spec_.cos_theta;
      const auto& v = spec_.value;
      if (c.size() < 2 || c.size() != v.size())
        throw InputError(key + ": tabulated phase needs >= 2 (cos_theta, value) pairs of equal length");
      for (std::size_t i = 0; i < c.size(); ++i) {
        if (!std::isfinite(c[i]) || c[i] < -1.0 || c[i] > 1.0 || (i > 0 && !(c[i] > c[i - 1])))
          throw InputError(key + ".cos_theta[" + std::to_string(i) + "] = " + num(c[i]) + ": must increase within [-1, 1]");
        if (!std::isfinite(v[i]) || v[i] < 0.0)
          throw InputError(key + ".value[" + std::to_string(i) + "] = " + num(v[i]) + ": must be finite and >= 0");
      }
      table_cdf_.assign(c.size(), 0.0);
      double m1 = 0.0;
      for (std::size_t i = 1; i < c.size(); ++i) {
        double dx = c[i] - c[i - 1];
        table_cdf_[i] = table_cdf_[i - 1] + 2.0 * kPi * 0.5 * dx * (v[i - 1] + v[i]);
        // exact integral of mu * linear: 2-point Gauss-Legendre
        for (double t : {0.2113248654051871, 0.7886751345948129}) {
          double mu = c[i - 1] + t * dx;
          m1 += 2.0 * kPi * 0.5 * dx * mu * (v[i - 1] + t * (v[i] - v[i - 1]));
        }
      }
      if (!(table_cdf_.back() > 0.0)) throw InputError(key + ": tabulated phase integrates to 0");
      table_norm_ = 1.0 / table_cdf_.back();
      for (double& x : table_cdf_) x *= table_norm_;
      mean_cos_ = m1 * table_norm_;
      break;
    }
  }
}

// shared::phase_analytic takes the model's code in this order.
static_assert(static_cast<int>(PhaseSpec::Model::HenyeyGreenstein) == 1 &&
              static_cast<int>(PhaseSpec::Model::CornetteShanks) == 2 &&
              static_cast<int>(PhaseSpec::Model::DoubleHenyeyGreenstein) == 3);

double PhaseFunction::value(double mu) const {
  using M = PhaseSpec::Model;
  mu = std::clamp(mu, -1.0, 1.0);
  switch (spec_.model) {
    case M::Rayleigh: return shared::phase_analytic(0, mu, spec_.depolarization, spec_.g2, spec_.weight);
    case M::HenyeyGreenstein:
    case M::CornetteShanks:
    case M::DoubleHenyeyGreenstein:  // shared/geometry.glsl.hpp, as the GPU's phase_value
      return shared::phase_analytic(static_cast<int>(spec_.model), mu, spec_.g, spec_.g2, spec_.weight);
    case M::Tabulated: {
      const auto& c = spec_.cos_theta;
      if (mu < c.front() || mu > c.back()) return 0.0;
      auto it = std::upper_bound(c.begin(), c.end(), mu);
      std::size_t i = it == c.end() ? c.size() - 1 : static_cast<std::size_t>(it - c.begin());
      if (i == 0) i = 1;
      double t = (mu - c[i - 1]) / (c[i] - c[i - 1]);
      return table_norm_ * (spec_.value[i - 1] + t * (spec_.value[i] - spec_.value[i - 1]));
    }
  }
  return 0.0;
}

double PhaseFunction::mean_cosine() const { return mean_cos_; }

double PhaseFunction::cdf_rayleigh(double mu) const {
  double gamma = spec_.depolarization / (2.0 - spec_.depolarization);
  double a = 1.0 + 3.0 * gamma, b = 1.0 - gamma;
  double A = 3.0 / (16.0 * kPi * (1.0 + 2.0 * gamma));
  return 2.0 * kPi * A * (a * (mu + 1.0) + b * (mu * mu * mu + 1.0) / 3.0);
}

double PhaseFunction::sample(double u) const {
  using M = PhaseSpec::Model;
  if (!std::isfinite(u)) throw InputError("phase sample: u = " + num(u) + ": must be finite");
  u = std::clamp(u, 0.0, 1.0);
  switch (spec_.model) {
    case M::HenyeyGreenstein: return sample_hg(spec_.g, u);
    case M::DoubleHenyeyGreenstein: {
      double w = spec_.weight;
      if (u < w) return sample_hg(spec_.g, w > 0.0 ? u / w : 0.0);
      return sample_hg(spec_.g2, w < 1.0 ? (u - w) / (1.0 - w) : 1.0);
    }
    case M::Rayleigh: {
      double lo = -1.0, hi = 1.0, mu = 2.0 * u - 1.0;
      for (int it = 0; it < 60; ++it) {
        double f = cdf_rayleigh(mu) - u;
        if (std::abs(f) < 1e-15) break;
        (f < 0.0 ? lo : hi) = mu;
        double step = f / pdf(mu);
        double next = mu - step;
        mu = (next > lo && next < hi) ? next : 0.5 * (lo + hi);
      }
      return mu;
    }
    case M::CornetteShanks: {
      // Find v with G(v) = u by cubic Hermite interpolation of G (slopes known).
      double g = spec_.g;
      auto slope = [&](double v) {
        double mu = sample_hg(g, v);
        return 1.5 * (1.0 + mu * mu) / (2.0 + g * g) / cs_cdf_.back();
      };
      auto it = std::upper_bound(cs_cdf_.begin(), cs_cdf_.end(), u);
      int i = std::clamp(static_cast<int>(it - cs_cdf_.begin()), 1, static_cast<int>(cs_cdf_.size()) - 1);
      const double v0 = cs_v_[static_cast<std::size_t>(i) - 1], h = cs_v_[static_cast<std::size_t>(i)] - v0;
      double G0 = cs_cdf_[i - 1], G1 = cs_cdf_[i];
      double d0 = slope(v0) * h, d1 = slope(v0 + h) * h;
      double t = (G1 > G0) ? (u - G0) / (G1 - G0) : 0.0;
      for (int k = 0; k < 30; ++k) {
        double t2 = t * t, t3 = t2 * t;
        double H = (2 * t3 - 3 * t2 + 1) * G0 + (t3 - 2 * t2 + t) * d0 + (-2 * t3 + 3 * t2) * G1 + (t3 - t2) * d1;
        double dH = (6 * t2 - 6 * t) * G0 + (3 * t2 - 4 * t + 1) * d0 + (-6 * t2 + 6 * t) * G1 + (3 * t2 - 2 * t) * d1;
        if (!(dH > 0.0)) break;
        double step = (H - u) / dH;
        t = std::clamp(t - step, 0.0, 1.0);
        if (std::abs(step) < 1e-15) break;
      }
      return sample_hg(g, v0 + t * h);
    }
    case M::Tabulated: {
      const auto& c = spec_.cos_theta;
      const auto& v = spec_.value;
      auto it = std::upper_bound(table_cdf_.begin(), table_cdf_.end(), u);
      std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - table_cdf_.begin()), 1, c.size() - 1);
      // Solve 2 pi norm [p0 x + (p1 - p0) x^2 / (2 dx)] = u - F0 for x in [0, dx].
      double dx = c[i] - c[i - 1];
      double p0 = 2.0 * kPi * table_norm_ * v[i - 1], p1 = 2.0 * kPi * table_norm_ * v[i];
      double target = u - table_cdf_[i - 1];
      double a = 0.5 * (p1 - p0) / dx, b = p0;
      double x;
      if (std::abs(a) * dx < 1e-12 * std::max(b, 1e-300)) {
        x = b > 0.0 ? target / b : 0.0;
      } else {
        double disc = std::max(0.0, b * b + 4.0 * a * target);
        x = 2.0 * target / (b + std::sqrt(disc));  // stable root
      }
      return std::clamp(c[i - 1] + std::clamp(x, 0.0, dx), -1.0, 1.0);
    }
  }
  return 0.0;
}

LegendreMoments PhaseFunction::legendre_moments(int n) const {
  if (n < 1 || n > 4096) throw InputError("legendre moments: count " + std::to_string(n) + ": must be in [1, 4096]");
  LegendreMoments out;
  using M = PhaseSpec::Model;
  if (spec_.model == M::HenyeyGreenstein) {
    out.chi.resize(n);
    double p = 1.0;
    for (int l = 0; l < n; ++l, p *= spec_.g) out.chi[l] = p;
    return out;
  }
  auto f = [this](double mu) { return value(mu); };
  std::vector<double> z, zh;
  if (spec_.model == M::Tabulated) {
    // Piecewise linear between the table's nodes (0 outside them): composite
    // Gauss-Legendre with the nodes as breaks, so no piece straddles a kink.
    z = sh::zonal_coefficients(f, n, spec_.cos_theta, 16);
    zh = sh::zonal_coefficients(f, n, spec_.cos_theta, 8);
  } else {
    // Peaked lobes (HG-like, Rayleigh is smooth): p ~ ((1 - g)^2 + 2 g s)^(-3/2) in
    // s = 1 - mu (s = 1 + mu for a backward lobe), a peak of width s0 = (1 - g)^2 / 2.
    // Composite Gauss-Legendre on pieces graded geometrically away from each end,
    // [0, s0], [s0, 2 s0], ..., up to mu = 0: on every piece the pole of the lobe, at
    // s ~ -s0, is as far away relative to the piece as for [0, s0], so a fixed number of
    // points per piece converges geometrically (g = 0.999: s0 = 5e-7, 21 pieces a side).
    // A single Gauss-Legendre rule of 4096 points missed chi_0 by 1.8e-3 at g = 0.999.
    double gmax = 0.0;
    if (spec_.model == M::CornetteShanks) gmax = std::abs(spec_.g);
    if (spec_.model == M::DoubleHenyeyGreenstein) gmax = std::max(std::abs(spec_.g), std::abs(spec_.g2));
    const double s0 = std::max(0.5 * (1.0 - gmax) * (1.0 - gmax), 1e-300);
    std::vector<double> lo;  // distances from the ends, ascending
    for (double s = s0; s < 1.0; s *= 2.0) lo.push_back(s);
    std::vector<double> breaks{-1.0};
    for (double s : lo) breaks.push_back(-1.0 + s);
    breaks.push_back(0.0);
    for (auto it = lo.rbegin(); it != lo.rend(); ++it) breaks.push_back(1.0 - *it);
    breaks.push_back(1.0);
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    z = sh::zonal_coefficients(f, n, breaks, 24);
    zh = sh::zonal_coefficients(f, n, breaks, 12);
  }
  out.chi.resize(n);
  for (int l = 0; l < n; ++l) {
    double y = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi));
    out.chi[l] = z[l] / y;
    out.error_estimate = std::max(out.error_estimate, std::abs(z[l] - zh[l]) / y);
  }
  return out;
}

DeltaM PhaseFunction::delta_m(int n) const {
  if (n < 1) throw InputError("delta-M: moment count " + std::to_string(n) + ": must be >= 1");
  // Delta-M truncates a forward peak (f = chi_n in [0, 1)); for a backward-peaked
  // function chi_n alternates in sign with n and the scaled moments are meaningless.
  if (mean_cos_ < 0.0)
    throw InputError("delta-M: mean cosine " + num(mean_cos_) + " < 0: only forward-peaked functions are truncated");
  auto m = legendre_moments(n + 1);
  DeltaM out;
  out.f = m.chi[n];
  if (!(out.f < 1.0))
    throw InputError("delta-M: chi_" + std::to_string(n) + " = " + num(out.f) + ": must be < 1 to truncate");
  out.truncated.resize(n);
  for (int l = 0; l < n; ++l) out.truncated[l] = (m.chi[l] - out.f) / (1.0 - out.f);
  return out;
}

}  // namespace atmosh::atmo
