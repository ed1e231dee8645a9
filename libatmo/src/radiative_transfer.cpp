// Monte-Carlo radiative transfer (radiative_transfer.hpp): one transport kernel,
// two media (the spherical atmosphere and the homogeneous slab) as policies.
#include "atmosh/atmo/radiative_transfer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"

namespace atmosh::atmo {

namespace sg = shared;

namespace {

constexpr double kPi = 3.14159265358979323846;
// A safety stop far beyond any path that roulette and escape leave alive (a
// conservative slab of optical thickness 1e3 needs ~1e6 orders only on paths of
// probability ~0); documented as "every order".
constexpr int kOrderCap = 1 << 22;

// ---------------------------------------------------------------------------
// Random numbers: xoshiro256++ (Blackman & Vigna 2019), seeded by SplitMix64.
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream_a, std::uint64_t stream_b) {
    std::uint64_t x = seed;
    x = mix(x ^ mix(stream_a + 0x632BE59BD9B4E019ull) ^ mix(mix(stream_b) + 0x8CB92BA72F3D8DD7ull));
    for (auto& v : s_) v = splitmix(x);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Exponential with rate 1 (never infinite).
  double exponential() { return -std::log1p(-uniform()); }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  static std::uint64_t mix(std::uint64_t x) { return splitmix(x); }
  std::uint64_t s_[4];
};

// Orthonormal basis around a unit vector (Duff et al. 2017, JCGT 6(1)).
void basis(const glm::dvec3& n, glm::dvec3& b1, glm::dvec3& b2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  b1 = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

// The direction at angle acos(cos_t) from d, azimuth phi about it.
glm::dvec3 turn(const glm::dvec3& d, double cos_t, double phi) {
  glm::dvec3 b1, b2;
  basis(d, b1, b2);
  const double sin_t = std::sqrt(std::max(0.0, (1.0 - cos_t) * (1.0 + cos_t)));
  return glm::normalize(cos_t * d + sin_t * (std::cos(phi) * b1 + std::sin(phi) * b2));
}

glm::dvec3 cosine_hemisphere(const glm::dvec3& n, Rng& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform();
  return turn(n, std::sqrt(1.0 - u1), 2.0 * kPi * u2);
}

enum class Event { Scatter, Ground, Escape };

// Per-path running sums.
struct Sums {
  double s = 0, s2 = 0, orders = 0;
  std::int64_t n = 0;
  void add(double x) {
    s += x;
    s2 += x * x;
    ++n;
  }
  void merge(const Sums& o) {
    s += o.s;
    s2 += o.s2;
    orders += o.orders;
    n += o.n;
  }
  double mean() const { return n ? s / static_cast<double>(n) : 0.0; }
  double stderr_() const {
    if (n < 2) return 0.0;
    const double dn = static_cast<double>(n);
    const double m = s / dn;
    const double var = std::max(0.0, (s2 - dn * m * m) / (dn - 1.0));
    return std::sqrt(var / dn);
  }
};

// ---------------------------------------------------------------------------
// The transport kernel. A Medium provides
//   using Ray;                                      position and unit direction
//   Event flight(Ray&, Rng&, bool force, double& w) moves the ray to its next event;
//                                                   on Scatter w *= sigma_s/sigma_t
//                                                   (and the forced-collision factor)
//   double sun_scatter(const Ray&)                  E * sum_c (sigma_s,c/sigma_s) p_c * T_sun
//   glm::dvec3 sample_scatter(const Ray&, Rng&, double& w)  new direction; w *= f / q
//                                                   (phase f over the sampling density q)
//   double sun_ground(const Ray&)                   E * A/pi * mu_sun * T_sun
//   glm::dvec3 ground_normal(const Ray&)
//   double albedo()
template <class Medium>
double trace(const Medium& m, typename Medium::Ray ray, Rng& rng, const RtOptions& o, bool force_first,
             double& orders) {
  double w = 1.0, L = 0.0;
  const int max_orders = o.max_orders > 0 ? o.max_orders : kOrderCap;
  // With a line estimate, the sunlight a vertex's next flight would collect by its
  // next-event estimate is integrated along that flight instead (its expectation), and
  // the next vertex's own estimate is skipped.
  const bool line = m.line_estimates();
  for (int k = 1; k <= max_orders; ++k) {
    const Event ev = m.flight(ray, rng, force_first && k == 1, w);
    if (ev == Event::Escape) break;
    orders += 1.0;
    const bool count = !line || k == 1;
    if (ev == Event::Scatter) {
      if (count) L += w * m.sun_scatter(ray);
      if (k == max_orders) break;
      ray.d = m.sample_scatter(ray, rng, w);
    } else {
      if (count) L += w * m.sun_ground(ray);
      if (k == max_orders) break;
      w *= m.albedo();
      if (!(w > 0.0)) break;
      ray.d = cosine_hemisphere(m.ground_normal(ray), rng);
    }
    if (line) L += w * m.line_estimate(ray, rng);
    if (w < o.roulette_weight) {
      if (rng.uniform() * o.roulette_weight >= w) break;
      w = o.roulette_weight;
    }
  }
  return L;
}

void check_run(const RtOptions& o) {
  if (o.paths < 1) throw InputError("paths = " + std::to_string(o.paths) + ": must be >= 1");
  if (o.max_orders < 0) throw InputError("max_orders = " + std::to_string(o.max_orders) + ": must be >= 0");
  resolve_threads(o.threads);  // the toolkit's policy: 0..1024
  if (o.batches < 1 || o.batches > 1 << 20) throw InputError("batches = " + std::to_string(o.batches) + ": must be in [1, 2^20]");
  if (!(o.roulette_weight > 0.0 && o.roulette_weight <= 1.0))
    throw InputError("roulette_weight = " + std::to_string(o.roulette_weight) + ": must be in (0, 1]");
}

// Runs `paths` paths as `batches` fixed batches of stream (tag, batch): sample(rng)
// returns one path's estimate and adds its vertices to `orders`. Deterministic for
// any thread count (batch sums added in batch order).
template <class Sample>
Sums run_batches(std::int64_t paths, const RtOptions& o, std::uint64_t tag, Sample&& sample) {
  const std::int64_t B = std::min<std::int64_t>(o.batches, paths);
  std::vector<Sums> part(static_cast<std::size_t>(B));
  parallel_for(static_cast<std::size_t>(B), o.threads, [&](std::size_t b) {
    const std::int64_t n = paths / B + (static_cast<std::int64_t>(b) < paths % B ? 1 : 0);
    Rng rng(o.seed, tag, b);
    Sums s;
    for (std::int64_t i = 0; i < n; ++i) s.add(sample(rng, s.orders));
    part[b] = s;
  });
  Sums total;
  for (const auto& s : part) total.merge(s);
  return total;
}

// ---------------------------------------------------------------------------
// The slab: vertical coordinate z in optical depth from the bottom (0) to the top
// (tau); incident beam of unit flux per unit area normal to it, propagating along
// (sqrt(1 - mu0^2), 0, -mu0).
class SlabMedium {
 public:
  struct Ray {
    double z = 0;
    glm::dvec3 d{0, 0, 1};
  };
  SlabMedium(const SlabSpec& s, double mu0)
      : s_(s), mu0_(mu0), phase_(make_phase(s)), sun_(-std::sqrt(std::max(0.0, 1.0 - mu0 * mu0)), 0.0, mu0) {}

  Event flight(Ray& r, Rng& rng, bool force, double& w) const {
    double dist = std::numeric_limits<double>::infinity();
    bool bottom = false;
    if (r.d.z > 0) {
      dist = (s_.tau - r.z) / r.d.z;
    } else if (r.d.z < 0) {
      dist = r.z / -r.d.z;
      bottom = true;
    }
    const bool boundary_dark = !bottom || s_.ground_albedo == 0.0;
    double t;
    if (force && boundary_dark && std::isfinite(dist) && dist > 0) {
      const double p = -std::expm1(-dist);  // probability of a collision before the boundary
      t = -std::log1p(-rng.uniform() * p);
      t = std::min(t, dist);
      w *= p;
    } else {
      t = rng.exponential();
      if (t >= dist) {
        if (!bottom) return Event::Escape;
        r.z = 0.0;
        return s_.ground_albedo > 0.0 ? Event::Ground : Event::Escape;
      }
    }
    r.z = std::clamp(r.z + t * r.d.z, 0.0, s_.tau);
    w *= s_.omega;
    return Event::Scatter;
  }
  double sun_scatter(const Ray& r) const {
    return phase_.value(glm::dot(r.d, sun_)) * std::exp(-(s_.tau - r.z) / mu0_);
  }
  glm::dvec3 sample_scatter(const Ray& r, Rng& rng, double&) const {
    const double c = phase_.sample(rng.uniform());
    return turn(r.d, c, 2.0 * kPi * rng.uniform());
  }
  double sun_ground(const Ray&) const { return s_.ground_albedo / kPi * mu0_ * std::exp(-s_.tau / mu0_); }
  bool line_estimates() const { return false; }
  double line_estimate(const Ray&, Rng&) const { return 0.0; }
  glm::dvec3 ground_normal(const Ray&) const { return {0, 0, 1}; }
  double albedo() const { return s_.ground_albedo; }

 private:
  static PhaseFunction make_phase(const SlabSpec& s) {
    switch (s.phase) {
      case SlabPhase::Isotropic:
        return PhaseFunction(PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0), "slab phase");
      case SlabPhase::HenyeyGreenstein:
        return PhaseFunction(PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, s.g), "slab phase");
      case SlabPhase::Rayleigh: {
        PhaseSpec p = PhaseSpec::of(PhaseSpec::Model::Rayleigh);
        p.depolarization = 0.0;
        return PhaseFunction(p, "slab phase");
      }
    }
    throw InputError("slab phase: unknown model");
  }
  SlabSpec s_;
  double mu0_;
  PhaseFunction phase_;
  glm::dvec3 sun_;  // toward the sun
};

void check_slab(const SlabSpec& s, double mu0) {
  if (!(std::isfinite(s.tau) && s.tau > 0)) throw InputError("slab tau = " + std::to_string(s.tau) + ": must be finite and > 0");
  if (!(s.omega >= 0 && s.omega <= 1)) throw InputError("slab omega = " + std::to_string(s.omega) + ": must be in [0, 1]");
  if (!(std::abs(s.g) < 1)) throw InputError("slab g = " + std::to_string(s.g) + ": must be in (-1, 1)");
  if (!(s.ground_albedo >= 0 && s.ground_albedo <= 1))
    throw InputError("slab ground albedo = " + std::to_string(s.ground_albedo) + ": must be in [0, 1]");
  if (!(mu0 > 0 && mu0 <= 1)) throw InputError("mu0 = " + std::to_string(mu0) + ": must be in (0, 1]");
}

// Estimates pi I / mu0 of paths started at the top (reflection) or bottom
// (transmission) along the viewed light's reversed direction; dir(rng) gives the
// propagation direction of the viewed light and the estimator's weight.
template <class Dir>
Sums slab_run(const SlabMedium& m, const SlabSpec& s, double mu0, bool top, const RtOptions& o, std::uint64_t tag,
              Dir&& dir) {
  return run_batches(o.paths, o, tag, [&](Rng& rng, double& orders) {
    SlabMedium::Ray r;
    r.z = top ? s.tau : 0.0;
    r.d = -dir(rng);
    return kPi / mu0 * trace(m, r, rng, o, true, orders);
  });
}

// ---------------------------------------------------------------------------
// The spherical atmosphere, one wavelength.
struct SphereModel {
  const Atmosphere* atm = nullptr;
  double R = 0, T = 0;
  std::vector<PhaseFunction> phase;  // Rayleigh, Mie
  // sup over [h, top] of each profile: exact from its kinks (monotone between them).
  struct Envelope {
    bool present = false;
    std::vector<double> kink_h;      // ascending, within [0, top]
    std::vector<double> suffix_max;  // max of rho at kink_h[j..]
    double rho_top = 0;
  };
  std::array<Envelope, 3> env;
  std::unique_ptr<OpticalDepthLut> lut;
  std::unique_ptr<OpticalDepthReference> od;
  bool exact_sun = false;

  double rho_sup(int c, double h) const {
    const Envelope& e = env[c];
    if (!e.present) return 0.0;
    h = std::clamp(h, 0.0, T - R);
    double m = std::max(atm->profile(c)(h), e.rho_top);
    auto it = std::lower_bound(e.kink_h.begin(), e.kink_h.end(), h);
    if (it != e.kink_h.end()) m = std::max(m, e.suffix_max[static_cast<std::size_t>(it - e.kink_h.begin())]);
    return m * (1.0 + 1e-12);
  }
  // Sun column from radius r with zenith cosine mu_s; false when the ground blocks it.
  bool sun_column(double r, double mu_s, glm::dvec3& x) const {
    r = std::clamp(r, R, T);
    if (exact_sun) {
      const RayColumn c = od->column(r, std::clamp(mu_s, -1.0, 1.0));
      x = c.column;
      return !c.hits_ground;
    }
    const LutColumn c = lut->sun(r, std::clamp(mu_s, -1.0, 1.0));
    x = c.column;
    return !c.hits_ground;
  }
};

// The view ray of one radiance() call (the same for every path): its nodes and the
// column from its start to each, for the first collision. Nodes: every <= 250 m of
// altitude and <= 5 km of length, and where the ray crosses a profile kink; the column
// of each piece by 8-point Gauss-Legendre (the densities are smooth within a piece:
// <= 250 m of a >= 1.2 km scale height, relative error < 1e-13).
struct ViewRay {
  bool empty = true;  // misses the atmosphere
  glm::dvec3 o{0.0}, v{0, 0, 1};  // start (entry into the atmosphere) and direction
  double length = 0;
  bool ground = false;
  std::vector<double> s;          // nodes: s[0] = 0 ... s.back() = length
  std::vector<glm::dvec3> X;      // column from the start to each node [m]
};

glm::dvec3 piece_column(const SphereModel& m, const glm::dvec3& o, const glm::dvec3& v, double a, double b) {
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  glm::dvec3 x(0.0);
  for (int i = 0; i < 4; ++i) {
    const double dx = h * sg::gauss8_node(i), w = h * sg::gauss8_weight(i);
    for (const double sgn : {-1.0, 1.0}) {
      const double alt = glm::length(o + (c + sgn * dx) * v) - m.R;
      x += w * m.atm->density(std::max(alt, 0.0));
    }
  }
  return x;
}

ViewRay make_view_ray(const SphereModel& m, const glm::dvec3& origin, const glm::dvec3& v, double max_dh = 250.0,
                      double max_ds = 5000.0) {
  ViewRay vr;
  const double R = m.R, T = m.T;
  glm::dvec3 o = origin;
  double r = glm::length(o), mu = glm::dot(o, v) / r;
  if (r > T) {
    const double s_in = sg::distance_to_top_from_outside(r, mu, T);
    if (!(s_in >= 0)) return vr;
    o += s_in * v;
    r = glm::length(o);
    mu = glm::dot(o, v) / r;
  }
  r = std::max(r, R);
  vr.empty = false;
  vr.o = o;
  vr.v = v;
  vr.ground = sg::ray_hits_ground(r, mu, R);
  vr.length = vr.ground ? sg::distance_to_ground(r, mu, R) : sg::distance_to_top(r, mu, T);
  std::vector<double> cuts;
  const double b = glm::dot(o, v), c0 = glm::dot(o, o);
  for (int k = 0; k < 3; ++k)
    for (double hk : m.env[static_cast<std::size_t>(k)].kink_h) {
      const double rk = R + hk, disc = b * b - (c0 - rk * rk);
      if (disc < 0) continue;
      for (const double sgn : {-1.0, 1.0}) {
        const double sk = -b + sgn * std::sqrt(disc);
        if (sk > 0 && sk < vr.length) cuts.push_back(sk);
      }
    }
  std::sort(cuts.begin(), cuts.end());
  vr.s.push_back(0.0);
  vr.X.push_back(glm::dvec3(0.0));
  std::size_t next_cut = 0;
  double s = 0.0;
  while (s < vr.length) {
    const glm::dvec3 q = o + s * v;
    const double muq = std::abs(glm::dot(q, v)) / glm::length(q);
    double step = std::min(max_ds, max_dh / std::max(muq, 1e-6));
    double s1 = std::min(s + step, vr.length);
    while (next_cut < cuts.size() && cuts[next_cut] <= s) ++next_cut;
    if (next_cut < cuts.size() && cuts[next_cut] < s1) s1 = cuts[next_cut];
    if (vr.length - s1 < 1e-6 * step) s1 = vr.length;
    vr.X.push_back(vr.X.back() + piece_column(m, o, v, s, s1));
    vr.s.push_back(s1);
    s = s1;
  }
  return vr;
}

// The pilot's map of where a first vertex on the view ray sends light toward the
// observer (RtSkyOptions::guide), one wavelength: g_piece[j] the value at view-ray
// piece j (next-event estimate + the integral over directions of the phase function
// times the line estimate, per unit weight), and per pilot point (at s[k]) the cell
// distribution of outgoing directions in the local frame (z = d . up in nz cells with
// edges sign(u) u^2, u uniform: fine near the horizon; azimuth about up from the sun's
// vertical plane in nphi uniform cells).
struct FirstGuide {
  bool active = false;
  std::vector<double> s;
  int nz = 0, nphi = 0;
  std::vector<double> z_edges;
  std::vector<double> cell_p;    // [point][cell], each point's cells sum to 1
  std::vector<double> cell_cdf;  // [point][cell + 1]
  std::vector<double> g_piece;
  std::vector<double> h;  // altitude of each pilot point
  std::size_t nearest_altitude(double hv) const {
    std::size_t best = 0;
    for (std::size_t k = 1; k < h.size(); ++k)
      if (std::abs(h[k] - hv) < std::abs(h[best] - hv)) best = k;
    return best;
  }
  std::size_t nearest(double sv) const {
    const auto it = std::lower_bound(s.begin(), s.end(), sv);
    if (it == s.begin()) return 0;
    if (it == s.end()) return s.size() - 1;
    const std::size_t k = static_cast<std::size_t>(it - s.begin());
    return (sv - s[k - 1] <= s[k] - sv) ? k - 1 : k;
  }
};

// Local frame at p for the guide: up and the horizontal axes toward the sun's azimuth.
void guide_frame(const glm::dvec3& p, const glm::dvec3& sun, glm::dvec3& up, glm::dvec3& e1, glm::dvec3& e2) {
  up = glm::normalize(p);
  glm::dvec3 h = sun - glm::dot(sun, up) * up;
  if (glm::length(h) < 1e-12) {
    glm::dvec3 b2;
    basis(up, h, b2);
  }
  e1 = glm::normalize(h);
  e2 = glm::cross(up, e1);
}

class SphereMedium {
 public:
  struct Ray {
    glm::dvec3 p{0.0};  // planet-centred [m]
    glm::dvec3 d{0, 0, 1};
  };
  SphereMedium(const SphereModel& m, const Coefficients& k, double irradiance, const glm::dvec3& sun, double albedo,
               const ViewRay& view, double cone_share, double cone_half_angle_deg, bool line,
               const FirstGuide* guide = nullptr, double guide_share = 0.0, double guide_defensive = 1.0)
      : m_(m), ext_(k.extinction), sca_(k.scattering), e_(irradiance), sun_(sun), albedo_(albedo), view_(view),
        cone_share_(cone_share), cone_cos_(std::cos(cone_half_angle_deg * kPi / 180.0)), line_(line),
        guide_(guide && guide->active ? guide : nullptr), guide_share_(guide_ ? guide_share : 0.0) {
    for (int c = 0; c < 3; ++c)
      if (!m.atm->has(c)) ext_[c] = sca_[c] = 0.0;
    sca_[kOzone] = 0.0;
    if (!view.empty) {  // the first collision's sampling tables
      const std::size_t n = view.s.size();
      tau_.resize(n);
      for (std::size_t j = 0; j < n; ++j) tau_[j] = glm::dot(ext_, view.X[j]);
      const double p_all = -std::expm1(-tau_.back());  // probability of a collision on the ray
      if (p_all > 1e-300) {
        cdf_.resize(n);
        for (std::size_t j = 0; j < n; ++j) cdf_[j] = -std::expm1(-tau_[j]) / p_all;
        cdf_.back() = 1.0;
        p_ground_ = view.ground ? std::exp(-tau_.back()) : 0.0;
        if (guide_ && guide_->g_piece.size() + 1 == n) {
          // Pieces with probability P_j (a + (1 - a) G_j / sum_i P_i G_i): the collision
          // density times the pilot's value, mixed with the plain density (share a).
          double tot = 0.0;
          for (std::size_t j = 0; j + 1 < n; ++j) tot += (cdf_[j + 1] - cdf_[j]) * guide_->g_piece[j];
          if (tot > 0 && std::isfinite(tot)) {
            const double a = guide_defensive;
            std::vector<double> c(n, 0.0);
            for (std::size_t j = 0; j + 1 < n; ++j) {
              const double P = cdf_[j + 1] - cdf_[j];
              c[j + 1] = c[j] + P * (a + (1.0 - a) * guide_->g_piece[j] / tot);
            }
            for (std::size_t j = 0; j < n; ++j) cdf_[j] = c[j] / c.back();
            cdf_.back() = 1.0;
          }
        }
      }
    }
  }

  // Share of the first collisions sampled uniformly over the view ray's pieces (the
  // rest follow the collision density sigma_t e^{-tau}): keeps high, thin layers
  // sampled (twilight, where the lit atmosphere is high).
  static constexpr double kUniformShare = 0.0;

  // First collision on the view ray, importance-sampled: the ground (if the ray meets
  // it) with its probability e^{-tau}, else a point s with density
  // q(s) = (a / n + (1 - a) P_j) / h_j in piece j (P_j its share of the collision
  // probability, h_j its length, n pieces), weight sigma_s(s) e^{-tau(s)} / (q(s)
  // (1 - p_ground)) with the exact tau(s) (piece start + Gauss-Legendre to s).
  Event first_flight(Ray& ray, Rng& rng, double& w) const {
    if (view_.empty) return Event::Escape;
    if (cdf_.empty() && !view_.ground) return Event::Escape;  // nothing to collide with
    if (cdf_.empty() || (p_ground_ > 0 && rng.uniform() < p_ground_)) {
      ray.p = view_.o + view_.length * view_.v;
      ray.p *= m_.R / glm::length(ray.p);
      ray.d = view_.v;
      return Event::Ground;
    }
    const std::size_t n = view_.s.size() - 1;  // pieces
    std::size_t j;
    if (rng.uniform() < kUniformShare) {
      j = std::min<std::size_t>(static_cast<std::size_t>(rng.uniform() * static_cast<double>(n)), n - 1);
    } else {
      const double u = rng.uniform();
      j = static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
      j = std::clamp<std::size_t>(j == 0 ? 0 : j - 1, 0, n - 1);
    }
    const double a = view_.s[j], b = view_.s[j + 1], h = b - a;
    const double s = a + rng.uniform() * h;
    const double P = cdf_[j + 1] - cdf_[j];
    const double q = (kUniformShare / static_cast<double>(n) + (1.0 - kUniformShare) * P) / h;
    const double tau = tau_[j] + glm::dot(ext_, piece_column(m_, view_.o, view_.v, a, s));
    ray.p = view_.o + s * view_.v;
    ray.d = view_.v;
    const glm::dvec3 rho = m_.atm->density(std::max(glm::length(ray.p) - m_.R, 0.0));
    w *= glm::dot(sca_, rho) * std::exp(-tau) / (q * (1.0 - p_ground_));
    last_rho_ = rho;
    first_point_ = guide_ ? static_cast<int>(guide_->nearest(s)) : -1;
    return Event::Scatter;
  }

  Event flight(Ray& ray, Rng& rng, bool force, double& w) const {
    first_point_ = -1;
    if (force) return first_flight(ray, rng, w);
    const double R = m_.R, T = m_.T;
    double r = glm::length(ray.p);
    double mu = glm::dot(ray.p, ray.d) / r;
    if (r > T) {
      const double s_in = sg::distance_to_top_from_outside(r, mu, T);
      if (!(s_in >= 0)) return Event::Escape;
      ray.p += s_in * ray.d;
      r = glm::length(ray.p);
      mu = glm::dot(ray.p, ray.d) / r;
    }
    r = std::max(r, R);
    const bool ground = sg::ray_hits_ground(r, mu, R);
    const double s_end = ground ? sg::distance_to_ground(r, mu, R) : sg::distance_to_top(r, mu, T);
    double s = 0.0, sig_t = 0.0;
    if (track(ray.p, ray.d, s_end, ground, rng, s, sig_t)) {
      ray.p += s * ray.d;
      const glm::dvec3 rho = m_.atm->density(std::max(glm::length(ray.p) - R, 0.0));
      w *= sig_t > 0 ? glm::dot(sca_, rho) / sig_t : 0.0;
      last_rho_ = rho;
      if (guide_) first_point_ = static_cast<int>(guide_->nearest_altitude(glm::length(ray.p) - R));
      return Event::Scatter;
    }
    if (!ground) return Event::Escape;
    ray.p += s_end * ray.d;
    ray.p *= R / glm::length(ray.p);
    return Event::Ground;
  }
  bool line_estimates() const { return line_; }
  // The expected next-event estimate of the next vertex along ray.d from ray.p: the
  // single-scattering integral of the sunlight along that ray, plus the lit ground it
  // ends on, times its transmittance; one uniformly placed point per piece (<= 1 km of
  // altitude, <= 20 km of length: stratified, unbiased), the optical depth to it exact
  // (piece columns by Gauss-Legendre), the rest of the ray dropped once its optical
  // depth exceeds 60 (e^-60 ~ 1e-26).
  double line_estimate(const Ray& ray, Rng& rng) const {
    const ViewRay vr = make_view_ray(m_, ray.p, ray.d, 1000.0, 20000.0);
    if (vr.empty) return 0.0;
    const double nu = glm::dot(ray.d, sun_);
    const double p_r = m_.atm->has(kRayleigh) ? m_.phase[0].value(nu) : 0.0;
    const double p_m = m_.atm->has(kMie) ? m_.phase[1].value(nu) : 0.0;
    double sum = 0.0;
    const std::size_t n = vr.s.size() - 1;
    for (std::size_t j = 0; j < n; ++j) {
      const double tau_j = glm::dot(ext_, vr.X[j]);
      if (tau_j > 60.0) return sum;
      const double a = vr.s[j], h = vr.s[j + 1] - a;
      const double s = a + rng.uniform() * h;
      const glm::dvec3 p = vr.o + s * vr.v;
      const double r = glm::length(p);
      const glm::dvec3 rho = m_.atm->density(std::max(r - m_.R, 0.0));
      const double f = sca_[kRayleigh] * rho[kRayleigh] * p_r + sca_[kMie] * rho[kMie] * p_m;
      if (!(f > 0)) continue;
      glm::dvec3 x;
      if (!m_.sun_column(r, glm::dot(p, sun_) / r, x)) continue;
      const double tau = tau_j + glm::dot(ext_, piece_column(m_, vr.o, vr.v, a, s));
      sum += h * f * std::exp(-tau - glm::dot(ext_, x));
    }
    if (vr.ground && albedo_ > 0) {
      Ray g;
      g.p = vr.o + vr.length * vr.v;
      g.p *= m_.R / glm::length(g.p);
      sum += std::exp(-glm::dot(ext_, vr.X.back())) * sun_ground(g) / e_;
    }
    return e_ * sum;
  }

  double sun_scatter(const Ray& ray) const {
    const double r = glm::length(ray.p);
    glm::dvec3 x;
    if (!m_.sun_column(r, glm::dot(ray.p, sun_) / r, x)) return 0.0;
    const double nu = glm::dot(ray.d, sun_);
    const double sr = sca_[kRayleigh] * last_rho_[kRayleigh], sm = sca_[kMie] * last_rho_[kMie];
    const double ss = sr + sm;
    if (!(ss > 0)) return 0.0;
    const double p = (sr * (sr > 0 ? m_.phase[0].value(nu) : 0.0) + sm * (sm > 0 ? m_.phase[1].value(nu) : 0.0)) / ss;
    return e_ * p * transmittance(glm::dot(ext_, x));
  }
  // Next direction: with probability 1 - kConeShare from the phase functions (a
  // constituent picked by its share of sigma_s), else uniformly inside the cone of
  // half-angle kConeHalfAngle about the sun (where, in twilight, the lit atmosphere
  // lies); one-sample multiple importance sampling: w *= f / ((1 - b) f + b p_cone), f
  // the mixed phase function [1/sr] (<= 1 / (1 - b)).
  glm::dvec3 sample_scatter(const Ray& ray, Rng& rng, double& w) const {
    const double sr = sca_[kRayleigh] * last_rho_[kRayleigh], sm = sca_[kMie] * last_rho_[kMie];
    // With a guide: the cell distribution of the vertex's pilot point, share g.
    const bool guided = guide_ && first_point_ >= 0;
    const double g = guided ? guide_share_ : 0.0;
    glm::dvec3 up, e1, e2;
    if (guided) guide_frame(ray.p, sun_, up, e1, e2);
    glm::dvec3 d;
    if (g > 0 && rng.uniform() < g) {
      d = guide_sample(static_cast<std::size_t>(first_point_), up, e1, e2, rng);
    } else if (cone_share_ > 0 && rng.uniform() < cone_share_) {
      const double c = 1.0 - rng.uniform() * (1.0 - cone_cos_);
      d = turn(sun_, c, 2.0 * kPi * rng.uniform());
    } else {
      const int c = rng.uniform() * (sr + sm) < sr ? 0 : 1;
      const double cos_t = m_.phase[static_cast<std::size_t>(c)].sample(rng.uniform());
      d = turn(ray.d, cos_t, 2.0 * kPi * rng.uniform());
    }
    if (cone_share_ > 0 || g > 0) {
      const double nu = glm::dot(ray.d, d);
      const double f = (sr * (sr > 0 ? m_.phase[0].value(nu) : 0.0) + sm * (sm > 0 ? m_.phase[1].value(nu) : 0.0)) / (sr + sm);
      const double p_cone = glm::dot(d, sun_) >= cone_cos_ ? 1.0 / (2.0 * kPi * (1.0 - cone_cos_)) : 0.0;
      const double p_rest = (1.0 - cone_share_) * f + cone_share_ * p_cone;
      const double p_g = g > 0 ? guide_pdf(static_cast<std::size_t>(first_point_), up, e1, e2, d) : 0.0;
      w *= f / (g * p_g + (1.0 - g) * p_rest);
    }
    return d;
  }
  // A direction from pilot point k's cells: a cell by its probability, then uniform in
  // z and azimuth inside it; its density [1/sr] is guide_pdf.
  glm::dvec3 guide_sample(std::size_t k, const glm::dvec3& up, const glm::dvec3& e1, const glm::dvec3& e2,
                          Rng& rng) const {
    const FirstGuide& G = *guide_;
    const std::size_t nc = static_cast<std::size_t>(G.nz) * G.nphi;
    const double* cdf = &G.cell_cdf[k * (nc + 1)];
    const double u = rng.uniform();
    std::size_t c = static_cast<std::size_t>(std::upper_bound(cdf, cdf + nc + 1, u) - cdf);
    c = std::clamp<std::size_t>(c == 0 ? 0 : c - 1, 0, nc - 1);
    while (c + 1 < nc && !(G.cell_p[k * nc + c] > 0)) ++c;  // never a cell of probability 0
    const std::size_t iz = c / static_cast<std::size_t>(G.nphi), ip = c % static_cast<std::size_t>(G.nphi);
    const double z = G.z_edges[iz] + rng.uniform() * (G.z_edges[iz + 1] - G.z_edges[iz]);
    const double phi = -kPi + (static_cast<double>(ip) + rng.uniform()) * 2.0 * kPi / G.nphi;
    const double st = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
    return glm::normalize(z * up + st * (std::cos(phi) * e1 + std::sin(phi) * e2));
  }
  double guide_pdf(std::size_t k, const glm::dvec3& up, const glm::dvec3& e1, const glm::dvec3& e2,
                   const glm::dvec3& d) const {
    const FirstGuide& G = *guide_;
    const double z = std::clamp(glm::dot(d, up), -1.0, 1.0);
    std::size_t iz = static_cast<std::size_t>(std::upper_bound(G.z_edges.begin(), G.z_edges.end(), z) - G.z_edges.begin());
    iz = std::clamp<std::size_t>(iz == 0 ? 0 : iz - 1, 0, static_cast<std::size_t>(G.nz) - 1);
    const double phi = std::atan2(glm::dot(d, e2), glm::dot(d, e1));
    const double dphi = 2.0 * kPi / G.nphi;
    const int ip = std::clamp(static_cast<int>((phi + kPi) / dphi), 0, G.nphi - 1);
    const std::size_t nc = static_cast<std::size_t>(G.nz) * G.nphi;
    const double P = G.cell_p[k * nc + iz * static_cast<std::size_t>(G.nphi) + static_cast<std::size_t>(ip)];
    return P / ((G.z_edges[iz + 1] - G.z_edges[iz]) * dphi);
  }
  // The pilot's value at a first vertex at p (view direction v): next-event estimate
  // and, per cell, phase x line estimate x the cell's solid angle (one jittered
  // direction per cell), into cell[]; returns the next-event estimate. Sets the vertex.
  double pilot(const glm::dvec3& p, const glm::dvec3& v, const FirstGuide& G, Rng& rng, double* cell) const {
    last_rho_ = m_.atm->density(std::max(glm::length(p) - m_.R, 0.0));
    Ray ray;
    ray.p = p;
    ray.d = v;
    const double nee = sun_scatter(ray);
    const double sr = sca_[kRayleigh] * last_rho_[kRayleigh], sm = sca_[kMie] * last_rho_[kMie];
    glm::dvec3 up, e1, e2;
    guide_frame(p, sun_, up, e1, e2);
    const double dphi = 2.0 * kPi / G.nphi;
    for (int iz = 0; iz < G.nz; ++iz)
      for (int ip = 0; ip < G.nphi; ++ip) {
        const double z = G.z_edges[iz] + rng.uniform() * (G.z_edges[iz + 1] - G.z_edges[iz]);
        const double phi = -kPi + (ip + rng.uniform()) * dphi;
        const double st = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
        Ray out;
        out.p = p;
        out.d = glm::normalize(z * up + st * (std::cos(phi) * e1 + std::sin(phi) * e2));
        const double nu = glm::dot(v, out.d);
        const double f =
            sr + sm > 0 ? (sr * (sr > 0 ? m_.phase[0].value(nu) : 0.0) + sm * (sm > 0 ? m_.phase[1].value(nu) : 0.0)) / (sr + sm)
                        : 0.0;
        const double le = f > 0 ? line_estimate(out, rng) : 0.0;
        cell[iz * G.nphi + ip] = f * le * (G.z_edges[iz + 1] - G.z_edges[iz]) * dphi;
      }
    return nee;
  }
  double sun_ground(const Ray& ray) const {
    const glm::dvec3 n = ground_normal(ray);
    const double mu_s = glm::dot(n, sun_);
    if (!(mu_s > 0) || albedo_ <= 0) return 0.0;
    glm::dvec3 x;
    if (!m_.sun_column(m_.R, mu_s, x)) return 0.0;
    return e_ * albedo_ / kPi * mu_s * transmittance(glm::dot(ext_, x));
  }
  glm::dvec3 ground_normal(const Ray& ray) const { return glm::normalize(ray.p); }
  double albedo() const { return albedo_; }

 private:
  // Delta tracking from p along d up to s_end; true with s, sigma_t at a real collision.
  bool track(const glm::dvec3& p, const glm::dvec3& d, double s_end, bool ground, Rng& rng, double& s,
             double& sig_t) const {
    const double R = m_.R;
    s = 0.0;
    for (int guard = 0; guard < 100000000; ++guard) {
      const glm::dvec3 q = p + s * d;
      const double rq = glm::length(q);
      const double muq = glm::dot(q, d) / rq;
      double h_min;
      if (muq >= 0)
        h_min = rq - R;
      else if (ground)
        h_min = 0.0;
      else
        h_min = std::sqrt(sg::tangent_radius_sq(rq, muq)) - R;
      double maj = 0.0;
      for (int c = 0; c < 3; ++c)
        if (ext_[c] > 0) maj += ext_[c] * m_.rho_sup(c, h_min);
      if (!(maj > 0)) return false;
      s += rng.exponential() / maj;
      if (s >= s_end) return false;
      const double h = std::max(glm::length(p + s * d) - R, 0.0);
      sig_t = glm::dot(ext_, m_.atm->density(h));
      if (rng.uniform() * maj < sig_t) return true;
    }
    return false;
  }

  const SphereModel& m_;
  glm::dvec3 ext_, sca_;
  double e_;
  glm::dvec3 sun_;
  double albedo_;
  const ViewRay& view_;
  std::vector<double> tau_, cdf_;  // view ray: optical depth and collision CDF at the nodes
  double p_ground_ = 0.0;
  double cone_share_ = 0.0, cone_cos_ = 1.0;
  bool line_ = false;
  const FirstGuide* guide_ = nullptr;
  double guide_share_ = 0.0;
  mutable int first_point_ = -1;
  bool guide_all_ = std::getenv("GUIDE_ALL") != nullptr;  // the first vertex's pilot point while it scatters (guide)
  mutable glm::dvec3 last_rho_{0.0};  // densities at the last collision (one medium per path thread)
};

glm::dvec3 unit(const glm::dvec3& v, const char* what) {
  const double n = glm::length(v);
  if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-6)
    throw InputError(std::string(what) + " direction is not a finite unit vector");
  return v / n;
}

}  // namespace

// ---------------------------------------------------------------------------
SlabResult slab_reflection_transmission(const SlabSpec& slab, double mu0, double mu, double phi_rad,
                                        const RtOptions& options) {
  check_slab(slab, mu0);
  check_run(options);
  if (!(mu > 0 && mu <= 1)) throw InputError("mu = " + std::to_string(mu) + ": must be in (0, 1]");
  if (!std::isfinite(phi_rad)) throw InputError("phi is not finite");
  const auto t0 = std::chrono::steady_clock::now();
  const SlabMedium m(slab, mu0);
  const double st = std::sqrt(std::max(0.0, (1.0 - mu) * (1.0 + mu)));
  const glm::dvec3 up(st * std::cos(phi_rad), st * std::sin(phi_rad), mu);
  const glm::dvec3 down(up.x, up.y, -mu);
  const Sums r = slab_run(m, slab, mu0, true, options, 1, [&](Rng&) { return up; });
  const Sums t = slab_run(m, slab, mu0, false, options, 2, [&](Rng&) { return down; });
  SlabResult out;
  out.reflection = r.mean();
  out.reflection_stderr = r.stderr_();
  out.transmission = t.mean();
  out.transmission_stderr = t.stderr_();
  out.paths = options.paths;
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

SlabFluxResult slab_fluxes(const SlabSpec& slab, double mu0, const RtOptions& options) {
  check_slab(slab, mu0);
  check_run(options);
  const auto t0 = std::chrono::steady_clock::now();
  const SlabMedium m(slab, mu0);
  // Viewed light propagating into the hemisphere with density mu / pi: E[R] = flux ratio.
  auto hemi = [](Rng& rng, double sign) {
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const double mu = std::sqrt(1.0 - u1);  // in (0, 1]
    const double st = std::sqrt(u1);
    return glm::dvec3(st * std::cos(2 * kPi * u2), st * std::sin(2 * kPi * u2), sign * mu);
  };
  const Sums r = slab_run(m, slab, mu0, true, options, 3, [&](Rng& rng) { return hemi(rng, 1.0); });
  const Sums t = slab_run(m, slab, mu0, false, options, 4, [&](Rng& rng) { return hemi(rng, -1.0); });
  SlabFluxResult out;
  out.albedo = r.mean();
  out.albedo_stderr = r.stderr_();
  out.transmittance = t.mean();
  out.transmittance_stderr = t.stderr_();
  out.paths = options.paths;
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

// ---------------------------------------------------------------------------
struct MonteCarloSky::Impl {
  SphereModel model;
};

MonteCarloSky::MonteCarloSky(const Atmosphere& atmosphere, SolarSpectrum solar, RtSkyOptions options)
    : atm_(atmosphere), solar_(std::move(solar)), opt_(options), impl_(std::make_unique<Impl>()) {
  check_run(opt_.run);
  const std::size_t nw = atm_.wavelengths_nm().size();
  if (solar_.size() != nw)
    throw InputError("solar spectrum has " + std::to_string(solar_.size()) + " values for " + std::to_string(nw) +
                     " wavelengths");
  for (double e : solar_)
    if (!std::isfinite(e) || e < 0) throw InputError("solar irradiance " + std::to_string(e) + " is not finite and >= 0");
  if (!(opt_.sun_distance_au > 0) || !std::isfinite(opt_.sun_distance_au))
    throw InputError("sun distance " + std::to_string(opt_.sun_distance_au) + " AU: must be finite and > 0");
  if (opt_.ground_albedo > 1 || std::isnan(opt_.ground_albedo))
    throw InputError("ground albedo " + std::to_string(opt_.ground_albedo) + ": must be <= 1");
  if (!(opt_.sun_cone_share >= 0 && opt_.sun_cone_share < 1))
    throw InputError("sun_cone_share = " + std::to_string(opt_.sun_cone_share) + ": must be in [0, 1)");
  if (!(opt_.sun_cone_half_angle_deg > 0 && opt_.sun_cone_half_angle_deg <= 180))
    throw InputError("sun_cone_half_angle_deg = " + std::to_string(opt_.sun_cone_half_angle_deg) + ": must be in (0, 180]");
  if (opt_.guide_points < 2 || opt_.guide_points > 256)
    throw InputError("guide_points = " + std::to_string(opt_.guide_points) + ": must be in [2, 256]");
  if (opt_.guide_zenith < 2 || opt_.guide_zenith > 256)
    throw InputError("guide_zenith = " + std::to_string(opt_.guide_zenith) + ": must be in [2, 256]");
  if (opt_.guide_azimuth < 1 || opt_.guide_azimuth > 256)
    throw InputError("guide_azimuth = " + std::to_string(opt_.guide_azimuth) + ": must be in [1, 256]");
  if (!(opt_.guide_share >= 0 && opt_.guide_share < 1))
    throw InputError("guide_share = " + std::to_string(opt_.guide_share) + ": must be in [0, 1)");
  if (!(opt_.guide_defensive > 0 && opt_.guide_defensive <= 1))
    throw InputError("guide_defensive = " + std::to_string(opt_.guide_defensive) + ": must be in (0, 1]");
  if (!std::isfinite(opt_.guide_below_deg))
    throw InputError("guide_below_deg is not finite");
  SphereModel& m = impl_->model;
  m.atm = &atm_;
  m.R = atm_.ground_radius();
  m.T = atm_.top_radius();
  const auto& s = atm_.spec();
  m.phase.emplace_back(s.rayleigh ? s.rayleigh->phase : PhaseSpec::of(PhaseSpec::Model::Rayleigh), "rayleigh.phase");
  m.phase.emplace_back(s.mie ? s.mie->phase : PhaseSpec::of(PhaseSpec::Model::HenyeyGreenstein, 0.0), "mie.phase");
  const double top = atm_.top_altitude();
  for (int c = 0; c < 3; ++c) {
    auto& e = m.env[static_cast<std::size_t>(c)];
    e.present = atm_.has(c);
    if (!e.present) continue;
    const auto& prof = atm_.profile(c);
    for (double h : prof.kinks())
      if (h >= 0 && h <= top) e.kink_h.push_back(h);
    std::sort(e.kink_h.begin(), e.kink_h.end());
    e.suffix_max.assign(e.kink_h.size(), 0.0);
    double mx = 0.0;
    for (std::size_t j = e.kink_h.size(); j-- > 0;) {
      mx = std::max(mx, prof(e.kink_h[j]));
      e.suffix_max[j] = mx;
    }
    e.rho_top = prof(top);
  }
  m.od = std::make_unique<OpticalDepthReference>(atm_);
  if (opt_.sun_depth == RtSunDepth::Exact) {
    m.exact_sun = true;
    sun_depth_rel_error_ = 1e-12;
  } else {
    if (opt_.table_shells < 4 || opt_.table_shells > 4096)
      throw InputError("table_shells = " + std::to_string(opt_.table_shells) + ": must be in [4, 4096]");
    if (opt_.table_directions < 4 || opt_.table_directions > 65536)
      throw InputError("table_directions = " + std::to_string(opt_.table_directions) + ": must be in [4, 65536]");
    LutOptions lo;
    lo.shells = opt_.table_shells;
    lo.view_directions = opt_.table_directions;
    lo.sun_directions = opt_.table_directions;
    lo.view_tables = false;
    lo.threads = opt_.run.threads;
    m.lut = std::make_unique<OpticalDepthLut>(atm_, lo);
    sun_depth_rel_error_ = m.lut->estimate_max_rel_error();
  }
}

MonteCarloSky::~MonteCarloSky() = default;

RtSkyResult MonteCarloSky::radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const {
  return radiance(altitude_m, view, sun, opt_.run);
}

RtSkyResult MonteCarloSky::radiance(double altitude_m, const glm::dvec3& view_in, const glm::dvec3& sun_in,
                                    const RtOptions& run) const {
  check_run(run);
  if (!std::isfinite(altitude_m) || altitude_m < 0)
    throw InputError("observer altitude " + std::to_string(altitude_m) + " m: must be finite and >= 0");
  const glm::dvec3 view = unit(view_in, "view");
  const glm::dvec3 sun = unit(sun_in, "sun");
  const auto t0 = std::chrono::steady_clock::now();
  const SphereModel& m = impl_->model;
  const std::size_t nw = atm_.wavelengths_nm().size();
  const double albedo = opt_.ground_albedo >= 0 ? opt_.ground_albedo : atm_.spec().planet.ground_albedo;
  const double scale = 1.0 / (opt_.sun_distance_au * opt_.sun_distance_au);
  const glm::dvec3 origin(0.0, 0.0, m.R + altitude_m);

  // The view ray's nodes and columns (the first collision's sampling).
  const ViewRay vray = make_view_ray(m, origin, view);

  // The pilot of the guided first scattering, per wavelength (its own stream).
  const bool guided = !vray.empty && vray.s.size() >= 2 &&
                      (opt_.guide == RtLineEstimate::On ||
                       (opt_.guide == RtLineEstimate::DeepTwilight && sun.z < std::sin(opt_.guide_below_deg * kPi / 180.0)));
  // The guide steers vertices toward where the line estimate finds light: it implies it.
  const bool line = guided || opt_.line_estimate == RtLineEstimate::On ||
                    (opt_.line_estimate == RtLineEstimate::DeepTwilight &&
                     sun.z < std::sin(kRtDeepTwilightDeg * kPi / 180.0));
  std::vector<FirstGuide> guides(nw);
  if (guided)
    parallel_for(nw, run.threads, [&](std::size_t i) {
      FirstGuide& G = guides[i];
      const SphereMedium med(m, atm_.coefficients(i), solar_[i] * scale, sun, std::max(albedo, 0.0), vray,
                             opt_.sun_cone_share, opt_.sun_cone_half_angle_deg, true);
      const std::size_t np = vray.s.size() - 1;
      const std::size_t K = std::min<std::size_t>(static_cast<std::size_t>(opt_.guide_points), np);
      G.nz = opt_.guide_zenith;
      G.nphi = opt_.guide_azimuth;
      for (int e = 0; e <= G.nz; ++e) {
        const double u = -1.0 + 2.0 * e / G.nz;
        G.z_edges.push_back(u < 0 ? -u * u : u * u);
      }
      G.z_edges.front() = -1.0;
      G.z_edges.back() = 1.0;
      const std::size_t nc = static_cast<std::size_t>(G.nz) * G.nphi;
      G.cell_p.assign(K * nc, 0.0);
      G.cell_cdf.assign(K * (nc + 1), 0.0);
      std::vector<double> gk(K, 0.0);
      Rng rng(run.seed, 0x6775696465ull + i, 0x70696C6F74ull);
      for (std::size_t k = 0; k < K; ++k) {
        const std::size_t j = std::min(np - 1, static_cast<std::size_t>((k + 0.5) * static_cast<double>(np) / K));
        G.s.push_back(0.5 * (vray.s[j] + vray.s[j + 1]));
        G.h.push_back(glm::length(vray.o + G.s.back() * vray.v) - m.R);
        double* cell = &G.cell_p[k * nc];
        const double nee = med.pilot(vray.o + G.s.back() * vray.v, vray.v, G, rng, cell);
        double sum = 0.0;
        for (std::size_t c = 0; c < nc; ++c) sum += cell[c];
        gk[k] = nee + sum;
        for (std::size_t c = 0; c < nc; ++c)  // no light found: cells by solid angle
          cell[c] = sum > 0 && std::isfinite(sum)
                        ? cell[c] / sum
                        : (G.z_edges[c / G.nphi + 1] - G.z_edges[c / G.nphi]) / (2.0 * static_cast<double>(G.nphi));
        double* cdf = &G.cell_cdf[k * (nc + 1)];
        for (std::size_t c = 0; c < nc; ++c) cdf[c + 1] = cdf[c] + cell[c];
        for (std::size_t c = 0; c <= nc; ++c) cdf[c] /= cdf[nc];
        cdf[nc] = 1.0;
      }
      // The value at every piece: log-linear between the pilot points (constant
      // beyond), 1e-30 of the largest where the pilot found none.
      const double gmax = *std::max_element(gk.begin(), gk.end());
      if (!(gmax > 0) || !std::isfinite(gmax)) return;  // nothing lit: the plain sampling
      std::vector<double> lg(K);
      for (std::size_t k = 0; k < K; ++k) lg[k] = std::log(std::max(gk[k], 1e-30 * gmax));
      G.g_piece.resize(np);
      for (std::size_t j = 0; j < np; ++j) {
        const double sm = 0.5 * (vray.s[j] + vray.s[j + 1]);
        const auto it = std::lower_bound(G.s.begin(), G.s.end(), sm);
        double l;
        if (it == G.s.begin()) l = lg.front();
        else if (it == G.s.end()) l = lg.back();
        else {
          const std::size_t k = static_cast<std::size_t>(it - G.s.begin());
          const double f = (sm - G.s[k - 1]) / (G.s[k] - G.s[k - 1]);
          l = (1.0 - f) * lg[k - 1] + f * lg[k];
        }
        G.g_piece[j] = std::exp(l);
      }
      G.active = true;
    });

  const std::int64_t per_wl = std::max<std::int64_t>(1, run.paths / static_cast<std::int64_t>(nw));
  const std::int64_t B = std::min<std::int64_t>(run.batches, per_wl);
  std::vector<Sums> part(nw * static_cast<std::size_t>(B));
  parallel_for(part.size(), run.threads, [&](std::size_t task) {
    const std::size_t i = task / static_cast<std::size_t>(B);
    const std::int64_t b = static_cast<std::int64_t>(task % static_cast<std::size_t>(B));
    const Coefficients& k = atm_.coefficients(i);
    const SphereMedium med(m, k, solar_[i] * scale, sun, std::max(albedo, 0.0), vray, opt_.sun_cone_share,
                           opt_.sun_cone_half_angle_deg, line, &guides[i], opt_.guide_share, opt_.guide_defensive);
    const std::int64_t n = per_wl / B + (b < per_wl % B ? 1 : 0);
    Rng rng(run.seed, i, static_cast<std::uint64_t>(b));
    Sums s;
    for (std::int64_t j = 0; j < n; ++j) {
      SphereMedium::Ray ray;
      ray.p = origin;
      ray.d = view;
      s.add(trace(med, ray, rng, run, true, s.orders));
    }
    part[task] = s;
  });

  RtSkyResult out;
  out.wavelengths_nm = atm_.wavelengths_nm();
  out.radiance.assign(nw, 0.0);
  out.radiance_stderr.assign(nw, 0.0);
  double orders = 0;
  for (std::size_t i = 0; i < nw; ++i) {
    Sums s;
    for (std::int64_t b = 0; b < B; ++b) s.merge(part[i * static_cast<std::size_t>(B) + static_cast<std::size_t>(b)]);
    out.radiance[i] = s.mean();
    out.radiance_stderr[i] = s.stderr_();
    orders += s.orders;
  }
  const SpectralToXyz to_xyz(out.wavelengths_nm);
  out.xyz = to_xyz(out.radiance);
  double vx = 0, vy = 0, vz = 0;
  for (std::size_t i = 0; i < nw; ++i) {
    const Cmf& w = to_xyz.weights()[i];
    const double e2 = out.radiance_stderr[i] * out.radiance_stderr[i];
    vx += w.x * w.x * e2;
    vy += w.y * w.y * e2;
    vz += w.z * w.z * e2;
  }
  out.xyz_stderr = Xyz{std::sqrt(vx), std::sqrt(vy), std::sqrt(vz)};
  out.luminance = out.xyz.Y;
  out.luminance_stderr = out.xyz_stderr.Y;
  out.paths_per_wavelength = per_wl;
  out.paths = per_wl * static_cast<std::int64_t>(nw);
  out.mean_orders = orders / static_cast<double>(out.paths);
  out.sun_depth_rel_error = sun_depth_rel_error_;
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

RtConvergence rt_time_to_rel_stderr(const MonteCarloSky& sky, double sun_elevation_deg, double target_rel_stderr,
                                    double max_seconds, std::int64_t first_paths, const RtOptions& run) {
  if (!(target_rel_stderr > 0)) throw InputError("target relative standard error must be > 0");
  if (!(max_seconds > 0)) throw InputError("time budget must be > 0 s");
  RtConvergence c;
  c.target_rel_stderr = target_rel_stderr;
  c.threads = resolve_threads(run.threads);
  RtOptions o = run;
  o.paths = std::max<std::int64_t>(first_paths, 1);
  const glm::dvec3 sun = enu_direction(sun_elevation_deg, 180.0);
  const glm::dvec3 zenith(0, 0, 1);
  for (;;) {
    const RtSkyResult r = sky.radiance(0.0, zenith, sun, o);
    c.paths = r.paths;
    c.time_s = r.time_s;
    c.luminance = r.luminance;
    c.reached_rel_stderr = r.luminance > 0 ? r.luminance_stderr / r.luminance : 1.0;
    c.paths_per_second = r.time_s > 0 ? static_cast<double>(r.paths) / r.time_s : 0.0;
    c.extrapolated_time_s = r.time_s * std::pow(std::max(c.reached_rel_stderr / target_rel_stderr, 1.0), 2);
    if (c.reached_rel_stderr <= target_rel_stderr) {
      c.reached = true;
      break;
    }
    // Paths needed ~ paths (rel / target)^2; at least double, predicted time within budget.
    const double need = static_cast<double>(r.paths) * std::pow(c.reached_rel_stderr / target_rel_stderr, 2) * 1.1;
    const double next = std::max(need, 2.0 * static_cast<double>(r.paths));
    if (r.time_s * next / static_cast<double>(r.paths) > max_seconds) break;
    o.paths = static_cast<std::int64_t>(next);
  }
  return c;
}

std::vector<RtViewDirection> rt_reference_view_set() {
  return {{90, 0}, {5, 0}, {5, 90}, {5, 180}, {30, 180}, {60, 180}};
}

std::vector<double> rt_reference_sun_elevations() { return {60, 30, 10, 0, -3, -6, -9, -12, -15}; }

std::vector<RtReferenceRow> rt_reference_views(const MonteCarloSky& sky, const std::vector<RtViewDirection>& views,
                                               const std::vector<double>& sun_elevations_deg, double altitude_m,
                                               const RtOptions& run) {
  std::vector<RtReferenceRow> rows;
  std::uint64_t k = 0;
  for (double se : sun_elevations_deg)
    for (const auto& v : views) {
      RtReferenceRow row;
      row.sun_elevation_deg = se;
      row.view_elevation_deg = v.elevation_deg;
      row.view_relative_azimuth_deg = v.relative_azimuth_deg;
      RtOptions o = run;
      o.seed = run.seed + 0x9E3779B9ull * ++k;  // independent streams per row
      row.result = sky.radiance(altitude_m, enu_direction(v.elevation_deg, 180.0 + v.relative_azimuth_deg),
                                enu_direction(se, 180.0), o);
      rows.push_back(std::move(row));
    }
  return rows;
}

}  // namespace atmosh::atmo
