#include "atmosh/atmo/optical_depth.hpp"

#include <algorithm>
#include <cstdint>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fast_exp.hpp"
#include "integrate.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::atmo {

namespace sg = shared;

namespace {
std::string num(double v) { return atmosh::format_double(v); }

void check_ray(double r, double mu) {
  if (!std::isfinite(r) || r <= 0.0) throw InputError("ray origin radius " + num(r) + " m: must be finite and > 0");
  if (!std::isfinite(mu) || mu < -1.0 - 1e-12 || mu > 1.0 + 1e-12)
    throw InputError("ray cos(zenith) " + num(mu) + ": must be in [-1, 1]");
}

// Adds the distances (in (0, L)) at which the ray crosses the sphere of radius rho.
void add_crossings(double r, double mu, double L, double rho, std::vector<double>& pts) {
  double rt = std::sqrt(sg::tangent_radius_sq(r, mu));
  if (rho < rt) return;
  double q = std::sqrt((rho - rt) * (rho + rt));
  double s1 = -r * mu - q, s2 = -r * mu + q;
  if (s1 > 0.0 && s1 < L) pts.push_back(s1);
  if (s2 > 0.0 && s2 < L) pts.push_back(s2);
}
// p(h) = sum_k J_k (h_k - h)_+ : slope jumps J_k at the altitudes h_k, 0 above them
// and below the ground (as its closed-form column, whose first node is at 0).
double kink_ramps(const std::vector<DensityProfile::Kink>& kinks, double h) {
  double p = 0.0;
  if (h < 0.0) return p;
  for (const auto& k : kinks) p += k.excess_jump * std::max(0.0, k.altitude_m - h);
  return p;
}
}  // namespace

double optical_depth(const Coefficients& k, const glm::dvec3& column) { return glm::dot(k.extinction, column); }

double transmittance(double tau) {
  if (std::isnan(tau)) return 0.0;
  if (tau > 745.2) return 0.0;  // exp underflows below the smallest subnormal: exactly 0
  return std::exp(-tau);
}

// ---------------------------------------------------------------- piecewise-linear column

PiecewiseLinearColumn::PiecewiseLinearColumn(const DensityProfile& profile, double ground_radius) {
  const auto& spec = profile.spec();
  switch (profile.kind()) {
    case DensityProfileSpec::Kind::Tent:
      *this = PiecewiseLinearColumn({spec.bottom_m, spec.peak_m, spec.top_m}, {0.0, 1.0, 0.0}, ground_radius);
      break;
    case DensityProfileSpec::Kind::Tabulated:
      *this = PiecewiseLinearColumn(spec.altitude_m, spec.value, ground_radius);
      break;
    default:
      throw InputError("closed-form column: the profile is exponential, not piecewise linear");
  }
}

namespace {
// InputError unless the ground radius is finite and > 0, h and v have one length,
// the altitudes h ascend and all are finite; `what` names the column, `item` a node.
void check_column_nodes(const std::vector<double>& h, const std::vector<double>& v, double ground_radius,
                        const std::string& what, const std::string& item) {
  if (!std::isfinite(ground_radius) || ground_radius <= 0.0)
    throw InputError("ground radius " + num(ground_radius) + " m: must be finite and > 0");
  if (h.size() != v.size()) throw InputError(what + ": altitudes and values differ in length");
  for (std::size_t i = 0; i < h.size(); ++i)
    if (!std::isfinite(h[i]) || !std::isfinite(v[i]) || (i > 0 && !(h[i] > h[i - 1])))
      throw InputError(what + ": " + item + " " + std::to_string(i) + " (" + num(h[i]) + " m, " + num(v[i]) +
                       ") is not finite or not ascending");
}
}  // namespace

PiecewiseLinearColumn::PiecewiseLinearColumn(const std::vector<double>& h, const std::vector<double>& v,
                                             double ground_radius) {
  check_column_nodes(h, v, ground_radius, "closed-form column", "node");
  radius_.resize(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) radius_[i] = ground_radius + h[i];
  value_ = v;
  nonnegative_ = std::all_of(v.begin(), v.end(), [](double x) { return x >= 0.0; });
  slope_.assign(h.size(), 0.0);
  for (std::size_t i = 0; i + 1 < h.size(); ++i) slope_[i] = (v[i + 1] - v[i]) / (h[i + 1] - h[i]);
}

double PiecewiseLinearColumn::operator()(double r, double mu, double length) const {
  if (!(length > 0.0) || radius_.empty()) return 0.0;
  const int n = static_cast<int>(radius_.size());
  // Scratch for the shared traversal (shared/geometry.glsl.hpp).
  constexpr int kStack = 32;
  double q_stack[kStack];
  std::vector<double> q_heap;
  double* q = q_stack;
  if (n > kStack) {
    q_heap.resize(n);
    q = q_heap.data();
  }
  const double column = sg::piecewise_linear_column(r, mu, length, radius_.data(), value_.data(), slope_.data(), n, q);
  return nonnegative_ ? std::max(column, 0.0) : column;
}

QuadraticRampsColumn::QuadraticRampsColumn(const std::vector<double>& h, const std::vector<double>& half_curv,
                                           double ground_radius) {
  check_column_nodes(h, half_curv, ground_radius, "quadratic ramps", "ramp");
  ground_radius_ = ground_radius;
  for (double x : h) radius_.push_back(ground_radius + x);
  half_curv_ = half_curv;
}

double QuadraticRampsColumn::operator()(double r, double mu, double length) const {
  return sg::quadratic_ramps_column(r, mu, length, radius_.data(), half_curv_.data(), ramps());
}

double QuadraticRampsColumn::at(double h) const {  // shared/geometry.glsl.hpp, as the GPU table build's
  return sg::quadratic_ramps_at(h, radius_.data(), half_curv_.data(), static_cast<int>(radius_.size()), ground_radius_);
}

// ---------------------------------------------------------------- reference

OpticalDepthReference::OpticalDepthReference(const Atmosphere& atmosphere, ReferenceOptions options)
    : atm_(atmosphere), opt_(options) {
  if (!(opt_.rel_tol > 0.0) || !(opt_.abs_tol_fraction > 0.0) || opt_.max_intervals < 1)
    throw InputError("reference options: tolerances must be > 0 and max_intervals >= 1");
  glm::dvec3 v = atm_.vertical_column();
  for (int c = 0; c < 3; ++c) abs_tol_[c] = std::max(v[c] * opt_.abs_tol_fraction, 1e-300);
  // The altitude of a point on a ray, r(s) - R, carries a rounding error of ~eps R, so
  // exp(-h/H) carries eps R / H relative: no quadrature gets below that. Asking for
  // less only makes the adaptive loop bisect noise up to max_intervals (H = 10 m on
  // Earth: 6e5 evaluations, converged = false, for a value good to 3e-12).
  double h_min = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 3; ++c)
    if (atm_.has(c) && atm_.profile(c).kind() == DensityProfileSpec::Kind::Exponential)
      h_min = std::min(h_min, atm_.profile(c).spec().scale_height_m);
  rel_tol_ = std::max(opt_.rel_tol, std::numeric_limits<double>::epsilon() * atm_.ground_radius() / h_min);
}

RayColumn OpticalDepthReference::column(double r, double mu, double length) const {
  check_ray(r, mu);
  if (std::isnan(length)) throw InputError("ray length is NaN");
  mu = std::clamp(mu, -1.0, 1.0);
  const double R = atm_.ground_radius(), T = atm_.top_radius();
  RayColumn out;
  if (r > T) {
    double s0 = sg::distance_to_top_from_outside(r, mu, T);
    if (s0 < 0.0) return out;  // misses the atmosphere
    mu = std::clamp((r * mu + s0) / T, -1.0, 1.0);
    r = T;
    if (length >= 0.0) {
      length -= s0;
      if (length <= 0.0) return out;
    }
  }
  if (r < R) {
    if (r < R * (1.0 - 1e-9)) throw InputError("ray origin radius " + num(r) + " m: below the ground");
    r = R;
  }
  bool hits = sg::ray_hits_ground(r, mu, R);
  double L = hits ? sg::distance_to_ground(r, mu, R) : sg::distance_to_top(r, mu, T);
  if (length >= 0.0 && length < L) {
    L = length;
    hits = false;
  }
  out.hits_ground = hits;
  out.length_m = L;
  if (!(L > 0.0)) return out;

  std::vector<double> pts;
  double st = sg::tangent_distance(r, mu);
  bool tangent_inside = st > 0.0 && st < L;
  if (tangent_inside) pts.push_back(st);
  for (double k : atm_.kinks()) add_crossings(r, mu, L, R + k, pts);
  double h_low = tangent_inside ? std::sqrt(sg::tangent_radius_sq(r, mu)) - R
                                : std::min(r, sg::radius_along(r, mu, L)) - R;
  h_low = std::max(h_low, 0.0);
  for (int c = 0; c < 3; ++c) {
    if (!atm_.has(c) || atm_.profile(c).kind() != DensityProfileSpec::Kind::Exponential) continue;
    double H = atm_.profile(c).spec().scale_height_m;
    for (double f : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0}) add_crossings(r, mu, L, R + h_low + f * H, pts);
  }
  auto f = [&](double s) { return atm_.density(sg::radius_along(r, mu, s) - R); };
  auto q = integrate_adaptive<glm::dvec3>(f, 0.0, L, pts, abs_tol_, rel_tol_, opt_.max_intervals);
  out.column = q.value;
  out.error = q.error;
  out.evaluations = q.evaluations;
  out.converged = q.converged;
  return out;
}

// ---------------------------------------------------------------- lookup tables

OpticalDepthLut::OpticalDepthLut(const Atmosphere& atmosphere, LutOptions options)
    : atm_(atmosphere), opt_(options) {
  if (opt_.shells < 4 || opt_.shells > 4096)
    throw InputError("lut shells = " + std::to_string(opt_.shells) + ": must be in [4, 4096]");
  if (opt_.view_directions < 4 || opt_.view_directions > 65536)
    throw InputError("lut view_directions = " + std::to_string(opt_.view_directions) + ": must be in [4, 65536]");
  if (opt_.sun_directions < 4 || opt_.sun_directions > 65536)
    throw InputError("lut sun_directions = " + std::to_string(opt_.sun_directions) + ": must be in [4, 65536]");
  if (!std::isfinite(opt_.uniform_share) || opt_.uniform_share < 0.0)
    throw InputError("lut uniform_share = " + num(opt_.uniform_share) + ": must be >= 0");
  if (!std::isfinite(opt_.altitude_share) || opt_.altitude_share < 0.0)
    throw InputError("lut altitude_share = " + num(opt_.altitude_share) + ": must be >= 0");
  if (opt_.gauss_points < 2 || opt_.gauss_points > 64)
    throw InputError("lut gauss_points = " + std::to_string(opt_.gauss_points) + ": must be in [2, 64]");
  if (opt_.analytic_max_nodes < 0)
    throw InputError("lut analytic_max_nodes = " + std::to_string(opt_.analytic_max_nodes) + ": must be >= 0");
  resolve_threads(opt_.threads, "lut threads");  // the toolkit's policy: 0..1024
  if (opt_.subtracted_kinks < 0 || opt_.subtracted_kinks > 15)
    throw InputError("lut subtracted_kinks = " + std::to_string(opt_.subtracted_kinks) + ": must be in [0, 15]");
  auto t0 = std::chrono::steady_clock::now();
  R_ = atm_.ground_radius();
  T_ = atm_.top_radius();
  Hh_ = std::sqrt((T_ - R_) * (T_ + R_));
  const double top = atm_.top_altitude();
  glm::dvec3 vc = atm_.vertical_column();
  int n_present = 0;
  for (int c = 0; c < 3; ++c) {
    present_[c] = atm_.has(c) && vc[c] > 0.0;
    // Piecewise-linear profiles with few nodes: closed-form column at lookup;
    // they take no part in shell placement or kink handling of the tables.
    const auto& prof = atm_.profile(c);
    analytic_[c] = present_[c] && prof.kind() != DensityProfileSpec::Kind::Exponential &&
                   static_cast<int>(prof.kinks().size()) <= opt_.analytic_max_nodes;
    if (analytic_[c]) {
      linear_[c] = PiecewiseLinearColumn(prof, R_);
      present_[c] = false;
      continue;
    }
    n_present += present_[c];
    // Tabulated and tent profiles that are interpolated from the tables: their
    // table entries are built in closed form (exact), not by quadrature.
    if (present_[c] && prof.kind() != DensityProfileSpec::Kind::Exponential) {
      build_linear_[c] = PiecewiseLinearColumn(prof, R_);
      build_closed_[c] = true;
    }
    log_encoded_[c] = present_[c] && atm_.profile(c).positive_on(top);
    has_kinks_ = has_kinks_ || (present_[c] && !log_encoded_[c]);
    support_top_[c] = top;
    if (present_[c] && !log_encoded_[c]) {
      const auto& ks = atm_.profile(c).kinks();
      if (!ks.empty() && atm_.profile(c)(ks.back() + 1e-9 * top) == 0.0 && atm_.profile(c)(top) == 0.0) support_top_[c] = ks.back();
    }
  }
  // Long tables interpolated in log: their strongest kinks are subtracted before
  // tabulating, p(h) = sum_k J_k (h_k - h)_+ on [0, top] (0 above the highest h_k):
  // slope jumps J_k (the kinks' excess jumps) at the h_k and none elsewhere above the
  // ground, so rho - p is smooth there; p's column is added back in closed form
  // (and q's, the curvature jumps' quadratic ramps, below). Only while |p + q| stays
  // within 1/2 of rho at every node (the relative error of the tabulated part then
  // grows by at most 2x in the total); otherwise none.
  if (opt_.subtracted_kinks > 0)
    for (int c = 0; c < 3; ++c) {
      if (!(build_closed_[c] && log_encoded_[c])) continue;
      const auto& prof = atm_.profile(c);
      std::vector<DensityProfile::Kink> ks;
      for (const auto& k : prof.strongest_kink_jumps(opt_.subtracted_kinks, 0.0, top, kSubtractedKinkRatio))
        if (k.excess_jump != 0.0) ks.push_back(k);
      if (ks.empty()) continue;
      auto p_at = [&](double h) { return kink_ramps(ks, h); };
      std::vector<double> h{0.0}, v, hq, cq;
      for (const auto& k : ks) h.push_back(k.altitude_m);
      for (double x : h) v.push_back(p_at(x));
      // q(h) = sum_k -D_k / 2 (h_k - h)_+^2 with D_k the curvature jump: q'' jumps by
      // -D_k at h_k (0 above, -D_k below), so rho - p - q is C2 there as well.
      if (opt_.subtract_curvature)
        for (const auto& k : ks)
          if (k.curvature_jump != 0.0) {
            hq.push_back(k.altitude_m);
            cq.push_back(-0.5 * k.curvature_jump);
          }
      const QuadraticRampsColumn q(hq, cq, R_);
      bool ok = true;
      auto check = [&](double x) {
        const double rho = prof(x), p = p_at(x) + q.at(x);
        ok = ok && std::abs(p) <= 0.5 * rho && p >= -rho;
      };
      check(0.0);
      check(top);
      for (double x : prof.spec().altitude_m)
        if (x > 0.0 && x < top) check(x);
      if (!ok) continue;
      subtracted_[c] = PiecewiseLinearColumn(h, v, R_);
      subtracted_curvature_[c] = q;
      subtracted_kinks_[c] = ks;
      has_subtracted_[c] = true;
      // The table entries: rho - p is piecewise linear on the table's nodes and 0 (p's
      // nodes are among them), so its column is one closed form too; q's column is
      // subtracted from it (build_column).
      std::vector<double> th = prof.spec().altitude_m, tv;
      if (th.front() < 0.0 && !std::binary_search(th.begin(), th.end(), 0.0))
        th.insert(std::upper_bound(th.begin(), th.end(), 0.0), 0.0);
      for (double x : th) tv.push_back(prof(x) - p_at(x));
      build_linear_[c] = PiecewiseLinearColumn(th, tv, R_);
    }
  // Shares of the two geometric coordinates (uniform in rho and in altitude); with no
  // interpolated constituent and both shares 0, rho-uniform alone.
  const double a = opt_.altitude_share;
  const double u = (n_present == 0 && opt_.uniform_share == 0.0 && a == 0.0) ? 1.0 : opt_.uniform_share;
  // Tabulated profiles positive up to the top: their coordinate is the fraction
  // of the e-folds of density below h, sum |d ln rho| (the table stores ln of the
  // mean density, whose variation across a shell interval this bounds), not of
  // the column, which saturates where the scale height shrinks upward and leaves
  // the upper atmosphere to the rho share alone. cum[c][i]: e-folds below node i.
  std::array<std::vector<double>, 3> cum;
  std::array<double, 3> efolds{}, efolds0{};
  auto efolds_below = [&](int c, double h) {
    const auto& a = atm_.profile(c).spec().altitude_m;
    const auto& v = atm_.profile(c).spec().value;
    std::size_t i = static_cast<std::size_t>(std::upper_bound(a.begin(), a.end(), h) - a.begin());
    i = std::clamp<std::size_t>(i, 1, a.size() - 1) - 1;
    return cum[c][i] + std::abs(std::log(atm_.profile(c)(h) / v[i]));
  };
  for (int c = 0; c < 3; ++c) {
    if (!present_[c] || !log_encoded_[c] || atm_.profile(c).kind() != DensityProfileSpec::Kind::Tabulated) continue;
    const auto& v = atm_.profile(c).spec().value;
    cum[c].assign(v.size(), 0.0);
    for (std::size_t i = 1; i < v.size(); ++i) cum[c][i] = cum[c][i - 1] + std::abs(std::log(v[i] / v[i - 1]));
    efolds0[c] = efolds_below(c, 0.0);
    efolds[c] = efolds_below(c, top) - efolds0[c];
  }
  auto mass = [&](double h) {
    double m = 0.0;
    for (int c = 0; c < 3; ++c)
      if (present_[c])
        m += efolds[c] > 0.0 ? (efolds_below(c, h) - efolds0[c]) / efolds[c]
                             : atm_.profile(c).vertical_column(0.0, h) / vc[c];
    m += u * std::sqrt(h * (2.0 * R_ + h)) / Hh_ + a * h / top;
    return m / (n_present + u + a);
  };
  const int S = opt_.shells;
  radii_.assign(S, R_);
  radii_.back() = T_;
  for (int k = 1; k < S - 1; ++k) {
    double target = static_cast<double>(k) / (S - 1), lo = 0.0, hi = top;
    for (int it = 0; it < 200 && hi - lo > 1e-9 * top; ++it) {
      double mid = 0.5 * (lo + hi);
      (mass(mid) < target ? lo : hi) = mid;
    }
    radii_[k] = R_ + 0.5 * (lo + hi);
  }
  // Every profile kink inside the atmosphere becomes an extra shell, so that no
  // shell interval contains a kink (interpolation of kinked profiles stays inside
  // a smooth region, see interpolate()).
  for (int c = 0; c < 3; ++c)
    if (present_[c] && !log_encoded_[c])
      for (double kink : atm_.profile(c).kinks())
        if (kink > 0.0 && kink < top) radii_.push_back(R_ + kink);
  std::sort(radii_.begin(), radii_.end());
  radii_.erase(std::unique(radii_.begin(), radii_.end(), [&](double x, double y) { return std::abs(x - y) < 1e-6 * top; }),
               radii_.end());
  radii_.back() = T_;
  const int S2 = static_cast<int>(radii_.size());
  if (S2 < 4)  // an atmosphere too thin to separate 4 shells in double precision
    throw InputError("optical-depth tables: only " + std::to_string(S2) + " distinct shells between radius " +
                     std::to_string(R_) + " m and the top " + std::to_string(T_) + " m (need 4)");
  rho_.resize(S2);
  for (int k = 0; k < S2; ++k) rho_[k] = std::sqrt(std::max(0.0, (radii_[k] - R_) * (radii_[k] + R_)));
  shell_index_ = SortedIndex(rho_);
  lagrange_den_.assign(static_cast<std::size_t>(S2 - 3) * 4, 1.0);
  for (int w = 0; w + 3 < S2; ++w)
    for (int i = 0; i < 4; ++i) {
      double d = 1.0;
      for (int j = 0; j < 4; ++j)
        if (j != i) d *= rho_[w + i] - rho_[w + j];
      lagrange_den_[w * 4 + i] = 1.0 / d;
    }
  region_.assign(S2, 0);
  for (int k = 1; k < S2; ++k) {
    bool kink_at_k = false;
    for (int c = 0; c < 3; ++c)
      if (present_[c] && !log_encoded_[c])
        for (double kink : atm_.profile(c).kinks()) kink_at_k = kink_at_k || std::abs(radii_[k - 1] - (R_ + kink)) < 1e-6;
    region_[k] = region_[k - 1] + (kink_at_k ? 1 : 0);
  }
  kink_windows_.assign(S2 - 1, KinkWindow{});
  for (int kk = 0; kk + 1 < S2; ++kk) {
    int lo = kk, hi = kk + 1, reg = region_[kk + 1];
    while (hi - lo < 3) {
      bool grew = false;
      if (lo > 0 && region_[lo] == reg) { --lo; grew = true; }
      if (hi - lo < 3 && hi + 1 < S2 && region_[hi + 1] == reg) { ++hi; grew = true; }
      if (!grew) break;
    }
    KinkWindow& kw = kink_windows_[kk];
    kw.lo = lo;
    kw.count = hi - lo + 1;
    for (int i = 0; i < kw.count; ++i) {
      double d = 1.0;
      for (int j = 0; j < kw.count; ++j)
        if (j != i) d *= rho_[lo + i] - rho_[lo + j];
      kw.inv_den[i] = 1.0 / d;
    }
  }
  // Quadrature (exponential profiles only, smooth) cuts the table rays at the shells;
  // profiles with kinks are built in closed form and need no cuts.
  crossing_radii_ = radii_;
  for (int c = 0; c < 3; ++c)
    if (present_[c] && !build_closed_[c]) expo_.push_back(c);
  auto gl = sh::gauss_legendre(opt_.gauss_points);
  for (std::size_t i = 0; i < gl.nodes.size(); ++i) {
    gl_x_.push_back(0.5 * (gl.nodes[i] + 1.0));
    gl_w_.push_back(0.5 * gl.weights[i]);
  }
  if (opt_.view_tables) {
    fill(view_up_, opt_.view_directions, false);
    fill(view_ground_, opt_.view_directions, true);
  }
  // The sun table's rays are those of the view table's sky branch (same shells,
  // same direction coordinate): with as many directions, the same entries.
  if (opt_.view_tables && opt_.sun_directions == opt_.view_directions)
    sun_up_ = view_up_;
  else
    fill(sun_up_, opt_.sun_directions, false);
  build_time_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::size_t OpticalDepthLut::estimate_table_bytes(const LutOptions& o) {
  const long double per_shell = 4.0L * sizeof(double) *
      ((o.view_tables ? 2.0L * std::max(o.view_directions, 0) : 0.0L) + std::max(o.sun_directions, 0));
  const long double b = per_shell * std::max(o.shells, 0);
  return b >= static_cast<long double>(SIZE_MAX) ? SIZE_MAX : static_cast<std::size_t>(b);
}

WorkEstimate OpticalDepthLut::estimate_build_work(const LutOptions& o) {
  // One table entry on one core: a + b x shells [s] (an entry's ray crosses up to all the
  // shells), fitted to bench_work BM_WorkLutBuild at 40 to 160 shells, 64 and 256
  // directions (docs/hostile-input.md, "Work estimates").
  constexpr double a = 3.3e-6, b = 0.032e-6;
  const double dirs = (o.view_tables ? 2.0 * std::max(o.view_directions, 0) : 0.0) + std::max(o.sun_directions, 0);
  return {mul_units(std::max(o.shells, 0), dirs), a + b * std::max(o.shells, 0), "optical-depth table entries"};
}

std::size_t OpticalDepthLut::table_bytes() const {
  return (view_up_.v.size() + view_ground_.v.size() + sun_up_.v.size()) * sizeof(double);
}

namespace {
// sum_k w_k exp(-h_k / H) over quadrature nodes at distances s_k along a ray
// (u0 = r mu, c2 = its tangent radius squared): h_k = sqrt((s_k + u0)^2 + c2) - R
// (shared::radius_along). Branch-free, vectorised, compiled for AVX2/FMA too
// (atmosh/dispatch.hpp); exp_neg is within 4e-16 of libm's exp.
ATMOSH_DISPATCH_NO_ERRNO double exponential_column_sum(std::size_t n, const double* __restrict s,
                                                       const double* __restrict w, double u0, double c2, double R,
                                                       double inv_H) {
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = s[k] + u0;
    const double h = std::sqrt(d * d + c2) - R;
    sum += w[k] * exp_neg((h > 0.0 ? h : 0.0) * inv_H);  // max(h, 0), inlined in every clone
  }
  return sum;
}
}  // namespace

namespace {
// The 4 x 4 window of a table lookup: out[c] = sum_i lw[i] sum_m xw[m] e[i][m][c] over
// the entries e (padded to 4 per sample: one vector each) of 4 shells `stride`
// apart, 4 consecutive directions from `base`. Compiled for AVX2/FMA as well.
ATMOSH_DISPATCH void window_sum(const double* __restrict base, std::size_t stride, const double* __restrict lw,
                                const double* __restrict xw, double* __restrict out) {
  using v4d = double __attribute__((vector_size(32)));  // one sample's entries
  using v4du = double __attribute__((vector_size(32), aligned(8), may_alias));  // an unaligned load
#define WINDOW_ENTRY(i, m) (*reinterpret_cast<const v4du*>(base + static_cast<std::size_t>(i) * stride + 4 * (m)))
  v4d acc;
  const v4d zero = {0.0, 0.0, 0.0, 0.0};
  ATMOSH_LUT_WINDOW_SUM(v4d, zero, acc, lw, xw, WINDOW_ENTRY);  // shared/lut.glsl.hpp, the GPU's interpolate too
#undef WINDOW_ENTRY
  std::memcpy(out, &acc, sizeof acc);
}
}  // namespace

glm::dvec3 OpticalDepthLut::build_column(double r, double mu, double L) const {
  glm::dvec3 sum(0.0);
  if (!(L > 0.0)) return sum;
  const double H = build_scale_height();
  const int n = static_cast<int>(gl_x_.size());
  // The quadrature nodes of the whole ray first (distance s, weight w), then one
  // vectorised sum per exponential constituent.
  thread_local std::vector<double> node_s, node_w;
  node_s.clear();
  node_w.clear();
  const double rt2 = std::max(0.0, r * r * ((1.0 - mu) * (1.0 + mu)));
  auto rule_x = [&](int g) { return gl_x_[static_cast<std::size_t>(g)]; };
  auto rule_w = [&](int g) { return gl_w_[static_cast<std::size_t>(g)]; };
  auto node = [&](double s, double w) {
    node_s.push_back(s);
    node_w.push_back(w);
  };
  // The sub-pieces and their nodes: shared/lut.glsl.hpp, as the GPU build's.
  using namespace sg;  // the macro's functions
  auto piece = [&](double a, double b) { ATMOSH_LUT_PIECE_NODES(double, r, mu, rt2, a, b, H, n, rule_x, rule_w, node); };
  if (!expo_.empty()) {
    auto radius_at = [&](int i) { return crossing_radii_[static_cast<std::size_t>(i)]; };
    const int N = static_cast<int>(crossing_radii_.size());
    ATMOSH_LUT_RAY_PIECES(double, r, mu, L, N, radius_at, piece);
    for (int c : expo_)
      sum[c] = exponential_column_sum(node_s.size(), node_s.data(), node_w.data(), r * mu,
                                      sg::tangent_radius_sq(r, mu), R_, 1.0 / atm_.profile(c).spec().scale_height_m);
  }
  for (int c = 0; c < 3; ++c)
    if (build_closed_[c]) sum[c] = build_linear_[c](r, mu, L) - subtracted_curvature_[c](r, mu, L);
  return sum;
}

double OpticalDepthLut::build_scale_height() const {
  // The tables store the logarithm of each mean density, so even a constituent far
  // above its scale height (the Mie layer at 80 km) is integrated to full relative
  // accuracy: the smallest scale height at every altitude.
  double H = std::numeric_limits<double>::infinity();
  for (int c : expo_) H = std::min(H, atm_.profile(c).spec().scale_height_m);
  return H;
}

glm::dvec3 OpticalDepthLut::tabulated_density(double h) const {
  glm::dvec3 d = atm_.density(h);
  for (int c = 0; c < 3; ++c)
    if (has_subtracted_[c])
      d[c] -= kink_ramps(subtracted_kinks_[c], h) + subtracted_curvature_[c].at(h);
  return d;
}

glm::dvec3 OpticalDepthLut::subtracted_column(double r, double mu, double L) const {
  glm::dvec3 p(0.0);
  for (int c = 0; c < 3; ++c)
    if (has_subtracted_[c]) p[c] = subtracted_[c](r, mu, L) + subtracted_curvature_[c](r, mu, L);
  return p;
}

void OpticalDepthLut::add_closed_form(glm::dvec3& column, double r, double mu, double L) const {
  for (int c = 0; c < 3; ++c) {
    if (analytic_[c]) column[c] = linear_[c](r, mu, L);
    if (has_subtracted_[c])  // shared/geometry.glsl.hpp, the GPU's sun lookup too
      column[c] = sg::column_added_back(column[c], subtracted_[c](r, mu, L), subtracted_curvature_[c](r, mu, L));
  }
}

glm::dvec3 OpticalDepthLut::encode(const glm::dvec3& mean) const {
  glm::dvec3 e;
  for (int c = 0; c < 3; ++c) e[c] = log_encoded_[c] ? std::log(std::max(mean[c], 1e-300)) : mean[c];
  return e;
}

glm::dvec3 OpticalDepthLut::decode(const glm::dvec3& v) const {
  glm::dvec3 d;
  for (int c = 0; c < 3; ++c) d[c] = sg::lut_decode(v[c], log_encoded_[c]);  // the GPU's too
  return d;
}

void OpticalDepthLut::fill(Table& t, int n, bool ground) {
  const int S = static_cast<int>(radii_.size());
  t.n = n;
  t.ground = ground;
  t.v.assign(static_cast<std::size_t>(S) * n * 4, 0.0);
  // One shell per task (each writes its own rows only: the entries do not depend on
  // the thread count); the upper shells' rays are shorter, so dynamic scheduling.
  parallel_for(static_cast<std::size_t>(S), opt_.threads, [&](std::size_t ks) {
    const int k = static_cast<int>(ks);
    double r = radii_[k], rho = rho_[k];
    glm::dvec3 at_r = tabulated_density(r - R_);
    for (int j = 0; j < n; ++j) {
      double x = static_cast<double>(j) / (n - 1);
      // The entry's ray (shared/lut.glsl.hpp, also the GPU build's).
      const double d = sg::lut_table_distance(r, rho, x, R_, T_, Hh_, ground);
      const glm::dvec3 mean = d <= 0.0 ? at_r : build_column(r, sg::lut_table_mu(r, rho, d, T_, ground), d) / d;
      glm::dvec3 e = encode(mean);
      double* dst = &t.v[(static_cast<std::size_t>(k) * n + j) * 4];
      dst[0] = e[0];
      dst[1] = e[1];
      dst[2] = e[2];
    }
  });
}

double OpticalDepthLut::x_up(double r, double rho, double mu, double& d) const {
  d = sg::distance_to_top(r, mu, T_);
  double dmin = T_ - r, dmax = rho + Hh_;
  return sg::lut_x(d, dmin, dmax);
}

double OpticalDepthLut::x_ground(double r, double rho, double mu, double& d) const {
  d = sg::distance_to_ground(r, mu, R_);
  double dmin = r - R_, dmax = rho;
  return sg::lut_x(d, dmin, dmax);
}

OpticalDepthLut::ShellWeights OpticalDepthLut::shell_weights(double rho) const {
  const int S = static_cast<int>(radii_.size());
  ShellWeights sw;
  // Window choice and weights: shared/lut.glsl.hpp (the GPU's interpolate too).
  // Shell search: the same k as the GPU's bisection (ATMOSH_LUT_SHELL_INDEX), in O(1).
  sw.k = shell_index_.find(rho);
  using namespace sg;  // the macro's functions
  auto rho_at = [&](int i) { return rho_[static_cast<std::size_t>(i)]; };
  auto den_at = [&](int i) { return lagrange_den_[static_cast<std::size_t>(i)]; };
  ATMOSH_LUT_SHELL_WEIGHTS(sw.lw, sw.w, sw.k, S, rho, rho_at, den_at);
  if (has_kinks_) {
    // Profiles with kinks: Lagrange in rho only over shells of the same smooth
    // region (between kinks), of degree <= 3 (window and inverse denominators
    // precomputed per shell interval).
    const KinkWindow& kw = kink_windows_[std::clamp(sw.k, 0, S - 2)];
    sw.klo = kw.lo;
    sw.kcount = kw.count;
    for (int i = 0; i < kw.count; ++i) {
      double p = kw.inv_den[i];
      for (int j = 0; j < kw.count; ++j)
        if (j != i) p *= rho - rho_[kw.lo + j];
      sw.li[i] = p;
    }
  }
  return sw;
}

double OpticalDepthLut::kinked_shell_sum(const Table& t, const ShellWeights& sw, int j, int c) const {
  double v = 0.0;
  for (int i = 0; i < sw.kcount; ++i) v += sw.li[i] * t.v[(static_cast<std::size_t>(sw.klo + i) * t.n + j) * 4 + c];
  return v;
}

glm::dvec3 OpticalDepthLut::interpolate(const Table& t, double rho, double x) const {
  const int n = t.n;
  const ShellWeights sw = shell_weights(rho);
  using namespace sg;  // the macro's functions
  int jw;
  double xw[4];
  ATMOSH_LUT_DIRECTION_WEIGHTS(xw, jw, x, n);  // shared/lut.glsl.hpp, the GPU's interpolate too
  double acc[4];
  window_sum(&t.v[(static_cast<std::size_t>(sw.w) * n + jw) * 4], static_cast<std::size_t>(n) * 4, sw.lw, xw, acc);
  glm::dvec3 out(acc[0], acc[1], acc[2]);
  if (has_kinks_)
    for (int c = 0; c < 3; ++c) {
      if (log_encoded_[c] || !present_[c]) continue;
      double v = 0.0;
      for (int m = 0; m < 4; ++m) v += xw[m] * kinked_shell_sum(t, sw, jw + m, c);
      out[c] = v;
    }
  return out;
}

LutColumn OpticalDepthLut::finish_up(const glm::dvec3& e, double r, double mu, double d) const {
  LutColumn out;
  out.column = decode(e) * d;
  add_closed_form(out.column, r, mu, d);
  if (has_kinks_) {
    // A ray that stays above the top of a profile with compact support has an
    // exactly zero column of it (removes interpolation ringing across the kink).
    double h_min = (mu < 0.0 ? std::sqrt(sg::tangent_radius_sq(r, mu)) : r) - R_;
    for (int c = 0; c < 3; ++c)
      if (present_[c] && !log_encoded_[c] && h_min >= support_top_[c]) out.column[c] = 0.0;
  }
  return out;
}

LutColumn OpticalDepthLut::lookup(const Table& up, const Table* ground, double r, double mu) const {
  LutColumn out;
  mu = std::clamp(mu, -1.0, 1.0);
  if (r > T_) {
    double s0 = sg::distance_to_top_from_outside(r, mu, T_);
    if (s0 < 0.0) return out;
    mu = std::clamp((r * mu + s0) / T_, -1.0, 1.0);
    r = T_;
  }
  r = std::max(r, R_);
  if (sg::ray_hits_ground(r, mu, R_)) {
    out.hits_ground = true;
    if (!ground) return out;
    const double rho = std::sqrt(std::max(0.0, (r - R_) * (r + R_)));
    double d;
    double x = x_ground(r, rho, mu, d);
    out.column = decode(interpolate(*ground, rho, x)) * d;
    add_closed_form(out.column, r, mu, d);
    return out;
  }
  const double rho = std::sqrt(std::max(0.0, (r - R_) * (r + R_)));
  double d;
  double x = x_up(r, rho, mu, d);
  return finish_up(interpolate(up, rho, x), r, mu, d);
}

OpticalDepthLut::SunAtRadius OpticalDepthLut::sun_at(double r) const {
  SunAtRadius s;
  s.lut_ = this;
  if (!(r <= T_)) {  // above the top (or NaN): lookups transport the origin, per direction
    s.outside_ = true;
    s.r_ = r;
    return s;
  }
  s.r_ = std::max(r, R_);
  s.rho_ = std::sqrt(std::max(0.0, (s.r_ - R_) * (s.r_ + R_)));
  const Table& t = sun_up_;
  const ShellWeights sw = shell_weights(s.rho_);
  s.v_.assign(static_cast<std::size_t>(t.n) * 4, 0.0);
  for (int j = 0; j < t.n; ++j) {
    double* dst = &s.v_[static_cast<std::size_t>(j) * 4];
    for (int i = 0; i < 4; ++i) {
      const double* e = &t.v[(static_cast<std::size_t>(sw.w + i) * t.n + j) * 4];
      for (int c = 0; c < 4; ++c) dst[c] += sw.lw[i] * e[c];
    }
    if (has_kinks_)
      for (int c = 0; c < 3; ++c)
        if (!log_encoded_[c] && present_[c]) dst[c] = kinked_shell_sum(t, sw, j, c);
  }
  return s;
}

OpticalDepthLut::SunAtRadius OpticalDepthLut::sun_at(double r, double mu_lo, double mu_hi, int max_samples) const {
  SunAtRadius s = sun_at(r);
  if (s.outside_ || !(mu_lo <= mu_hi)) return s;
  const double rr = s.r_;
  const double lo = std::clamp(mu_lo, -1.0, 1.0);
  // A degenerate range (one direction) gets a width of 1e-12.
  const double hi = mu_hi > lo ? std::min(mu_hi, 1.0) : std::min(1.0, lo + 1e-12);
  // Blocked rays have no column; ray_hits_ground is monotone in mu.
  if (!(hi > lo) || sg::ray_hits_ground(rr, lo, R_)) return s;
  // Where the lookup is not smooth in mu: at the table's direction samples (between
  // two, the interpolation is one cubic in x, and x is smooth in mu), and where the
  // tangent point of the ray lies on a node sphere of a closed-form profile (a kink
  // of its column) or at the top of a kinked interpolated one (its column is set to
  // 0 above: finish_up).
  std::vector<double> breaks{lo, hi};
  const auto add = [&](double mu) {
    if (mu > lo && mu < hi) breaks.push_back(mu);
  };
  const int n = sun_up_.n;
  const double dmin = T_ - rr, dmax = s.rho_ + Hh_;
  for (int j = 1; j + 1 < n; ++j) {
    const double d = dmin + (dmax - dmin) * j / (n - 1);  // x = j / (n - 1): T^2 = r^2 + d^2 + 2 r d mu
    if (d > 0.0) add(((T_ - rr) * (T_ + rr) - d * d) / (2.0 * rr * d));
  }
  const auto add_tangent = [&](double Rk) {
    if (Rk < rr) add(-std::sqrt((rr - Rk) * (rr + Rk)) / rr);
  };
  for (int c = 0; c < 3; ++c) {
    if (analytic_[c])
      for (double Rk : linear_[c].node_radii()) add_tangent(Rk);
    if (has_subtracted_[c])
      for (double Rk : subtracted_[c].node_radii()) add_tangent(Rk);
    if (has_kinks_ && present_[c] && !log_encoded_[c]) add_tangent(R_ + support_top_[c]);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  // The lookups themselves (s has no fit yet), degree 7 per part.
  const auto f = [&](double mu, double* out) {
    const LutColumn col = s(mu);
    for (int c = 0; c < 3; ++c) out[c] = col.column[c];
  };
  s.fit_ = ChebyshevFit::checked(f, std::move(breaks), 8, 3, 1e-10, max_samples);
  return s;
}

LutColumn OpticalDepthLut::SunAtRadius::lookup(double mu) const {
  const OpticalDepthLut& L = *lut_;
  if (outside_) return L.sun(r_, mu);
  mu = std::clamp(mu, -1.0, 1.0);
  if (sg::ray_hits_ground(r_, mu, L.R_)) {
    LutColumn out;
    out.hits_ground = true;
    return out;
  }
  double d;
  const double x = L.x_up(r_, rho_, mu, d);
  const int n = L.sun_up_.n;
  using namespace sg;  // the macro's functions
  int jw;
  double xw[4];
  ATMOSH_LUT_DIRECTION_WEIGHTS(xw, jw, x, n);
  glm::dvec3 e(0.0);
  for (int m = 0; m < 4; ++m) {
    const double* v = &v_[static_cast<std::size_t>(jw + m) * 4];
    e += xw[m] * glm::dvec3(v[0], v[1], v[2]);
  }
  return L.finish_up(e, r_, mu, d);
}

void OpticalDepthLut::replace_log_tables(const std::vector<float>& log_mean, int off_ground, int off_sun) {
  const std::size_t S = radii_.size();
  const std::size_t nv = S * static_cast<std::size_t>(view_up_.n) * 3, ns = S * static_cast<std::size_t>(sun_up_.n) * 3;
  if (off_ground < 0 || off_sun < 0 || static_cast<std::size_t>(off_ground) != nv ||
      static_cast<std::size_t>(off_sun) != 2 * nv || log_mean.size() != 2 * nv + ns)
    throw InputError("replacement tables: " + std::to_string(log_mean.size()) + " values (offsets " +
                     std::to_string(off_ground) + ", " + std::to_string(off_sun) + ") do not match " +
                     std::to_string(S) + " shells x " + std::to_string(view_up_.n) + "/" + std::to_string(sun_up_.n) +
                     " directions");
  for (std::size_t i = 0; i < log_mean.size(); ++i)
    if (log_encoded_[i % 3] && !std::isfinite(log_mean[i]))
      throw InputError("replacement tables: entry " + std::to_string(i) + " is not finite");
  auto copy = [&](Table& t, std::size_t off) {  // [..][3] into the padded [..][4]
    for (std::size_t e = 0; e < t.v.size() / 4; ++e)
      for (std::size_t c = 0; c < 3; ++c)
        if (log_encoded_[c]) t.v[4 * e + c] = static_cast<double>(log_mean[off + 3 * e + c]);
  };
  copy(view_up_, 0);
  copy(view_ground_, nv);
  copy(sun_up_, 2 * nv);
}

LutColumn OpticalDepthLut::view(double r, double mu) const {
  if (!opt_.view_tables)
    throw std::logic_error("OpticalDepthLut::view: the tables were built without view tables (LutOptions::view_tables)");
  return lookup(view_up_, &view_ground_, r, mu);
}
LutColumn OpticalDepthLut::sun(double r, double mu) const { return lookup(sun_up_, nullptr, r, mu); }

std::vector<ProbeRay> kink_probe_rays(const Atmosphere& atm, std::array<bool, 3> which) {
  std::vector<double> kinks;
  for (int c = 0; c < 3; ++c)
    if (atm.has(c) && which[static_cast<std::size_t>(c)]) {
      const auto k = atm.profile(c).strongest_kinks(kProbedKinks, 0.0, atm.top_altitude());
      kinks.insert(kinks.end(), k.begin(), k.end());
    }
  return kink_probe_rays(atm.ground_radius(), atm.top_altitude(), kinks);
}

std::vector<ProbeRay> kink_probe_rays(double ground_radius, double top_altitude, std::vector<double> kinks) {
  const double R = ground_radius, top = top_altitude;
  std::sort(kinks.begin(), kinks.end());
  kinks.erase(std::unique(kinks.begin(), kinks.end()), kinks.end());
  std::vector<ProbeRay> rays;
  const double r_top = R + 0.99999 * top;
  for (double hk : kinks) {
    if (!(hk > 0.0 && hk < top)) continue;
    for (double dh : {-100.0, 100.0}) {
      const double h = hk + dh;
      if (h > 0.0 && h < top)
        for (double mu : {0.0, 1e-3, -1e-3, 1e-2, -1e-2}) rays.push_back({R + h, mu});
    }
    for (double dt : {-100.0, -1.0, 1.0, 100.0}) {
      const double rt = R + hk + dt;
      if (rt > R && rt < r_top) rays.push_back({r_top, -std::sqrt((r_top - rt) * (r_top + rt)) / r_top});
    }
  }
  return rays;
}

double OpticalDepthLut::estimate_max_rel_error(double wavelength_nm) const {
  if (!(wavelength_nm >= 0.0) || !std::isfinite(wavelength_nm))
    throw InputError("wavelength " + std::to_string(wavelength_nm) + " nm for the LUT error estimate is not a finite value >= 0");
  double worst = 0.0;
  const auto& wl = atm_.wavelengths_nm();
  Coefficients kc = atm_.coefficients_at(wavelength_nm > 0.0 ? wavelength_nm : wl.empty() ? 550.0 : wl[wl.size() / 2]);
  auto rel = [&](const glm::dvec3& a, const glm::dvec3& b) {
    double ta = optical_depth(kc, a), tb = optical_depth(kc, b);
    return tb > 0.0 ? std::abs(ta - tb) / tb : std::abs(ta);
  };
  // Fresh build-quality columns, with the closed-form constituents that the tables do
  // not hold added in (as lookup() does).
  auto exact = [&](double r, double mu, double L) {
    glm::dvec3 c = build_column(r, mu, L);
    add_closed_form(c, r, mu, L);
    return c;
  };
  const int S = static_cast<int>(radii_.size());
  // Every shell interval at its midpoint in rho, every direction interval at its
  // midpoint in x (where a cubic's interpolation error is near its largest), both
  // branches; one shell interval per task (the maximum does not depend on the order).
  std::vector<double> worst_k(static_cast<std::size_t>(S - 1), 0.0);
  parallel_for(static_cast<std::size_t>(S - 1), opt_.threads, [&](std::size_t ks) {
    const int k = static_cast<int>(ks);
    double w = 0.0;
    const double rho = 0.5 * (rho_[k] + rho_[k + 1]);
    const double r = std::sqrt(rho * rho + R_ * R_);
    const int nd = opt_.view_tables ? opt_.view_directions : opt_.sun_directions;
    for (int j = 0; j + 1 < nd; ++j) {
      const double x = (j + 0.5) / (nd - 1);
      const double dmin = T_ - r, dmax = rho + Hh_, d = dmin + x * (dmax - dmin);
      const double mu = std::clamp(((T_ - r) * (T_ + r) - d * d) / (2.0 * r * d), -1.0, 1.0);
      const LutColumn up = opt_.view_tables ? view(r, mu) : sun(r, mu);
      w = std::max(w, rel(up.column, exact(r, mu, sg::distance_to_top(r, mu, T_))));
      if (!opt_.view_tables) continue;
      const double dg = (r - R_) + x * (rho - (r - R_));
      const double mug = std::clamp(-(rho * rho + dg * dg) / (2.0 * r * dg), -1.0, 1.0);
      if (sg::ray_hits_ground(r, mug, R_))
        w = std::max(w, rel(view(r, mug).column, exact(r, mug, sg::distance_to_ground(r, mug, R_))));
    }
    worst_k[ks] = w;
  });
  for (double w : worst_k) worst = std::max(worst, w);
  // Beside the kinks of interpolated profiles, where the tables' error peaks
  // (earth-physical: the U.S. 1976 layer boundaries).
  for (const ProbeRay& p : kink_probe_rays(atm_, present_)) {
    const bool ground = sg::ray_hits_ground(p.r, p.mu, R_);
    if (ground && !opt_.view_tables) continue;  // blocked sun ray: nothing to compare
    const LutColumn got = opt_.view_tables ? view(p.r, p.mu) : sun(p.r, p.mu);
    const double L = ground ? sg::distance_to_ground(p.r, p.mu, R_) : sg::distance_to_top(p.r, p.mu, T_);
    worst = std::max(worst, rel(got.column, exact(p.r, p.mu, L)));
  }
  return worst;
}

}  // namespace atmosh::atmo
