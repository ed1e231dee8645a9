// SH rotation: z-rotations in closed form and the real-basis Ry(90 deg) matrix from
// Wigner d^l(pi/2) by a stable recurrence.
#include "atmosh/sh/rotation.hpp"

#include <cmath>
#include <cstring>
#include <mutex>
#include <numbers>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/dispatch.hpp"

namespace atmosh::sh {

namespace {

constexpr double kPi = std::numbers::pi;

// Real-basis Ry(90) of band l, checkerboard-compacted:
//   cos block C[m'][m], m', m in 0..l, non-zero for m = (l+m') mod 2, step 2;
//   sin block S[m'][m], m', m in 1..l, non-zero for m = (l+m'+1) mod 2, step 2 (m >= 1).
struct BandY90 {
  int l = 0;
  std::vector<double> c;      // rows back to back
  std::vector<int> c_off;     // row start
  std::vector<double> s;
  std::vector<int> s_off;
};

// d^l_{m'm}(pi/2) for 0 <= m, m' <= l into d[m' * (l+1) + m].
void wigner_half_pi(int l, std::vector<double>& d) {
  const int n = l + 1;
  d.assign(static_cast<std::size_t>(n) * n, 0.0);
  std::vector<double> q(n + 1, 0.0);  // q[k] = sqrt((l-k)(l+k+1))
  for (int k = 0; k <= l; ++k) q[k] = std::sqrt(static_cast<double>(l - k) * (l + k + 1));
  // starting values d_{l,m} = (-1)^(l-m) sqrt(C(2l,l+m)) 2^-l as mant * 2^exp
  double mant = 1.0;
  int ex = -l;
  for (int m = l; m >= 0; --m) {
    if (m < l) {
      mant *= -std::sqrt(static_cast<double>(l + m + 1) / (l - m));
      int e2 = 0;
      mant = std::frexp(mant, &e2);
      ex += e2;
    }
    // recurrence in m' from l down to m:
    // d_{m'-1} = (2 m d_{m'} - q[m'] d_{m'+1}) / q[m'-1]
    double p1 = mant, p2 = 0.0;  // p1 = d_{m'}, p2 = d_{m'+1}
    int e = ex;
    auto value = [&](double v) { return e == 0 ? v : std::ldexp(v, e); };
    d[static_cast<std::size_t>(l) * n + m] = value(p1);
    for (int mp = l; mp > m; --mp) {
      const double p0 = (2.0 * m * p1 - q[mp] * p2) / q[mp - 1];
      p2 = p1;
      p1 = p0;
      if (e < 0 && std::abs(p1) > 0x1p+200) {
        const int k = std::min(-e, 200);
        p1 = std::ldexp(p1, -k);
        p2 = std::ldexp(p2, -k);
        e += k;
      }
      d[static_cast<std::size_t>(mp - 1) * n + m] = value(p1);
    }
    // symmetry d_{m m'} = (-1)^(m'-m) d_{m' m}
    for (int mp = m + 1; mp <= l; ++mp)
      d[static_cast<std::size_t>(m) * n + mp] = ((mp - m) & 1 ? -1.0 : 1.0) * d[static_cast<std::size_t>(mp) * n + m];
  }
}

void build_band(int l, BandY90& out) {
  std::vector<double> d;
  wigner_half_pi(l, d);
  const int n = l + 1;
  auto D = [&](int mp, int m) { return d[static_cast<std::size_t>(mp) * n + m]; };
  out.l = l;
  out.c.clear();
  out.s.clear();
  out.c_off.assign(l + 2, 0);
  out.s_off.assign(l + 2, 0);
  const double r2 = std::numbers::sqrt2;
  for (int mp = 0; mp <= l; ++mp) {
    out.c_off[mp] = static_cast<int>(out.c.size());
    for (int m = (l + mp) & 1; m <= l; m += 2) {
      double v;
      if (mp == 0 && m == 0)
        v = D(0, 0);
      else if (mp == 0 || m == 0)
        v = r2 * D(mp, m);
      else
        v = 2.0 * D(mp, m);
      out.c.push_back(v);
    }
  }
  out.c_off[l + 1] = static_cast<int>(out.c.size());
  for (int mp = 1; mp <= l; ++mp) {
    out.s_off[mp] = static_cast<int>(out.s.size());
    int m0 = (l + mp + 1) & 1;
    if (m0 == 0) m0 = 2;
    for (int m = m0; m <= l; m += 2) out.s.push_back(2.0 * D(mp, m));
  }
  out.s_off[l + 1] = static_cast<int>(out.s.size());
}

constexpr int kCacheBands = 256;

const BandY90& cached_band(int l) {
  static std::mutex mu;
  static std::vector<std::unique_ptr<BandY90>> cache(kCacheBands);
  std::lock_guard<std::mutex> lock(mu);
  if (!cache[l]) {
    auto b = std::make_unique<BandY90>();
    build_band(l, *b);
    cache[l] = std::move(b);
  }
  return *cache[l];
}

// v: band l coefficients, v[l + m] for m = -l..l.
inline void zrot_band(int l, double* v, const double* cs, const double* sn) {
  for (int m = 1; m <= l; ++m) {
    const double c = v[l + m], s = v[l - m];
    v[l + m] = c * cs[m] - s * sn[m];
    v[l - m] = c * sn[m] + s * cs[m];
  }
}

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // V4 is passed only between inlined internal functions
#endif
// 4 doubles: one AVX register in the AVX2/FMA clone, two SSE2 registers otherwise.
typedef double V4 __attribute__((vector_size(4 * sizeof(double))));
inline V4 load4(const double* p) {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Two independent 4-lane accumulators (8 products in flight), then a fixed-order tail.
inline double dot(const double* a, const double* b, int n) {
  V4 s0 = {0, 0, 0, 0}, s1 = {0, 0, 0, 0};
  int i = 0;
  for (; i + 7 < n; i += 8) {
    s0 += load4(a + i) * load4(b + i);
    s1 += load4(a + i + 4) * load4(b + i + 4);
  }
  if (i + 3 < n) {
    s0 += load4(a + i) * load4(b + i);
    i += 4;
  }
  double t = 0;
  for (; i < n; ++i) t += a[i] * b[i];
  const V4 s = s0 + s1;
  return ((s[0] + s[1]) + (s[2] + s[3])) + t;
}

// Four dots of rows mp, mp+2, mp+4, mp+6 (same length n) with one input x.
inline void dot4(const double* m, const int* off, int mp, const double* x, int n, double* r) {
  const double* a0 = m + off[mp];
  const double* a1 = m + off[mp + 2];
  const double* a2 = m + off[mp + 4];
  const double* a3 = m + off[mp + 6];
  V4 s0 = {0, 0, 0, 0}, s1 = s0, s2 = s0, s3 = s0;
  int i = 0;
  for (; i + 3 < n; i += 4) {
    const V4 xv = load4(x + i);
    s0 += load4(a0 + i) * xv;
    s1 += load4(a1 + i) * xv;
    s2 += load4(a2 + i) * xv;
    s3 += load4(a3 + i) * xv;
  }
  double t0 = 0, t1 = 0, t2 = 0, t3 = 0;
  for (; i < n; ++i) {
    t0 += a0[i] * x[i];
    t1 += a1[i] * x[i];
    t2 += a2[i] * x[i];
    t3 += a3[i] * x[i];
  }
  r[0] = ((s0[0] + s0[1]) + (s0[2] + s0[3])) + t0;
  r[1] = ((s1[0] + s1[1]) + (s1[2] + s1[3])) + t1;
  r[2] = ((s2[0] + s2[1]) + (s2[2] + s2[3])) + t2;
  r[3] = ((s3[0] + s3[1]) + (s3[2] + s3[3])) + t3;
}

// v <- Y90 v for band l (v[l + m]); work needs 2(l+1) doubles.
ATMOSH_DISPATCH
void apply_y90(const BandY90& B, double* v, double* work) {
  const int l = B.l;
  // split by parity: cos part c_m (m = 0..l), sin part s_m (m = 1..l)
  double* ce = work;                 // c_{2j}
  double* co = ce + (l / 2 + 1);     // c_{2j+1}
  double* se = co + (l + 1) / 2 + 1; // s_{2+2j}
  double* so = se + l / 2 + 1;       // s_{1+2j}
  int ne = 0, no = 0;
  for (int m = 0; m <= l; m += 2) ce[ne++] = v[l + m];
  for (int m = 1; m <= l; m += 2) co[no++] = v[l + m];
  int nse = 0, nso = 0;
  for (int m = 2; m <= l; m += 2) se[nse++] = v[l - m];
  for (int m = 1; m <= l; m += 2) so[nso++] = v[l - m];
  // rows of equal parity share their input and length: four rows at a time
  for (int p = 0; p < 2; ++p) {
    int mp = p;
    for (; mp + 6 <= l; mp += 8) {
      const int len = B.c_off[mp + 1] - B.c_off[mp];
      const double* src = ((l + mp) & 1) ? co : ce;
      double r[4];
      dot4(B.c.data(), B.c_off.data(), mp, src, len, r);
      for (int k = 0; k < 4; ++k) v[l + mp + 2 * k] = r[k];
    }
    for (; mp <= l; mp += 2) {
      const int len = B.c_off[mp + 1] - B.c_off[mp];
      const double* src = ((l + mp) & 1) ? co : ce;
      v[l + mp] = dot(B.c.data() + B.c_off[mp], src, len);
    }
    mp = 1 + p;
    for (; mp + 6 <= l; mp += 8) {
      const int len = B.s_off[mp + 1] - B.s_off[mp];
      const double* src = ((l + mp + 1) & 1) ? so : se;
      double r[4];
      dot4(B.s.data(), B.s_off.data(), mp, src, len, r);
      for (int k = 0; k < 4; ++k) v[l - mp - 2 * k] = r[k];
    }
    for (; mp <= l; mp += 2) {
      const int len = B.s_off[mp + 1] - B.s_off[mp];
      const double* src = ((l + mp + 1) & 1) ? so : se;
      v[l - mp] = dot(B.s.data() + B.s_off[mp], src, len);
    }
  }
}

void trig_table(int bands, double angle, std::vector<double>& c, std::vector<double>& s) {
  c.resize(bands);
  s.resize(bands);
  for (int m = 0; m < bands; ++m) {
    // direct evaluation (no recurrence drift); reduce m*angle exactly enough
    c[m] = std::cos(m * angle);
    s[m] = std::sin(m * angle);
  }
}

void check_rotation_matrix(const glm::dmat3& M) {
  double err = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(M[i][j])) throw InputError("rotation matrix has a NaN or infinite entry");
      double s = 0;
      for (int k = 0; k < 3; ++k) s += M[i][k] * M[j][k];
      err = std::max(err, std::abs(s - (i == j ? 1.0 : 0.0)));
    }
  const double det = glm::determinant(M);
  if (err > 1e-6 || det < 0)
    throw InputError("matrix is not a rotation: |M^T M - I| = " + std::to_string(err) + ", det = " + std::to_string(det));
}

}  // namespace

glm::dmat3 matrix_from_euler(const EulerZYZ& e) {
  auto rz = [](double a) {
    glm::dmat3 m(1.0);
    m[0][0] = std::cos(a);
    m[0][1] = std::sin(a);
    m[1][0] = -std::sin(a);
    m[1][1] = std::cos(a);
    return m;
  };
  glm::dmat3 ry(1.0);
  ry[0][0] = std::cos(e.beta);
  ry[0][2] = -std::sin(e.beta);
  ry[2][0] = std::sin(e.beta);
  ry[2][2] = std::cos(e.beta);
  return rz(e.alpha) * ry * rz(e.gamma);
}

EulerZYZ euler_from_matrix(const glm::dmat3& M) {
  check_rotation_matrix(M);
  auto R = [&](int i, int j) { return M[j][i]; };
  EulerZYZ e;
  const double sb = std::hypot(R(0, 2), R(1, 2));
  e.beta = std::atan2(sb, R(2, 2));
  if (sb < 1e-14) {
    e.gamma = 0.0;
    if (R(2, 2) > 0)
      e.alpha = std::atan2(R(1, 0), R(0, 0));
    else
      e.alpha = std::atan2(-R(1, 0), -R(0, 0));
  } else {
    e.alpha = std::atan2(R(1, 2), R(0, 2));
    e.gamma = std::atan2(R(2, 1), -R(2, 0));
  }
  return e;
}

glm::dmat3 matrix_from_quaternion(const glm::dquat& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!std::isfinite(n) || n == 0.0) throw InputError("quaternion has zero length or a NaN component");
  return glm::mat3_cast(glm::dquat(q.w / n, q.x / n, q.y / n, q.z / n));
}

Rotation::Rotation(int bands, const EulerZYZ& e) : bands_(bands), e_(e) {
  check_bands(bands, "Rotation", 8192);
  if (!std::isfinite(e.alpha) || !std::isfinite(e.beta) || !std::isfinite(e.gamma))
    throw InputError("Rotation: Euler angle is not finite");
  trig_table(bands, e.alpha + kPi / 2, ca_, sa_);
  trig_table(bands, e.beta - kPi, cb_, sb_);
  trig_table(bands, e.gamma + kPi / 2, cg_, sg_);
}

Rotation::Rotation(int bands, const glm::dmat3& m) : Rotation(bands, euler_from_matrix(m)) {}
Rotation::Rotation(int bands, const glm::dquat& q) : Rotation(bands, euler_from_matrix(matrix_from_quaternion(q))) {}

void Rotation::apply(const double* in, double* out) const {
  std::vector<double> work(2 * bands_ + 16);
  BandY90 local;
  out[0] = in[0];
  for (int l = 1; l < bands_; ++l) {
    double* v = out + l * l;  // band l occupies [l^2, (l+1)^2), v[l + m]
    for (int i = 0; i < 2 * l + 1; ++i) v[i] = in[l * l + i];
    const BandY90* B;
    if (l < kCacheBands) {
      B = &cached_band(l);
    } else {
      build_band(l, local);
      B = &local;
    }
    zrot_band(l, v, cg_.data(), sg_.data());
    apply_y90(*B, v, work.data());
    zrot_band(l, v, cb_.data(), sb_.data());
    apply_y90(*B, v, work.data());
    zrot_band(l, v, ca_.data(), sa_.data());
  }
}

std::vector<double> Rotation::apply(const std::vector<double>& in) const {
  if (static_cast<int>(in.size()) < sh_count(bands_))
    throw InputError("Rotation::apply: coefficient vector has " + std::to_string(in.size()) + " entries, need " +
                     std::to_string(sh_count(bands_)));
  std::vector<double> out(sh_count(bands_));
  apply(in.data(), out.data());
  return out;
}

std::vector<double> Rotation::band_matrix(int l) const {
  if (l < 0 || l >= bands_) throw InputError("band_matrix: band " + std::to_string(l) + " out of range");
  const int n = 2 * l + 1;
  std::vector<double> M(static_cast<std::size_t>(n) * n);
  Rotation one(l + 1, e_);
  std::vector<double> in(sh_count(l + 1), 0.0), out(sh_count(l + 1));
  for (int j = 0; j < n; ++j) {
    in[l * l + j] = 1.0;
    one.apply(in.data(), out.data());
    in[l * l + j] = 0.0;
    for (int i = 0; i < n; ++i) M[static_cast<std::size_t>(i) * n + j] = out[l * l + i];
  }
  return M;
}

void rotate_z(int bands, double alpha, const double* in, double* out) {
  check_bands(bands, "rotate_z", 1 << 20);
  if (!std::isfinite(alpha)) throw InputError("rotate_z: angle is not finite");
  for (int l = 0; l < bands; ++l) {
    out[l * (l + 1)] = in[l * (l + 1)];
  }
  for (int m = 1; m < bands; ++m) {
    const double c = std::cos(m * alpha), s = std::sin(m * alpha);
    for (int l = m; l < bands; ++l) {
      const int i = l * (l + 1);
      const double a = in[i + m], b = in[i - m];
      out[i + m] = a * c - b * s;
      out[i - m] = a * s + b * c;
    }
  }
}

}  // namespace atmosh::sh
