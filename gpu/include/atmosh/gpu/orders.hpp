// atmosh/gpu/orders.hpp — the successive-orders tables (atmo::ScatteringOrders,
// scattering_orders.hpp) built on the GPU (OpenGL 4.3 compute, headless EGL).
//
// atmo::ScatteringOrders computes its set-up on the CPU (the texels' rays and their
// transmittance, the scattering density's sphere rule and phase matrices, the direct
// sun on the ground); the GPU runs every pass, the tables staying there between passes:
//   orders_single.comp    S_1 (sky_lib.glsl's sun lookups on the build's own tables);
//   orders_incoming.comp  I_{k-1} on the sphere rule (table lookup + the ground's light);
//   orders_density.comp   J_k at every texel (the phase matrices times I_{k-1}), log;
//   orders_ground.comp    E_{k-1}, the sky's irradiance on the ground, per sun sample;
//   orders_radiance.comp  S_k at every texel (transmittance x J_k along its ray), log,
//                          and the sum of the orders.
// Each shader is assembled from shared/geometry.glsl.hpp (float and double) and
// shared/orders.glsl.hpp (double: the tables' parametrisations, lookup coordinates,
// blend, ray nodes), the same functions the CPU build calls, and
// gpu/shaders/orders_lib.glsl (buffers) and gpu/shaders/orders_lookup.glsl (the
// per-wavelength corner loop, which the sky pass's orders term uses too); S_1 from the
// sky pass's parts (gpu::sky_parts) and the same orders block. The sums of the orders
// that these passes build are the tables the sky pass looks up (gpu/sky.hpp). Positions and table
// coordinates in double, table values and sums in float (as the CPU's float tables;
// the CPU sums in double); S_1's sun lookups take float altitudes and cosines.
// Agreement with the CPU tables: docs/gpu.md ("Successive orders on the GPU"), test
// GpuOrders.*. At most 64 wavelengths (Unsupported otherwise).
#pragma once

#include <memory>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/scattering_orders.hpp"
#include "atmosh/atmo/shared/orders.glsl.hpp"  // ATMOSH_ORDERS_MAX_WAVELENGTHS
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/program.hpp"

namespace atmosh::gpu {

// Where the sum of the orders goes at the end of a GPU build. ReadBack: read back into
// the ScatteringOrders (radiance_table(); what any CPU lookup needs: SkyIntegrator's
// radiance, summarize_sky, sky_irradiance, the studies' rows). Resident: its logarithm
// taken on the GPU (orders_log.comp) and kept there in an OrdersResidentTable
// (ScatteringOrders::device_table()); nothing is read back, radiance_table() stays
// empty and the CPU's radiance lookup throws; gpu::render_sky in the same context binds
// it (no upload). ResidentAndReadBack: both (the sky pass binds the kept table, the CPU
// lookups have theirs). The ground table (small) is on the CPU in every case. A kept
// table can be read back later, in part (ScatteringOrders::read_back_at: the lookups at
// one observer) or in full (read_back_all), through OrdersResidentTable::read.
// The build holds three tables of this size on the GPU (S_{k-1}, overwritten by S_k;
// J_k, which takes the kept log table at the end; the sum) and frees all but the kept
// one when it ends; on the CPU only what the mode reads back.
enum class OrdersTables { ReadBack, Resident, ResidentAndReadBack };

// The log table of the sum of orders 2..N ([r][mu][mu_s][phi][wavelength], floats, as
// ScatteringOrders::radiance_table()) in a storage buffer of the context that built it.
// Built by make_orders_passes' device, it holds that context; by
// build_scattering_orders, the caller's context must outlive it. Its destructor makes
// that context current on the thread (the buffer is deleted there, not in whichever
// context is current).
class OrdersResidentTable final : public atmo::OrdersDeviceTable {
 public:
  OrdersResidentTable(const Context& ctx, std::shared_ptr<const Context> owner, std::unique_ptr<Buffer> table)
      : owner_(std::move(owner)), ctx_(&ctx), table_(std::move(table)) {}
  ~OrdersResidentTable() override;
  OrdersResidentTable(const OrdersResidentTable&) = delete;
  OrdersResidentTable& operator=(const OrdersResidentTable&) = delete;
  const Context& context() const { return *ctx_; }
  const Buffer& buffer() const { return *table_; }
  // Values [first, first + count) of the table (its context made current on this thread).
  void read(std::size_t first, std::size_t count, float* out) const override;

 private:
  std::shared_ptr<const Context> owner_;  // keeps the context of a make_orders_passes device
  const Context* ctx_;
  std::unique_ptr<Buffer> table_;
};

// Seconds of the GPU side of a build, summed over builds: compile (the programs; llvmpipe
// JITs at the first dispatch), upload (the set-up's buffers, the tables' allocation and
// the sum's clearing), single (S_1 on the GPU: its inputs from the optical-depth table,
// the pass and the wait for it), passes of orders >= 2 with their read-backs. The rest of
// a build's wall time is the CPU's set-up (ScatteringOrders) and the sum's read-back.
struct OrdersGpuTimes {
  double compile_s = 0, upload_s = 0, single_s = 0, passes_s = 0;
};

// The tables of atmo::ScatteringOrders(atmosphere, o) with the passes of orders >= 2
// on the GPU of ctx (made current on this thread). InputError as the CPU build;
// Unsupported (gpu/sky.hpp) for more than 64 wavelengths.
std::unique_ptr<atmo::ScatteringOrders> build_scattering_orders(const Context& ctx, const atmo::Atmosphere& atmosphere,
                                                                const atmo::MultipleScatteringOptions& o,
                                                                OrdersGpuTimes* times = nullptr,
                                                                OrdersTables where = OrdersTables::ReadBack);

// The GPU passes as a device for atmo::MultipleScatteringOptions::orders_passes (any
// sky built with those options builds its orders tables on this GPU): they own `ctx`
// and make it current on the thread that builds. With OrdersTables::Resident every sky
// built with them keeps its sum table on this GPU (OrdersTables).
std::shared_ptr<atmo::OrdersPasses> make_orders_passes(std::shared_ptr<const Context> ctx,
                                                       OrdersGpuTimes* times = nullptr,
                                                       OrdersTables where = OrdersTables::ReadBack);

}  // namespace atmosh::gpu
