// atmosh/atmo/chebyshev.hpp — a checked piecewise Chebyshev interpolant of a smooth
// function on an interval, for functions that are evaluated very many times over a
// narrow range of their argument (the closed-form sun-ray columns of one node of a
// sky image row, which every pixel of the row needs at its own sun direction).
//
// ChebyshevFit::checked(f, a, b, n, pieces, tol) cuts [a, b] into `pieces` equal
// parts and on each samples f at the n Chebyshev points of the first kind
// (x_j = m + h cos(pi (j + 1/2) / n)), forms the coefficients of the degree n - 1
// interpolant by the discrete cosine sums (Trefethen, Approximation Theory and
// Approximation Practice, SIAM 2013, ch. 3-4), converted to powers of the part's
// local variable t in [-1, 1] and evaluated by Horner's rule (n <= 16: the power
// form of a degree <= 15 polynomial on [-1, 1] loses at most ~(1 + sqrt 2)^15
// ~ 6e5 ulp of the largest coefficient, which the check below sees). Each part is then checked against f at the n + 1 extrema of T_n,
// x = m + h cos(pi j / n) for j = 0..n (both ends and the points between the
// interpolation nodes, where the error of an interpolant of an analytic function
// peaks): valid() only if every check is within tol * scale, scale = the largest
// |f| over all samples (an all-zero f fits exactly). The check is sampled, not a
// proof; it is sharp for functions analytic near [a, b] (geometric convergence,
// error oscillating with the extrema of T_n). A caller must keep known
// singularities (kinks) out of [a, b]; the check catches near-singular cases by
// failing. n <= kMaxPoints = 16.
// Units: those of f and of its argument. Cost: pieces (2n + 1) evaluations of f and
// ~pieces n^2 flops to fit; n multiply-adds per evaluation.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace atmosh::atmo {

class ChebyshevFit {
 public:
  static constexpr int kMaxPoints = 16;

  ChebyshevFit() = default;  // empty: !valid()

  // n in [1, kMaxPoints], pieces >= 1, a < b finite; otherwise an invalid fit
  // (no sample taken). Stops sampling at the first part that fails its check.
  template <class F>
  static ChebyshevFit checked(F&& f, double a, double b, int n, int pieces, double tol) {
    ChebyshevFit c;
    if (!(n >= 1 && n <= kMaxPoints && pieces >= 1 && a < b && std::isfinite(a) && std::isfinite(b))) return c;
    c.a_ = a;
    c.b_ = b;
    c.n_ = n;
    c.pieces_ = pieces;
    c.inv_width_ = pieces / (b - a);
    c.c_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(pieces), 0.0);
    constexpr double kPi = 3.14159265358979323846;
    double scale = 0.0, worst = 0.0;
    std::array<double, kMaxPoints> v{};
    for (int p = 0; p < pieces; ++p) {
      const double pa = p == 0 ? a : a + (b - a) * p / pieces, pb = p + 1 == pieces ? b : a + (b - a) * (p + 1) / pieces;
      const double m = 0.5 * (pa + pb), h = 0.5 * (pb - pa);
      for (int j = 0; j < n; ++j) {
        v[static_cast<std::size_t>(j)] = f(m + h * std::cos(kPi * (j + 0.5) / n));
        if (!std::isfinite(v[static_cast<std::size_t>(j)])) return ChebyshevFit{};
        scale = std::max(scale, std::fabs(v[static_cast<std::size_t>(j)]));
      }
      // Chebyshev coefficients, then the powers of t: T_{k+1} = 2 t T_k - T_{k-1}.
      double* cp = &c.c_[static_cast<std::size_t>(p) * static_cast<std::size_t>(n)];
      std::array<double, kMaxPoints + 1> tk{}, prev{};  // T_k and T_{k-1} in powers of t
      tk[0] = 1.0;
      for (int k = 0; k < n; ++k) {
        double s = 0.0;
        for (int j = 0; j < n; ++j) s += v[static_cast<std::size_t>(j)] * std::cos(kPi * k * (j + 0.5) / n);
        const double ck = (k == 0 ? 1.0 : 2.0) * s / n;
        for (int i = 0; i <= k; ++i) cp[i] += ck * tk[static_cast<std::size_t>(i)];
        std::array<double, kMaxPoints + 1> next{};  // T_{k+1} = 2 t T_k - T_{k-1} (T_1 = t)
        for (int i = 0; i <= k; ++i) next[static_cast<std::size_t>(i) + 1] = (k == 0 ? 1.0 : 2.0) * tk[static_cast<std::size_t>(i)];
        for (int i = 0; i < k; ++i) next[static_cast<std::size_t>(i)] -= prev[static_cast<std::size_t>(i)];
        prev = tk;
        tk = next;
      }
      double piece_worst = 0.0, piece_scale = 0.0;
      for (int j = 0; j <= n; ++j) {
        // Clamped: rounding must not put the ends outside the part.
        const double x = std::clamp(m + h * std::cos(kPi * j / n), pa, pb);
        const double fx = f(x);
        if (!std::isfinite(fx)) return ChebyshevFit{};
        piece_scale = std::max(piece_scale, std::fabs(fx));
        piece_worst = std::max(piece_worst, std::fabs(horner(cp, n, (x - m) / h) - fx));
      }
      scale = std::max(scale, piece_scale);
      worst = std::max(worst, piece_worst);
      if (!(piece_worst <= tol * scale)) return ChebyshevFit{};
    }
    c.check_error_ = worst;
    c.valid_ = worst <= tol * scale;
    return c;
  }

  bool valid() const { return valid_; }
  // valid() and lo() <= x <= hi().
  bool covers(double x) const { return valid_ && x >= a_ && x <= b_; }
  double lo() const { return a_; }
  double hi() const { return b_; }
  int points() const { return n_; }
  int pieces() const { return pieces_; }
  // Largest |fit - f| seen by the check.
  double check_error() const { return check_error_; }
  // The interpolant at x (meant for x in [lo, hi]).
  double operator()(double x) const {
    const double u = (x - a_) * inv_width_;
    const int p = std::clamp(static_cast<int>(u), 0, pieces_ - 1);
    return horner(&c_[static_cast<std::size_t>(p) * static_cast<std::size_t>(n_)], n_, 2.0 * (u - p) - 1.0);
  }

 private:
  // sum_i c[i] t^i.
  static double horner(const double* c, int n, double t) {
    double v = c[n - 1];
    for (int i = n - 2; i >= 0; --i) v = v * t + c[i];
    return v;
  }

  std::vector<double> c_;  // [piece][n]: powers of the local t
  double a_ = 0.0, b_ = 0.0, inv_width_ = 0.0, check_error_ = 0.0;
  int n_ = 0, pieces_ = 0;
  bool valid_ = false;
};

}  // namespace atmosh::atmo
