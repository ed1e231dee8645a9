// atmosh/atmo/shared/orders.glsl.hpp — the per-texel math of the successive-orders
// tables (ScatteringOrders, scattering_orders.hpp), written once for the CPU build
// (libatmo/src/scattering_orders.cpp; real = double) and the GPU build
// (gpu/shaders/orders_*.comp, which paste this block once, in double, after
// shared/geometry.glsl.hpp in float and in double). Same common subset and
// conventions as geometry.glsl.hpp; no exp, log, pow or trigonometry on `real`
// (GLSL has none in double): the callers pass cosines and take their logarithms.
//
// Tables [radius i][view j][sun k][azimuth a][wavelength], log of the value:
//   radius   rho = sqrt(r^2 - R^2) = H i / (nr - 1), H = sqrt(T^2 - R^2);
//   view     j < nh: rays to the ground, uniform in their length between r - R and
//            rho; j >= nh: rays to the top, between T - r and rho + H, gathered toward
//            the shortest (orders_top_fraction);
//   sun      u = k / (ns - 1) -> mu_s (orders_mus_of_u), m = sin(36 deg) below the horizon;
//   azimuth  cos(phi) = 1 - 2 a / (na - 1).
// Lookups: multilinear in (rho, view, sun, 1 - cos phi) of the logarithms, with the
// curvature correction (orders_curvature). Accuracy: exact up to rounding.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "atmosh/atmo/shared/geometry.glsl.hpp"

namespace atmosh::atmo::shared {

using real = double;
#define ATMOSH_FN inline

// ATMOSH_GLSL_BEGIN

// Interpolation coordinates of a lookup: radius and view (cells i0, j0, fractions fr,
// fm), and sun and azimuth (k0, a0, fs, fa). 0 <= fractions <= 1.
struct OrdersRayCoord {
  int i0;
  int j0;
  float fr;
  float fm;
};
struct OrdersSunCoord {
  int k0;
  int a0;
  float fs;
  float fa;
};

// Values below kOrdersFloor are stored as it (its logarithm kOrdersLogFloor) and read
// as 0 (orders_log_visible).
const float kOrdersFloor = 1e-30f;
const float kOrdersLogFloor = -69.07755279f;
ATMOSH_FN bool orders_log_visible(float l) { return l > kOrdersLogFloor + 0.7f; }

// Log interpolation and its curvature correction. Multilinear interpolation of the
// logarithms l is exact where the light falls exponentially along an axis (the Earth's
// shadow) and low where it varies smoothly: linear interpolation of a function g
// between samples at 0 and 1 exceeds g(f) by f (1 - f) g'' / 2 to second order.
// The lookup therefore subtracts, for each axis a with cell [k, k + 1] and fraction f,
//   f (1 - f) / 2 ((1 - f) D(k) + f D(k + 1)),   D(p) = l[p - 1] + l[p + 1] - 2 l[p],
// the second differences (in sample units) at the cell's two samples, on the line along
// the axis through the lookup's nearest sample on the other three axes; a sample at an
// end of its axis (or of its half of the view axis) takes its neighbour's D. Quadratic
// in the logarithm along each axis, so to second order right both for smooth light (as
// linear interpolation of the values) and for exponential falls (where the geometric
// mean of the corners is exact), and continuous along the axis (a single D at the
// nearest sample jumps by up to ~1 % where the cell's middle is crossed in deep
// twilight). A D is dropped (0) where one of its samples is at the visibility floor,
// and an axis of fewer than 3 samples has no correction. (It replaces a correction by
// the corners' variance, c(V) = (V / 2) / (1 + (V / 0.1)^2), which restored the
// arithmetic mean also where the light falls exponentially: order 2 alone was 2.6 %
// high on the horizon away from the sun at sun -3 deg, and 3.9 % at -6 deg with 2-4x
// finer tables, against an independent quadrature; docs/sky.md, "Second order against a
// quadrature".)
struct OrdersCurvature {
  glm::ivec4 centre;  // the nearest sample on each axis: radius, view, sun, azimuth
  glm::ivec4 at0;     // per axis: the samples p0, p1 whose D are blended (the cell's
  glm::ivec4 at1;     // two, moved inside the axis)
  glm::vec4 g0;       // per axis: the weights of D(p0), D(p1); 0: no correction
  glm::vec4 g1;
};
// Sample p moved inside the samples lo .. lo + n - 1 of its axis (n >= 3).
ATMOSH_FN int orders_curvature_at(int p, int lo, int n) {
  return glm::clamp(p, lo + 1, lo + n - 2);
}
ATMOSH_FN float orders_curvature_weight(float f, int n) {
  return n < 3 ? 0.0f : 0.5f * f * (1.0f - f);
}
ATMOSH_FN OrdersCurvature orders_curvature(OrdersRayCoord c, OrdersSunCoord s, int nr, int nh, int ns, int na) {
  OrdersCurvature k;
  int lo = c.j0 < nh ? 0 : nh;  // the view axis's half
  k.centre = glm::ivec4(c.fr < 0.5f ? c.i0 : c.i0 + 1, c.fm < 0.5f ? c.j0 : c.j0 + 1, s.fs < 0.5f ? s.k0 : s.k0 + 1,
                        s.fa < 0.5f ? s.a0 : s.a0 + 1);
  k.at0 = glm::ivec4(orders_curvature_at(c.i0, 0, nr), orders_curvature_at(c.j0, lo, nh),
                     orders_curvature_at(s.k0, 0, ns), orders_curvature_at(s.a0, 0, na));
  k.at1 = glm::ivec4(orders_curvature_at(c.i0 + 1, 0, nr), orders_curvature_at(c.j0 + 1, lo, nh),
                     orders_curvature_at(s.k0 + 1, 0, ns), orders_curvature_at(s.a0 + 1, 0, na));
  glm::vec4 f = glm::vec4(c.fr, c.fm, s.fs, s.fa);
  glm::vec4 g = glm::vec4(orders_curvature_weight(c.fr, nr), orders_curvature_weight(c.fm, nh),
                          orders_curvature_weight(s.fs, ns), orders_curvature_weight(s.fa, na));
  k.g0 = g * (glm::vec4(1.0f) - f);
  k.g1 = g * f;
  return k;
}
// One term g D of the samples lm, lc, lp around p (0 where one is at the floor).
ATMOSH_FN float orders_curvature_term(float g, float lm, float lc, float lp) {
  bool seen = orders_log_visible(lm) && orders_log_visible(lc) && orders_log_visible(lp);
  return seen ? g * (lm + lp - 2.0f * lc) : 0.0f;
}
// The ground table (one axis, ns samples): the blend of the samples a = l[k0], b = l[k0 + 1]
// at fraction fs, minus its curvature terms t (orders_curvature_term at
// orders_curvature_at(k0, 0, ns) and (k0 + 1, 0, ns), weights
// orders_curvature_weight(fs, ns) (1 - fs) and fs).
ATMOSH_FN float orders_ground_log(float a, float b, float fs) {
  return (1.0f - fs) * a + fs * b;
}

// Radius [m] of radius sample i of nr.
ATMOSH_FN real orders_radius(int i, int nr, real R, real H) {
  real rho = H * real(i) / real(nr - 1);
  return sqrt(rho * rho + R * R);
}

// Rays to the top: sample coordinate x in [0, 1] -> fraction f of the distance range
// [T - r, rho + H] of the ray's length, f = x (B + (1 - B) x), B = 0.3: the samples are
// 1 / B = 3.3x denser than uniform at the shortest rays (toward the zenith) and
// 1 / (2 - B) = 0.6x as dense at the longest (the horizon). Uniform in the length
// (B = 1, Bruneton 2017's mapping) leaves one interval of 48 view samples between the
// zenith and ~43 deg up at the ground, where the deep-twilight sky away from the sun
// bends in the view angle (measured: sun -9 deg, 60 deg up away from the sun -6.2 %
// against the Monte-Carlo reference with B = 1, -3.1 % with B = 0.3; docs/sky.md,
// "Multiple scattering"). orders_top_coordinate is the inverse (the root of the
// quadratic written without cancellation).
ATMOSH_FN real orders_top_fraction(real x) {
  real B = real(3) / real(10);
  return x * (B + (real(1) - B) * x);
}
ATMOSH_FN real orders_top_coordinate(real f) {
  real B = real(3) / real(10);
  return real(2) * f / (B + sqrt(B * B + real(4) * (real(1) - B) * f));
}

// View sample j (0 .. 2 nh - 1) at radius r: the ray's zenith cosine and length [m].
struct OrdersView {
  real mu;
  real d;
};
ATMOSH_FN OrdersView orders_view(real r, int j, int nh, real R, real T, real H) {
  OrdersView v;
  real rho = sqrt(glm::max(r * r - R * R, real(0)));
  if (j < nh) {
    real x = real(j) / real(nh - 1), dmin = r - R, dmax = rho;
    v.d = dmin + x * (dmax - dmin);
    v.mu = v.d == real(0) ? real(-1) : glm::clamp(-(rho * rho + v.d * v.d) / (real(2) * r * v.d), real(-1), real(1));
  } else {
    real x = real(j - nh) / real(nh - 1), dmin = T - r, dmax = rho + H;
    v.d = dmin + orders_top_fraction(x) * (dmax - dmin);
    v.mu = v.d == real(0) ? real(1) : glm::clamp((H * H - rho * rho - v.d * v.d) / (real(2) * r * v.d), real(-1), real(1));
  }
  return v;
}

// Sun coordinate u in [0, 1] <-> mu_s. m = -sin(lowest tabulated elevation) (the caller's
// constant); u0 = m / (1 + m) at the horizon; on each side x in [-1, 1] and
// mu_s = s x (A + (1 - A)|x|) (s = m below, 1 above, A = 0.3): ~6x denser near the
// horizon than uniform in mu_s. Below -m: clamped.
ATMOSH_FN real orders_mus_of_u(real u, real m) {
  real A = real(3) / real(10), u0 = m / (real(1) + m);
  if (u < u0) {
    real x = (u0 - u) / u0;
    return -m * x * (A + (real(1) - A) * x);
  }
  real x = (u - u0) / (real(1) - u0);
  return x * (A + (real(1) - A) * x);
}
ATMOSH_FN real orders_u_of_mus(real mu_s, real m) {
  real A = real(3) / real(10), u0 = m / (real(1) + m);
  real v = mu_s < real(0) ? glm::min(-mu_s / m, real(1)) : glm::min(mu_s, real(1));
  real x = (-A + sqrt(A * A + real(4) * (real(1) - A) * v)) / (real(2) * (real(1) - A));
  return mu_s < real(0) ? u0 * (real(1) - x) : u0 + (real(1) - u0) * x;
}

// cos(phi) of azimuth sample a of na (uniform in cos phi).
ATMOSH_FN real orders_azimuth_cos(int a, int na) {
  return glm::clamp(real(1) - real(2) * real(a) / real(na - 1), real(-1), real(1));
}
// cos(view, sun) from the two zenith cosines and the cosine of the azimuth between them.
ATMOSH_FN real orders_nu(real mu, real mu_s, real cphi) {
  return glm::clamp(mu * mu_s + sqrt(glm::max(real(0), (real(1) - mu * mu) * (real(1) - mu_s * mu_s))) * cphi,
                    real(-1), real(1));
}
// The sun's zenith cosine at distance t along the ray from radius r (view mu, sun mu_s,
// cos(view, sun) nu), where the radius is rt: (r mu_s + t nu) / rt. At the ground
// end (t = d, rt = R) it is the sun's cosine on the ground.
ATMOSH_FN real orders_sun_cosine_at(real r, real mu_s, real t, real nu, real rt) {
  return glm::clamp((r * mu_s + t * nu) / rt, real(-1), real(1));
}

// cos(view, sun) from the zenith cosines and their sines (sn, ss) and cos(azimuth).
ATMOSH_FN real orders_nu_of_sines(real mu, real mu_s, real sn, real ss, real cphi) {
  return glm::clamp(mu * mu_s + sn * ss * cphi, real(-1), real(1));
}
// Weight of the (radius, view, sun) corner (di, dj, dk) of a lookup (the azimuth's
// fraction is applied separately).
ATMOSH_FN float orders_corner_weight(float fr, float fm, float fs, int di, int dj, int dk) {
  return (di != 0 ? fr : 1.0f - fr) * (dj != 0 ? fm : 1.0f - fm) * (dk != 0 ? fs : 1.0f - fs);
}

// The sun's zenith cosine on the ground where a ray from radius r (sun mu_s, cos(view,
// sun) nu) of length d ends (not clamped: the caller tests its sign).
ATMOSH_FN real orders_ground_sun_cosine(real r, real mu_s, real d, real nu, real R) {
  return (r * mu_s + d * nu) / R;
}

// Interpolation coordinates of the radius and the view (independent of the sun).
ATMOSH_FN OrdersRayCoord orders_ray_coord(real r, real mu, bool ground, real R, real T, real H, int nr, int nh) {
  OrdersRayCoord c;
  real rho = sqrt(glm::max(r * r - R * R, real(0)));
  real ur = glm::clamp(rho / H, real(0), real(1)) * real(nr - 1);
  c.i0 = glm::min(int(ur), nr - 2);
  c.fr = float(ur - real(c.i0));
  real d, dmin, dmax;
  if (ground) {
    d = glm::max(distance_to_ground(r, mu, R), real(0));
    dmin = r - R;
    dmax = rho;
  } else {
    d = glm::max(distance_to_top(r, mu, T), real(0));
    dmin = T - r;
    dmax = rho + H;
  }
  real x = dmax > dmin ? glm::clamp((d - dmin) / (dmax - dmin), real(0), real(1)) : real(0);
  if (!ground) x = orders_top_coordinate(x);
  real um = x * real(nh - 1);
  c.j0 = glm::min(int(um), nh - 2);
  c.fm = float(um - real(c.j0));
  if (!ground) c.j0 += nh;
  return c;
}
// Sun and azimuth coordinates of a lookup (view mu, sun mu_s, cos(view, sun) nu).
ATMOSH_FN OrdersSunCoord orders_sun_coord(real mu, real mu_s, real nu, int ns, int na, real m) {
  OrdersSunCoord s;
  real us = orders_u_of_mus(mu_s, m) * real(ns - 1);
  s.k0 = glm::min(int(us), ns - 2);
  s.fs = float(us - real(s.k0));
  real den = sqrt(glm::max(real(0), (real(1) - mu * mu) * (real(1) - mu_s * mu_s)));
  real cphi = den > real(1e-9) ? glm::clamp((nu - mu * mu_s) / den, real(-1), real(1)) : real(1);
  real ua = real(0.5) * (real(1) - cphi) * real(na - 1);  // t = (1 - cos phi) / 2
  s.a0 = glm::min(int(ua), na - 2);
  s.fa = float(ua - real(s.a0));
  return s;
}
// The ground table's coordinate (k0, fs) at the ground's sun cosine mu_s.
ATMOSH_FN OrdersSunCoord orders_ground_coord(real mu_s, int ns, real m) {
  OrdersSunCoord s;
  real us = orders_u_of_mus(mu_s, m) * real(ns - 1);
  s.k0 = glm::min(int(us), ns - 2);
  s.fs = float(us - real(s.k0));
  s.a0 = 0;
  s.fa = 0.0f;
  return s;
}

// Node k of K steps (k = 0..K) along a table ray of length d from radius r (zenith
// cosine mu): positions gathered toward the densest point (the tangent point of rays to
// the top that dip first: two pieces; the ground; else the start); returns its
// distance t [m], radius and zenith cosine there (the ground's radius at the end of a
// ground ray).
struct OrdersNode {
  real t;
  real r;
  real mu;
};
ATMOSH_FN real orders_pow15(real x) {
#ifdef ATMOSH_GLSL
  return x * sqrt(x);  // GLSL has no pow in double
#else
  return std::pow(x, 1.5);
#endif
}
ATMOSH_FN OrdersNode orders_node(real r, real mu, real d, bool ground, int K, int k, real R) {
  real st = -r * mu, u = real(k) / real(K), t;
  if (!ground && mu < real(0) && st > real(0) && st < d) {  // two pieces around the tangent point
    int k_t = K / 2;
    if (k <= k_t) {
      real v = real(k) / real(k_t);
      t = st * (real(1) - orders_pow15(real(1) - v));
    } else {
      real v = real(k - k_t) / real(K - k_t);
      t = st + (d - st) * v * sqrt(v);
    }
  } else if (ground) {
    t = d * (real(1) - orders_pow15(real(1) - u));
  } else {
    t = d * u * sqrt(u);
  }
  OrdersNode n;
  n.t = t;
  n.r = (ground && k == K) ? R : glm::max(radius_along(r, mu, t), R);
  n.mu = mu_along(r, mu, t, n.r);
  return n;
}

// cos of the angle between the view (zenith cosine mu, sine sn, azimuth cosine/sine cp,
// sp) and a direction of the scattering density's sphere rule (muq, snq, cb, sb).
ATMOSH_FN real orders_sphere_cos(real mu, real sn, real cp, real sp, real muq, real snq, real cb, real sb) {
  return glm::clamp(mu * muq + sn * snq * (cp * cb + sp * sb), real(-1), real(1));
}
// The GPU build's layout (gpu/src/orders.cpp, gpu/shaders/orders_*.comp): texel index
// of a table [i][j][k][a] (times nw for the first wavelength), binding points and the
// parameter block (std430: doubles first, then 4-byte scalars; C++ layout the same).
ATMOSH_FN int orders_texel(int i, int j, int k, int a, int nmu, int ns, int na) {
  return ((i * nmu + j) * ns + k) * na + a;
}
#define ATMOSH_ORDERS_BIND_TAB_IN 0     // float: the table a pass reads (log) [texel][wavelength]
#define ATMOSH_ORDERS_BIND_TAB_OUT 1    // float: the table a pass writes (log)
#define ATMOSH_ORDERS_BIND_SUM 2        // float: sum of S_2..S_N (linear)
#define ATMOSH_ORDERS_BIND_INCOMING 3   // float: I_{k-1} on the sphere rule [i][k][z nphi + b][wavelength]
#define ATMOSH_ORDERS_BIND_NODES 4      // double: texel rays' nodes [ray][n] (t, r, mu, w)
#define ATMOSH_ORDERS_BIND_COORDS 5     // OrdersRayCoord of each node [ray][n]
#define ATMOSH_ORDERS_BIND_RAY_T 6      // float: transmittance start -> node [ray][n][wavelength]
#define ATMOSH_ORDERS_BIND_GEOM 7       // double: the rules and coefficients (GpuOrdersParams::off_*)
#define ATMOSH_ORDERS_BIND_PR 8         // float: Rayleigh phase matrix [i][j na + a][z nphi + b]
#define ATMOSH_ORDERS_BIND_PM 9         // float: Mie phase matrix
#define ATMOSH_ORDERS_BIND_GROUND_T 10  // float: t_ground [i][z][wavelength], then sun_ground
#define ATMOSH_ORDERS_BIND_GROUND 11    // float: log E of the previous order [k][wavelength]
#define ATMOSH_ORDERS_BIND_E_OUT 12     // float: E of the current table [k][wavelength]
#define ATMOSH_ORDERS_BIND_PARAMS 13    // GpuOrdersParams
#define ATMOSH_ORDERS_MAX_WAVELENGTHS 64  // per-invocation arrays
struct GpuOrdersParams {
  double R, T, H, sun_m, albedo;
  int nr, nmu, nh, ns, na, nn, nz, nphi, ng, nw;
  int order, n_items;
  // Offsets into the double buffer (ATMOSH_ORDERS_BIND_GEOM): sphere_mu [i][nz] at 0.
  int off_sphere_w, off_d_ground, off_cphi, off_sphi, off_up_mu, off_up_w, off_ray_mu;
  int off_sr, off_sm, off_rho_r, off_rho_m;
  int off_sun_ground;  // into ATMOSH_ORDERS_BIND_GROUND_T
  int pad;
};

// ---- The sky's orders term (SkyIntegrator with method orders; gpu/shaders/sky.comp) ----
// The ground table's value at fraction fs between samples a, b (logarithms), with its
// curvature terms t (orders_ground_log): the corrected blend's exp, 0 below the floor
// (ScatteringOrders::Impl::interp_ground).
ATMOSH_FN float orders_ground_value(float a, float b, float fs, float t) {
  float l = orders_ground_log(a, b, fs);
  return orders_log_visible(l) ? glm::exp(l - t) : 0.0f;
}
// The sky pass's binding points of the orders tables (gpu/src/sky.cpp binds them).
#define ATMOSH_SKY_BIND_ORDERS 15         // float: log of sum S_2..S_N [texel][wavelength]
#define ATMOSH_SKY_BIND_ORDERS_GROUND 16  // float: log of sum E_1..E_{N-1} [sun sample][wavelength]
#define ATMOSH_SKY_BIND_ORDERS_PARAMS 17  // GpuOrdersParams of those tables (nr = 0: no orders term)
// ATMOSH_GLSL_END

}  // namespace atmosh::atmo::shared
