// atmosh/atmo/scattering_orders.hpp — successive orders of scattering into tables
// (the scheme of E. Bruneton, "Precomputed Atmospheric Scattering: a New
// Implementation", 2017, and Bruneton & Neyret 2008; own code and parametrisation
// details below).
//
// Quantities, per wavelength of the atmosphere and per unit solar irradiance
// (E = 1 W m^-2 nm^-1 normal to the beam outside the atmosphere):
//   S_k(x, w)  radiance of order k arriving at x from the atmosphere along the ray
//              that leaves x in direction w (to the top or the ground) [1/sr];
//   E_k(mu_s)  irradiance of order k on the ground from the sky (k >= 1); E_0 the
//              direct sun mu_s T_sun;
//   I_k(x, w)  = S_k(x, w) + [w hits the ground at g] T(x, g) a/pi E_{k-1}(mu_s(g))
//              the radiance of order k arriving at x (ground reflection counts as
//              one scattering; a the Lambertian ground albedo);
//   J_k(y, w)  = int_sphere sum_c sigma_c(y) p_c(w . w') I_{k-1}(y, w') dw'
//              the scattering density of order k >= 2 toward a viewer looking along w;
//   S_k(x, w)  = int_0^d T(x, y) J_k(y, w) dt,  y = x + t w.
// S_1 is single scattering (with the phase functions), tabulated only as the source
// of J_2. Order by order k = 2..N: J_k, then S_k, then E_{k-1} = int_up S_{k-1} mu dw.
// The sky (SkyIntegrator, method orders) adds sum_{k=2..N} S_k at the observer's
// ray and, where the view ray ends on the ground, T_view a/pi sum_{k=1..N-1} E_k:
// with its own single scattering and direct ground term, all orders up to N.
//
// Tables (each value per wavelength, float, stored as its logarithm: in the Earth's
// shadow the light falls by orders of magnitude between neighbouring sun directions
// and geometric interpolation follows exponential falls):
//   radius:   rho = sqrt(r^2 - R^2) uniform over [0, H], H = sqrt(T^2 - R^2);
//   view:     half the samples for rays that hit the ground, half for rays to the
//             top, each uniform in the distance to the ground / top between its
//             extremes at that radius (Bruneton 2017's mapping: it resolves the horizon);
//   sun:      mu_s over [sin(-36 deg), 1] (below: clamped), ~6x denser near the
//             horizon than uniform (the terminator; ScatteringOrders::Impl::mus_of_u);
//   azimuth:  phi in [0, pi] between the view's and the sun's vertical planes, uniform
//             in cos phi (nu = mu mu_s + sqrt((1 - mu^2)(1 - mu_s^2)) cos phi: every
//             sample valid; the twilight sky's log is close to linear in cos phi);
// multilinear interpolation of the logarithms with a correction by their second
// differences along each axis (the plain geometric mean of log interpolation is biased
// low where the light varies smoothly and the bias compounds through the orders;
// orders_curvature in shared/orders.glsl.hpp). J uses a sphere rule of `orders_sphere_zenith` cosines
// (Gauss-Legendre on each side of the local horizon, gathered toward it) x
// `orders_sphere_azimuth` uniform azimuths, the phase functions normalised to 1 over
// the rule (energy kept where the rule cannot resolve a forward peak); the
// integrals along rays use `orders_ray_steps` trapezoid steps gathered toward the
// densest point (the tangent point, the ground, or the start). Errors, sizes and
// build times: docs/sky.md ("Multiple scattering").
#pragma once

#include <memory>
#include <vector>

#include "atmosh/atmo/multiple_scattering.hpp"

namespace atmosh::atmo {

namespace shared {
struct OrdersRayCoord;  // shared/orders.glsl.hpp (complete where OrdersSetup is built or read)
}
class Atmosphere;
class OpticalDepthLut;

// The build's set-up as the CPU computes it, handed to OrdersPasses (the passes of
// orders >= 2 on another device, gpu::OrdersGpuPasses): sizes, coefficients, the
// texels' rays and their nodes, the scattering density's sphere rule and phase
// matrices, and the single-scattering table S_1. Layouts as in scattering_orders.cpp.
struct OrdersSetup {
  int nr = 0, nmu = 0, half = 0, ns = 0, na = 0;  // table sizes
  int nn = 0;                                     // nodes per texel ray (orders_ray_steps + 1)
  int nz = 0, nphi = 0, n_ground = 0;             // sphere rule: zenith cosines (the first n_ground
                                                  // toward the ground), azimuths
  std::size_t nw = 0;
  double R = 0, T = 0, H = 0;
  double sun_m = 0;   // -sin(lowest tabulated sun elevation): sg::orders_mus_of_u's m
  double albedo = 0;  // ground
  std::vector<double> sr, sm;  // scattering coefficients [1/m] at the ground, [wavelength]
  std::vector<double> rho_r, rho_m;  // relative densities at the radius samples [i]
  // Texel rays [ray = i nmu + j][node n]: (t, r, mu, w) [m, m, -, m], their lookup
  // coordinates, and the transmittance start -> node [ray][n][wavelength].
  std::vector<double> node;
  std::vector<shared::OrdersRayCoord> node_coord;
  std::vector<float> ray_t;
  std::vector<double> ray_mu;  // [ray]
  // Per node [ray][n]: relative densities (Rayleigh, Mie) and the column start -> node
  // [m] (Rayleigh, Mie, ozone): 5 values.
  std::vector<double> node_dens;
  // The atmosphere and its optical-depth tables (the sun's transmittance), valid during
  // begin().
  const Atmosphere* atmosphere = nullptr;
  const OpticalDepthLut* lut = nullptr;
  // Sphere rule per radius: mu, w [i][nz], distance to the ground d_ground [i][n_ground],
  // transmittance to the ground t_ground [i][n_ground][wavelength]; azimuth cosines and
  // sines [nphi]; phase matrices Pr, Pm [i][(j na + a)][z nphi + b], rows normalised.
  std::vector<double> sphere_mu, sphere_w, d_ground, cphi, sphi;
  std::vector<float> t_ground, Pr, Pm;
  // Order 2's ground: the direct sun's transmittance at the ground point of each
  // ground-bound sphere direction, [i][k][z < n_ground][b][wavelength] (0: sun below
  // the horizon there).
  std::vector<float> sun_ground;
  // The ground irradiance's rule over the upper hemisphere: mu, weight (of d mu) [nz].
  std::vector<double> up_mu, up_w;
  const std::vector<float>* single = nullptr;  // log S_1, [i][j][k][a][wavelength]; nullptr
                                               // when the device computes it (single_on_device)
};

// A table kept on the device that built it (OrdersPasses::keep_sum); the device's code
// knows its type (gpu::OrdersResidentTable).
class OrdersDeviceTable {
 public:
  virtual ~OrdersDeviceTable() = default;
  // Copies values [first, first + count) of the kept log table (layout as
  // ScatteringOrders::radiance_table()) into out (the device's context made current on
  // the calling thread).
  virtual void read(std::size_t first, std::size_t count, float* out) const = 0;
};

// The passes of orders >= 2 on another device. The tables stay there between passes.
class OrdersPasses {
 public:
  virtual ~OrdersPasses() = default;
  // True if begin() computes S_1 itself (from the nodes and the sun table); the CPU
  // then skips its single-scattering pass.
  virtual bool single_on_device() const { return false; }
  // Uploads the set-up; the current table S is S_1.
  virtual void begin(const OrdersSetup& setup) = 0;
  // J_order from the current S and the ground's light of order - 1 (order 2: the direct
  // sun, setup.sun_ground; later: e_prev_log, log E_{order-2}... as the CPU: [k][wavelength]).
  virtual void density(int order, const std::vector<float>& e_prev_log) = 0;
  // E of the current S at every tabulated sun direction, [k][wavelength].
  virtual std::vector<double> ground_irradiance() = 0;
  // S_order from J_order: the current S becomes it, and it is added to the sum.
  virtual void radiance() = 0;
  // The sum of S_2..S_N (linear), [texel][wavelength].
  virtual void sum(std::vector<float>& sum_lin) = 0;
  // Called at the end of the build, before sum(): a device that keeps the sum's log
  // table (the table radiance_table() holds) returns it (ScatteringOrders::device_table());
  // nullptr (the default): it keeps none.
  virtual std::shared_ptr<const OrdersDeviceTable> keep_sum() { return nullptr; }
  // Whether the build reads the sum back (sum()) into radiance_table(), what any CPU
  // lookup needs: true by default; false only for a device that kept it (then
  // radiance_table() stays empty and radiance() throws).
  virtual bool read_back_sum() const { return true; }
  // Called last, after keep_sum() and sum(): the device may free its working tables (the
  // kept table stays); begin() allocates them again for the next build.
  virtual void end() {}
};

class ScatteringOrders {
 public:
  // Builds orders 2..o.orders (o.orders >= 2; InputError otherwise or for options out
  // of range). Threads: o.threads. The passes of orders >= 2 on o.orders_passes if set.
  ScatteringOrders(const Atmosphere& atmosphere, const MultipleScatteringOptions& o);
  // The same with the passes of orders >= 2 (scattering density, radiance, ground
  // irradiance), and S_1 if passes->single_on_device(), run by `passes` (nullptr: on
  // the CPU); the set-up stays here.
  ScatteringOrders(const Atmosphere& atmosphere, const MultipleScatteringOptions& o, OrdersPasses* passes);
  ~ScatteringOrders();

  // Radiance of orders 2..N [1/sr per unit solar irradiance] along the ray from
  // radius r [m] (R <= r <= T) with view zenith cosine mu (hitting the ground iff
  // `ground`), sun zenith cosine mu_s and cos(view, sun) nu, into out[0..n).
  // InputError if the table was kept on the device only (device_table(), radiance_table()
  // empty) and the lookup is outside what read_back_at read back.
  void radiance(double r, double mu, bool ground, double mu_s, double nu, double* out) const;
  // Irradiance of the sky on the ground, orders 1..N-1 [per unit solar irradiance],
  // at sun zenith cosine mu_s there, into out[0..n).
  void ground_irradiance(double mu_s, double* out) const;

  int orders() const { return orders_; }
  std::size_t wavelengths() const { return nw_; }
  // Entries (texels) of one 4-D table, and the bytes of all tables kept.
  std::size_t texels() const;
  std::size_t bytes() const;
  double build_time_s() const { return build_s_; }
  // Time of each pass: [0] the single-scattering table, then per order k >= 2 the
  // scattering density and the radiance (2 (k - 1) - 1 and 2 (k - 1)).
  const std::vector<double>& pass_times_s() const { return pass_s_; }
  // The tables as stored: log of sum_{k=2..N} S_k [i][j][k][a][wavelength] (sizes:
  // table_size; for a table kept on the device: empty, or what read_back_at /
  // read_back_all read) and log of sum_{k=1..N-1} E_k [k][wavelength].
  const std::vector<float>& radiance_table() const;
  const std::vector<float>& ground_table() const;
  // The radiance table kept on the device that built it (OrdersPasses::keep_sum), or
  // nullptr. radiance_table() is empty iff the build did not read it back as well
  // (OrdersPasses::read_back_sum) and no read_back_all() followed. The ground table is
  // always on the CPU.
  const OrdersDeviceTable* device_table() const { return device_.get(); }

  // Reading a kept table back (device_table() set, radiance_table() empty), for the CPU
  // lookups an output needs. Not thread-safe against lookups running at the same time:
  // call them before (they fill the CPU side of the tables, which radiance() reads).
  // read_back_at: the part of the table that the lookups of an observer at radius r [m]
  // with the sun at zenith cosine mu_s there need, for any view and azimuth: the
  // radius and sun rows of their cells with one more row on each side (so that the
  // same observer's lookups, their r and mu_s rounded differently, stay inside); an
  // observer at or above the top (r >= T: the rays enter at the top with the sun at
  // every cosine) gets every sun row. Afterwards radiance() answers lookups in that part
  // and throws InputError outside it. Returns the bytes read. read_back_all: the whole
  // table (radiance_table() then holds it). Both: nothing to do (0) if the table is
  // already on the CPU in full.
  std::size_t read_back_at(double r, double mu_s) const;
  std::size_t read_back_all() const;
  // The bytes of the radiance table that are on the CPU (radiance_table(), or the part
  // read_back_at read).
  std::size_t bytes_on_cpu() const;
  // nr, nmu, ns, na.
  std::vector<int> table_size() const;
  // m = -sin(lowest tabulated sun elevation) of the sun coordinate (shared
  // orders_mus_of_u): with table_size, what a lookup elsewhere (the GPU sky) needs.
  double sun_m() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  std::shared_ptr<const OrdersDeviceTable> device_;
  int orders_ = 0;
  std::size_t nw_ = 0;
  double build_s_ = 0;
  std::vector<double> pass_s_;
};

}  // namespace atmosh::atmo
