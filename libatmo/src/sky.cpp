#include "atmosh/atmo/sky.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <string>
#include <unordered_map>

#include "integrate.hpp"
#include "fast_exp.hpp"
#include "sky_impl.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/atmo/shared/ms_approx.glsl.hpp"
#include "atmosh/atmo/shared/scatter.glsl.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/dispatch.hpp"
#include "atmosh/error.hpp"
#include "atmosh/format.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::atmo {

namespace sg = shared;

namespace {

constexpr double kPi = 3.14159265358979323846;

using Ray = detail::SkyRay;

glm::dvec3 unit(const glm::dvec3& v, const char* what) {
  const double n = glm::length(v);
  if (!std::isfinite(n) || std::fabs(n - 1.0) > 1e-6)
    throw InputError(std::string(what) + " direction (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
                     std::to_string(v.z) + ") is not a finite unit vector");
  return v / n;
}

Ray make_ray(const Atmosphere& atm, double altitude, const glm::dvec3& view, const glm::dvec3& sun) {
  if (!std::isfinite(altitude) || altitude < -1e-9 * atm.ground_radius())
    throw InputError("observer altitude " + std::to_string(altitude) + " m is below the ground or not finite");
  const glm::dvec3 v = unit(view, "view"), l = unit(sun, "sun");
  // The shared set-up (shared/view_ray.glsl.hpp, the GPU's too).
  return sg::sky_view_ray_toward(atm.ground_radius() + std::max(altitude, 0.0), v, l, atm.ground_radius(),
                                 atm.top_radius());
}

std::vector<PhaseFunction> make_phases(const Atmosphere& atm) {
  std::vector<PhaseFunction> p;
  const auto& s = atm.spec();
  p.emplace_back(s.rayleigh ? s.rayleigh->phase : PhaseSpec::of(PhaseSpec::Model::Rayleigh), "rayleigh.phase");
  p.emplace_back(s.mie ? s.mie->phase : PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0), "mie.phase");
  return p;
}

void check_solar(const Atmosphere& atm, const SolarSpectrum& solar) {
  if (solar.size() != atm.wavelengths_nm().size())
    throw InputError("solar spectrum has " + std::to_string(solar.size()) + " values for " +
                     std::to_string(atm.wavelengths_nm().size()) + " wavelengths");
  for (double e : solar)
    if (!std::isfinite(e) || e < 0) throw InputError("solar irradiance " + std::to_string(e) + " is not finite and >= 0");
}


// Distances in (0, s_end) where the ray crosses the sphere of radius k.
template <class Out>
void crossings(const Ray& ray, double k, Out&& out) {
  const double disc = k * k - sg::tangent_radius_sq(ray.r, ray.mu);
  if (disc < 0) return;
  const double q = std::sqrt(disc), t = -ray.r * ray.mu;
  for (double s : {t - q, t + q})
    if (s > 0 && s < ray.s_end) out(s);
}

// Distances in (0, s_end) where the view ray crosses the edge of the Earth's shadow
// (shared formula: shared/lut.glsl.hpp, shadow_edge_distance).
template <class Out>
void shadow_crossings(const Ray& ray, double R, Out&& out) {
  for (int i = 0; i < 2; ++i) {
    const double s = sg::shadow_edge_distance(ray.r, ray.mu, ray.mu_s, ray.nu, R, i);
    if (s > 0 && s < ray.s_end) out(s);
  }
}

// The spectral loop (detail::accumulate_sky_nodes): sg::column_optical_depth and
// sg::scattering_term spelt out in float (the shared functions take `real`, double on
// the CPU), for a block of nodes so that the constants of exp_neg_f are loaded once.
[[gnu::always_inline]] inline void accumulate_nodes_body(std::size_t n, const float* __restrict ext,
                                                         const float* __restrict sca,
                                                         const detail::SkyNodeTerms* __restrict nodes,
                                                         std::size_t count, double* __restrict acc) {
  const float* __restrict er = ext;
  const float* __restrict em = ext + n;
  const float* __restrict eo = ext + 2 * n;
  const float* __restrict cr = sca;
  const float* __restrict cm = sca + n;
  for (std::size_t k = 0; k < count; ++k) {
    const float x0 = nodes[k].x[0], x1 = nodes[k].x[1], x2 = nodes[k].x[2], sr = nodes[k].sr, sm = nodes[k].sm;
    for (std::size_t i = 0; i < n; ++i)
      acc[i] += static_cast<double>(exp_neg_f(er[i] * x0 + em[i] * x1 + eo[i] * x2) * (cr[i] * sr + cm[i] * sm));
  }
}

// AVX2/FMA (8 wavelengths per vector) and baseline clones.
ATMOSH_DISPATCH void accumulate_nodes_avx2(std::size_t n, const float* ext, const float* sca,
                                           const detail::SkyNodeTerms* nodes, std::size_t count, double* acc) {
  accumulate_nodes_body(n, ext, sca, nodes, count, acc);
}

#if ATMOSH_HAS_DISPATCH
// 16 wavelengths per vector (GCC's x86-64-v4 prefers 256-bit vectors unless told).
ATMOSH_TARGET_AVX512 __attribute__((target("prefer-vector-width=512"))) void accumulate_nodes_avx512(
    std::size_t n, const float* ext, const float* sca, const detail::SkyNodeTerms* nodes, std::size_t count,
    double* acc) {
  accumulate_nodes_body(n, ext, sca, nodes, count, acc);
}
#endif

// The light reflected by the ground: out[i] += e[i] ground_term(albedo, mu_s, T_i) with
// T_i = exp(-tau_i) of the column x (view + sun) at each wavelength i < n; er, em, eo
// the extinction coefficients [1/m]. Branch-free exp (vectorises).
void add_ground_terms(std::size_t n, const double* __restrict er, const double* __restrict em,
                                               const double* __restrict eo, const double* __restrict e, double albedo,
                                               double mu_s, glm::dvec3 x, double* __restrict out) {
  for (std::size_t i = 0; i < n; ++i)
    out[i] += e[i] * sg::ground_term(albedo, mu_s, exp_neg(sg::column_optical_depth(er[i], em[i], eo[i], x[0], x[1], x[2])));
}

}  // namespace

// ---------------------------------------------------------------- fast path

void detail::accumulate_sky_nodes(std::size_t n, const float* ext, const float* sca, const SkyNodeTerms* nodes,
                                  std::size_t count, double* acc) {
#if ATMOSH_HAS_DISPATCH
  if (cpu_has_avx512()) return accumulate_nodes_avx512(n, ext, sca, nodes, count, acc);
#endif
  accumulate_nodes_avx2(n, ext, sca, nodes, count, acc);
}

std::size_t detail::sky_spectral_lanes() {
#if ATMOSH_HAS_DISPATCH
  if (cpu_has_avx512()) return 16;
#endif
  return 8;
}

std::vector<double> sky_part_column_weights(int n) {
  if (n < 1 || n > sg::kMaxPartNodes)
    throw InputError("samples per segment " + std::to_string(n) + " is outside [1, 8]");
  const auto gl = sh::gauss_legendre(n);
  std::vector<double> t{-1.0};
  t.insert(t.end(), gl.nodes.begin(), gl.nodes.end());
  t.push_back(1.0);
  const int m = n + 2;
  // Lagrange basis polynomial j through the points t at u.
  auto basis = [&](int j, double u) {
    double p = 1.0;
    for (int i = 0; i < m; ++i)
      if (i != j) p *= (u - t[i]) / (t[j] - t[i]);
    return p;
  };
  // Integrals from -1 to the upper limit by an (n + 2)-point Gauss-Legendre rule:
  // exact for the degree n + 1 of the basis polynomials.
  const auto q = sh::gauss_legendre(m);
  std::vector<double> w(static_cast<std::size_t>((n + 1) * m), 0.0);
  for (int row = 0; row <= n; ++row) {
    const double hi = row < n ? gl.nodes[static_cast<std::size_t>(row)] : 1.0;
    const double half = 0.5 * (hi + 1.0), mid = 0.5 * (hi - 1.0);
    for (int j = 0; j < m; ++j) {
      double sum = 0.0;
      for (std::size_t k = 0; k < q.nodes.size(); ++k) sum += q.weights[k] * basis(j, mid + half * q.nodes[k]);
      w[static_cast<std::size_t>(row * m + j)] = half * sum;
    }
  }
  return w;
}

SkyIntegrator::SkyIntegrator(const Atmosphere& atmosphere, SolarSpectrum solar, SkyOptions options)
    : own_atm_(std::make_shared<const Atmosphere>(atmosphere)), atm_(*own_atm_), solar_(std::move(solar)),
      opt_(options) {
  check_solar(atm_, solar_);
  if (opt_.samples_per_segment < 1 || opt_.samples_per_segment > 8)
    throw InputError("samples per segment " + std::to_string(opt_.samples_per_segment) + " is outside [1, 8]");
  const int max_segments = std::min(opt_.lut.shells - 1, sg::kMaxCutSpheres);  // shared/view_ray.glsl.hpp
  if (opt_.segments < 1 || opt_.segments > max_segments)
    throw InputError("view-ray segments " + std::to_string(opt_.segments) + " is outside [1, " +
                     std::to_string(max_segments) + "] (at most shells - 1 and 64)");
  if (!(opt_.max_piece_optical_depth > 0))
    throw InputError("max piece optical depth " + format_double(opt_.max_piece_optical_depth) + " must be > 0");
  if (!(opt_.sun_distance_au > 0) || !std::isfinite(opt_.sun_distance_au))
    throw InputError("sun distance " + format_double(opt_.sun_distance_au) + " AU must be > 0");
  opt_.lut.view_tables = false;  // view depths are accumulated along the ray: the sun table only
  lut_ = std::make_unique<OpticalDepthLut>(atm_, opt_.lut);
  phase_ = make_phases(atm_);
  const auto gl = sh::gauss_legendre(opt_.samples_per_segment);
  gl_x_ = gl.nodes;
  gl_w_ = gl.weights;
  part_w_ = sky_part_column_weights(opt_.samples_per_segment);
  const auto& radii = lut_->shell_radii();
  const int S = static_cast<int>(radii.size());
  for (int i = 1; i < opt_.segments; ++i)  // ground and top are ray ends already
    cut_radii_.push_back(radii[static_cast<std::size_t>(std::lround(double(i) * (S - 1) / opt_.segments))]);
  const std::size_t n = atm_.wavelengths_nm().size();
  ext_.resize(3 * n);  // structure of arrays: [constituent][wavelength]
  sca_.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& k = atm_.coefficients(i);
    for (int c = 0; c < 3; ++c) {
      ext_[c * n + i] = atm_.has(c) ? k.extinction[c] : 0.0;
      ext_max_[c] = std::max(ext_max_[c], ext_[c * n + i]);
      sca_[c * n + i] = atm_.has(c) ? k.scattering[c] : 0.0;
    }
  }
  // Single precision, each constituent's row padded with zero coefficients (their
  // terms are exp(0) x 0 = 0).
  const std::size_t lanes = detail::sky_spectral_lanes();
  n_pad_ = (n + lanes - 1) / lanes * lanes;
  ext_f_.assign(3 * n_pad_, 0.0f);
  sca_f_.assign(2 * n_pad_, 0.0f);
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < n; ++i) {
      ext_f_[c * n_pad_ + i] = static_cast<float>(ext_[c * n + i]);
      if (c < 2) sca_f_[c * n_pad_ + i] = static_cast<float>(sca_[c * n + i]);
    }
  const double scale = 1.0 / (opt_.sun_distance_au * opt_.sun_distance_au);
  for (double e : solar_) solar_scaled_.push_back(e * scale);
  validate(opt_.scattering);
  if (opt_.scattering.method == ScatteringMethod::Approximate)
    ms_lut_ = std::make_unique<MultipleScatteringLut>(atm_, *lut_, opt_.scattering);
  if (opt_.scattering.method == ScatteringMethod::Orders && opt_.scattering.orders >= 2)
    orders_ = std::make_unique<ScatteringOrders>(atm_, opt_.scattering);
}

template <class Ray, class Visit>  // Ray = detail::SkyRay (the header names no private type)
glm::dvec3 SkyIntegrator::trace(const Ray& ray, const double* cuts, int nc, Visit&& visit) const {
  // The walk along the ray: shared/view_ray.glsl.hpp (the GPU's sky.comp runs it too).
  return sg::sky_trace(
      ray, cuts, nc, atm_.ground_radius(), ext_max_, opt_.max_piece_optical_depth, gl_x_.data(),
      gl_w_.data(), static_cast<int>(gl_x_.size()), part_w_.data(), [&](double h) { return atm_.density(h); },
      visit);
}

template <class Ray, class ForEachNode, class SunColumn>  // Ray = detail::SkyRay
void SkyIntegrator::shade(const Ray& ray, ForEachNode&& for_each_node, SunColumn&& sun, double* out) const {
  const std::size_t nw = solar_.size();
  const double p_ray = atm_.has(kRayleigh) ? phase_[0].value(ray.nu) : 0.0;
  const double p_mie = atm_.has(kMie) ? phase_[1].value(ray.nu) : 0.0;
  double acc_small[64];
  std::vector<double> acc_big;
  double* acc = acc_small;
  if (n_pad_ > 64) {
    acc_big.assign(n_pad_, 0.0);
    acc = acc_big.data();
  } else {
    std::fill(acc_small, acc_small + n_pad_, 0.0);
  }
  // The nodes' terms go to the spectral loop in blocks, in order.
  constexpr std::size_t kBlock = 32;
  detail::SkyNodeTerms block[kBlock];
  std::size_t nb = 0;
  // Multiple scattering (approximate): sigma_s(x) Psi_ms(r, mu_s) T(observer, x) at
  // every node, those in the Earth's shadow included (multiple_scattering.hpp).
  double ms_small[64], psi_small[64];
  std::vector<double> ms_big, psi_big;
  double *acc_ms = nullptr, *psi = nullptr;
  if (ms_lut_) {
    if (nw > 64) {
      ms_big.assign(nw, 0.0);
      psi_big.assign(nw, 0.0);
      acc_ms = ms_big.data();
      psi = psi_big.data();
    } else {
      std::fill(ms_small, ms_small + nw, 0.0);
      acc_ms = ms_small;
      psi = psi_small;
    }
  }
  const glm::dvec3 column_end = for_each_node([&](const detail::SkyViewNode& nd) {
    const double mus = sg::sky_node_sun_cosine(ray, nd);
    if (acc_ms) add_ms_node(nw, nd, mus, psi, acc_ms);
    const LutColumn to_sun = sun(nd, mus);
    if (to_sun.hits_ground) return;  // in the Earth's shadow
    block[nb] = sg::sky_node_terms(nd, to_sun.column, p_ray, p_mie);  // the GPU's sky_visit's too
    if (++nb == kBlock) {
      detail::accumulate_sky_nodes(n_pad_, ext_f_.data(), sca_f_.data(), block, nb, acc);
      nb = 0;
    }
  });
  if (nb > 0) detail::accumulate_sky_nodes(n_pad_, ext_f_.data(), sca_f_.data(), block, nb, acc);
  for (std::size_t i = 0; i < nw; ++i) out[i] = solar_scaled_[i] * acc[i];
  if (acc_ms)
    for (std::size_t i = 0; i < nw; ++i) out[i] += solar_scaled_[i] * acc_ms[i];

  const double albedo = atm_.spec().planet.ground_albedo;
  if (orders_) {
    // Orders 2..N: one lookup for the whole ray, and the ground at its end lit by the
    // sky (orders 1..N-1 of its irradiance; scattering_orders.hpp).
    double ms_small2[64];
    std::vector<double> ms_big2;
    double* v = ms_small2;
    if (nw > 64) {
      ms_big2.assign(nw, 0.0);
      v = ms_big2.data();
    }
    orders_->radiance(ray.r, ray.mu, ray.ground, ray.mu_s, ray.nu, v);
    for (std::size_t i = 0; i < nw; ++i) out[i] += solar_scaled_[i] * v[i];
    if (ray.ground && albedo > 0) {
      const double mus_g = sg::sky_ground_sun_cosine(ray);
      orders_->ground_irradiance(mus_g, v);
      const double* er = ext_.data();
      const double* em = er + nw;
      const double* eo = em + nw;
      for (std::size_t i = 0; i < nw; ++i)
        out[i] += solar_scaled_[i] * albedo / kPi * v[i] *
                  exp_neg(er[i] * column_end[0] + em[i] * column_end[1] + eo[i] * column_end[2]);
    }
  }
  if (ray.ground && albedo > 0) {
    const double mus_g = sg::sky_ground_sun_cosine(ray);
    if (sg::sky_ground_lit(ray, albedo, mus_g)) {  // sky.comp's test too
      const LutColumn to_sun = lut_->sun(atm_.ground_radius(), mus_g);
      if (!to_sun.hits_ground)
        add_ground_terms(nw, ext_.data(), ext_.data() + nw, ext_.data() + 2 * nw, solar_scaled_.data(), albedo, mus_g,
                         column_end + to_sun.column, out);
    }
  }
}

template <class ViewNode>  // detail::SkyViewNode
void SkyIntegrator::add_ms_node(std::size_t nw, const ViewNode& nd, double mu_s, double* psi, double* acc) const {
  ms_lut_->psi(nd.r, mu_s, psi);
  const double* er = ext_.data();
  const double* em = er + nw;
  const double* eo = em + nw;
  const double* cr = sca_.data();
  const double* cm = cr + nw;
  const double rr = nd.rho[kRayleigh] * nd.w, rm = nd.rho[kMie] * nd.w;
  const glm::dvec3 x = nd.column;
  for (std::size_t i = 0; i < nw; ++i)
    acc[i] += sg::ms_sky_term(exp_neg(sg::column_optical_depth(er[i], em[i], eo[i], x[0], x[1], x[2])), psi[i], cr[i],
                              cm[i], rr, rm);  // sky.comp's too
}

void SkyIntegrator::radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun, double* out) const {
  std::fill(out, out + solar_.size(), 0.0);
  const Ray ray = make_ray(atm_, altitude_m, view, sun);
  if (ray.empty || !(ray.s_end > 0)) return;
  // Pieces between shell crossings, the tangent point and the shadow edges, walked
  // (shared/view_ray.glsl.hpp: sky_walk, the same function as the GPU's); the nodes are
  // shaded as they are traced (nothing stored).
  shade(
      ray,
      [&](auto&& visit) {
        return sg::sky_walk(ray, cut_radii_.data(), static_cast<int>(cut_radii_.size()), atm_.ground_radius(), ext_max_,
                            opt_.max_piece_optical_depth, gl_x_.data(), gl_w_.data(), static_cast<int>(gl_x_.size()),
                            part_w_.data(), [&](double h) { return atm_.density(h); }, visit);
      },
      [&](const detail::SkyViewNode& nd, double mus) { return lut_->sun(nd.r, mus); }, out);
}

void SkyIntegrator::radiance_same_zenith(double altitude_m, const glm::dvec3* views, std::size_t count,
                                         const glm::dvec3& sun, double* out) const {
  const std::size_t nw = solar_.size();
  if (count == 0) return;
  for (std::size_t k = 1; k < count; ++k)
    if (!(std::fabs(views[k].z - views[0].z) <= 1e-12))
      throw InputError("views of one zenith angle: z = " + std::to_string(views[k].z) + " differs from " +
                       std::to_string(views[0].z));
  std::fill(out, out + count * nw, 0.0);
  // The view ray of the row (the first view's; the others differ in the azimuth only).
  const Ray ray0 = make_ray(atm_, altitude_m, views[0], sun);
  if (ray0.empty || !(ray0.s_end > 0)) {  // nothing to share
    for (std::size_t k = 0; k < count; ++k) radiance(altitude_m, views[k], sun, out + k * nw);
    return;
  }
  const double R = atm_.ground_radius();
  const sg::ViewRayCuts vc = sg::view_ray_sphere_cuts(ray0.r, ray0.mu, ray0.s_end, sg::tangent_radius_sq(ray0.r, ray0.mu),
                                                      cut_radii_.data(), static_cast<int>(cut_radii_.size()));
  // Which views share the row's nodes: not those whose ray crosses the edge of the
  // Earth's shadow (their cuts depend on the azimuth) or differs in kind.
  std::vector<Ray> rays(count);
  std::vector<char> own(count);
  std::size_t n_shared = 0;
  for (std::size_t k = 0; k < count; ++k) {
    Ray& ray = rays[k];
    ray = make_ray(atm_, altitude_m, views[k], sun);
    own[k] = ray.empty || ray.ground != ray0.ground ||
             sg::view_ray_crosses_shadow(ray.r, ray.mu, ray.mu_s, ray.nu, R, ray.s_end);
    if (own[k]) continue;
    ++n_shared;
    ray.r = ray0.r;  // the row's geometry (equal up to rounding in the azimuth)
    ray.mu = ray0.mu;
    ray.s_end = ray0.s_end;
    ray.ground = ray0.ground;
  }
  std::vector<detail::SkyViewNode> nodes;
  glm::dvec3 column_end(0.0);
  std::vector<OpticalDepthLut::SunAtRadius> sun_at;
  if (n_shared > 0) {
    column_end = trace(ray0, vc.s, vc.n, [&](const detail::SkyViewNode& nd) { nodes.push_back(nd); });
    sun_at.reserve(nodes.size());
    // The sun's zenith cosine at a node over the row's views: the expression shade()
    // evaluates, (r mu_s + s nu) / r_node, is non-decreasing in nu and in mu_s, and a
    // view's mu_s is the same for the row or (observer above the top, mu_s carried
    // to the entry point) non-decreasing in its nu. Rounding keeps that order, so
    // the views of least and largest nu give every node's range (a value that
    // rounding still puts outside, e.g. from the 1e-12 spread of the views' z, is
    // looked up in the table instead of the fit). The node's
    // sun lookups are fitted over that range when the row is long enough to pay for
    // it (at most a quarter of the lookups it replaces).
    std::size_t k_lo = count, k_hi = count;
    for (std::size_t k = 0; k < count; ++k) {
      if (own[k]) continue;
      if (k_lo == count || rays[k].nu < rays[k_lo].nu) k_lo = k;
      if (k_hi == count || rays[k].nu > rays[k_hi].nu) k_hi = k;
    }
    const int budget = static_cast<int>(std::min<std::size_t>(n_shared / 4, 1 << 20));
    for (const auto& nd : nodes) {
      const Ray &a = rays[k_lo], &b = rays[k_hi];
      const double lo = sg::sky_node_sun_cosine(a, nd);
      const double hi = sg::sky_node_sun_cosine(b, nd);
      sun_at.push_back(budget >= 17 ? lut_->sun_at(nd.r, lo, hi, budget) : lut_->sun_at(nd.r));
    }
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (own[k]) {
      radiance(altitude_m, views[k], sun, out + k * nw);
      continue;
    }
    shade(
        rays[k],
        [&](auto&& visit) {
          for (const auto& nd : nodes) visit(nd);
          return column_end;
        },
        [&](const detail::SkyViewNode& nd, double mus) {
          return sun_at[static_cast<std::size_t>(&nd - nodes.data())](mus);
        },
        out + k * nw);
  }
}

std::vector<double> SkyIntegrator::radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const {
  std::vector<double> out(solar_.size());
  radiance(altitude_m, view, sun, out.data());
  return out;
}

std::vector<double> SkyIntegrator::sun_transmittance(double altitude_m, const glm::dvec3& sun) const {
  const Ray ray = make_ray(atm_, altitude_m, sun, sun);
  std::vector<double> t(solar_.size(), 1.0);
  if (ray.empty) return t;
  if (ray.ground) return std::vector<double>(solar_.size(), 0.0);
  const LutColumn c = lut_->sun(ray.r, ray.mu);  // a ray toward the top: the sun table
  for (std::size_t i = 0; i < t.size(); ++i)
    t[i] = transmittance(optical_depth(atm_.coefficients(i), c.column));
  return t;
}

// ---------------------------------------------------------------- reference

SkyReference::SkyReference(const Atmosphere& atmosphere, SolarSpectrum solar, SkyReferenceOptions options)
    : own_atm_(std::make_shared<const Atmosphere>(atmosphere)), atm_(*own_atm_), solar_(std::move(solar)),
      opt_(options), od_(atm_), phase_(make_phases(atm_)) {
  check_solar(atm_, solar_);
  if (!(opt_.rel_tol > 0) || opt_.rel_tol >= 1) throw InputError("reference tolerance must be in (0, 1)");
}

SkyReferenceResult SkyReference::radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const {
  const std::size_t nw = solar_.size();
  SkyReferenceResult res;
  res.radiance.assign(nw, 0.0);
  res.error.assign(nw, 0.0);
  const Ray ray = make_ray(atm_, altitude_m, view, sun);
  if (ray.empty || !(ray.s_end > 0)) return res;
  const double R = atm_.ground_radius();
  const double p_ray = atm_.has(kRayleigh) ? phase_[0].value(ray.nu) : 0.0;
  const double p_mie = atm_.has(kMie) ? phase_[1].value(ray.nu) : 0.0;

  // Exact columns at a node, cached: every wavelength group re-visits the same nodes.
  struct Node {
    glm::dvec3 x{0.0};    // view + sun column
    glm::dvec3 rho{0.0};
    bool shadow = false;
  };
  std::unordered_map<double, Node> cache;
  auto node = [&](double s) -> const Node& {
    auto it = cache.find(s);
    if (it != cache.end()) return it->second;
    Node n;
    const double rs = sg::radius_along(ray.r, ray.mu, s);
    const double mus = sg::cos_zenith_along(ray.r, ray.mu_s, ray.nu, s, rs);
    const RayColumn sunc = od_.column(rs, mus);
    if (sunc.hits_ground) {
      n.shadow = true;
    } else {
      n.x = od_.column(ray.r, ray.mu, s).column + sunc.column;
      n.rho = atm_.density(rs - R);
    }
    return cache.emplace(s, n).first->second;
  };

  // Breakpoints: tangent point, kinks, and altitudes 250 m * 2^k (exponential scales).
  std::vector<double> pts;
  const double st = sg::tangent_distance(ray.r, ray.mu);
  if (st > 0 && st < ray.s_end) pts.push_back(st);
  std::vector<double> alts = atm_.kinks();
  for (double h = 250.0; h < atm_.top_altitude(); h *= 2) alts.push_back(h);
  for (double h : alts) crossings(ray, R + h, [&](double s) { pts.push_back(s); });
  shadow_crossings(ray, R, [&](double s) { pts.push_back(s); });

  const double scale = 1.0 / (opt_.sun_distance_au * opt_.sun_distance_au);
  for (std::size_t g = 0; g < nw; g += 3) {
    glm::dvec3 e[3], sc[3];
    glm::dvec3 tol(0.0);
    for (int j = 0; j < 3; ++j) {
      const std::size_t i = std::min(g + j, nw - 1);
      const auto& k = atm_.coefficients(i);
      e[j] = k.extinction;
      sc[j] = k.scattering;
      for (int c = 0; c < 3; ++c)
        if (!atm_.has(c)) e[j][c] = sc[j][c] = 0.0;
      // Absolute floor: rel_tol * 1e-6 of a vertical-column scattering scale.
      tol[j] = opt_.rel_tol * 1e-6 * std::max(glm::dot(sc[j], atm_.vertical_column()) * sg::inv_four_pi(), 1e-30);
    }
    auto f = [&](double s) {
      const Node& n = node(s);
      glm::dvec3 v(0.0);
      if (n.shadow) return v;
      for (int j = 0; j < 3; ++j)
        v[j] = std::exp(-glm::dot(e[j], n.x)) * (sc[j][kRayleigh] * n.rho[kRayleigh] * p_ray +
                                                 sc[j][kMie] * n.rho[kMie] * p_mie);
      return v;
    };
    const auto q = integrate_adaptive<glm::dvec3>(f, 0.0, ray.s_end, pts, tol, opt_.rel_tol, opt_.max_intervals);
    res.evaluations += q.evaluations;
    res.converged = res.converged && q.converged;
    for (int j = 0; j < 3 && g + j < nw; ++j) {
      res.radiance[g + j] = solar_[g + j] * scale * q.value[j];
      res.error[g + j] = solar_[g + j] * scale * q.error[j];
    }
  }
  const double albedo = atm_.spec().planet.ground_albedo;
  if (ray.ground && albedo > 0) {
    const double rg = sg::radius_along(ray.r, ray.mu, ray.s_end);
    const double mus_g = sg::cos_zenith_along(ray.r, ray.mu_s, ray.nu, ray.s_end, rg);
    if (mus_g > 0) {
      const RayColumn sunc = od_.column(R, mus_g);
      if (!sunc.hits_ground) {
        const glm::dvec3 x = od_.column(ray.r, ray.mu).column + sunc.column;
        for (std::size_t i = 0; i < nw; ++i)
          res.radiance[i] += albedo / kPi * solar_[i] * scale * mus_g *
                             transmittance(optical_depth(atm_.coefficients(i), x));
      }
    }
  }
  return res;
}

std::vector<double> SkyReference::sun_transmittance(double altitude_m, const glm::dvec3& sun) const {
  const Ray ray = make_ray(atm_, altitude_m, sun, sun);
  std::vector<double> t(solar_.size(), 1.0);
  if (ray.empty) return t;
  if (ray.ground) return std::vector<double>(solar_.size(), 0.0);
  const RayColumn c = od_.column(ray.r, ray.mu);
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = transmittance(optical_depth(atm_.coefficients(i), c.column));
  return t;
}

}  // namespace atmosh::atmo
