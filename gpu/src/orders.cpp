#include "atmosh/gpu/orders.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "atmosh/atmo/shared/orders.glsl.hpp"
#include "atmosh/error.hpp"
#include "atmosh/gpu/program.hpp"
#include "atmosh/gpu/sky.hpp"
#include "sun_inputs.hpp"

namespace atmosh::gpu {

namespace {

namespace sg = atmo::shared;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The parameter block's C++ layout is its std430 layout (shared/orders.glsl.hpp).
static_assert(sizeof(sg::GpuOrdersParams) == 5 * 8 + 25 * 4 + 4);
static_assert(offsetof(sg::GpuOrdersParams, nr) == 40);
static_assert(sizeof(sg::OrdersRayCoord) == 16);

std::vector<ShaderPart> orders_parts(const std::string& main_shader) {
  const ShaderPart geometry = embedded_source("libatmo/include/atmosh/atmo/shared/geometry.glsl.hpp");
  return {geometry,
          real_type_part("double"),
          geometry,  // its ray geometry again, in double
          embedded_source("libatmo/include/atmosh/atmo/shared/orders.glsl.hpp"),
          embedded_source("gpu/shaders/orders_lib.glsl"),
          embedded_source("gpu/shaders/orders_lookup.glsl"),  // on orders_lib's tab_in
          embedded_source(main_shader)};
}

template <class T>
std::unique_ptr<Buffer> buffer_of(const std::vector<T>& v) {
  const T zero{};
  return v.empty() ? std::make_unique<Buffer>(sizeof(T), &zero) : std::make_unique<Buffer>(v.size() * sizeof(T), v.data());
}

// 1-D items in work groups of 64, as (gx, gy) within the per-dimension limit (the
// shaders' orders_item).
void dispatch_items(const Program& prog, std::size_t n) {
  const std::size_t groups = std::max<std::size_t>((n + 63) / 64, 1);
  const std::size_t gx = std::min<std::size_t>(groups, 65535), gy = (groups + gx - 1) / gx;
  prog.dispatch(static_cast<unsigned>(gx), static_cast<unsigned>(gy));
}

// The S_1 pass's parts: the sky pass's (sun_lookup, phase_value) with the shared orders
// block in double after the view-ray block.
std::vector<ShaderPart> single_parts() {
  std::vector<ShaderPart> parts = sky_parts("gpu/shaders/orders_single.comp");
  const auto at = std::find_if(parts.begin(), parts.end(), [](const ShaderPart& p) {
    return p.path == "libatmo/include/atmosh/atmo/shared/view_ray.glsl.hpp";
  });
  parts.insert(at + 1, embedded_source("libatmo/include/atmosh/atmo/shared/orders.glsl.hpp"));
  return parts;
}

class OrdersGpuPasses final : public atmo::OrdersPasses {
 public:
  bool single_on_device() const override { return true; }

  OrdersGpuPasses(const Context& ctx, OrdersGpuTimes* times, OrdersTables where)
      : ctx_(ctx), times_(times), where_(where) {}
  OrdersGpuPasses(std::shared_ptr<const Context> ctx, OrdersGpuTimes* times, OrdersTables where)
      : own_(std::move(ctx)), ctx_(*own_), times_(times), where_(where) {}

  void begin(const atmo::OrdersSetup& s) override {
    if (s.nw > ATMOSH_ORDERS_MAX_WAVELENGTHS)
      throw Unsupported("GPU orders: " + std::to_string(s.nw) + " wavelengths (at most " +
                        std::to_string(ATMOSH_ORDERS_MAX_WAVELENGTHS) + ")");
    ctx_.make_current();
    auto t0 = Clock::now();
    incoming_ = std::make_unique<Program>(orders_parts("gpu/shaders/orders_incoming.comp"));
    density_ = std::make_unique<Program>(orders_parts("gpu/shaders/orders_density.comp"));
    ground_ = std::make_unique<Program>(orders_parts("gpu/shaders/orders_ground.comp"));
    radiance_ = std::make_unique<Program>(orders_parts("gpu/shaders/orders_radiance.comp"));
    if (where_ != OrdersTables::ReadBack && !log_)
      log_ = std::make_unique<Program>(orders_parts("gpu/shaders/orders_log.comp"));
    if (times_) times_->compile_s += since(t0);
    t0 = Clock::now();
    sg::GpuOrdersParams& p = p_;
    p = sg::GpuOrdersParams{};
    p.R = s.R, p.T = s.T, p.H = s.H, p.sun_m = s.sun_m, p.albedo = s.albedo;
    p.nr = s.nr, p.nmu = s.nmu, p.nh = s.half, p.ns = s.ns, p.na = s.na, p.nn = s.nn;
    p.nz = s.nz, p.nphi = s.nphi, p.ng = s.n_ground, p.nw = static_cast<int>(s.nw);
    std::vector<double> geom = s.sphere_mu;
    auto put = [&](int& off, const std::vector<double>& v) {
      off = static_cast<int>(geom.size());
      geom.insert(geom.end(), v.begin(), v.end());
    };
    put(p.off_sphere_w, s.sphere_w);
    put(p.off_d_ground, s.d_ground);
    put(p.off_cphi, s.cphi);
    put(p.off_sphi, s.sphi);
    put(p.off_up_mu, s.up_mu);
    put(p.off_up_w, s.up_w);
    put(p.off_ray_mu, s.ray_mu);
    put(p.off_sr, s.sr);
    put(p.off_sm, s.sm);
    put(p.off_rho_r, s.rho_r);
    put(p.off_rho_m, s.rho_m);
    std::vector<float> gt = s.t_ground;
    p.off_sun_ground = static_cast<int>(gt.size());
    gt.insert(gt.end(), s.sun_ground.begin(), s.sun_ground.end());
    n_tab_ = static_cast<std::size_t>(s.nr) * s.nmu * s.ns * s.na * s.nw;
    const std::size_t nq = static_cast<std::size_t>(s.nz) * s.nphi;
    n_incoming_ = static_cast<std::size_t>(s.nr) * s.ns * nq;
    b_geom_ = buffer_of(geom);
    b_nodes_ = buffer_of(s.node);
    b_coords_ = buffer_of(s.node_coord);
    b_ray_t_ = buffer_of(s.ray_t);
    b_pr_ = buffer_of(s.Pr);
    b_pm_ = buffer_of(s.Pm);
    b_gt_ = buffer_of(gt);
    if (s.single) {
      b_prev_ = buffer_of(*s.single);
    } else {  // S_1 here: sky_lib.glsl's sun lookups on the build's own optical-depth tables
      b_prev_ = std::make_unique<Buffer>(n_tab_ * sizeof(float));
      finish();
      if (times_) times_->upload_s += since(t0);
      auto t1 = Clock::now();
      const Program single(single_parts());
      if (times_) times_->compile_s += since(t1);
      t1 = Clock::now();
      const SunLookupInputs in = sun_lookup_inputs(*s.lut, *s.atmosphere);
      const auto b_tab = buffer_of(in.tables), b_shells = buffer_of(in.shells), b_spec = buffer_of(in.spectral);
      const auto b_sky = std::make_unique<Buffer>(sizeof(in.params), &in.params);
      const auto b_dens = buffer_of(s.node_dens);
      b_tab->bind(ATMOSH_BIND_TABLES);
      b_shells->bind(ATMOSH_BIND_SHELLS);
      b_spec->bind(ATMOSH_BIND_SPECTRAL);
      b_sky->bind(ATMOSH_BIND_PARAMS);
      b_nodes_->bind(7);
      b_dens->bind(8);
      b_geom_->bind(9);
      b_prev_->bind(10);
      p.n_items = static_cast<int>(n_tab_ / s.nw);
      const Buffer b_op(sizeof(p), &p);
      b_op.bind(11);
      single.use();
      check_gl("orders: S_1 set-up");
      dispatch_items(single, n_tab_ / s.nw);
      check_gl("orders: S_1");
      finish();
      if (times_) times_->single_s += since(t1);
      t0 = Clock::now();
    }
    // Three tables of this size on the device: S_{k-1} (then S_k, written over it: the
    // radiance pass reads J_k only), J_k and the sum, zeroed there.
    b_dens_ = std::make_unique<Buffer>(n_tab_ * sizeof(float));
    b_sum_ = std::make_unique<Buffer>(n_tab_ * sizeof(float));
    b_sum_->clear();
    b_incoming_ = std::make_unique<Buffer>(std::max<std::size_t>(n_incoming_ * s.nw, 1) * sizeof(float));
    b_e_ = std::make_unique<Buffer>(static_cast<std::size_t>(s.ns) * s.nw * sizeof(float));
    b_ground_ = std::make_unique<Buffer>(static_cast<std::size_t>(s.ns) * s.nw * sizeof(float));
    check_gl("orders: uploads");
    finish();
    if (times_) times_->upload_s += since(t0);
  }

  void density(int order, const std::vector<float>& e_prev_log) override {
    const auto t0 = Clock::now();
    if (!e_prev_log.empty()) b_ground_->upload(e_prev_log.data(), e_prev_log.size() * sizeof(float));
    p_.order = order;
    run(*incoming_, n_incoming_, *b_prev_, *b_dens_);
    run(*density_, n_tab_ / p_.nw, *b_prev_, *b_dens_);
    finish();
    if (times_) times_->passes_s += since(t0);
  }

  std::vector<double> ground_irradiance() override {
    const auto t0 = Clock::now();
    run(*ground_, static_cast<std::size_t>(p_.ns), *b_prev_, *b_dens_);
    std::vector<float> e(static_cast<std::size_t>(p_.ns) * p_.nw);
    b_e_->download(e.data(), e.size() * sizeof(float));
    if (times_) times_->passes_s += since(t0);
    return std::vector<double>(e.begin(), e.end());
  }

  void radiance() override {
    const auto t0 = Clock::now();
    run(*radiance_, n_tab_ / p_.nw, *b_dens_, *b_prev_);  // S_k over S_{k-1}
    finish();
    if (times_) times_->passes_s += since(t0);
  }

  void sum(std::vector<float>& sum_lin) override {
    sum_lin.resize(n_tab_);
    b_sum_->download(sum_lin.data(), n_tab_ * sizeof(float));
  }

  // Kept on the GPU: the sum's logarithm (orders_log.comp) into the scattering
  // density's table (free once the build is done), handed over with that buffer; the
  // linear sum stays for sum().
  std::shared_ptr<const atmo::OrdersDeviceTable> keep_sum() override {
    if (where_ == OrdersTables::ReadBack) return nullptr;
    const auto t0 = Clock::now();
    run(*log_, n_tab_, *b_prev_, *b_dens_);
    finish();
    if (times_) times_->passes_s += since(t0);
    return std::make_shared<OrdersResidentTable>(ctx_, own_, std::move(b_dens_));
  }
  bool read_back_sum() const override { return where_ != OrdersTables::Resident; }

  // The working buffers freed (on llvmpipe they are process memory); the programs stay
  // for the next build with these passes.
  void end() override {
    for (auto* b : {&b_geom_, &b_nodes_, &b_coords_, &b_ray_t_, &b_pr_, &b_pm_, &b_gt_, &b_prev_, &b_dens_, &b_sum_,
                    &b_incoming_, &b_e_, &b_ground_})
      b->reset();
  }

 private:
  // One pass over n items, reading `in` and writing `out`.
  void run(const Program& prog, std::size_t n, const Buffer& in, const Buffer& out) {
    p_.n_items = static_cast<int>(n);
    Buffer params(sizeof(p_), &p_);
    params.bind(ATMOSH_ORDERS_BIND_PARAMS);
    in.bind(ATMOSH_ORDERS_BIND_TAB_IN);
    out.bind(ATMOSH_ORDERS_BIND_TAB_OUT);
    b_sum_->bind(ATMOSH_ORDERS_BIND_SUM);
    b_incoming_->bind(ATMOSH_ORDERS_BIND_INCOMING);
    b_nodes_->bind(ATMOSH_ORDERS_BIND_NODES);
    b_coords_->bind(ATMOSH_ORDERS_BIND_COORDS);
    b_ray_t_->bind(ATMOSH_ORDERS_BIND_RAY_T);
    b_geom_->bind(ATMOSH_ORDERS_BIND_GEOM);
    b_pr_->bind(ATMOSH_ORDERS_BIND_PR);
    b_pm_->bind(ATMOSH_ORDERS_BIND_PM);
    b_gt_->bind(ATMOSH_ORDERS_BIND_GROUND_T);
    b_ground_->bind(ATMOSH_ORDERS_BIND_GROUND);
    b_e_->bind(ATMOSH_ORDERS_BIND_E_OUT);
    prog.use();
    check_gl("orders: pass set-up");
    dispatch_items(prog, n);
    check_gl("orders: dispatch");
  }

  std::shared_ptr<const Context> own_;
  const Context& ctx_;
  OrdersGpuTimes* times_;
  OrdersTables where_;
  sg::GpuOrdersParams p_{};
  std::size_t n_tab_ = 0, n_incoming_ = 0;
  std::unique_ptr<Program> incoming_, density_, ground_, radiance_, log_;
  std::unique_ptr<Buffer> b_geom_, b_nodes_, b_coords_, b_ray_t_, b_pr_, b_pm_, b_gt_, b_prev_, b_dens_, b_sum_,
      b_incoming_, b_e_, b_ground_;
};

}  // namespace

void OrdersResidentTable::read(std::size_t first, std::size_t count, float* out) const {
  if ((first + count) * sizeof(float) > table_->bytes())
    throw InputError("orders table read-back: values " + std::to_string(first) + " + " + std::to_string(count) +
                     " beyond the table");
  ctx_->make_current();
  table_->download(out, count * sizeof(float), first * sizeof(float));
}

OrdersResidentTable::~OrdersResidentTable() {
  try {
    ctx_->make_current();
  } catch (...) {  // the context is current on another thread: the buffer is left to it
    (void)table_.release();
  }
}

std::unique_ptr<atmo::ScatteringOrders> build_scattering_orders(const Context& ctx, const atmo::Atmosphere& atmosphere,
                                                                const atmo::MultipleScatteringOptions& o,
                                                                OrdersGpuTimes* times, OrdersTables where) {
  const std::size_t nw = atmosphere.wavelengths_nm().size();
  if (nw > ATMOSH_ORDERS_MAX_WAVELENGTHS)
    throw Unsupported("GPU orders: " + std::to_string(nw) + " wavelengths (at most " +
                      std::to_string(ATMOSH_ORDERS_MAX_WAVELENGTHS) + ")");
  OrdersGpuPasses passes(ctx, times, where);
  return std::make_unique<atmo::ScatteringOrders>(atmosphere, o, &passes);
}

std::shared_ptr<atmo::OrdersPasses> make_orders_passes(std::shared_ptr<const Context> ctx, OrdersGpuTimes* times,
                                                       OrdersTables where) {
  if (!ctx) throw InputError("GPU orders passes: no context");
  return std::make_shared<OrdersGpuPasses>(std::move(ctx), times, where);
}

}  // namespace atmosh::gpu
