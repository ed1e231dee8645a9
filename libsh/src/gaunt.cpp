// Wigner 3j symbols by the Schulten–Gordon recurrence, Gaunt coefficients of the real SH,
// the triple-product tensor and products of SH functions (see gaunt.hpp).
#include "atmosh/sh/gaunt.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/transform.hpp"

namespace atmosh::sh {

namespace {
void check_lm(int l, int m, const char* where) {
  if (l < 0 || std::abs(m) > l)
    throw InputError(std::string(where) + ": need l >= 0 and |m| <= l, got l = " + std::to_string(l) +
                     ", m = " + std::to_string(m));
}
}  // namespace

int wigner3j_family(int l2, int l3, int m2, int m3, std::vector<double>& out) {
  check_lm(l2, m2, "wigner3j_family");
  check_lm(l3, m3, "wigner3j_family");
  const int m1 = -m2 - m3;
  const int lmin = std::max(std::abs(l2 - l3), std::abs(m1));
  const int lmax = l2 + l3;
  const int n = lmax - lmin + 1;
  out.assign(n, 0.0);
  // Schulten & Gordon (1975): l A(l+1) f(l+1) + B(l) f(l) + (l+1) A(l) f(l-1) = 0 with
  // A(l) = sqrt((l^2 - (l2-l3)^2)((l2+l3+1)^2 - l^2)(l^2 - m1^2)),
  // B(l) = -(2l+1)(l2(l2+1) m1 - l3(l3+1) m1 - l(l+1)(m3 - m2)).
  const double d23 = static_cast<double>(l2 - l3), s23 = static_cast<double>(l2 + l3 + 1), dm1 = m1;
  auto A = [&](int l) {
    const double x = static_cast<double>(l) * l;
    return std::sqrt(std::max(0.0, (x - d23 * d23) * (s23 * s23 - x) * (x - dm1 * dm1)));
  };
  auto Bc = [&](int l) {
    return -(2.0 * l + 1.0) * (static_cast<double>(l2) * (l2 + 1) * dm1 - static_cast<double>(l3) * (l3 + 1) * dm1 -
                               static_cast<double>(l) * (l + 1) * (m3 - m2));
  };
  constexpr double kBig = 1e150;
  if (n == 1) {
    out[0] = 1.0;
  } else {
    // forward from lmin while the solution grows (|f(l)| >= |f(l-2)|); not possible from l = 0
    int lc = lmin;  // forward values are used for l <= lc
    if (lmin >= 1) {
      out[0] = 1.0;
      int l = lmin;
      for (; l < lmax; ++l) {
        const int i = l - lmin;
        const double prev = i >= 1 ? out[i - 1] : 0.0;
        out[i + 1] = -(Bc(l) * out[i] + (l + 1.0) * A(l) * prev) / (l * A(l + 1));
        if (std::abs(out[i + 1]) > kBig)
          for (int k = 0; k <= i + 1; ++k) out[k] /= kBig;
        if (i + 1 >= 2 && std::abs(out[i + 1]) < std::abs(out[i - 1])) break;
      }
      lc = std::min(l + 1, lmax);
    }
    if (lc < lmax || lmin == 0) {
      // backward from lmax down to max(lmin, lc - 2); matched over [lc - 2, lc]
      const int lo = lmin == 0 ? lmin : std::max(lmin, lc - 2);
      std::vector<double> g(lmax - lo + 2, 0.0);  // g[l - lo], g[lmax - lo + 1] = 0
      g[lmax - lo] = 1.0;
      for (int l = lmax; l > lo; --l) {
        const int i = l - lo;
        g[i - 1] = -(Bc(l) * g[i] + l * A(l + 1) * g[i + 1]) / ((l + 1.0) * A(l));
        if (std::abs(g[i - 1]) > kBig)
          for (int k = i - 1; k <= lmax - lo; ++k) g[k] /= kBig;
      }
      double scale = 1.0;
      int from = lo;  // backward values are used for l >= from
      if (lmin != 0) {
        double num = 0.0, den = 0.0;
        for (int l = lo; l <= lc; ++l) {
          num += out[l - lmin] * g[l - lo];
          den += g[l - lo] * g[l - lo];
        }
        scale = den > 0.0 ? num / den : 0.0;
        from = lc + 1;
        if (scale == 0.0) {  // the forward part is negligible: take the backward solution
          scale = 1.0;
          from = lo;
          for (int l = lmin; l < lo; ++l) out[l - lmin] = 0.0;
        }
      }
      for (int l = from; l <= lmax; ++l) out[l - lmin] = scale * g[l - lo];
    }
  }
  // normalise: sum (2l+1) f^2 = 1; sign of f(lmax) = (-1)^(l2-l3-m1)
  double big = 0.0;
  for (double v : out) big = std::max(big, std::abs(v));
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += (2.0 * (lmin + i) + 1.0) * (out[i] / big) * (out[i] / big);
  double norm = 1.0 / (big * std::sqrt(s));
  const int sgn = ((l2 - l3 - m1) % 2 == 0) ? 1 : -1;
  if ((out[n - 1] < 0) != (sgn < 0)) norm = -norm;
  for (double& v : out) v *= norm;
  return lmin;
}

double wigner3j(int l1, int l2, int l3, int m1, int m2, int m3) {
  check_lm(l1, m1, "wigner3j");
  check_lm(l2, m2, "wigner3j");
  check_lm(l3, m3, "wigner3j");
  if (m1 + m2 + m3 != 0 || l1 < std::abs(l2 - l3) || l1 > l2 + l3) return 0.0;
  std::vector<double> f;
  const int lmin = wigner3j_family(l2, l3, m2, m3, f);
  return l1 < lmin ? 0.0 : f[l1 - lmin];
}

namespace {
using cd = std::complex<double>;
// Real Y_lm = sum_k u[k] Y_l^mu[k] (complex SH, Condon–Shortley phase); returns the count.
int decompose(int m, int mu[2], cd u[2]) {
  const double r = std::numbers::sqrt2 / 2;
  if (m == 0) {
    mu[0] = 0;
    u[0] = 1.0;
    return 1;
  }
  const int a = std::abs(m);
  const double sg = (a % 2) ? -1.0 : 1.0;
  mu[0] = a;
  mu[1] = -a;
  if (m > 0) {
    u[0] = r;
    u[1] = sg * r;
  } else {  // (Y^a - (-1)^a Y^-a) / (i sqrt2)
    u[0] = cd(0, -r);
    u[1] = cd(0, sg * r);
  }
  return 2;
}

// Whether the real Gaunt coefficient can be non-zero by the m rules.
bool m_allowed(int m1, int m2, int m3) {
  const int neg = (m1 < 0) + (m2 < 0) + (m3 < 0);
  if (neg % 2) return false;
  const int a = std::abs(m1), b = std::abs(m2), c = std::abs(m3);
  return a == b + c || b == a + c || c == a + b;
}

// Gaunt coefficients G(l1 m1, l2 m2, l3 m3) for all l1 (family over l1 for fixed l2, m2,
// l3, m3, and every m1 with |m1| in {|m2|+|m3|, ||m2|-|m3||}) — calls out(l1, m1, value).
template <class F>
void gaunt_family(int l2, int m2, int l3, int m3, const std::vector<double>& f000, int lmin000, F&& out) {
  int mu2[2], mu3[2];
  cd u2[2], u3[2];
  const int n2 = decompose(m2, mu2, u2), n3 = decompose(m3, mu3, u3);
  // candidate m1 values
  const int a = std::abs(m2) + std::abs(m3), b = std::abs(std::abs(m2) - std::abs(m3));
  int cand[4], nc = 0;
  for (int v : {a, -a, b, -b}) {
    bool dup = false;
    for (int k = 0; k < nc; ++k) dup |= cand[k] == v;
    if (!dup) cand[nc++] = v;
  }
  std::vector<double> f[2][2];
  int lmin[2][2];
  for (int p = 0; p < n2; ++p)
    for (int q = 0; q < n3; ++q) lmin[p][q] = wigner3j_family(l2, l3, mu2[p], mu3[q], f[p][q]);
  const double pref = std::sqrt((2.0 * l2 + 1) * (2.0 * l3 + 1) / (4 * std::numbers::pi));
  for (int k = 0; k < nc; ++k) {
    const int m1 = cand[k];
    if (!m_allowed(m1, m2, m3)) continue;
    int mu1[2];
    cd u1[2];
    const int n1 = decompose(m1, mu1, u1);
    int start = lmin000;  // parity: l1 + l2 + l3 even
    while (start < std::abs(m1)) start += 2;
    for (int l1 = start; l1 <= l2 + l3; l1 += 2) {
      const double w000 = f000[l1 - lmin000];
      cd s = 0.0;
      for (int r = 0; r < n1; ++r)
        for (int p = 0; p < n2; ++p)
          for (int q = 0; q < n3; ++q) {
            if (mu1[r] + mu2[p] + mu3[q] != 0) continue;
            const int lm = lmin[p][q];
            if (l1 < lm) continue;
            s += u1[r] * u2[p] * u3[q] * f[p][q][l1 - lm];
          }
      const double v = pref * std::sqrt(2.0 * l1 + 1) * w000 * s.real();
      if (v != 0.0) out(l1, m1, v);
    }
  }
}
}  // namespace

double gaunt(int l1, int m1, int l2, int m2, int l3, int m3) {
  check_lm(l1, m1, "gaunt");
  check_lm(l2, m2, "gaunt");
  check_lm(l3, m3, "gaunt");
  if ((l1 + l2 + l3) % 2 || l1 < std::abs(l2 - l3) || l1 > l2 + l3 || !m_allowed(m1, m2, m3)) return 0.0;
  std::vector<double> f000;
  const int lmin000 = wigner3j_family(l2, l3, 0, 0, f000);
  double result = 0.0;
  gaunt_family(l2, m2, l3, m3, f000, lmin000, [&](int l, int m, double v) {
    if (l == l1 && m == m1) result = v;
  });
  return result;
}

TripleProduct::TripleProduct(int bands_a, int bands_b, int bands_out) : la_(bands_a), lb_(bands_b) {
  check_bands(bands_a, "TripleProduct", 4096);
  check_bands(bands_b, "TripleProduct", 4096);
  lo_ = bands_out > 0 ? bands_out : bands_a + bands_b - 1;
  check_bands(lo_, "TripleProduct", 8192);
  std::vector<double> f000;
  for (int la = 0; la < la_; ++la)
    for (int lb = 0; lb < lb_; ++lb) {
      const int lmin000 = wigner3j_family(la, lb, 0, 0, f000);
      for (int ma = -la; ma <= la; ++ma)
        for (int mb = -lb; mb <= lb; ++mb)
          gaunt_family(la, ma, lb, mb, f000, lmin000, [&](int l, int m, double v) {
            if (l < lo_) e_.push_back({sh_index(la, ma), sh_index(lb, mb), sh_index(l, m), v});
          });
    }
  std::sort(e_.begin(), e_.end(), [](const GauntEntry& x, const GauntEntry& y) {
    return x.k != y.k ? x.k < y.k : (x.i != y.i ? x.i < y.i : x.j < y.j);
  });
}

void TripleProduct::apply(const double* a, const double* b, double* c) const {
  std::fill(c, c + sh_count(lo_), 0.0);
  for (const GauntEntry& e : e_) c[e.k] += e.value * a[e.i] * b[e.j];
}

std::vector<double> TripleProduct::product_matrix(const double* a) const {
  const std::size_t nb = sh_count(lb_);
  std::vector<double> M(static_cast<std::size_t>(sh_count(lo_)) * nb, 0.0);
  for (const GauntEntry& e : e_) M[static_cast<std::size_t>(e.k) * nb + e.j] += e.value * a[e.i];
  return M;
}

std::vector<double> product(const std::vector<double>& a, int bands_a, const std::vector<double>& b, int bands_b,
                            int bands_out, int threads) {
  check_bands(bands_a, "product", 4096);
  check_bands(bands_b, "product", 4096);
  const int lp = bands_a + bands_b - 1;
  if (bands_out == 0) bands_out = lp;
  check_bands(bands_out, "product", 8192);
  if (static_cast<int>(a.size()) < sh_count(bands_a) || static_cast<int>(b.size()) < sh_count(bands_b))
    throw InputError("product: need " + std::to_string(sh_count(bands_a)) + " and " + std::to_string(sh_count(bands_b)) +
                     " coefficients, got " + std::to_string(a.size()) + " and " + std::to_string(b.size()));
  // Grid exact for the product's lp bands; the factors are synthesised at lp bands (zero padded).
  const GaussGrid g = gauss_grid(lp);
  std::vector<double> pa(sh_count(lp), 0.0), pb(sh_count(lp), 0.0);
  std::copy(a.begin(), a.begin() + sh_count(bands_a), pa.begin());
  std::copy(b.begin(), b.begin() + sh_count(bands_b), pb.begin());
  std::vector<double> va = synthesise(g, pa.data(), threads);
  const std::vector<double> vb = synthesise(g, pb.data(), threads);
  for (std::size_t k = 0; k < va.size(); ++k) va[k] *= vb[k];
  std::vector<double> c = analyse(g, va.data(), threads);
  c.resize(sh_count(bands_out), 0.0);  // truncated, or zero padded above lp bands
  return c;
}

}  // namespace atmosh::sh
