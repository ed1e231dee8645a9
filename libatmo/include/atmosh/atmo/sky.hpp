// atmosh/atmo/sky.hpp — spectral single-scattering sky radiance (Nishita et al.
// 1993), a fast table-driven integrator and its exact reference.
//
// Radiance seen by an observer at altitude h (metres above the ground; above the
// top of the atmosphere is fine) along the unit view direction v, with the sun in
// the unit direction l (both in the observer's East-North-Up frame, z up, pointing
// away from the observer):
//
//   L(lambda) = E(lambda) / d^2 * int_0^S  sum_c sigma_c(lambda) rho_c(h(s)) p_c(nu)
//                 * exp(-tau_view(0, s) - tau_sun(s)) ds
//             + albedo / pi * E / d^2 * max(mu_sun_ground, 0) * T_sun(ground) * T_view(S)  (ray hits ground)
//
// with E the extraterrestrial solar spectral irradiance at 1 AU [W m^-2 nm^-1], d
// the Earth-Sun distance [AU], sigma_c the scattering coefficient of constituent c
// at relative density 1 [1/m] (ozone absorbs only), rho_c its relative density,
// p_c its phase function [1/sr] at nu = dot(v, l), tau the optical depths. A sun
// ray that meets the ground contributes nothing (the Earth's shadow), so twilight
// skies (sun below the horizon) are dark but finite. Result: spectral radiance in
// W m^-2 sr^-1 nm^-1 per wavelength of the Atmosphere. The sun disc itself is not
// included (add_sun_disc in sun_disc.hpp puts it into images). Refraction is ignored (straight rays; use the geometric elevation).
//
// SkyIntegrator (fast): the view ray is cut where it crosses `segments` of the
// shells of the Nishita tables (OpticalDepthLut; shells sit at equal optical mass)
// at the tangent point and at the edge of the Earth's shadow; pieces longer than `max_piece_optical_depth` in
// extinction are split further (near-horizontal rays near the ground), and each
// piece gets an n-point Gauss-Legendre rule (n = samples_per_segment). The view
// depth from the observer to a node is accumulated along the ray from the
// densities at the nodes and part ends (sky_part_column_weights; as in Nishita et
// al. 1993, no table), the sun depth is one lookup in the sun table. Bound: relative
// error <= 1 % against SkyReference above the horizon for sun elevations >= 0 with the
// default settings (`atmosh converge sky`; measured errors and times per ray in
// docs/sky.md, the checks in docs/validation.md, "Sky").
//
// SkyReference (exact, slow): globally adaptive Gauss-Kronrod over the view ray,
// split at the tangent point and at profile kinks, with exact optical depths
// (OpticalDepthReference) at every node; relative tolerance 1e-6 by default, with
// an error estimate (its cost per ray: docs/sky.md).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/multiple_scattering.hpp"
#include "atmosh/atmo/optical_depth.hpp"
#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/scattering_orders.hpp"

namespace atmosh::atmo {

// The sun's shape for the direct beam, the transmitted sun colour and the sun's image
// (atmosh/atmo/sun_disc.hpp): a limb-darkened disc of the true angular size (default),
// or a point. The sky's in-scattering is the same for both.
enum class SunModel { Disc, Point };

struct SkyOptions {
  // Table sizes (view_tables is set false: the sun table only). 32 shells, not the
  // tables' own default of 40: the sky's error budget is the integration's (docs/sky.md).
  LutOptions lut{.shells = 32};
  int segments = 16;              // shells (of the table's, evenly picked) that cut the view ray, 1..min(lut.shells-1, 64)
  int samples_per_segment = 2;    // Gauss-Legendre points per piece (1..8)
  double max_piece_optical_depth = 0.5;  // pieces are split until their extinction optical depth
                                         // (most extinct wavelength, densest end) stays below this
  double sun_distance_au = 1.0;   // Earth-Sun distance; irradiance scales as 1/d^2
  SunModel sun_model = SunModel::Disc;  // direct beam and sun image only (sun_disc.hpp)
  // Light scattered more than once (multiple_scattering.hpp). The library default is
  // single scattering; scenes choose (the default scene: docs/scene-format.md).
  MultipleScatteringOptions scattering;
};

// Weights of the view column inside a part of a view ray (SkyIntegrator and the GPU
// sky): for the n-point Gauss-Legendre rule (1 <= n <= 8) on [-1, 1] and the n + 2
// points t_0 = -1, t_1..t_n = its nodes x_0..x_{n-1}, t_{n+1} = 1, row q < n holds
// c_j = integral from -1 to x_q of l_j(t) dt (l_j the Lagrange basis polynomial of
// point j) and row n the same integral up to 1. The column of a constituent from the
// start of a part of half-length h [m] to its node q is h * sum_j c_j rho(t_j): exact
// when the density along the part is a polynomial of degree <= n + 1. (n + 1) x
// (n + 2) values, row-major; InputError for n outside [1, 8].
std::vector<double> sky_part_column_weights(int n);

// Where the light comes from: E(lambda) at 1 AU for each wavelength of the
// atmosphere [W m^-2 nm^-1].
using SolarSpectrum = std::vector<double>;

class SkyIntegrator {
 public:
  // Builds the optical-depth tables the atmosphere needs (only its constituents).
  // Lifetime: the integrator keeps its own copy of `atmosphere` (the spec and the
  // per-wavelength coefficients: small next to the tables), so the argument may go
  // away right after construction; atmosphere() and the tables refer to that copy,
  // which lives on the heap and so stays put when the integrator is moved.
  SkyIntegrator(const Atmosphere& atmosphere, SolarSpectrum solar, SkyOptions options = {});

  // Spectral radiance along `view` into out[0..n_wavelengths). InputError for
  // non-unit or non-finite directions or altitude below the ground.
  void radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun, double* out) const;
  std::vector<double> radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const;
  // Spectral radiance along `count` views that share one zenith angle (a row of an
  // equirect image) into out[k * n_wavelengths + i]. The nodes of the view ray, their
  // densities and view columns depend on the zenith angle only and are computed once;
  // the sun table is reduced once per node radius (OpticalDepthLut::sun_at), and for
  // rows of >= 68 views each node's sun lookups (closed-form ozone included) are
  // fitted over the range of the sun's direction across the row (checked to 1e-10 of
  // each column's largest value in the range; at most a quarter of the lookups it
  // replaces). Per view only the sun columns, the phase functions and the spectral
  // loop remain. Equal to radiance() per view up to rounding (the same nodes and
  // table weights, summed in another order) and the fit's 1e-10. A view whose ray crosses the edge of the Earth's shadow (its cuts
  // depend on the azimuth) is integrated on its own by radiance(). InputError as
  // radiance(), or if the views' z components differ by more than 1e-12.
  void radiance_same_zenith(double altitude_m, const glm::dvec3* views, std::size_t count, const glm::dvec3& sun,
                            double* out) const;
  // Direct-beam transmittance from the observer toward the sun, per wavelength
  // (0 when the ground blocks it).
  std::vector<double> sun_transmittance(double altitude_m, const glm::dvec3& sun) const;

  // The integrator's copy of the atmosphere: valid while the integrator lives.
  const Atmosphere& atmosphere() const { return atm_; }
  const OpticalDepthLut& lut() const { return *lut_; }
  const SkyOptions& options() const { return opt_; }
  const SolarSpectrum& solar() const { return solar_; }
  // Radii [m] of the shells that cut every view ray (segments - 1 of the table's
  // shells, evenly picked, ascending; shared view_ray_cuts).
  const std::vector<double>& cut_radii() const { return cut_radii_; }
  ScatteringMethod method() const { return opt_.scattering.method; }
  // The approximation's table (method approximate), else nullptr.
  const MultipleScatteringLut* ms_lut() const { return ms_lut_.get(); }
  // The successive-orders tables (method orders with orders >= 2), else nullptr.
  const ScatteringOrders* orders_tables() const { return orders_.get(); }

 private:
  // Calls visit(node) for the nodes of a view ray cut at cuts[0..n_cuts), in order;
  // returns the ray's whole view column.
  // The view-ray helpers work on sky.cpp's private ray and node types (libatmo/src/
  // sky_impl.hpp); they are templates on them so that this header names none of them,
  // defined and instantiated in sky.cpp only.
  template <class Ray, class Visit>
  glm::dvec3 trace(const Ray& ray, const double* cuts, int n_cuts, Visit&& visit) const;
  // Radiance from the nodes that for_each_node(visit) visits (it returns the whole view
  // column); sun(node, mu_s) is the sun-table column of a node.
  // The approximation's term of one node into acc[0..nw) (psi: scratch of nw values).
  template <class ViewNode>
  void add_ms_node(std::size_t nw, const ViewNode& nd, double mu_s, double* psi, double* acc) const;
  template <class Ray, class ForEachNode, class SunColumn>
  void shade(const Ray& ray, ForEachNode&& for_each_node, SunColumn&& sun, double* out) const;

  std::shared_ptr<const Atmosphere> own_atm_;  // the copy this integrator owns
  const Atmosphere& atm_;                       // *own_atm_ (the tables refer to it too)
  SolarSpectrum solar_;
  SkyOptions opt_;
  std::vector<double> solar_scaled_;  // solar_ / sun_distance_au^2
  std::unique_ptr<OpticalDepthLut> lut_;
  std::vector<PhaseFunction> phase_;  // per present scattering constituent
  std::vector<double> gl_x_, gl_w_;
  std::vector<double> part_w_;        // sky_part_column_weights(samples_per_segment)
  std::vector<double> ext_, sca_;     // [constituent][wavelength]
  std::vector<float> ext_f_, sca_f_;  // the same in single precision, each row padded with
                                      // zeros to n_pad_ wavelengths (spectral loop)
  std::size_t n_pad_ = 0;             // wavelengths rounded up to the spectral loop's lanes
  std::vector<double> cut_radii_;     // shells that cut the view ray
  glm::dvec3 ext_max_{0.0};           // largest extinction per constituent over wavelengths
  std::unique_ptr<MultipleScatteringLut> ms_lut_;  // method approximate
  std::unique_ptr<ScatteringOrders> orders_;       // method orders, orders >= 2
};

struct SkyReferenceOptions {
  double rel_tol = 1e-6;
  int max_intervals = 4000;
  double sun_distance_au = 1.0;
};

struct SkyReferenceResult {
  std::vector<double> radiance;  // W m^-2 sr^-1 nm^-1
  std::vector<double> error;     // estimated absolute error
  int evaluations = 0;
  bool converged = true;
};

class SkyReference {
 public:
  // Keeps its own copy of `atmosphere`, as SkyIntegrator does.
  SkyReference(const Atmosphere& atmosphere, SolarSpectrum solar, SkyReferenceOptions options = {});
  SkyReferenceResult radiance(double altitude_m, const glm::dvec3& view, const glm::dvec3& sun) const;
  std::vector<double> sun_transmittance(double altitude_m, const glm::dvec3& sun) const;

 private:
  std::shared_ptr<const Atmosphere> own_atm_;  // the copy this reference owns
  const Atmosphere& atm_;                       // *own_atm_
  SolarSpectrum solar_;
  SkyReferenceOptions opt_;
  OpticalDepthReference od_;
  std::vector<PhaseFunction> phase_;
};

}  // namespace atmosh::atmo
