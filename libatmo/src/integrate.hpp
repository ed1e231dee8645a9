// integrate.hpp (private to libatmo) — globally adaptive Gauss-Kronrod (G7-K15)
// quadrature in double, for scalar or glm::dvec3 integrands.
//
// The interval [a, b] is first split at the given breakpoints (kinks, tangent
// points...), then the sub-interval with the largest error is bisected until
// every component satisfies error <= max(abs_tol, rel_tol * |value|) or
// max_intervals is reached (then `converged` is false). The error estimate of
// an interval is |K15 - G7| (no QUADPACK rescaling: it over-estimates the true
// error of smooth integrands by orders of magnitude, which is the safe side).
// Nodes and weights: Piessens et al., QUADPACK (1983), qk15.
#pragma once

#include <algorithm>
#include <cmath>
#include <queue>
#include <vector>

#include <glm/glm.hpp>

namespace atmosh::atmo {

template <class V>
struct QuadResult {
  V value{};
  V error{};
  int evaluations = 0;
  bool converged = true;
};

namespace detail {
inline constexpr double kXgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                                   0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                                   0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                                   0.207784955007898467600689403773245, 0.0};
inline constexpr double kWgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                                   0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                                   0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                                   0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr double kWg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                  0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

inline double comp_max(double v) { return std::abs(v); }
inline double comp_max(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }
inline double vabs(double v) { return std::abs(v); }
inline glm::dvec3 vabs(const glm::dvec3& v) { return glm::abs(v); }
// Largest ratio error / tolerance over components.
inline double worst(double err, double val, double abs_tol, double rel) {
  return err / std::max(abs_tol, rel * std::abs(val));
}
inline double worst(const glm::dvec3& err, const glm::dvec3& val, const glm::dvec3& abs_tol, double rel) {
  double w = 0.0;
  for (int i = 0; i < 3; ++i) w = std::max(w, err[i] / std::max(abs_tol[i], rel * std::abs(val[i])));
  return w;
}

template <class V, class F>
void gk15(F& f, double a, double b, V& res, V& err) {
  double c = 0.5 * (a + b), h = 0.5 * (b - a);
  V fc = f(c);
  V rk = fc * kWgk[7];
  V rg = fc * kWg[3];
  for (int j = 0; j < 7; ++j) {
    double dx = h * kXgk[j];
    V f1 = f(c - dx), f2 = f(c + dx);
    rk += (f1 + f2) * kWgk[j];
    if (j % 2 == 1) rg += (f1 + f2) * kWg[j / 2];
  }
  res = rk * h;
  err = vabs((rk - rg) * h);
}
}  // namespace detail

// f: double -> V (double or glm::dvec3). points: breakpoints (any order; those
// outside (a, b) are ignored). abs_tol must be > 0 in every component.
template <class V, class F>
QuadResult<V> integrate_adaptive(F&& f, double a, double b, std::vector<double> points, V abs_tol,
                                 double rel_tol, int max_intervals = 4000) {
  struct Piece {
    double a, b;
    V value, error;
    double key;
    bool operator<(const Piece& o) const { return key < o.key; }
  };
  QuadResult<V> out;
  out.value = V(0.0);
  out.error = V(0.0);
  if (!(b > a)) return out;
  std::vector<double> cuts{a};
  std::sort(points.begin(), points.end());
  for (double p : points)
    if (p > a && p < b && p > cuts.back()) cuts.push_back(p);
  cuts.push_back(b);
  std::priority_queue<Piece> heap;
  V total(0.0), total_err(0.0);
  auto make = [&](double lo, double hi) {
    Piece p{lo, hi, V(0.0), V(0.0), 0.0};
    detail::gk15<V>(f, lo, hi, p.value, p.error);
    out.evaluations += 15;
    p.key = detail::worst(p.error, V(0.0), abs_tol, 0.0);  // error in units of abs_tol (> 0)
    return p;
  };
  for (std::size_t i = 1; i < cuts.size(); ++i) {
    Piece p = make(cuts[i - 1], cuts[i]);
    total += p.value;
    total_err += p.error;
    heap.push(p);
  }
  int intervals = static_cast<int>(heap.size());
  while (detail::worst(total_err, total, abs_tol, rel_tol) > 1.0) {
    if (intervals >= max_intervals || heap.empty()) {
      out.converged = false;
      break;
    }
    Piece p = heap.top();
    heap.pop();
    double m = 0.5 * (p.a + p.b);
    if (!(m > p.a && m < p.b)) {  // cannot split further: keep as is
      out.converged = false;
      heap.push(p);
      break;
    }
    Piece l = make(p.a, m), r = make(m, p.b);
    total += l.value + r.value - p.value;
    total_err += l.error + r.error - p.error;
    heap.push(l);
    heap.push(r);
    ++intervals;
  }
  // Re-sum to remove drift from the incremental updates.
  V sum(0.0), esum(0.0);
  while (!heap.empty()) {
    sum += heap.top().value;
    esum += heap.top().error;
    heap.pop();
  }
  out.value = sum;
  out.error = esum;
  return out;
}

}  // namespace atmosh::atmo
