#include "atmosh/gpu/sky.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "atmosh/atmo/colour.hpp"
#include "atmosh/atmo/shared/geometry.glsl.hpp"
#include "atmosh/atmo/shared/lut.glsl.hpp"
#include "atmosh/atmo/shared/ms_approx.glsl.hpp"
#include "atmosh/atmo/shared/orders.glsl.hpp"
#include "atmosh/atmo/shared/sky_params.glsl.hpp"
#include "atmosh/atmo/shared/view_ray.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/gpu/orders.hpp"
#include "atmosh/gpu/program.hpp"
#include "sun_inputs.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/quadrature.hpp"

namespace atmosh::gpu {

namespace {

namespace sg = atmo::shared;
using atmo::DensityProfileSpec;

using sg::kMaxWavelengths;
constexpr int kMaxOzoneNodes = sg::kMaxLinearNodes;  // GLSL build of shared/geometry.glsl.hpp

// The parameter block's C++ layout is its std430 layout (shared/sky_params.glsl.hpp):
// doubles first, then 4-byte scalars and scalar arrays, no padding.
using Params = sg::GpuSkyParams;
static_assert(sizeof(double) == 8 && sizeof(float) == 4 && sizeof(int) == 4);
static_assert(offsetof(Params, cut_radii) == 32 && offsetof(Params, gauss_x) == 32 + 8 * sg::kMaxCutSpheres);
static_assert(offsetof(Params, build_scale_height) == offsetof(Params, part_w) + 8 * sg::kMaxPartWeights);
static_assert(offsetof(Params, ground_radius) == offsetof(Params, build_scale_height) + 8);
static_assert(sizeof(sg::GpuLinearNodes) == 4 * (3 * sg::kMaxLinearNodes + 1));
static_assert(sizeof(sg::GpuRamps) == 4 * (2 * sg::kMaxLinearNodes + 1));
static_assert(offsetof(Params, ozone) == offsetof(Params, albedo) + 4);
static_assert(offsetof(Params, n_items) == offsetof(Params, build_ramps) + 3 * sizeof(sg::GpuRamps));
static_assert(offsetof(Params, ms_altitudes) == offsetof(Params, log_encoded) + 3 * sizeof(int));
static_assert(sizeof(Params) == offsetof(Params, ms_unused) + sizeof(int));

// Closed-form column at lookup (OpticalDepthLut: piecewise-linear profiles with
// few nodes), else interpolated from the tables.
bool analytic(const atmo::Atmosphere& atm, const atmo::LutOptions& o, int c) {
  const auto& p = atm.profile(c);
  return atm.has(c) && p.kind() != DensityProfileSpec::Kind::Exponential &&
         static_cast<int>(p.kinks().size()) <= o.analytic_max_nodes;
}

bool tabulated(const atmo::Atmosphere& atm, int c) {
  return atm.has(c) && atm.vertical_column()[c] > 0.0 && !analytic(atm, atmo::LutOptions{}, c);
}

// (altitude, value) nodes of a piecewise-linear profile.
void profile_nodes(const atmo::DensityProfile& p, std::vector<double>& h, std::vector<double>& v) {
  const auto& spec = p.spec();
  if (spec.kind == DensityProfileSpec::Kind::Tent) {
    h = {spec.bottom_m, spec.peak_m, spec.top_m};
    v = {0.0, 1.0, 0.0};
  } else {
    h = spec.altitude_m;
    v = spec.value;
  }
}

// The nodes of a closed-form column as the parameter block holds them (radius, value,
// slope to the next node; at most kMaxLinearNodes, the GLSL build's array size).
sg::GpuLinearNodes linear_nodes(const atmo::PiecewiseLinearColumn& p) {
  sg::GpuLinearNodes g{};
  const auto& r = p.node_radii();
  const auto& v = p.node_values();
  g.n = std::min(p.nodes(), sg::kMaxLinearNodes);
  for (int i = 0; i < g.n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    g.radius[i] = static_cast<float>(r[k]);
    g.value[i] = static_cast<float>(v[k]);
    g.slope[i] = static_cast<float>(k + 1 < r.size() ? (v[k + 1] - v[k]) / (r[k + 1] - r[k]) : 0.0);
  }
  return g;
}

// Quadratic ramps as the parameter block holds them: radius - R0 (R0 = 0: the radius,
// R0 = R: the altitude), half curvature; at most kMaxLinearNodes.
sg::GpuRamps ramps(const atmo::QuadraticRampsColumn& q, double R0) {
  sg::GpuRamps g{};
  g.n = std::min(q.ramps(), sg::kMaxLinearNodes);
  for (int k = 0; k < g.n; ++k) {
    g.radius[k] = static_cast<float>(q.ramp_radii()[static_cast<std::size_t>(k)] - R0);
    g.half_curv[k] = static_cast<float>(q.half_curvatures()[static_cast<std::size_t>(k)]);
  }
  return g;
}

// The integrator's table entries (log of the mean relative density), recovered
// exactly at the table nodes through the public lookup: at a node the Lagrange
// weights are 1 and 0, so lookup / distance is the stored mean.
}  // namespace

std::vector<float> lut_tables_from_cpu(const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm, int& off_ground,
                                       int& off_sun) {
  const auto& radii = lut.shell_radii();
  const double R = atm.ground_radius(), T = atm.top_radius(), Hh = std::sqrt((T - R) * (T + R));
  const int S = static_cast<int>(radii.size());
  // No view tables in a sun-only build (LutOptions::view_tables, e.g. the sky's): the
  // view parts are empty and off_ground = off_sun = 0.
  const int nv = lut.options().view_tables ? lut.options().view_directions : 0, ns = lut.options().sun_directions;
  std::vector<float> out;
  out.reserve(static_cast<std::size_t>(S) * (2 * nv + ns) * 3);
  // Once per constituent (its vertical column is an integral over the profile: asked per
  // entry it was nearly all of this function's time).
  const bool tab[3] = {tabulated(atm, 0), tabulated(atm, 1), tabulated(atm, 2)};
  auto table = [&](int n, int kind) {  // 0 view up, 1 view ground, 2 sun
    for (int k = 0; k < S; ++k) {
      const double r = radii[static_cast<std::size_t>(k)];
      const double rho = std::sqrt(std::max(0.0, (r - R) * (r + R)));
      for (int j = 0; j < n; ++j) {
        const double x = static_cast<double>(j) / (n - 1);
        glm::dvec3 mean = lut.tabulated_density(r - R);
        const double d = sg::lut_table_distance(r, rho, x, R, T, Hh, kind == 1);  // the entry's ray
        if (kind != 1) {
          if (d > 0.0) {
            double mu = sg::lut_table_mu(r, rho, d, T, false);
            atmo::LutColumn c = kind == 0 ? lut.view(r, mu) : lut.sun(r, mu);
            for (int t = 0; t < 64 && (c.hits_ground || sg::ray_hits_ground(r, mu, R)); ++t) {
              mu = std::nextafter(mu, 2.0);  // grazing node rounded into the ground
              c = kind == 0 ? lut.view(r, mu) : lut.sun(r, mu);
            }
            const double dd = sg::distance_to_top(r, mu, T);
            if (dd > 0.0) mean = (c.column - lut.subtracted_column(r, mu, dd)) / dd;
          }
        } else {
          if (d > 0.0) {
            double mu = sg::lut_table_mu(r, rho, d, T, true);
            atmo::LutColumn c = lut.view(r, mu);
            for (int t = 0; t < 64 && !c.hits_ground; ++t) {
              mu = std::nextafter(mu, -2.0);
              c = lut.view(r, mu);
            }
            const double dd = sg::distance_to_ground(r, mu, R);
            if (dd > 0.0) mean = (c.column - lut.subtracted_column(r, mu, dd)) / dd;
          }
        }
        for (int c = 0; c < 3; ++c)
          out.push_back(tab[c] ? static_cast<float>(std::log(std::max(mean[c], 1e-300))) : 0.0f);
      }
    }
  };
  table(nv, 0);
  off_ground = static_cast<int>(out.size());
  table(nv, 1);
  off_sun = static_cast<int>(out.size());
  table(ns, 2);
  return out;
}

std::vector<ShaderPart> sky_pass_parts() {
  std::vector<ShaderPart> parts = sky_parts("gpu/shaders/sky.comp");
  const auto at = std::find_if(parts.begin(), parts.end(), [](const ShaderPart& p) {
    return p.path == "libatmo/include/atmosh/atmo/shared/view_ray.glsl.hpp";
  });
  parts.insert(at + 1, embedded_source("libatmo/include/atmosh/atmo/shared/orders.glsl.hpp"));
  parts.insert(parts.end() - 1, embedded_source("gpu/shaders/sky_orders.glsl"));
  parts.insert(parts.end() - 1, embedded_source("gpu/shaders/orders_lookup.glsl"));
  return parts;
}

std::vector<ShaderPart> sky_parts(const std::string& main_shader) {
  const ShaderPart lut = embedded_source("libatmo/include/atmosh/atmo/shared/lut.glsl.hpp");
  const ShaderPart scatter = embedded_source("libatmo/include/atmosh/atmo/shared/scatter.glsl.hpp");
  const ShaderPart geometry = embedded_source("libatmo/include/atmosh/atmo/shared/geometry.glsl.hpp");
  const ShaderPart ms = embedded_source("libatmo/include/atmosh/atmo/shared/ms_approx.glsl.hpp");
  return {geometry,
          lut,
          scatter,
          ms,
          real_type_part("double"),
          geometry,  // its ray geometry again, in double (the rest is pasted once)
          lut,
          scatter,
          ms,
          embedded_source("libatmo/include/atmosh/atmo/shared/view_ray.glsl.hpp"),
          embedded_source("libatmo/include/atmosh/atmo/shared/sky_params.glsl.hpp"),
          embedded_source("gpu/shaders/sky_lib.glsl"),
          real_type_part("float"),
          embedded_source(main_shader)};
}

namespace {

int phase_code(atmo::PhaseSpec::Model m) {
  using M = atmo::PhaseSpec::Model;
  switch (m) {
    case M::Rayleigh: return 0;
    case M::HenyeyGreenstein: return 1;
    case M::CornetteShanks: return 2;
    case M::DoubleHenyeyGreenstein: return 3;
    default: return -1;
  }
}

atmo::PhaseSpec phase_spec(const atmo::Atmosphere& atm, int c) {
  const auto& s = atm.spec();
  if (c == 0) return s.rayleigh ? s.rayleigh->phase : atmo::PhaseSpec::of(atmo::PhaseSpec::Model::Rayleigh);
  return s.mie ? s.mie->phase : atmo::PhaseSpec::of(atmo::PhaseSpec::Model::HenyeyGreenstein, 0.0);
}

}  // namespace

std::string sky_unsupported_reason(const atmo::SkyIntegrator& sky) {
  const auto& atm = sky.atmosphere();
  const auto& lo = sky.lut().options();
  if (lo.analytic_max_nodes != atmo::LutOptions{}.analytic_max_nodes) return "non-default lut analytic_max_nodes";
  const double top = atm.top_altitude();
  for (int c = 0; c < 2; ++c)
    if (atm.has(c) && (analytic(atm, lo, c) || !atm.profile(c).positive_on(top)))
      return std::string(c == 0 ? "rayleigh" : "mie") + " profile is not positive up to the top";
  if (atm.has(atmo::kOzone)) {
    const auto& p = atm.profile(atmo::kOzone);
    if (!analytic(atm, lo, atmo::kOzone)) return "ozone profile is not piecewise linear with few nodes";
    const int nodes = static_cast<int>(p.kind() == DensityProfileSpec::Kind::Tent ? 3 : p.spec().altitude_m.size());
    if (nodes > kMaxOzoneNodes || static_cast<int>(p.kinks().size()) > sky.lut().options().analytic_max_nodes)
      return "ozone profile has more than " + std::to_string(kMaxOzoneNodes) + " nodes";
  }
  for (int c = 0; c < 2; ++c)
    if (atm.has(c) && phase_code(phase_spec(atm, c).model) < 0) return "tabulated phase functions";
  if (atm.wavelengths_nm().size() > static_cast<std::size_t>(kMaxWavelengths))
    return "more than " + std::to_string(kMaxWavelengths) + " wavelengths";
  if (sky.options().segments - 1 > sg::kMaxCutSpheres)
    return "more than " + std::to_string(sg::kMaxCutSpheres + 1) + " view-ray segments";
  return "";
}

namespace {

// The inputs of sky_lib.glsl that depend on the integrator alone: its optical-depth
// tables and shells, the piecewise-linear densities and the spectral coefficients in
// storage buffers, and the parameter block's fields that describe them (with the
// closed-form nodes of ozone and the subtracted kinks, the cut radii and the quadrature). Shared by the
// sky pass and the sun-lookup pass, so both run on the same data.
class SkyInputs {
 public:
  SkyInputs(const Context& ctx, const atmo::SkyIntegrator& sky, bool gpu_tables);
  void bind() const {
    b_shell_d_->bind(ATMOSH_BIND_SHELLS);
    b_tab_->bind(ATMOSH_BIND_TABLES);
    b_shell_->bind(ATMOSH_BIND_NODES);
    b_spec_->bind(ATMOSH_BIND_SPECTRAL);
    if (b_ms_) b_ms_->bind(ATMOSH_BIND_MS_TABLE);
    if (b_orders_params_) {
      orders_table_->bind(ATMOSH_SKY_BIND_ORDERS);
      b_orders_ground_->bind(ATMOSH_SKY_BIND_ORDERS_GROUND);
      b_orders_params_->bind(ATMOSH_SKY_BIND_ORDERS_PARAMS);
    }
  }
  // The successive-orders tables the sky pass looks up (sky_orders.glsl): those of
  // `orders` — its radiance table bound where it is, if the GPU passes of this context
  // kept it (gpu::OrdersTables::Resident), else its CPU copy uploaded; the ground table
  // uploaded — or none (op.nr = 0: no orders term).
  void set_orders_tables(const Context& ctx, const atmo::ScatteringOrders* orders, const atmo::Atmosphere& atm) {
    sg::GpuOrdersParams op{};
    const float zero = 0.0f;
    if (orders) {
      const std::vector<int> n = orders->table_size();
      op.R = atm.ground_radius();
      op.T = atm.top_radius();
      op.H = std::sqrt(op.T * op.T - op.R * op.R);  // as ScatteringOrders'
      op.sun_m = orders->sun_m();
      op.albedo = atm.spec().planet.ground_albedo;
      op.nr = n[0], op.nmu = n[1], op.nh = n[1] / 2, op.ns = n[2], op.na = n[3];
      op.nw = static_cast<int>(orders->wavelengths());
      const auto& g = orders->ground_table();
      const auto* kept = dynamic_cast<const OrdersResidentTable*>(orders->device_table());
      if (kept && &kept->context() == &ctx) {
        orders_table_ = &kept->buffer();
      } else if (orders->device_table()) {
        throw Unsupported("GPU sky: the orders table is kept on another GPU context");
      } else {
        const auto& t = orders->radiance_table();
        b_orders_ = std::make_unique<Buffer>(t.size() * sizeof(float), t.data());
        orders_table_ = b_orders_.get();
      }
      b_orders_ground_ = std::make_unique<Buffer>(g.size() * sizeof(float), g.data());
    } else {
      b_orders_ = std::make_unique<Buffer>(sizeof(float), &zero);
      orders_table_ = b_orders_.get();
      b_orders_ground_ = std::make_unique<Buffer>(sizeof(float), &zero);
    }
    b_orders_params_ = std::make_unique<Buffer>(sizeof(op), &op);
  }
  // The multiple-scattering table the sky pass adds (log Psi, [altitude][sun][wavelength]),
  // `altitudes` x `suns` entries; none: single scattering.
  void set_ms_table(const std::vector<float>& t, int altitudes, int suns) {
    b_ms_ = std::make_unique<Buffer>(t.size() * sizeof(float), t.data());
    p_.ms_altitudes = altitudes;
    p_.ms_suns = suns;
  }
  // The parameter block describing these inputs (the pass adds its own fields).
  const Params& params() const { return p_; }

 private:
  Params p_{};
  std::unique_ptr<Buffer> b_tab_, b_shell_, b_spec_, b_shell_d_, b_ms_, b_orders_, b_orders_ground_, b_orders_params_;
  const Buffer* orders_table_ = nullptr;  // b_orders_ or a resident table's buffer
};

// The constituents' fields of the parameter block common to the sky and table passes.
void set_constituents(Params& p, const atmo::Atmosphere& atm) {
  const double R = atm.ground_radius(), T = atm.top_radius();
  p.ground_radius_d = R;
  p.top_radius_d = T;
  p.horizon_rho_d = std::sqrt((T - R) * (T + R));
  p.ground_radius = static_cast<float>(R);
  p.top_radius = static_cast<float>(T);
  for (int c = 0; c < 3; ++c) {
    const bool expo = atm.has(c) && atm.profile(c).kind() == DensityProfileSpec::Kind::Exponential;
    p.has_ext[c] = atm.has(c) ? 1 : 0;
    p.tabulated[c] = tabulated(atm, c) ? 1 : 0;
    p.scale_height[c] = static_cast<float>(expo ? atm.profile(c).spec().scale_height_m : 1.0);
  }
}

// Binds the parameter block; the buffer lives as long as the pass.
std::unique_ptr<Buffer> bind_params(const Params& p) {
  auto b = std::make_unique<Buffer>(sizeof(Params), &p);
  b->bind(ATMOSH_BIND_PARAMS);
  return b;
}

SkyInputs::SkyInputs(const Context& ctx, const atmo::SkyIntegrator& sky, bool gpu_tables) {
  const auto& atm = sky.atmosphere();
  const auto& lut = sky.lut();
  const double R = atm.ground_radius();
  set_constituents(p_, atm);
  p_.nw = static_cast<int>(atm.wavelengths_nm().size());
  // Tables and shells.
  int off_ground = 0;
  const std::vector<float> tab = gpu_tables ? build_lut_tables(ctx, lut, atm, off_ground, p_.off_sun)
                                            : lut_tables_from_cpu(lut, atm, off_ground, p_.off_sun);
  ctx.make_current();
  p_.n_sun = lut.options().sun_directions;
  // The table's shell parameters and the view-ray cut radii, as libatmo has them.
  const std::vector<double>& rho = lut.shell_rho();
  const std::vector<double>& inv_den = lut.shell_inverse_denominators();
  p_.n_shells = static_cast<int>(rho.size());
  std::vector<double> shells_d = rho;
  shells_d.insert(shells_d.end(), inv_den.begin(), inv_den.end());
  p_.n_cuts = static_cast<int>(sky.cut_radii().size());  // <= kMaxCutSpheres (SkyIntegrator checks)
  std::copy(sky.cut_radii().begin(), sky.cut_radii().end(), p_.cut_radii);
  std::vector<float> shells;
  if (atm.has(atmo::kOzone)) p_.ozone = linear_nodes(atmo::PiecewiseLinearColumn(atm.profile(atmo::kOzone), R));
  for (int c = 0; c < 2; ++c) {
    p_.sub[c] = linear_nodes(lut.subtracted(c));
    p_.subq[c] = ramps(lut.subtracted_curvature(c), 0.0);
  }
  // Piecewise-linear densities (altitude, value) for the shader's density_at.
  for (int c = 0; c < 3; ++c) {
    if (!atm.has(c) || atm.profile(c).kind() == DensityProfileSpec::Kind::Exponential) continue;
    std::vector<double> h, v;
    profile_nodes(atm.profile(c), h, v);
    p_.off_nodes[c] = static_cast<int>(shells.size());
    p_.n_nodes[c] = static_cast<int>(h.size());
    for (double x : h) shells.push_back(static_cast<float>(x));
    for (double x : v) shells.push_back(static_cast<float>(x));
  }
  // Spectral coefficients: ext[3][nw], sca[3][nw], solar[nw].
  const int nw = p_.nw;
  std::vector<float> spec(static_cast<std::size_t>(7 * nw), 0.0f);
  for (int i = 0; i < nw; ++i) {
    const auto& k = atm.coefficients(static_cast<std::size_t>(i));
    for (int c = 0; c < 3; ++c) {
      const double e = atm.has(c) ? k.extinction[c] : 0.0, s = atm.has(c) ? k.scattering[c] : 0.0;
      spec[sg::sky_spectral(c, nw, i)] = static_cast<float>(e);
      spec[sg::sky_spectral(3 + c, nw, i)] = static_cast<float>(s);
      p_.ext_max[c] = std::max(p_.ext_max[c], static_cast<float>(e));
    }
    spec[sg::sky_spectral(6, nw, i)] = static_cast<float>(sky.solar()[static_cast<std::size_t>(i)]);
  }
  const auto gl = sh::gauss_legendre(sky.options().samples_per_segment);
  p_.n_gauss = static_cast<int>(gl.nodes.size());  // <= kMaxPartNodes (SkyIntegrator checks)
  std::copy(gl.nodes.begin(), gl.nodes.end(), p_.gauss_x);
  std::copy(gl.weights.begin(), gl.weights.end(), p_.gauss_w);
  const auto part_w = atmo::sky_part_column_weights(sky.options().samples_per_segment);  // view column in a part
  std::copy(part_w.begin(), part_w.end(), p_.part_w);
  for (int c = 0; c < 2; ++c) {
    const auto ps = phase_spec(atm, c);
    p_.phase_model[c] = phase_code(ps.model);
    p_.phase_p[4 * c] = static_cast<float>(ps.model == atmo::PhaseSpec::Model::Rayleigh ? ps.depolarization : ps.g);
    p_.phase_p[4 * c + 1] = static_cast<float>(ps.g2);
    p_.phase_p[4 * c + 2] = static_cast<float>(ps.weight);
  }
  p_.max_piece_optical_depth = static_cast<float>(sky.options().max_piece_optical_depth);
  p_.irradiance_scale = static_cast<float>(1.0 / (sky.options().sun_distance_au * sky.options().sun_distance_au));
  p_.albedo = static_cast<float>(atm.spec().planet.ground_albedo);
  b_tab_ = std::make_unique<Buffer>(tab.size() * sizeof(float), tab.data());
  b_shell_ = std::make_unique<Buffer>(shells.size() * sizeof(float), shells.data());
  b_spec_ = std::make_unique<Buffer>(spec.size() * sizeof(float), spec.data());
  b_shell_d_ = std::make_unique<Buffer>(shells_d.size() * sizeof(double), shells_d.data());
  const float none = 0.0f;  // never an unbound buffer: the sky pass declares the table
  b_ms_ = std::make_unique<Buffer>(sizeof(float), &none);
}

// Work groups for n items, as (gx, gy) within the per-dimension limit (shared
// ATMOSH_ITEM_GROUP_SIZE and kMaxGroupsX; the shaders' item_index).
void dispatch_items(const Program& prog, std::size_t n) {
  const std::size_t groups = (n + ATMOSH_ITEM_GROUP_SIZE - 1) / ATMOSH_ITEM_GROUP_SIZE;
  const std::size_t gx = std::clamp<std::size_t>(groups, 1, sg::kMaxGroupsX), gy = (groups + gx - 1) / gx;
  prog.dispatch(static_cast<unsigned>(gx), static_cast<unsigned>(std::max<std::size_t>(gy, 1)));
}

// The multiple-scattering table on the GPU (ms_build.comp) from the inputs' sun table:
// one invocation per entry, every wavelength; [entry][wavelength] log Psi.
std::vector<float> ms_table_on_gpu(const SkyInputs& inputs, const atmo::MultipleScatteringOptions& o) {
  atmo::validate(o);
  static const std::vector<ShaderPart> parts = sky_parts("gpu/shaders/ms_build.comp");
  Program prog(parts);
  // The zenith rule's Gauss-Legendre nodes, below then above the horizon (as the CPU).
  const int n_lo = sg::ms_zenith_below(o.ms_zenith_directions), n_hi = o.ms_zenith_directions - n_lo;
  std::vector<double> rule;
  for (int n : {n_lo, n_hi}) {
    const auto gl = sh::gauss_legendre(n);
    rule.insert(rule.end(), gl.nodes.begin(), gl.nodes.end());
    rule.insert(rule.end(), gl.weights.begin(), gl.weights.end());
  }
  Params params = inputs.params();
  const std::size_t entries = static_cast<std::size_t>(o.ms_altitudes) * o.ms_sun_directions;
  params.n_items = static_cast<int>(entries);
  params.ms_altitudes = o.ms_altitudes;
  params.ms_suns = o.ms_sun_directions;
  params.ms_zenith = o.ms_zenith_directions;
  params.ms_azimuths = o.ms_azimuth_directions;
  params.ms_steps = o.ms_ray_steps;
  Buffer b_rule(rule.size() * sizeof(double), rule.data()),
      b_out(entries * static_cast<std::size_t>(params.nw) * sizeof(float));
  inputs.bind();
  b_rule.bind(ATMOSH_BIND_RULE);
  b_out.bind(ATMOSH_BIND_TABLE_OUT);
  const auto b_params = bind_params(params);
  check_gl("multiple-scattering table parameters");
  dispatch_items(prog, entries);
  std::vector<float> t(entries * static_cast<std::size_t>(params.nw));
  b_out.download(t.data(), t.size() * sizeof(float));
  return t;
}

}  // namespace

std::vector<float> build_ms_table(const Context& ctx, const atmo::SkyIntegrator& sky, bool gpu_tables, double* seconds) {
  const std::string why = sky_unsupported_reason(sky);
  if (!why.empty()) throw Unsupported("GPU multiple-scattering table: " + why);
  ctx.make_current();
  const auto t0 = std::chrono::steady_clock::now();
  const SkyInputs inputs(ctx, sky, gpu_tables);
  std::vector<float> t = ms_table_on_gpu(inputs, sky.options().scattering);
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

std::vector<float> ms_table_from_cpu(const atmo::MultipleScatteringLut& lut) {
  std::vector<float> t(lut.log_table().size());
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = static_cast<float>(lut.log_table()[k]);
  return t;
}

atmo::SkyImage render_sky(const Context& ctx, const atmo::SkyIntegrator& sky, atmo::SkyProjection projection,
                          int width, int height, double altitude_m, const glm::dvec3& sun, bool keep_spectral,
                          bool gpu_tables) {
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw InputError("image size " + std::to_string(width) + "x" + std::to_string(height) + " is out of range");
  const std::string why = sky_unsupported_reason(sky);
  if (!why.empty()) throw Unsupported("GPU sky: " + why);
  // Same input validation as the CPU path (throws InputError): the observer's altitude
  // and the sun's direction. An orders table kept on the GPU (OrdersTables::Resident)
  // has no CPU lookup: there the check is make_ray's alone (sun_transmittance, after
  // the sun's direction as make_ray checks it, so that the message names the sun).
  if (sky.orders_tables() && sky.orders_tables()->device_table()) {
    const double n = glm::length(sun);
    if (!std::isfinite(n) || std::fabs(n - 1.0) > 1e-6)
      throw InputError("sun direction (" + std::to_string(sun.x) + ", " + std::to_string(sun.y) + ", " +
                       std::to_string(sun.z) + ") is not a finite unit vector");
    (void)sky.sun_transmittance(altitude_m, sun);
  } else {
    (void)sky.radiance(altitude_m, glm::dvec3(0, 0, 1), sun);
  }
  ctx.make_current();
  const auto t0 = std::chrono::steady_clock::now();
  const auto& atm = sky.atmosphere();
  const int nw = static_cast<int>(atm.wavelengths_nm().size());

  static const std::vector<ShaderPart> parts = sky_pass_parts();
  // The shared walk along the ray with sky.comp's hooks; the approximation's and the orders'
  // terms compiled in only for a sky that has their tables (less code for llvmpipe to
  // compile for the others).
  const bool ms_term = sky.method() == atmo::ScatteringMethod::Approximate;
  Program prog(parts, std::string("#define ATMOSH_SKY_TRACE 1\n") + (ms_term ? "#define ATMOSH_SKY_MS 1\n" : "") +
                          (sky.orders_tables() != nullptr ? "#define ATMOSH_SKY_ORDERS 1\n" : ""));
  SkyInputs inputs(ctx, sky, gpu_tables);
  // Orders: the integrator's tables (built on the CPU, or by the GPU's passes when its
  // options named them: MultipleScatteringOptions::orders_passes), uploaded, or bound
  // where they are when those passes kept them on this context's GPU.
  inputs.set_orders_tables(ctx, sky.orders_tables(), atm);
  if (sky.method() == atmo::ScatteringMethod::Approximate) {
    // The integrator's table (it builds one anyway), or the same table built on the GPU.
    const auto& mo = sky.options().scattering;
    inputs.set_ms_table(gpu_tables || !sky.ms_lut() ? ms_table_on_gpu(inputs, mo) : ms_table_from_cpu(*sky.ms_lut()),
                        mo.ms_altitudes, mo.ms_sun_directions);
  }

  // Pixel directions (the CPU projection).
  const std::size_t n = static_cast<std::size_t>(width) * height;
  std::vector<float> dirs(4 * n, 0.0f);
  atmo::SkyImage img;
  img.width = width;
  img.height = height;
  img.wavelengths_nm = atm.wavelengths_nm();
  img.valid.assign(n, 0);
  // Rows in parallel (the CPU side of a large image is otherwise serial work
  // comparable to the dispatch itself on a fast GPU).
  parallel_for_ranges(static_cast<std::size_t>(height), 8, 0, [&](std::size_t y0, std::size_t y1) {
    for (int y = static_cast<int>(y0); y < static_cast<int>(y1); ++y)
      for (int x = 0; x < width; ++x) {
        glm::dvec3 d;
        const std::size_t p = static_cast<std::size_t>(y) * width + x;
        if (!atmo::sky_pixel_direction(projection, width, height, x, y, d)) continue;
        d = glm::normalize(d);
        dirs[4 * p] = static_cast<float>(d.x);
        dirs[4 * p + 1] = static_cast<float>(d.y);
        dirs[4 * p + 2] = static_cast<float>(d.z);
        dirs[4 * p + 3] = 1.0f;
        img.valid[p] = 1;
      }
  });
  const long rays = static_cast<long>(std::count(img.valid.begin(), img.valid.end(), std::uint8_t{1}));

  Buffer b_dirs(dirs.size() * sizeof(float), dirs.data()), b_out(n * static_cast<std::size_t>(nw) * sizeof(float));
  b_dirs.bind(ATMOSH_BIND_ITEMS);
  b_out.bind(ATMOSH_BIND_RESULT);
  inputs.bind();
  Params params = inputs.params();
  params.n_items = static_cast<int>(n);
  params.observer_radius_d = atm.ground_radius() + std::max(altitude_m, 0.0);
  const glm::dvec3 l = glm::normalize(sun);
  for (int k = 0; k < 3; ++k) params.sun_dir[k] = static_cast<float>(l[k]);
  const auto b_params = bind_params(params);
  check_gl("sky parameters");
  dispatch_items(prog, n);

  std::vector<float> L(n * static_cast<std::size_t>(nw));
  b_out.download(L.data(), L.size() * sizeof(float));
  const atmo::SpectralToXyz cmf(img.wavelengths_nm);
  for (auto* c : {&img.X, &img.Y, &img.Z, &img.R, &img.G, &img.B}) c->assign(n, 0.0f);
  if (keep_spectral) img.spectral.assign(n * static_cast<std::size_t>(nw), 0.0f);
  parallel_for_ranges(n, 4096, 0, [&](std::size_t p0, std::size_t p1) {
    std::vector<double> Ld(static_cast<std::size_t>(nw));
    for (std::size_t p = p0; p < p1; ++p) {
      if (!img.valid[p]) continue;
      for (int i = 0; i < nw; ++i) Ld[i] = L[p * nw + i];
      atmo::store_sky_pixel(img, p, cmf, Ld);  // the CPU image's colour step
    }
  });
  img.rays = rays;
  img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return img;
}

SunLookups sun_lookups(const Context& ctx, const atmo::SkyIntegrator& sky, const std::vector<glm::vec2>& h_mu,
                       int repeats) {
  const std::string why = sky_unsupported_reason(sky);
  if (!why.empty()) throw Unsupported("GPU sun lookups: " + why);
  if (repeats < 1 || repeats > 1000) throw InputError("sun lookups: repeats = " + std::to_string(repeats) + ": must be in [1, 1000]");
  if (h_mu.size() > (std::size_t{1} << 26))
    throw InputError("sun lookups: " + std::to_string(h_mu.size()) + " origins: at most 2^26 per call");
  const double top = sky.atmosphere().top_altitude();
  for (std::size_t i = 0; i < h_mu.size(); ++i)
    if (!(h_mu[i].x >= 0.0f && h_mu[i].x <= top && std::fabs(h_mu[i].y) <= 1.0f))
      throw InputError("sun lookups: origin " + std::to_string(i) + " (altitude " + std::to_string(h_mu[i].x) +
                       " m, mu " + std::to_string(h_mu[i].y) + "): altitude must be in [0, top], |mu| <= 1");
  SunLookups out;
  out.column.assign(h_mu.size(), glm::vec4(0.0f));
  if (h_mu.empty()) return out;
  ctx.make_current();
  static const std::vector<ShaderPart> parts = sky_parts("gpu/shaders/sun_lookup.comp");
  Program prog(parts);
  const SkyInputs inputs(ctx, sky, false);
  std::vector<glm::vec4> in(h_mu.size());
  for (std::size_t i = 0; i < h_mu.size(); ++i) in[i] = glm::vec4(h_mu[i].x, h_mu[i].y, 0.0f, 0.0f);
  Buffer b_in(in.size() * sizeof(glm::vec4), in.data()), b_out(in.size() * sizeof(glm::vec4));
  b_in.bind(ATMOSH_BIND_ITEMS);
  b_out.bind(ATMOSH_BIND_RESULT);
  inputs.bind();
  Params params = inputs.params();
  params.n_items = static_cast<int>(in.size());
  const auto b_params = bind_params(params);
  check_gl("sun lookup parameters");
  dispatch_items(prog, in.size());  // warm-up (shader compilation on first use)
  finish();
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < repeats; ++k) dispatch_items(prog, in.size());
  finish();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.lookups = static_cast<long>(in.size()) * repeats;
  b_out.download(out.column.data(), out.column.size() * sizeof(glm::vec4));
  return out;
}

atmo::SkyImage render_sky(const atmo::SkyIntegrator& sky, atmo::SkyProjection projection, int width, int height,
                          double altitude_m, const glm::dvec3& sun, bool keep_spectral) {
  const std::string why = sky_unsupported_reason(sky);
  if (!why.empty()) throw Unsupported("GPU sky: " + why);
  Context ctx;
  return render_sky(ctx, sky, projection, width, height, altitude_m, sun, keep_spectral);
}


std::vector<float> build_lut_tables(const Context& ctx, const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm,
                                    int& off_ground, int& off_sun, double* seconds) {
  const auto& lo = lut.options();
  const double top = atm.top_altitude();
  if (lo.analytic_max_nodes != atmo::LutOptions{}.analytic_max_nodes)
    throw Unsupported("GPU tables: non-default lut analytic_max_nodes");
  for (int c = 0; c < 3; ++c)
    if (tabulated(atm, c) && !atm.profile(c).positive_on(top))
      throw Unsupported("GPU tables: a tabulated constituent is not positive up to the top");
  ctx.make_current();
  const auto t0 = std::chrono::steady_clock::now();
  static const std::vector<ShaderPart> parts = sky_parts("gpu/shaders/lut_build.comp");
  Program prog(parts);
  const double R = atm.ground_radius();
  const auto& radii = lut.shell_radii();
  std::vector<double> cross(radii.begin(), radii.end());
  for (double k : atm.kinks()) cross.push_back(R + k);
  std::sort(cross.begin(), cross.end());
  const auto gl = sh::gauss_legendre(lo.gauss_points);
  std::vector<double> rule;
  for (double x : gl.nodes) rule.push_back(0.5 * (x + 1.0));
  for (double w : gl.weights) rule.push_back(0.5 * w);
  // Density nodes for sky_lib's density_at: the densities the tables hold (with
  // subtracted kinks: the profile's less p, piecewise linear on its nodes and 0).
  std::vector<float> nodes;
  int off_nodes[3] = {0, 0, 0}, n_nodes[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    if (!atm.has(c) || atm.profile(c).kind() == DensityProfileSpec::Kind::Exponential) continue;
    std::vector<double> h, v;
    profile_nodes(atm.profile(c), h, v);
    if (lut.subtracted(c).nodes() > 0) {
      if (h.front() < 0.0 && h.back() > 0.0 && !std::binary_search(h.begin(), h.end(), 0.0))
        h.insert(std::upper_bound(h.begin(), h.end(), 0.0), 0.0);
      // On the nodes: rho - p (piecewise linear there); q is the shader's (table_density).
      v.clear();
      for (double x : h) v.push_back(lut.tabulated_density(x)[c] + lut.subtracted_curvature(c).at(x));
    }
    off_nodes[c] = static_cast<int>(nodes.size());
    n_nodes[c] = static_cast<int>(h.size());
    for (double x : h) nodes.push_back(static_cast<float>(x));
    for (double x : v) nodes.push_back(static_cast<float>(x));
  }
  const int S = static_cast<int>(radii.size());
  const int nv = lo.view_tables ? lo.view_directions : 0, ns = lo.sun_directions;  // as lut_tables_from_cpu
  nodes.push_back(0.0f);  // never an empty buffer (no profile with nodes)
  Buffer b_nodes(nodes.size() * sizeof(float), nodes.data()), b_cross(cross.size() * sizeof(double), cross.data()),
      b_rule(rule.size() * sizeof(double), rule.data()), b_radii(radii.size() * sizeof(double), radii.data());
  Buffer b_rho(lut.shell_rho().size() * sizeof(double), lut.shell_rho().data());
  b_rho.bind(ATMOSH_BIND_SHELLS);
  b_nodes.bind(ATMOSH_BIND_NODES);
  b_cross.bind(ATMOSH_BIND_CROSSINGS);
  b_rule.bind(ATMOSH_BIND_RULE);
  b_radii.bind(ATMOSH_BIND_SHELL_RADII);
  Params params{};
  set_constituents(params, atm);
  params.n_cross = static_cast<int>(cross.size());
  params.n_rule = static_cast<int>(gl.nodes.size());
  params.build_scale_height = lut.build_scale_height();  // the CPU build's sub-pieces
  for (int c = 0; c < 3; ++c) {
    params.off_nodes[c] = off_nodes[c];
    params.n_nodes[c] = n_nodes[c];
    params.build_ramps[c] = ramps(lut.subtracted_curvature(c), R);
    params.log_encoded[c] = tabulated(atm, c) && atm.profile(c).positive_on(top) ? 1 : 0;
  }
  std::vector<float> out;
  auto run = [&](int n, int kind) {
    const int entries = S * n;
    if (entries == 0) return;
    Buffer b_out(static_cast<std::size_t>(entries) * 3 * sizeof(float));
    b_out.bind(ATMOSH_BIND_TABLE_OUT);
    params.n_dirs = n;
    params.table_kind = kind;
    params.n_items = entries;
    const auto b_params = bind_params(params);
    prog.dispatch(static_cast<unsigned>((entries + 63) / 64));
    std::vector<float> t(static_cast<std::size_t>(entries) * 3);
    b_out.download(t.data(), t.size() * sizeof(float));
    out.insert(out.end(), t.begin(), t.end());
  };
  run(nv, 0);
  off_ground = static_cast<int>(out.size());
  run(nv, 1);
  off_sun = static_cast<int>(out.size());
  if (nv == ns) {  // the sun table's rays are the view table's sky branch (as the CPU build)
    const std::vector<float> up(out.begin(), out.begin() + off_ground);
    out.insert(out.end(), up.begin(), up.end());
  } else {
    run(ns, 0);
  }
  if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

// ---- The sun lookups' inputs for another table (gpu/src/sun_inputs.hpp): SkyInputs'
// fields that sun_lookup and phase_value read, for `lut` (built for `atm`).
SunLookupInputs sun_lookup_inputs(const atmo::OpticalDepthLut& lut, const atmo::Atmosphere& atm) {
  SunLookupInputs in;
  Params& p = in.params;
  set_constituents(p, atm);
  const int nw = static_cast<int>(atm.wavelengths_nm().size());
  p.nw = nw;
  int off_ground = 0;
  in.tables = lut_tables_from_cpu(lut, atm, off_ground, p.off_sun);
  p.n_sun = lut.options().sun_directions;
  in.shells = lut.shell_rho();
  in.shells.insert(in.shells.end(), lut.shell_inverse_denominators().begin(), lut.shell_inverse_denominators().end());
  p.n_shells = static_cast<int>(lut.shell_rho().size());
  if (atm.has(atmo::kOzone))
    p.ozone = linear_nodes(atmo::PiecewiseLinearColumn(atm.profile(atmo::kOzone), atm.ground_radius()));
  for (int c = 0; c < 2; ++c) {
    p.sub[c] = linear_nodes(lut.subtracted(c));
    p.subq[c] = ramps(lut.subtracted_curvature(c), 0.0);
    const auto ps = phase_spec(atm, c);
    p.phase_model[c] = phase_code(ps.model);
    p.phase_p[4 * c] = static_cast<float>(ps.model == atmo::PhaseSpec::Model::Rayleigh ? ps.depolarization : ps.g);
    p.phase_p[4 * c + 1] = static_cast<float>(ps.g2);
    p.phase_p[4 * c + 2] = static_cast<float>(ps.weight);
  }
  in.spectral.assign(static_cast<std::size_t>(7 * nw), 0.0f);
  for (int i = 0; i < nw; ++i) {
    const auto& k = atm.coefficients(static_cast<std::size_t>(i));
    for (int c = 0; c < 3; ++c) {
      in.spectral[sg::sky_spectral(c, nw, i)] = static_cast<float>(atm.has(c) ? k.extinction[c] : 0.0);
      in.spectral[sg::sky_spectral(3 + c, nw, i)] = static_cast<float>(atm.has(c) ? k.scattering[c] : 0.0);
    }
  }
  return in;
}

}  // namespace atmosh::gpu
