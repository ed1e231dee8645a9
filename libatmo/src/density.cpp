#include "atmosh/atmo/density.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"

namespace atmosh::atmo {

namespace {
std::string num(double v) { return atmosh::format_double(v); }
}  // namespace

DensityProfile::DensityProfile(const DensityProfileSpec& spec, const std::string& key) : spec_(spec) {
  using K = DensityProfileSpec::Kind;
  switch (spec.kind) {
    case K::Exponential:
      // >= 1 mm: below that exp(-h/H) overflows for altitudes rounded just below 0.
      if (!std::isfinite(spec.scale_height_m) || spec.scale_height_m < 1e-3)
        throw InputError(key + ".scale_height_m = " + num(spec.scale_height_m) + ": must be >= 1e-3 m");
      break;
    case K::Tent:
      if (!std::isfinite(spec.bottom_m) || !std::isfinite(spec.peak_m) || !std::isfinite(spec.top_m) ||
          !(spec.bottom_m < spec.peak_m && spec.peak_m < spec.top_m) || std::abs(spec.bottom_m) > 1e9 ||
          std::abs(spec.top_m) > 1e9)
        throw InputError(key + ": tent needs bottom_m < peak_m < top_m, all within +-1e9 m (got " + num(spec.bottom_m) + ", " +
                         num(spec.peak_m) + ", " + num(spec.top_m) + ")");
      kinks_ = {spec.bottom_m, spec.peak_m, spec.top_m};
      break;
    case K::Tabulated: {
      if (spec.altitude_m.size() < 2 || spec.altitude_m.size() != spec.value.size())
        throw InputError(key + ": tabulated profile needs >= 2 (altitude_m, value) pairs of equal length");
      for (std::size_t i = 0; i < spec.altitude_m.size(); ++i) {
        if (!std::isfinite(spec.altitude_m[i]) || std::abs(spec.altitude_m[i]) > 1e9 ||
            (i > 0 && !(spec.altitude_m[i] > spec.altitude_m[i - 1])))
          throw InputError(key + ".altitude_m[" + std::to_string(i) + "] = " + num(spec.altitude_m[i]) +
                           ": must be increasing, within +-1e9 m");
        if (!std::isfinite(spec.value[i]) || spec.value[i] < 0.0 || spec.value[i] > 1e30)
          throw InputError(key + ".value[" + std::to_string(i) + "] = " + num(spec.value[i]) +
                           ": relative density must be in [0, 1e30]");
      }
      kinks_ = spec.altitude_m;
      index_ = SortedIndex(spec.altitude_m);
      break;
    }
  }
}

namespace {
// Second derivative at x of the cubic through the nodes x[0], x[dir], x[2 dir],
// x[3 dir] (values y at the same offsets): the Lagrange form differentiated twice.
double cubic_second_derivative(const double* x, const double* y, int dir, double at) {
  double xs[4], ys[4];
  for (int j = 0; j < 4; ++j) {
    xs[j] = x[j * dir];
    ys[j] = y[j * dir];
  }
  double d2 = 0.0;
  for (int j = 0; j < 4; ++j) {
    double den = 1.0, num = 0.0;
    int o[3], n = 0;
    for (int k = 0; k < 4; ++k)
      if (k != j) {
        den *= xs[j] - xs[k];
        o[n++] = k;
      }
    // d2/dx2 of (x - a)(x - b)(x - c) = 2 [(x - a) + (x - b) + (x - c)]
    for (int k = 0; k < 3; ++k) num += 2.0 * (at - xs[o[k]]);
    d2 += ys[j] * num / den;
  }
  return d2;
}
}  // namespace

std::vector<DensityProfile::Kink> DensityProfile::strongest_kink_jumps(int n, double lo, double hi,
                                                                      double min_ratio) const {
  if (n <= 0) return {};
  std::vector<Kink> out;
  if (spec_.kind != DensityProfileSpec::Kind::Tabulated) {  // tent: its three corners
    if (spec_.kind == DensityProfileSpec::Kind::Tent) {
      const double s1 = 1.0 / (spec_.peak_m - spec_.bottom_m), s2 = -1.0 / (spec_.top_m - spec_.peak_m);
      for (Kink k : {Kink{spec_.bottom_m, s1}, Kink{spec_.peak_m, s2 - s1}, Kink{spec_.top_m, -s2}})
        if (k.altitude_m > lo && k.altitude_m < hi) out.push_back(k);
    }
    return out;
  }
  const auto& a = spec_.altitude_m;
  const auto& v = spec_.value;
  const std::size_t m = a.size();
  std::vector<double> slope(m + 1, 0.0);  // slope[i]: on (a[i-1], a[i]); 0 outside the table
  for (std::size_t i = 1; i < m; ++i) slope[i] = (v[i] - v[i - 1]) / (a[i] - a[i - 1]);
  std::vector<double> jump(m), excess(m), smooth(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) jump[i] = slope[i + 1] - slope[i];
  auto half_span = [&](std::size_t i) { return 0.5 * (a[i + 1] - a[i - 1]); };  // interior i
  for (std::size_t i = 0; i < m; ++i) {
    excess[i] = jump[i];
    if (i == 0 || i + 1 == m) continue;
    double kappa[4];
    int count = 0;
    for (int dj : {-2, -1, 1, 2}) {
      const long j = static_cast<long>(i) + dj;
      if (j > 0 && j + 1 < static_cast<long>(m))
        kappa[count++] = jump[static_cast<std::size_t>(j)] / half_span(static_cast<std::size_t>(j));
    }
    std::sort(kappa, kappa + count);
    if (count > 0) smooth[i] = 0.5 * (kappa[(count - 1) / 2] + kappa[count / 2]) * half_span(i);
    excess[i] -= smooth[i];
  }
  std::vector<std::pair<double, std::size_t>> rank;  // (score, node)
  for (std::size_t i = 0; i < m; ++i) {
    double scale = v[i];
    if (i > 0) scale = std::max(scale, v[i - 1]);
    if (i + 1 < m) scale = std::max(scale, v[i + 1]);
    const double e = std::abs(excess[i]);
    rank.push_back({scale > 0.0 ? e / scale : e > 0.0 ? std::numeric_limits<double>::infinity() : 0.0, i});
  }
  std::stable_sort(rank.begin(), rank.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<char> taken(m, 0);
  for (const auto& [score, i] : rank) {
    if (static_cast<int>(out.size()) == n) break;
    if (!(a[i] > lo && a[i] < hi) || !(std::abs(excess[i]) > min_ratio * std::abs(smooth[i])) ||
        (i > 0 && taken[i - 1]) || (i + 1 < m && taken[i + 1]))
      continue;
    taken[i] = 1;
    // The curvature jump from one-sided cubics; 0 when a window holds a node with a
    // larger excess (a stronger kink nearby, whose jump the cubic would take for
    // curvature).
    double curvature = 0.0;
    bool clear = i >= 3 && i + 3 < m;
    for (std::size_t j = i > 3 ? i - 3 : 0; clear && j <= i + 3 && j < m; ++j)
      clear = j == i || std::abs(excess[j]) <= std::abs(excess[i]);
    if (clear)
      curvature = cubic_second_derivative(&a[i], &v[i], 1, a[i]) - cubic_second_derivative(&a[i], &v[i], -1, a[i]);
    out.push_back({a[i], excess[i], smooth[i], curvature});
  }
  std::sort(out.begin(), out.end(), [](const Kink& x, const Kink& y) { return x.altitude_m < y.altitude_m; });
  return out;
}

std::vector<double> DensityProfile::strongest_kinks(int n, double lo, double hi) const {
  std::vector<double> out;
  if (n <= 0) return out;
  if (static_cast<int>(kinks_.size()) <= n) {
    for (double k : kinks_)
      if (k > lo && k < hi) out.push_back(k);
    return out;
  }
  for (const Kink& k : strongest_kink_jumps(n, lo, hi)) out.push_back(k.altitude_m);
  return out;
}

double DensityProfile::operator()(double h) const {
  using K = DensityProfileSpec::Kind;
  switch (spec_.kind) {
    case K::Exponential:
      return shared::density_exponential(h, spec_.scale_height_m);
    case K::Tent:
      return shared::density_tent(h, spec_.bottom_m, spec_.peak_m, spec_.top_m);
    case K::Tabulated: {
      const auto& a = spec_.altitude_m;
      if (h < a.front() || h > a.back()) return 0.0;
      // i: first node above h (std::upper_bound), clamped to [1, n - 1]
      std::size_t i = static_cast<std::size_t>(std::clamp(index_.find(h) + 1, 1, static_cast<int>(a.size()) - 1));
      return shared::linear_between(h, a[i - 1], a[i], spec_.value[i - 1], spec_.value[i]);  // the GPU's too
    }
  }
  return 0.0;
}

bool DensityProfile::positive_on(double top_m) const {
  using K = DensityProfileSpec::Kind;
  switch (spec_.kind) {
    case K::Exponential:
      return true;
    case K::Tent:
      return false;
    case K::Tabulated:
      if (spec_.altitude_m.front() > 0.0 || spec_.altitude_m.back() < top_m) return false;
      for (double v : spec_.value)
        if (!(v > 0.0)) return false;
      return true;
  }
  return false;
}

double DensityProfile::vertical_column(double h0, double h1) const {
  using K = DensityProfileSpec::Kind;
  if (!(h1 > h0)) return 0.0;
  switch (spec_.kind) {
    case K::Exponential: {
      double H = spec_.scale_height_m;
      // H (e^{-h0/H} - e^{-h1/H}) = H e^{-h0/H} (1 - e^{-(h1-h0)/H})
      return -H * std::exp(-h0 / H) * std::expm1(-(h1 - h0) / H);
    }
    case K::Tent:
    case K::Tabulated: {
      // Exact trapezoid integral of the piecewise linear function, split at nodes.
      std::vector<double> pts{h0};
      for (double k : kinks_)
        if (k > h0 && k < h1) pts.push_back(k);
      pts.push_back(h1);
      double sum = 0.0;
      for (std::size_t i = 1; i < pts.size(); ++i)
        sum += 0.5 * (pts[i] - pts[i - 1]) * ((*this)(pts[i - 1]) + (*this)(pts[i]));
      return sum;
    }
  }
  return 0.0;
}

double DensityProfile::feature_length() const {
  using K = DensityProfileSpec::Kind;
  if (spec_.kind == K::Exponential) return spec_.scale_height_m;
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < kinks_.size(); ++i) m = std::min(m, kinks_[i] - kinks_[i - 1]);
  return m;
}

}  // namespace atmosh::atmo
