// atmosh/atmo/multiple_scattering.hpp — light scattered more than once: the
// scattering methods of the sky and the tables behind them.
//
// ScatteringMethod (SkyOptions::scattering, scene [scattering] method):
//   single       single scattering only (the sky integrator of sky.hpp as it always was);
//   approximate  single scattering + Hillaire's (2020) all-orders approximation
//                (MultipleScatteringLut below): a small table, quick to rebuild;
//   orders       single scattering + orders 2..N of successive orders of scattering
//                (ScatteringOrders, scattering_orders.hpp; Bruneton 2017 scheme).
//
// MultipleScatteringLut — Hillaire, "A Scalable and Production Ready Sky and
// Atmosphere Rendering Technique", EGSR 2020 (Computer Graphics Forum 39(4)),
// section 5.5.2. At a point x (radius r) with the sun at zenith cosine mu_s, with
// unit solar irradiance (E = 1 normal to the beam, outside the atmosphere):
//
//   L'(x, w)  = int_0^d sigma_s(y) p~(w . l) T(x, y) T_sun(y) dt
//             + T(x, g) a / pi max(mu_s(g), 0) T_sun(g)        (ray hits the ground at g)
//   L_2nd(x)  = int_sphere L'(x, w) p_u dw                      (eq. 5, 6)
//   f_ms(x)   = int_sphere [int_0^d sigma_s(y) T(x, y) dt] p_u dw   (eq. 7, 8)
//   Psi_ms(x) = L_2nd(x) / (1 - f_ms(x))                       (eq. 9, 10: F_ms = 1 + f + f^2 + ...)
//
// y = x + t w, d the distance to the top or the ground along w, sigma_s the total
// scattering coefficient (Rayleigh + Mie) [1/m], T the transmittance, T_sun(y) that
// toward the sun (0 in the Earth's shadow), a the ground albedo, p_u = 1/(4 pi).
// The second scattering (at x) and every later one are isotropic, as in the paper;
// the first (at y) uses the true phase functions p~ (Rayleigh + Mie weighted by
// their scattering coefficients) normalised to 1 over the direction rule (the
// paper's eq. 6 uses p_u there; the sun's phase is known exactly and costs nothing).
// Psi_ms [1/sr] is per unit irradiance; the sky adds, along the view ray,
//   L_ms = E int sigma_s(x) Psi_ms(r(x), mu_s(x)) T(observer, x) ds      (eq. 11)
// at the integrator's own nodes. The table also holds points in the Earth's shadow
// (mu_s below the horizon): their sunlit surroundings light them, which is what
// keeps twilight skies from going black.
//
// Table: `altitudes` x `sun_directions` entries per wavelength; altitude u =
// sqrt(h / top) (resolution near the ground); sun: x = 2u - 1, mu_s = x (1/4 + 3/4 |x|)
// over the whole [-1, 1] (four times denser at the horizon than uniform); bilinear
// interpolation of log Psi (in the Earth's shadow Psi falls exponentially with the
// sun's depression). Each entry integrates a zenith rule of `zenith_directions`
// cosines (Gauss-Legendre on each side of the local horizon cosine, a quarter below,
// the sky side gathered toward the horizon) x `azimuth_directions` azimuths
// (midpoints over [0, pi], mirrored: the integrand is symmetric about the sun's
// vertical plane), and `ray_steps` steps per ray (trapezoid rule on t = d u^1.5, u
// uniform; the transmittance by the same rule). Errors and build times: docs/sky.md
// ("Multiple scattering").
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace atmosh::atmo {

class Atmosphere;
class OpticalDepthLut;
class OrdersPasses;  // scattering_orders.hpp

enum class ScatteringMethod { Single, Orders, Approximate };
// "single", "orders", "approximate".
const char* scattering_method_name(ScatteringMethod m);
// The method of a name; InputError naming `key` for another one.
ScatteringMethod parse_scattering_method(const std::string& name, const std::string& key = "scattering.method");

struct MultipleScatteringOptions {
  ScatteringMethod method = ScatteringMethod::Single;
  // orders: the highest order of scattering computed (>= 1; 1 = single scattering only).
  // 5: orders 5 and 6 add 0.3-0.8 % at sun -4 to -9 deg, 0.1 % by day (docs/sky.md).
  int orders = 5;
  // approximate: table size and the integration of each entry.
  int ms_altitudes = 32;        // >= 2
  int ms_sun_directions = 64;   // >= 2
  int ms_zenith_directions = 16;  // Gauss-Legendre zenith cosines over [-1, 1], >= 2
  int ms_azimuth_directions = 8;  // azimuths over [0, pi], >= 1
  int ms_ray_steps = 32;          // per ray, >= 4
  // orders: table sizes (scattering_orders.hpp). The defaults put N = 5 within 0.25 % of
  // the Monte-Carlo reference by day, 0.75 % to sun -6 deg and 2.5 % to -12 deg, and order
  // 2 alone within 0.8 % of an independent quadrature from sun 60 to -6 deg (docs/sky.md,
  // "Multiple scattering"). The sphere rule (16 x 16) and the ray steps (32) set the
  // second order's error by day once the interpolation follows the curvature (12 x 12
  // and 24 steps left it ~1 % high).
  int orders_radii = 14;         // >= 4
  int orders_view_directions = 48;  // view zenith cosines (half up, half down), even, >= 8
  int orders_sun_directions = 48;   // >= 4
  int orders_azimuths = 16;         // cos(view, sun) samples, >= 4
  int orders_sphere_zenith = 16;    // scattering density: zenith directions of its sphere rule, >= 4
  int orders_sphere_azimuth = 16;   // and azimuths over [0, 2 pi), >= 4
  int orders_ray_steps = 32;        // steps per ray of the in-scattered radiance, >= 4
  int threads = 0;                  // table builds (0..1024; 0 = the CPUs this process may use)
  // orders: the device that runs the passes of orders >= 2 (nullptr: the CPU), e.g. the
  // GPU's (gpu::make_orders_passes, gpu/orders.hpp). Used only while tables are built.
  std::shared_ptr<OrdersPasses> orders_passes;
};
// InputError naming the option (as "scattering.<name>") for values out of range.
void validate(const MultipleScatteringOptions& o);

class MultipleScatteringLut {
 public:
  // `sun` is the sky's sun table (OpticalDepthLut with sun lookups); the table keeps
  // no reference to either. InputError for options out of range.
  MultipleScatteringLut(const Atmosphere& atmosphere, const OpticalDepthLut& sun, const MultipleScatteringOptions& o);

  // Psi_ms [1/sr] per wavelength of the atmosphere at radius r [m] and sun zenith
  // cosine mu_s (clamped to the table) into out[0..n).
  void psi(double r, double mu_s, double* out) const;
  // The same, computed directly (no table): what an entry holds. For tests and the
  // error study.
  static std::vector<double> psi_direct(const Atmosphere& atmosphere, const OpticalDepthLut& sun,
                                        const MultipleScatteringOptions& o, double r, double mu_s);

  int altitudes() const { return na_; }
  int sun_directions() const { return ns_; }
  std::size_t wavelengths() const { return nw_; }
  std::size_t bytes() const { return table_.size() * sizeof(double); }
  // The table itself: log Psi [log(1/sr)] as [altitude][sun direction][wavelength], in
  // the coordinates of shared/ms_approx.glsl.hpp (the GPU sky uploads it; tests compare
  // the GPU's build with it), and the radii it was built for [m].
  const std::vector<double>& log_table() const { return table_; }
  double ground_radius() const { return R_; }
  double top_altitude() const { return top_; }
  double build_time_s() const { return build_s_; }

 private:
  double R_ = 0, top_ = 0;
  int na_ = 0, ns_ = 0;
  std::size_t nw_ = 0;
  std::vector<double> table_;  // [altitude][sun][wavelength]
  double build_s_ = 0;
};

}  // namespace atmosh::atmo
