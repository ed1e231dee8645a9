// atmosh/atmo/chebyshev.hpp — a checked piecewise Chebyshev interpolant of a
// piecewise-smooth function on an interval (a few channels at once), for functions
// that are evaluated very many times over a narrow range of their argument: the
// sun-ray columns of one node of a sky image row, which every pixel of the row
// needs at its own sun direction.
//
// ChebyshevFit::checked(f, breaks, n, channels, tol, max_samples) starts from the
// parts between the given breakpoints (where the caller knows f to be non-smooth)
// and on each samples f at the n Chebyshev points of the first kind
// (x_j = m + h cos(pi (j + 1/2) / n)), forms the coefficients of the degree n - 1
// interpolant by the discrete cosine sums (Trefethen, Approximation Theory and
// Approximation Practice, SIAM 2013, ch. 3-4), converted to powers of the part's
// local variable t in [-1, 1] (evaluated by Horner's rule, or Estrin's scheme for
// n = 8; n <= 16: the power form of a degree <= 15 polynomial on [-1, 1] loses at
// most ~(1 + sqrt 2)^15 ~ 6e5 ulp of the largest coefficient, which the check below
// sees). Each part is then
// checked against f at the n + 1 extrema of T_n, x = m + h cos(pi j / n) for
// j = 0..n (both ends and the points between the interpolation nodes, where the
// error of an interpolant of an analytic function peaks): a part passes if every
// channel c is within tol * scale_c there (scale_c = the largest |f_c| sampled so
// far; an all-zero channel fits exactly); a part that fails is halved and tried
// again. valid() once every part passes within max_samples evaluations of f in
// all (and parts no narrower than 1e-9 of the interval). The check is sampled, not
// a proof; it is sharp for functions analytic near each part (geometric
// convergence, error oscillating with the extrema of T_n).
// Units: those of f and of its argument. Cost: 2n + 1 evaluations of f and ~n^2
// flops per part tried; per evaluation a constant-time search over the parts
// (SortedIndex) and n multiply-adds per channel.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "atmosh/atmo/sorted_index.hpp"

namespace atmosh::atmo {

class ChebyshevFit {
 public:
  static constexpr int kMaxPoints = 16;
  static constexpr int kMaxChannels = 4;

  ChebyshevFit() = default;  // empty: !valid()

  // f(x, out) writes out[0..channels). breaks: ascending, finite, >= 2 values
  // (the interval is [breaks.front(), breaks.back()]). n in [1, kMaxPoints],
  // channels in [1, kMaxChannels]; otherwise an invalid fit (no sample taken).
  template <class F>
  static ChebyshevFit checked(F&& f, std::vector<double> breaks, int n, int channels, double tol, int max_samples) {
    ChebyshevFit c;
    if (!(n >= 1 && n <= kMaxPoints && channels >= 1 && channels <= kMaxChannels && breaks.size() >= 2)) return c;
    for (std::size_t i = 0; i < breaks.size(); ++i)
      if (!std::isfinite(breaks[i]) || (i > 0 && !(breaks[i] > breaks[i - 1]))) return c;
    c.n_ = n;
    c.channels_ = channels;
    const double min_width = 1e-9 * (breaks.back() - breaks.front());
    constexpr double kPi = 3.14159265358979323846;
    std::array<double, kMaxChannels> scale{};
    int samples = 0;
    // Parts still to fit, in order: (start, end), the front one first.
    std::vector<std::pair<double, double>> todo;
    for (std::size_t i = breaks.size() - 1; i > 0; --i) todo.emplace_back(breaks[i - 1], breaks[i]);
    // The cosines, once for every part and channel: nodes, the cosine transform, checks.
    std::array<double, kMaxPoints> node{};
    std::array<std::array<double, kMaxPoints>, kMaxPoints> dct{};
    std::array<double, kMaxPoints + 1> extremum{};
    for (int j = 0; j < n; ++j) node[static_cast<std::size_t>(j)] = std::cos(kPi * (j + 0.5) / n);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        dct[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] = std::cos(kPi * k * (j + 0.5) / n);
    for (int j = 0; j <= n; ++j) extremum[static_cast<std::size_t>(j)] = std::cos(kPi * j / n);
    std::array<std::array<double, kMaxChannels>, kMaxPoints> v{};
    std::vector<double> coef(static_cast<std::size_t>(n * kMaxChannels));  // [i][channel]
    double out[kMaxChannels];
    c.breaks_.push_back(breaks.front());
    while (!todo.empty()) {
      const auto [pa, pb] = todo.back();
      todo.pop_back();
      samples += 2 * n + 1;
      if (samples > max_samples || !(pb - pa >= min_width)) return ChebyshevFit{};
      const double m = 0.5 * (pa + pb), h = 0.5 * (pb - pa);
      for (int j = 0; j < n; ++j) {
        f(m + h * node[static_cast<std::size_t>(j)], out);
        for (int ch = 0; ch < channels; ++ch) {
          if (!std::isfinite(out[ch])) return ChebyshevFit{};
          v[static_cast<std::size_t>(j)][static_cast<std::size_t>(ch)] = out[ch];
          scale[static_cast<std::size_t>(ch)] = std::max(scale[static_cast<std::size_t>(ch)], std::fabs(out[ch]));
        }
      }
      std::fill(coef.begin(), coef.end(), 0.0);
      // Chebyshev coefficients, then the powers of t: T_{k+1} = 2 t T_k - T_{k-1}.
      std::array<double, kMaxPoints + 1> tk{}, prev{};  // T_k and T_{k-1} in powers of t
      tk[0] = 1.0;
      for (int k = 0; k < n; ++k) {
        for (int ch = 0; ch < channels; ++ch) {
          double s = 0.0;
          for (int j = 0; j < n; ++j)
            s += v[static_cast<std::size_t>(j)][static_cast<std::size_t>(ch)] *
                 dct[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)];
          const double ck = (k == 0 ? 1.0 : 2.0) * s / n;
          for (int i = 0; i <= k; ++i)
            coef[static_cast<std::size_t>(i * kMaxChannels + ch)] += ck * tk[static_cast<std::size_t>(i)];
        }
        std::array<double, kMaxPoints + 1> next{};
        for (int i = 0; i <= k; ++i)
          next[static_cast<std::size_t>(i) + 1] = (k == 0 ? 1.0 : 2.0) * tk[static_cast<std::size_t>(i)];
        for (int i = 0; i < k; ++i) next[static_cast<std::size_t>(i)] -= prev[static_cast<std::size_t>(i)];
        prev = tk;
        tk = next;
      }
      bool pass = true;
      double worst = 0.0;
      for (int j = 0; j <= n && pass; ++j) {
        // Clamped: rounding must not put the ends outside the part.
        const double x = std::clamp(m + h * extremum[static_cast<std::size_t>(j)], pa, pb);
        f(x, out);
        double fit[kMaxChannels];
        polynomial(coef.data(), n, (x - m) / h, fit);
        for (int ch = 0; ch < channels; ++ch) {
          if (!std::isfinite(out[ch])) return ChebyshevFit{};
          scale[static_cast<std::size_t>(ch)] = std::max(scale[static_cast<std::size_t>(ch)], std::fabs(out[ch]));
          const double e = std::fabs(fit[ch] - out[ch]);
          worst = std::max(worst, e / std::max(scale[static_cast<std::size_t>(ch)], 1e-300));
          if (!(e <= tol * scale[static_cast<std::size_t>(ch)])) pass = false;
        }
      }
      if (!pass) {  // halve it: the front half next
        todo.emplace_back(m, pb);
        todo.emplace_back(pa, m);
        continue;
      }
      c.breaks_.push_back(pb);
      c.mid_.push_back(m);
      c.inv_half_.push_back(1.0 / h);
      c.coef_.insert(c.coef_.end(), coef.begin(), coef.end());
      c.check_error_ = std::max(c.check_error_, worst);
    }
    c.samples_ = samples;
    c.index_ = SortedIndex(c.breaks_);
    c.valid_ = true;
    return c;
  }

  bool valid() const { return valid_; }
  // valid() and lo() <= x <= hi().
  bool covers(double x) const { return valid_ && x >= breaks_.front() && x <= breaks_.back(); }
  double lo() const { return breaks_.empty() ? 0.0 : breaks_.front(); }
  double hi() const { return breaks_.empty() ? 0.0 : breaks_.back(); }
  int points() const { return n_; }
  int pieces() const { return static_cast<int>(mid_.size()); }
  int samples() const { return samples_; }
  // Largest |fit - f| / scale seen by the checks of the parts kept.
  double check_error() const { return check_error_; }
  // The interpolant at x (meant for x in [lo, hi]) into out[0..channels).
  void operator()(double x, double* out) const {
    double v[kMaxChannels];
    evaluate_all(x, v);
    for (int ch = 0; ch < channels_; ++ch) out[ch] = v[ch];
  }
  // The same for all kMaxChannels channels (those past channels() are 0): no
  // run-time count, for the callers' fast paths.
  void evaluate_all(double x, double (&out)[kMaxChannels]) const {
    // The part holding x: the last whose start is <= x (the first part below lo,
    // the last at or above hi); constant time (SortedIndex).
    const int k = std::clamp(index_.find(x), 0, static_cast<int>(mid_.size()) - 1);
    const std::size_t p = static_cast<std::size_t>(k);
    const double t = (x - mid_[p]) * inv_half_[p];
    polynomial(&coef_[p * static_cast<std::size_t>(n_ * kMaxChannels)], n_, t, out);
  }

 private:
  // v[ch] = sum_i c[i][ch] t^i for all kMaxChannels channels at once (unused
  // channels have zero coefficients). Horner's rule, except for n = 8 (the sky's
  // fits): Estrin's scheme, whose multiply-adds form a tree of depth 3 instead of a
  // chain of 7 (the same bound on rounding for |t| <= 1).
  static void polynomial(const double* c, int n, double t, double* v) {
    constexpr int C = kMaxChannels;
    if (n == 8) {
      const double t2 = t * t, t4 = t2 * t2;
      for (int ch = 0; ch < C; ++ch) {
        const double a0 = c[0 * C + ch] + c[1 * C + ch] * t, a1 = c[2 * C + ch] + c[3 * C + ch] * t;
        const double a2 = c[4 * C + ch] + c[5 * C + ch] * t, a3 = c[6 * C + ch] + c[7 * C + ch] * t;
        v[ch] = (a0 + a1 * t2) + (a2 + a3 * t2) * t4;
      }
      return;
    }
    double v0 = c[(n - 1) * C], v1 = c[(n - 1) * C + 1], v2 = c[(n - 1) * C + 2], v3 = c[(n - 1) * C + 3];
    for (int i = n - 2; i >= 0; --i) {
      const double* ci = c + i * C;
      v0 = v0 * t + ci[0];
      v1 = v1 * t + ci[1];
      v2 = v2 * t + ci[2];
      v3 = v3 * t + ci[3];
    }
    v[0] = v0;
    v[1] = v1;
    v[2] = v2;
    v[3] = v3;
  }

  std::vector<double> breaks_;           // part p is [breaks_[p], breaks_[p + 1]]
  SortedIndex index_;                    // over breaks_
  std::vector<double> mid_, inv_half_;   // per part
  std::vector<double> coef_;             // [part][n][kMaxChannels]: powers of the local t
  double check_error_ = 0.0;
  int n_ = 0, channels_ = 0, samples_ = 0;
  bool valid_ = false;
};

}  // namespace atmosh::atmo
