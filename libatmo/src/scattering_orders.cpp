#include "atmosh/atmo/scattering_orders.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "atmosh/atmo/atmosphere.hpp"
#include "fast_exp.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/orders.glsl.hpp"
#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::atmo {

namespace sg = shared;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kElevationMin = -36.0 * kPi / 180.0;  // lowest tabulated sun elevation
// Values below sg::kOrdersFloor are stored as it, read as 0 (sg::orders_log_visible).

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Zenith rule at radius r (as the approximation's): Gauss-Legendre on each side of the
// horizon cosine, a quarter below, gathered toward the horizon on both sides.
void zenith_rule(double R, double r, int n, std::vector<double>& mu, std::vector<double>& w, int& n_ground) {
  mu.clear();
  w.clear();
  const double mu_h = -std::sqrt(std::max(0.0, 1.0 - (R / r) * (R / r)));
  const int n_lo = std::max(1, n / 4), n_hi = n - n_lo;
  const auto lo = sh::gauss_legendre(n_lo), hi = sh::gauss_legendre(n_hi);
  for (std::size_t k = 0; k < lo.nodes.size(); ++k) {
    const double v = 0.5 * (lo.nodes[k] + 1.0);
    mu.push_back(mu_h - (mu_h + 1.0) * v * v);
    w.push_back((mu_h + 1.0) * v * lo.weights[k]);
  }
  for (std::size_t k = 0; k < hi.nodes.size(); ++k) {
    const double v = 0.5 * (hi.nodes[k] + 1.0);
    mu.push_back(mu_h + (1.0 - mu_h) * v * v);
    w.push_back((1.0 - mu_h) * v * hi.weights[k]);
  }
  n_ground = n_lo;
}
}  // namespace

// The tables hold logarithms and are interpolated multilinearly in them, with the
// curvature correction of shared/orders.glsl.hpp (orders_curvature): a weighted
// geometric mean of the corners alone is right for the exponential falls of the
// Earth's shadow but, where the light varies smoothly (daylight), at or below the
// weighted arithmetic mean (AM-GM) -- a low bias that compounds through the orders
// (every order interpolates the previous one), measured at -0.3 to -1.8 % of the sky's
// luminance against the Monte-Carlo reference (docs/radiative-transfer.md). The
// second difference of the logarithms along each axis restores the curvature the
// multilinear blend leaves out, in both cases.

namespace {
// One lookup: the 8 (radius, view, sun) corners p[n] (each with its azimuths a0 and
// a0 + 1 at p[n] and p[n] + nw) with weights w[n] and the azimuth fraction fa; per axis x
// (radius, view, sun, azimuth) the two samples b0[x], b1[x] of sg::orders_curvature
// whose second differences (neighbours at -+ st[x] floats) are blended with the weights
// g0[x], g1[x].
struct Lookup {
  const float* p[8];
  float w[8];
  float fa;
  const float* b0[4];
  const float* b1[4];
  std::ptrdiff_t st[4];
  float g0[4], g1[4];
};
// exp of the weighted mean of the 16 corners' logarithms minus the curvature terms, into
// out[0..nw) (0 below the visibility floor). Mean about the first corner (precision).
// Vectorised over the wavelengths (AVX2 clone: 8 per vector; exp_neg_f, relative error
// <= 2e-7).
typedef float V8f __attribute__((vector_size(32)));
typedef int V8i __attribute__((vector_size(32)));
[[gnu::always_inline]] inline V8f load8(const float* p) {
  V8f v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
ATMOSH_DISPATCH void blend_log_corners(std::size_t nw, const Lookup& L, float* __restrict out) {
  float acc[256];
  const float* ref = L.p[0];
  float w0[8], w1[8];
  for (int n = 0; n < 8; ++n) {
    w0[n] = L.w[n] * (1 - L.fa);
    w1[n] = L.w[n] * L.fa;
  }
  const float floor_seen = sg::kOrdersLogFloor + 0.7f;  // sg::orders_log_visible
  // g D of the samples around b (sg::orders_curvature_term), 8 wavelengths.
  auto term8 = [floor_seen](float g, const float* b, std::ptrdiff_t st) {
    const V8f lm = load8(b - st), lc = load8(b), lp = load8(b + st);
    const V8i seen = (lm > floor_seen) & (lp > floor_seen) & (lc > floor_seen);
    const V8f t = g * (lm + lp - 2.0f * lc);
    return (V8f)((V8i)t & seen);  // the term where all three are seen, else 0
  };
  std::size_t q = 0;
  for (; q + 8 <= nw; q += 8) {  // 8 wavelengths at a time, the 16 corners in registers
    const V8f r = load8(ref + q);
    V8f a = {}, corr = {};
    for (int n = 0; n < 8; ++n) a += w0[n] * (load8(L.p[n] + q) - r) + w1[n] * (load8(L.p[n] + nw + q) - r);
    for (int x = 0; x < 4; ++x) {
      if (L.g0[x] > 0) corr += term8(L.g0[x], L.b0[x] + q, L.st[x]);
      if (L.g1[x] > 0) corr += term8(L.g1[x], L.b1[x] + q, L.st[x]);
    }
    __builtin_memcpy(acc + q, &a, sizeof a);
    __builtin_memcpy(out + q, &corr, sizeof corr);
  }
  for (; q < nw; ++q) {
    float a = 0, corr = 0;
    for (int n = 0; n < 8; ++n) a += w0[n] * (L.p[n][q] - ref[q]) + w1[n] * (L.p[n][nw + q] - ref[q]);
    for (int x = 0; x < 4; ++x) {
      const float *b0 = L.b0[x] + q, *b1 = L.b1[x] + q;
      const std::ptrdiff_t st = L.st[x];
      if (L.g0[x] > 0) corr += sg::orders_curvature_term(L.g0[x], b0[-st], b0[0], b0[st]);
      if (L.g1[x] > 0) corr += sg::orders_curvature_term(L.g1[x], b1[-st], b1[0], b1[st]);
    }
    acc[q] = a;
    out[q] = corr;
  }
  for (q = 0; q < nw; ++q) {
    const float l = ref[q] + acc[q];
    const float v = exp_neg_f(out[q] - l);
    out[q] = sg::orders_log_visible(l) ? v : 0.0f;
  }
}

// acc[q] += wn T[q] exp(blend) (the S pass's quadrature along a ray), q < nw.
ATMOSH_DISPATCH void blend_log_corners_acc(std::size_t nw, const Lookup& L, double wn, const float* __restrict T,
                                           double* __restrict acc) {
  float J[256];
  blend_log_corners(nw, L, J);
  for (std::size_t q = 0; q < nw; ++q) acc[q] += wn * T[q] * J[q];
}

// a[q] += (sr[q] wr + sm[q] wm) exp(-(er[q] x0 + em[q] x1 + eo[q] x2)), q < nw: one
// node's single scattering toward one sun texel (branch-free exp: vectorises).
ATMOSH_DISPATCH void accumulate_single(std::size_t nw, const double* __restrict sr, const double* __restrict sm,
                                       const double* __restrict er, const double* __restrict em,
                                       const double* __restrict eo, double wr, double wm, glm::dvec3 x,
                                       double* __restrict a) {
  const double x0 = x[0], x1 = x[1], x2 = x[2];
  for (std::size_t q = 0; q < nw; ++q) a[q] += (sr[q] * wr + sm[q] * wm) * exp_neg(er[q] * x0 + em[q] * x1 + eo[q] * x2);
}

// jr[w] = sum_q Pr[q] I[q][w], jm[w] = sum_q Pm[q] I[q][w], w < nw: the scattering
// density's sphere rule for one outgoing direction (q < nq incoming directions).
ATMOSH_DISPATCH void phase_products(std::size_t nw, std::size_t nq, const float* __restrict Pr,
                                    const float* __restrict Pm, const float* __restrict I, float* __restrict jr,
                                    float* __restrict jm) {
  for (std::size_t w = 0; w < nw; ++w) jr[w] = jm[w] = 0.0f;
  for (std::size_t q = 0; q < nq; ++q) {
    const float* __restrict Iq = I + q * nw;
    const float a = Pr[q], b = Pm[q];
    for (std::size_t w = 0; w < nw; ++w) {
      jr[w] += a * Iq[w];
      jm[w] += b * Iq[w];
    }
  }
}
}  // namespace

struct ScatteringOrders::Impl {
  int nr = 0, nmu = 0, ns = 0, na = 0, half = 0;
  std::size_t nw = 0;
  double R = 0, T = 0, H = 0;
  std::vector<float> sum;   // log of sum_{k=2..N} S_k, [r][mu][mu_s][phi][wavelength]: the
                            // radius rows [part_i, part_i + part_ni) and sun rows [part_k,
                            // part_k + part_nk) of the table (all of it, or the part
                            // read_back_at read from the device)
  int part_i = 0, part_ni = 0, part_k = 0, part_nk = 0;
  std::vector<float> esum;  // log of sum_{k=1..N-1} E_k at the ground, [mu_s][wavelength]

  std::size_t texels() const { return static_cast<std::size_t>(nr) * nmu * ns * na; }
  std::size_t index(int i, int j, int k, int a) const {
    return ((((static_cast<std::size_t>(i) * nmu + j) * ns + k) * na + a) * nw);
  }
  double r_of(int i) const { return sg::orders_radius(i, nr, R, H); }
  // View sample j at radius r: its cosine and the ray's length.
  void mu_of(double r, int j, double& mu, double& d) const {
    const sg::OrdersView v = sg::orders_view(r, j, half, R, T, H);
    mu = v.mu;
    d = v.d;
  }
  // Sun coordinate u in [0, 1]: u0 = m / (1 + m) at the horizon (m = -sin(min
  // elevation)); on each side x in [-1, 1] and mu_s = s x (a + (1 - a)|x|) (s = m
  // below, 1 above, a = 0.3): ~6x denser near the horizon than uniform in mu_s, where
  // the light changes fastest (the terminator).
  // (sg::orders_mus_of_u, sg::orders_u_of_mus with m = -sin(kElevationMin).)
  double mus_of(int k) const { return mus_of_u(double(k) / (ns - 1)); }
  static double sun_m() { return -std::sin(kElevationMin); }
  static double mus_of_u(double u) { return sg::orders_mus_of_u(u, sun_m()); }
  static double u_of_mus(double mu_s) { return sg::orders_u_of_mus(mu_s, sun_m()); }
  // Azimuth samples uniform in cos(phi): t = (1 - cos phi) / 2 in [0, 1]. In twilight
  // the sky about the sun's vertical plane is close to log L = A + B cos phi (tens of
  // times brighter toward the sun than away from it), which this coordinate
  // interpolates exactly where a uniform phi grid (its previous form) bends it: with 8
  // azimuths the uniform phi grid put orders N = 4 7-14 % low at sun -9 deg, this one
  // within -5.4 ... +2.3 % (docs/radiative-transfer.md, "Twilight").
  // (t = (1 - cos phi) / 2: sg::orders_sun_coord.)
  double phi_of(int a) const { return std::acos(sg::orders_azimuth_cos(a, na)); }
  static double nu_of(double mu, double mu_s, double phi) { return sg::orders_nu(mu, mu_s, std::cos(phi)); }

  // Interpolation coordinates of the radius and the view (independent of the sun), and
  // of the sun and the azimuth (the rest of the corners' position).
  using RayCoord = sg::OrdersRayCoord;
  using SunCoord = sg::OrdersSunCoord;
  RayCoord ray_coord(double r, double mu, bool ground) const {
    return sg::orders_ray_coord(r, mu, ground, R, T, H, nr, half);
  }
  SunCoord sun_coord(double mu, double mu_s, double nu) const {
    return sg::orders_sun_coord(mu, mu_s, nu, ns, na, sun_m());
  }
  // exp of the interpolation of a log table into out[0..nw) (blend_log_corners).
  void interp(const float* tab, const RayCoord& c, double mu, double mu_s, double nu, float* out) const {
    interp(tab, c, sun_coord(mu, mu_s, nu), out);
  }
  void interp(const float* tab, const RayCoord& c, const SunCoord& s, float* out) const {
    Lookup L;
    lookup(tab, c, s, L);
    blend_log_corners(nw, L, out);
  }
  // A lookup at (c, s) of a table whose texel (i, j, k, a) is at tab + (i - i_base,
  // j, k - k_base, a) of a block with nk sun samples (the whole table: 0, 0, ns).
  void lookup(const float* tab, const RayCoord& c, const SunCoord& s, Lookup& L, int i_base = 0, int k_base = 0,
              int nk = 0) const {
    if (nk == 0) nk = ns;
    const std::ptrdiff_t sa = static_cast<std::ptrdiff_t>(nw), sk = sa * na, sj = sk * nk, si = sj * nmu;
    auto at = [&](int i, int j, int k, int a) { return tab + (i - i_base) * si + j * sj + (k - k_base) * sk + a * sa; };
    int n = 0;
    for (int di = 0; di < 2; ++di)
      for (int dj = 0; dj < 2; ++dj)
        for (int dk = 0; dk < 2; ++dk, ++n) {
          L.w[n] = sg::orders_corner_weight(c.fr, c.fm, s.fs, di, dj, dk);
          L.p[n] = at(c.i0 + di, c.j0 + dj, s.k0 + dk, s.a0);
        }
    L.fa = s.fa;
    const sg::OrdersCurvature k = sg::orders_curvature(c, s, nr, half, ns, na);
    L.st[0] = si, L.st[1] = sj, L.st[2] = sk, L.st[3] = sa;
    for (int x = 0; x < 4; ++x) {
      glm::ivec4 t0 = k.centre, t1 = k.centre;  // the line along axis x
      t0[x] = k.at0[x];
      t1[x] = k.at1[x];
      L.b0[x] = at(t0[0], t0[1], t0[2], t0[3]);
      L.b1[x] = at(t1[0], t1[1], t1[2], t1[3]);
      L.g0[x] = k.g0[x];
      L.g1[x] = k.g1[x];
    }
  }
  // Whether the 16 corners of a lookup at (c, sc), and the neighbours of its curvature
  // samples, are in the sum's part: read_back_at reads the radius and sun samples i0 - 1
  // .. i0 + 2 and k0 - 1 .. k0 + 2 of the lookups at one radius and sun cosine, and the
  // curvature samples are i0 and i0 + 1 (k0, k0 + 1) moved inside the table.
  bool in_part(const RayCoord& c, const SunCoord& sc) const {
    const sg::OrdersCurvature k = sg::orders_curvature(c, sc, nr, half, ns, na);
    const int i_lo = std::min(c.i0, k.at0[0] - (nr >= 3)), i_hi = std::max(c.i0 + 1, k.at1[0] + (nr >= 3));
    const int k_lo = std::min(sc.k0, k.at0[2] - (ns >= 3)), k_hi = std::max(sc.k0 + 1, k.at1[2] + (ns >= 3));
    return i_lo >= part_i && i_hi < part_i + part_ni && k_lo >= part_k && k_hi < part_k + part_nk;
  }
  void set_full_part() { part_i = 0, part_ni = nr, part_k = 0, part_nk = ns; }
  bool sum_is_full() const { return !sum.empty() && part_ni == nr && part_nk == ns; }
  // Ground irradiance table (log, [mu_s sample][wavelength]) at mu_s.
  void interp_ground(const std::vector<float>& e, double mu_s, float* out) const {
    const sg::OrdersSunCoord c = sg::orders_ground_coord(mu_s, ns, sun_m());
    const float g = sg::orders_curvature_weight(c.fs, ns), g0 = g * (1 - c.fs), g1 = g * c.fs;
    const std::size_t k0 = static_cast<std::size_t>(c.k0) * nw;
    const std::size_t p0 = static_cast<std::size_t>(ns >= 3 ? sg::orders_curvature_at(c.k0, 0, ns) : 1) * nw,
                      p1 = static_cast<std::size_t>(ns >= 3 ? sg::orders_curvature_at(c.k0 + 1, 0, ns) : 1) * nw;
    for (std::size_t q = 0; q < nw; ++q) {
      const float t = g > 0 ? sg::orders_curvature_term(g0, e[p0 - nw + q], e[p0 + q], e[p0 + nw + q]) +
                                  sg::orders_curvature_term(g1, e[p1 - nw + q], e[p1 + q], e[p1 + nw + q])
                            : 0.0f;
      out[q] = sg::orders_ground_value(e[k0 + q], e[k0 + nw + q], c.fs, t);
    }
  }
};

ScatteringOrders::~ScatteringOrders() = default;

std::size_t ScatteringOrders::texels() const { return impl_->texels(); }
std::size_t ScatteringOrders::bytes() const {
  return (impl_->texels() * impl_->nw + impl_->esum.size()) * sizeof(float);  // on the device or here
}

ScatteringOrders::ScatteringOrders(const Atmosphere& atm, const MultipleScatteringOptions& o)
    : ScatteringOrders(atm, o, o.orders_passes.get()) {}

const std::vector<float>& ScatteringOrders::radiance_table() const { return impl_->sum; }
const std::vector<float>& ScatteringOrders::ground_table() const { return impl_->esum; }
std::vector<int> ScatteringOrders::table_size() const { return {impl_->nr, impl_->nmu, impl_->ns, impl_->na}; }
double ScatteringOrders::sun_m() const { return Impl::sun_m(); }

ScatteringOrders::ScatteringOrders(const Atmosphere& atm, const MultipleScatteringOptions& o, OrdersPasses* passes)
    : impl_(std::make_unique<Impl>()) {
  validate(o);
  if (o.orders < 2) throw InputError("scattering.orders = " + std::to_string(o.orders) + ": the tables need >= 2");
  const auto t_start = Clock::now();
  Impl& m = *impl_;
  orders_ = o.orders;
  m.nr = o.orders_radii;
  m.nmu = o.orders_view_directions;
  m.half = m.nmu / 2;
  m.ns = o.orders_sun_directions;
  m.na = o.orders_azimuths;
  m.nw = nw_ = atm.wavelengths_nm().size();
  if (m.nw > 256) throw InputError("scattering orders: at most 256 wavelengths (" + std::to_string(m.nw) + " given)");
  m.R = atm.ground_radius();
  m.T = atm.top_radius();
  m.H = std::sqrt(m.T * m.T - m.R * m.R);
  const std::size_t nw = m.nw;
  const int threads = o.threads;
  const double albedo = atm.spec().planet.ground_albedo;

  // Coefficients [wavelength] and phase functions.
  std::vector<double> er(nw), em(nw), eo(nw), sr(nw), sm(nw);
  for (std::size_t i = 0; i < nw; ++i) {
    const auto& k = atm.coefficients(i);
    er[i] = atm.has(kRayleigh) ? k.extinction[kRayleigh] : 0.0;
    em[i] = atm.has(kMie) ? k.extinction[kMie] : 0.0;
    eo[i] = atm.has(kOzone) ? k.extinction[kOzone] : 0.0;
    sr[i] = atm.has(kRayleigh) ? k.scattering[kRayleigh] : 0.0;
    sm[i] = atm.has(kMie) ? k.scattering[kMie] : 0.0;
  }
  const PhaseFunction pr(atm.spec().rayleigh ? atm.spec().rayleigh->phase : PhaseSpec::of(PhaseSpec::Model::Rayleigh),
                         "rayleigh.phase");
  const PhaseFunction pm(atm.spec().mie ? atm.spec().mie->phase
                                        : PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0),
                         "mie.phase");
  LutOptions lo;
  lo.threads = threads;
  const OpticalDepthLut lut(atm, lo);  // sun and view columns
  auto tr = [&](const glm::dvec3& x, std::size_t i) { return exp_neg(er[i] * x[0] + em[i] * x[1] + eo[i] * x[2]); };

  // ---- the texels' rays: nodes, weights, densities, transmittance from the start.
  const int K = o.orders_ray_steps, nn = K + 1;
  struct Node {
    double t, r, mu, w;
    double rho_r, rho_m;
    glm::dvec3 col;
    Impl::RayCoord c;
  };
  const std::size_t nrays = static_cast<std::size_t>(m.nr) * m.nmu;
  std::vector<Node> nodes(nrays * nn);
  std::vector<float> ray_t(nrays * nn * nw);  // transmittance start -> node
  std::vector<double> ray_mu(nrays);
  parallel_for(nrays, threads, [&](std::size_t ij) {
    const int i = static_cast<int>(ij / m.nmu), j = static_cast<int>(ij % m.nmu);
    const double r = m.r_of(i);
    double mu, d;
    m.mu_of(r, j, mu, d);
    ray_mu[ij] = mu;
    const bool ground = j < m.half;
    Node* nd = &nodes[ij * nn];
    // Steps gathered toward the densest point: the tangent point (rays to the top
    // that dip first), the ground, or the start (sg::orders_node).
    for (int k = 0; k < nn; ++k) {
      const sg::OrdersNode q = sg::orders_node(r, mu, d, ground, K, k, m.R);
      nd[k].t = q.t;
      nd[k].r = q.r;
      nd[k].mu = q.mu;
      const glm::dvec3 rho = atm.density(std::max(nd[k].r - m.R, 0.0));
      nd[k].rho_r = rho[kRayleigh];
      nd[k].rho_m = rho[kMie];
      nd[k].w = 0;
      nd[k].col = glm::dvec3(0.0);
      nd[k].c = m.ray_coord(nd[k].r, nd[k].mu, ground);
    }
    glm::dvec3 rho_prev = atm.density(std::max(nd[0].r - m.R, 0.0));
    for (int k = 1; k < nn; ++k) {
      const double dt = nd[k].t - nd[k - 1].t;
      const glm::dvec3 rho = atm.density(std::max(nd[k].r - m.R, 0.0));
      nd[k].col = nd[k - 1].col + 0.5 * dt * (rho_prev + rho);
      rho_prev = rho;
      nd[k - 1].w += 0.5 * dt;
      nd[k].w += 0.5 * dt;
    }
    for (int k = 0; k < nn; ++k)
      for (std::size_t q = 0; q < nw; ++q) ray_t[(ij * nn + k) * nw + q] = static_cast<float>(tr(nd[k].col, q));
  });

  // The full-size tables here only for what runs here: with the passes on a device, S_1
  // (if the CPU computes it) until it is uploaded, and the sum if it is read back at the
  // end; the CPU's passes need S_{k-1}, J_k, S_k and the sum (4 x the table).
  const std::size_t N = m.texels() * nw;
  const bool single_on_device = passes && passes->single_on_device();
  std::vector<float> prev(passes && single_on_device ? 0 : N), next(passes ? 0 : N), dens(passes ? 0 : N);
  std::vector<float> sum_lin(passes ? 0 : N, 0.0f);
  auto to_log = [](double v) { return std::log(std::max(static_cast<float>(v), sg::kOrdersFloor)); };

  // ---- S_1: single scattering with the phase functions (on the device if it does it).
  auto t0 = Clock::now();
  if (!single_on_device)
    parallel_for(nrays, threads, [&](std::size_t ij) {
    const int i = static_cast<int>(ij / m.nmu), j = static_cast<int>(ij % m.nmu);
    const double r = m.r_of(i), mu = ray_mu[ij];
    const Node* nd = &nodes[ij * nn];
    const std::size_t nka = static_cast<std::size_t>(m.ns) * m.na;
    std::vector<double> acc(nka * nw, 0.0), nu(nka), mus(nka), ph_r(nka), ph_m(nka);
    for (int k = 0; k < m.ns; ++k)
      for (int a = 0; a < m.na; ++a) {
        const std::size_t ka = static_cast<std::size_t>(k) * m.na + a;
        mus[ka] = m.mus_of(k);
        nu[ka] = Impl::nu_of(mu, mus[ka], m.phi_of(a));
        ph_r[ka] = pr.value(nu[ka]);
        ph_m[ka] = pm.value(nu[ka]);
      }
    for (int n = 0; n < nn; ++n) {
      if (!(nd[n].w > 0)) continue;
      const auto sun_at = lut.sun_at(nd[n].r);
      for (std::size_t ka = 0; ka < nka; ++ka) {
        const double mus_y = sg::orders_sun_cosine_at(r, mus[ka], nd[n].t, nu[ka], nd[n].r);
        const LutColumn c = sun_at(mus_y);
        if (c.hits_ground) continue;
        const glm::dvec3 x = nd[n].col + c.column;
        const double wr = nd[n].w * nd[n].rho_r * ph_r[ka], wm = nd[n].w * nd[n].rho_m * ph_m[ka];
        accumulate_single(nw, sr.data(), sm.data(), er.data(), em.data(), eo.data(), wr, wm, x, &acc[ka * nw]);
      }
    }
    for (int k = 0; k < m.ns; ++k)
      for (int a = 0; a < m.na; ++a) {
        const double* s = &acc[(static_cast<std::size_t>(k) * m.na + a) * nw];
        float* out = &prev[m.index(i, j, k, a)];
        for (std::size_t q = 0; q < nw; ++q) out[q] = to_log(s[q]);
      }
  });
  pass_s_.push_back(since(t0));

  // ---- the sphere rule and the phase matrices of the scattering density, per radius:
  // P_c[(j, a), q] = w_q p_c(w_ja . w_q), each row normalised to 1 over the rule.
  const int nz = o.orders_sphere_zenith, nphi = o.orders_sphere_azimuth;
  const std::size_t nq = static_cast<std::size_t>(nz) * nphi, nout = static_cast<std::size_t>(m.nmu) * m.na;
  struct Sphere {
    std::vector<double> mu, w;
    int n_ground = 0;
    float *Pr = nullptr, *Pm = nullptr;  // [out][q]: this radius's rows of Pr_all, Pm_all
    std::vector<float> t_ground;   // [q][wavelength] transmittance to the ground (ground directions)
    std::vector<double> d_ground;  // [q] distance to the ground
  };
  std::vector<Sphere> sph(static_cast<std::size_t>(m.nr));
  // Every radius's phase matrices in one array each, handed to the device as they are.
  std::vector<float> Pr_all(static_cast<std::size_t>(m.nr) * nout * nq), Pm_all(Pr_all.size());
  std::vector<double> cphi(nphi), sphi(nphi);
  for (int b = 0; b < nphi; ++b) {
    cphi[b] = std::cos(2.0 * kPi * (b + 0.5) / nphi);
    sphi[b] = std::sin(2.0 * kPi * (b + 0.5) / nphi);
  }
  parallel_for(static_cast<std::size_t>(m.nr), threads, [&](std::size_t i) {
    Sphere& S = sph[i];
    const double r = m.r_of(static_cast<int>(i));
    zenith_rule(m.R, r, nz, S.mu, S.w, S.n_ground);
    S.Pr = Pr_all.data() + i * nout * nq;
    S.Pm = Pm_all.data() + i * nout * nq;
    for (int j = 0; j < m.nmu; ++j) {
      double mu, d;
      m.mu_of(r, j, mu, d);
      const double sn = std::sqrt(std::max(0.0, 1 - mu * mu));
      for (int a = 0; a < m.na; ++a) {
        const double phi = m.phi_of(a), cp = std::cos(phi), sp = std::sin(phi);
        const std::size_t row = (static_cast<std::size_t>(j) * m.na + a) * nq;
        double nr_ = 0, nm_ = 0;
        for (int z = 0; z < nz; ++z) {
          const double snq = std::sqrt(std::max(0.0, 1 - S.mu[z] * S.mu[z]));
          for (int b = 0; b < nphi; ++b) {
            const double c = sg::orders_sphere_cos(mu, sn, cp, sp, S.mu[z], snq, cphi[b], sphi[b]);
            const double wq = S.w[z] * 2.0 * kPi / nphi;
            const double vr = wq * pr.value(c), vm = wq * pm.value(c);
            S.Pr[row + z * nphi + b] = static_cast<float>(vr);
            S.Pm[row + z * nphi + b] = static_cast<float>(vm);
            nr_ += vr;
            nm_ += vm;
          }
        }
        for (std::size_t q = 0; q < nq; ++q) {
          S.Pr[row + q] = static_cast<float>(S.Pr[row + q] / nr_);
          S.Pm[row + q] = static_cast<float>(S.Pm[row + q] / nm_);
        }
      }
    }
    S.t_ground.assign(static_cast<std::size_t>(S.n_ground) * nw, 0.0f);
    S.d_ground.assign(static_cast<std::size_t>(S.n_ground), 0.0);
    for (int z = 0; z < S.n_ground; ++z) {
      const LutColumn c = lut.view(r, S.mu[z]);
      S.d_ground[z] = sg::distance_to_ground(r, S.mu[z], m.R);
      for (std::size_t q = 0; q < nw; ++q) S.t_ground[z * nw + q] = static_cast<float>(tr(c.column, q));
    }
  });

  // Ground irradiance of the order in `tab` (its S), at every tabulated sun direction:
  // the upper hemisphere at the ground, Gauss-Legendre in mu on [0, 1] gathered toward
  // the horizon, uniform azimuths.
  auto ground_irradiance_of = [&](const std::vector<float>& tab) {
    std::vector<double> e(static_cast<std::size_t>(m.ns) * nw, 0.0);
    const auto gl = sh::gauss_legendre(nz);
    std::vector<float> L(nw);
    for (int k = 0; k < m.ns; ++k) {
      const double mu_s = m.mus_of(k);
      for (std::size_t z = 0; z < gl.nodes.size(); ++z) {
        const double v = 0.5 * (gl.nodes[z] + 1.0), mu = v * v, wmu = v * gl.weights[z];
        const Impl::RayCoord c = m.ray_coord(m.R, mu, false);
        for (int b = 0; b < nphi; ++b) {
          const double nu = sg::orders_nu(mu, mu_s, cphi[b]);
          m.interp(tab.data(), c, mu, mu_s, nu, L.data());
          for (std::size_t q = 0; q < nw; ++q) e[k * nw + q] += wmu * (2.0 * kPi / nphi) * mu * L[q];
        }
      }
    }
    return e;
  };
  std::vector<double> e_sum(static_cast<std::size_t>(m.ns) * nw, 0.0);
  std::vector<float> e_prev_log;  // E_{n-2} (log) for n > 2
  if (passes) {  // the set-up and S_1 to the device that runs the passes
    OrdersSetup st;
    st.nr = m.nr, st.nmu = m.nmu, st.half = m.half, st.ns = m.ns, st.na = m.na, st.nn = nn;
    st.nz = nz, st.nphi = nphi, st.n_ground = sph[0].n_ground, st.nw = nw;
    st.R = m.R, st.T = m.T, st.H = m.H, st.sun_m = Impl::sun_m(), st.albedo = albedo;
    st.sr = sr, st.sm = sm;
    for (int i = 0; i < m.nr; ++i) {
      const glm::dvec3 rho = atm.density(std::max(m.r_of(i) - m.R, 0.0));
      st.rho_r.push_back(rho[kRayleigh]);
      st.rho_m.push_back(rho[kMie]);
      Sphere& S = sph[static_cast<std::size_t>(i)];
      st.sphere_mu.insert(st.sphere_mu.end(), S.mu.begin(), S.mu.end());
      st.sphere_w.insert(st.sphere_w.end(), S.w.begin(), S.w.end());
      st.d_ground.insert(st.d_ground.end(), S.d_ground.begin(), S.d_ground.end());
      st.t_ground.insert(st.t_ground.end(), S.t_ground.begin(), S.t_ground.end());
      for (int k = 0; k < m.ns; ++k) {  // order 2's direct sun on the ground (as the J pass)
        const double r = m.r_of(i), mu_s = m.mus_of(k), ss = std::sqrt(std::max(0.0, 1 - mu_s * mu_s));
        for (int z = 0; z < S.n_ground; ++z) {
          const double snq = std::sqrt(std::max(0.0, 1 - S.mu[z] * S.mu[z]));
          for (int b = 0; b < nphi; ++b) {
            const double nu = sg::orders_nu_of_sines(S.mu[z], mu_s, snq, ss, cphi[b]);
            const double mus_g = sg::orders_ground_sun_cosine(r, mu_s, S.d_ground[z], nu, m.R);
            const LutColumn cs = mus_g > 0 ? lut.sun(m.R, std::min(mus_g, 1.0)) : LutColumn{};
            for (std::size_t q = 0; q < nw; ++q)
              st.sun_ground.push_back(mus_g > 0 && !cs.hits_ground ? static_cast<float>(tr(cs.column, q)) : 0.0f);
          }
        }
      }
    }
    for (const Node* nd = nodes.data(); nd != nodes.data() + nodes.size(); ++nd) {
      st.node.insert(st.node.end(), {nd->t, nd->r, nd->mu, nd->w});
      st.node_coord.push_back(nd->c);
      st.node_dens.insert(st.node_dens.end(), {nd->rho_r, nd->rho_m, nd->col[0], nd->col[1], nd->col[2]});
    }
    st.atmosphere = &atm;
    st.lut = &lut;
    st.ray_t = std::move(ray_t);  // the CPU's S pass does not run
    st.Pr = std::move(Pr_all);    // nor its J pass
    st.Pm = std::move(Pm_all);
    st.ray_mu = ray_mu;
    st.cphi = cphi;
    st.sphi = sphi;
    const auto gl = sh::gauss_legendre(nz);  // as ground_irradiance_of
    for (std::size_t z = 0; z < gl.nodes.size(); ++z) {
      const double v = 0.5 * (gl.nodes[z] + 1.0);
      st.up_mu.push_back(v * v);
      st.up_w.push_back(v * gl.weights[z]);
    }
    st.single = single_on_device ? nullptr : &prev;
    passes->begin(st);
    std::vector<float>().swap(prev);  // uploaded
  }

  for (int order = 2; order <= orders_; ++order) {
    // ---- J_order from I_{order-1} = S_{order-1} + the ground's light of order - 1.
    t0 = Clock::now();
    if (passes)
      passes->density(order, e_prev_log);
    else
      parallel_for(static_cast<std::size_t>(m.nr) * m.ns, threads, [&](std::size_t ik) {
      const int i = static_cast<int>(ik / m.ns), k = static_cast<int>(ik % m.ns);
      const Sphere& S = sph[static_cast<std::size_t>(i)];
      const double r = m.r_of(i), mu_s = m.mus_of(k), ss = std::sqrt(std::max(0.0, 1 - mu_s * mu_s));
      std::vector<float> I(nq * nw), g(nw);
      for (int z = 0; z < nz; ++z) {
        const bool ground = z < S.n_ground;
        const Impl::RayCoord c = m.ray_coord(r, S.mu[z], ground);
        const double snq = std::sqrt(std::max(0.0, 1 - S.mu[z] * S.mu[z]));
        for (int b = 0; b < nphi; ++b) {
          const double nu = sg::orders_nu_of_sines(S.mu[z], mu_s, snq, ss, cphi[b]);
          float* Iq = &I[(static_cast<std::size_t>(z) * nphi + b) * nw];
          m.interp(prev.data(), c, S.mu[z], mu_s, nu, Iq);
          if (!ground || !(albedo > 0)) continue;
          const double mus_g = sg::orders_ground_sun_cosine(r, mu_s, S.d_ground[z], nu, m.R);
          if (order == 2) {  // the direct sun on the ground
            if (!(mus_g > 0)) continue;
            const LutColumn cs = lut.sun(m.R, std::min(mus_g, 1.0));
            if (cs.hits_ground) continue;
            for (std::size_t q = 0; q < nw; ++q)
              Iq[q] += static_cast<float>(S.t_ground[z * nw + q] * albedo / kPi * mus_g * tr(cs.column, q));
          } else {
            m.interp_ground(e_prev_log, mus_g, g.data());
            for (std::size_t q = 0; q < nw; ++q)
              Iq[q] += static_cast<float>(S.t_ground[z * nw + q] * albedo / kPi) * g[q];
          }
        }
      }
      const glm::dvec3 rho = atm.density(std::max(r - m.R, 0.0));
      std::vector<float> jr(nw), jm(nw);
      for (std::size_t out = 0; out < nout; ++out) {
        phase_products(nw, nq, &S.Pr[out * nq], &S.Pm[out * nq], I.data(), jr.data(), jm.data());
        const int j = static_cast<int>(out / m.na), a = static_cast<int>(out % m.na);
        float* dst = &dens[m.index(i, j, k, a)];
        for (std::size_t w = 0; w < nw; ++w)
          dst[w] = to_log(sr[w] * rho[kRayleigh] * jr[w] + sm[w] * rho[kMie] * jm[w]);
      }
    });
    pass_s_.push_back(since(t0));

    // ---- E_{order-1} from S_{order-1} (for the next order's ground, and the sky's).
    const std::vector<double> e = passes ? passes->ground_irradiance() : ground_irradiance_of(prev);
    e_prev_log.assign(e.size(), 0.0f);
    for (std::size_t q = 0; q < e.size(); ++q) {
      e_prev_log[q] = to_log(e[q]);
      e_sum[q] += e[q];  // E_1..E_{N-1} over the orders
    }

    // ---- S_order = int T J_order along the texels' rays.
    t0 = Clock::now();
    if (passes)
      passes->radiance();
    else
      parallel_for(nrays, threads, [&](std::size_t ij) {
      const int i = static_cast<int>(ij / m.nmu), j = static_cast<int>(ij % m.nmu);
      const double r = m.r_of(i), mu = ray_mu[ij];
      const Node* nd = &nodes[ij * nn];
      const float* T = &ray_t[ij * nn * nw];
      const std::size_t nka = static_cast<std::size_t>(m.ns) * m.na;
      // Node by node (its radius and view corners stay in cache), every sun texel.
      std::vector<double> acc(nka * nw, 0.0), nu(nka), mus(nka);
      for (int k = 0; k < m.ns; ++k)
        for (int a = 0; a < m.na; ++a) {
          const std::size_t ka = static_cast<std::size_t>(k) * m.na + a;
          mus[ka] = m.mus_of(k);
          nu[ka] = Impl::nu_of(mu, mus[ka], m.phi_of(a));
        }
      Lookup L;
      for (int n = 0; n < nn; ++n) {
        if (!(nd[n].w > 0)) continue;
        const float* Tn = T + static_cast<std::size_t>(n) * nw;
        for (std::size_t ka = 0; ka < nka; ++ka) {
          const double mus_y = sg::orders_sun_cosine_at(r, mus[ka], nd[n].t, nu[ka], nd[n].r);
          const Impl::SunCoord sc = m.sun_coord(nd[n].mu, mus_y, nu[ka]);
          m.lookup(dens.data(), nd[n].c, sc, L);
          blend_log_corners_acc(nw, L, nd[n].w, Tn, &acc[ka * nw]);
        }
      }
      for (int k = 0; k < m.ns; ++k)
        for (int a = 0; a < m.na; ++a) {
          const double* s = &acc[(static_cast<std::size_t>(k) * m.na + a) * nw];
          float* dst = &next[m.index(i, j, k, a)];
          float* sl = &sum_lin[m.index(i, j, k, a)];
          for (std::size_t q = 0; q < nw; ++q) {
            dst[q] = to_log(s[q]);
            sl[q] += static_cast<float>(s[q]);
          }
        }
    });
    pass_s_.push_back(since(t0));
    std::swap(prev, next);
  }
  std::vector<float>().swap(prev);
  std::vector<float>().swap(next);
  std::vector<float>().swap(dens);
  if (passes) device_ = passes->keep_sum();
  if (!device_ || passes->read_back_sum()) {
    if (passes) passes->sum(sum_lin);
    parallel_for_ranges(sum_lin.size(), std::size_t(1) << 16, threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t q = b; q < e; ++q) sum_lin[q] = to_log(sum_lin[q]);  // in place: the table is its log
    });
    m.sum = std::move(sum_lin);
    m.set_full_part();
  }
  if (passes) passes->end();
  m.esum.resize(e_sum.size());
  for (std::size_t q = 0; q < e_sum.size(); ++q) m.esum[q] = to_log(e_sum[q]);
  build_s_ = since(t_start);
}

void ScatteringOrders::radiance(double r, double mu, bool ground, double mu_s, double nu, double* out) const {
  const Impl& m = *impl_;
  if (m.sum.empty()) throw InputError("orders radiance: the table is kept on the device that built it only");
  const Impl::RayCoord c = m.ray_coord(std::clamp(r, m.R, m.T), mu, ground);
  const Impl::SunCoord sc = m.sun_coord(mu, mu_s, nu);
  if (!m.in_part(c, sc))
    throw InputError("orders radiance: the lookup at r = " + std::to_string(r) + " m, mu_s = " + std::to_string(mu_s) +
                     " is outside the part of the table read back from the device");
  Lookup L;
  m.lookup(m.sum.data(), c, sc, L, m.part_i, m.part_k, m.part_nk);
  float v[256];
  blend_log_corners(m.nw, L, v);
  for (std::size_t q = 0; q < m.nw; ++q) out[q] = v[q];
}

std::size_t ScatteringOrders::read_back_at(double r, double mu_s) const {
  Impl& m = *impl_;
  if (!device_ || m.sum_is_full()) return 0;
  const Impl::RayCoord c = m.ray_coord(std::clamp(r, m.R, m.T), 1.0, false);
  const int i_lo = std::max(c.i0 - 1, 0), i_hi = std::min(c.i0 + 2, m.nr - 1);
  int k_lo = 0, k_hi = m.ns - 1;
  if (r < m.T) {  // inside: every lookup at this radius has this sun cosine
    const Impl::SunCoord sc = m.sun_coord(0.0, std::clamp(mu_s, -1.0, 1.0), 0.0);
    k_lo = std::max(sc.k0 - 1, 0);
    k_hi = std::min(sc.k0 + 2, m.ns - 1);
  }
  const int ni = i_hi - i_lo + 1, nk = k_hi - k_lo + 1;
  const std::size_t run = static_cast<std::size_t>(nk) * m.na * m.nw;  // sun and azimuth rows of one (i, j)
  std::vector<float> part(static_cast<std::size_t>(ni) * m.nmu * run);
  for (int i = i_lo; i <= i_hi; ++i)
    for (int j = 0; j < m.nmu; ++j)
      device_->read(m.index(i, j, k_lo, 0), run, &part[(static_cast<std::size_t>(i - i_lo) * m.nmu + j) * run]);
  m.sum = std::move(part);
  m.part_i = i_lo, m.part_ni = ni, m.part_k = k_lo, m.part_nk = nk;
  return m.sum.size() * sizeof(float);
}

std::size_t ScatteringOrders::read_back_all() const {
  Impl& m = *impl_;
  if (!device_ || m.sum_is_full()) return 0;
  std::vector<float> all(m.texels() * m.nw);
  device_->read(0, all.size(), all.data());
  m.sum = std::move(all);
  m.set_full_part();
  return m.sum.size() * sizeof(float);
}

std::size_t ScatteringOrders::bytes_on_cpu() const { return impl_->sum.size() * sizeof(float); }

void ScatteringOrders::ground_irradiance(double mu_s, double* out) const {
  const Impl& m = *impl_;
  float v[256];
  m.interp_ground(m.esum, mu_s, v);
  for (std::size_t q = 0; q < m.nw; ++q) out[q] = v[q];
}

}  // namespace atmosh::atmo
