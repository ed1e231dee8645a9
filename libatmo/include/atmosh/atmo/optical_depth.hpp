// atmosh/atmo/optical_depth.hpp — column densities along rays: the exact
// reference and Nishita's multi-shell lookup tables.
//
// Quantity: for each constituent c the column X_c = integral rho_c(h(s)) ds
// [metres] of its relative density along a straight ray (no refraction). It does
// not depend on wavelength; optical depth tau(lambda) = sum_c beta_c(lambda) X_c
// with the extinction coefficients of Atmosphere::coefficients (helper
// optical_depth below). Component order: (rayleigh, mie, ozone).
//
// A ray is given by the radius r of its origin [m] and the cosine mu of its
// zenith angle there (see shared/geometry.glsl.hpp). It runs to the top of the
// atmosphere, or to the ground if it meets it (hits_ground = true), or for
// `length` metres if that is shorter. An origin above the top is moved along the
// ray to where it enters the atmosphere (a ray that misses has zero column).
//
// OpticalDepthReference — exact: globally adaptive G7-K15 quadrature in double,
// split at the tangent point, at profile kinks and at the altitudes h0 + H 2^k of
// each exponential profile. Bound: relative error 1e-12 per constituent (absolute
// floor 1e-15 of its vertical column), or eps R / H_min if larger (the rounding of a
// point's altitude); the returned estimate |K15 - G7| is an upper bound of the actual
// error in practice (tests: the exact Chapman function, an independent quadrature).
//
// OpticalDepthLut — Nishita et al. (1993) multi-shell tables: per shell a view table
// (rays to the top and rays to the ground) and a sun table (rays to the top; a sun
// ray into the ground is blocked), direction parametrised as in Bruneton (2017),
// cubic Lagrange interpolation in direction and across shells. Piecewise-linear
// profiles with at most `analytic_max_nodes` nodes (the ozone tent) are computed in
// closed form at lookup (PiecewiseLinearColumn); long tabulated profiles stay
// interpolated less the kinks that stand out (subtracted_kinks).
// Bound (max relative error of the total optical depth over the study's grazing,
// tangent, kink and random rays) at the default 40 x 64: <= 1e-4 for the presets
// with exponential or tent profiles (earth-graphics, the default scene, test-planet),
// <= 1e-3 for earth-physical (206-node U.S. 1976 table); it holds while the
// atmosphere spans at most ~15 scale heights of every interpolated exponential (top
// / H <~ 15), beyond which high rays lose relative accuracy
// (estimate_max_rel_error grows with it).
// Method, parameters, measured errors, build and lookup times and their history:
// docs/atmosphere.md ("Optical depth", "The tables in detail", "Current results");
// the checks behind the bounds: docs/validation.md ("Atmosphere and optical depth").
#pragma once

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/chebyshev.hpp"
#include "atmosh/atmo/sorted_index.hpp"
#include "atmosh/work.hpp"

namespace atmosh::atmo {

struct RayColumn {
  glm::dvec3 column{0.0};  // [m] per constituent
  glm::dvec3 error{0.0};   // estimated absolute error [m] per constituent
  bool hits_ground = false;
  double length_m = 0.0;  // length of the ray inside the atmosphere
  int evaluations = 0;
  bool converged = true;
};

struct ReferenceOptions {
  double rel_tol = 1e-12;
  double abs_tol_fraction = 1e-15;  // of each constituent's vertical column
  int max_intervals = 20000;
};

// PiecewiseLinearColumn — exact column [m] of a tent or tabulated profile
// (linear in altitude between its nodes h_k, 0 outside them) along a straight
// ray, in closed form. The ray is cut at its tangent point and where it crosses
// the node spheres R_k = R + h_k, at u = +-sqrt(R_k^2 - r_t^2) with u = s + r mu
// (at most twice per node); on each piece the density is linear in the radius
// and shared::linear_piece_column integrates it exactly.
// Accuracy: rounding only. The absolute error of a piece is ~1e-16 R |slope|
// times its length (the same as evaluating the density at the rounded altitude
// r - R, which any quadrature does too): relative ~1e-16 R / l, with l the
// profile's local length scale rho / |d rho/dh| (~1e-13 for the 10-25-40 km
// ozone tent); for a ray whose tangent point lies delta above a node or the
// ground the problem itself has condition number ~R / delta.
// No allocation (its cost per lookup: docs/atmosphere.md).
// The ray runs from radius r (r > 0, |mu| <= 1) over s in [0, length]; it is the
// caller's job to stop it at the ground.
class PiecewiseLinearColumn {
 public:
  PiecewiseLinearColumn() = default;
  // InputError for an exponential profile or a ground radius <= 0.
  PiecewiseLinearColumn(const DensityProfile& profile, double ground_radius);
  // Any piecewise-linear function of altitude (nodes altitude_m ascending, values of
  // either sign, 0 outside the nodes); InputError for non-finite or unsorted input.
  PiecewiseLinearColumn(const std::vector<double>& altitude_m, const std::vector<double>& value, double ground_radius);
  double operator()(double r, double mu, double length) const;
  int nodes() const { return static_cast<int>(radius_.size()); }
  // Node radii [m], ascending: the kinks of the profile.
  const std::vector<double>& node_radii() const { return radius_; }
  const std::vector<double>& node_values() const { return value_; }

 private:
  std::vector<double> radius_, value_, slope_;  // slope_[i] on (radius_[i], radius_[i+1]) [1/m]
  bool nonnegative_ = true;                     // a density: its column is clamped at 0 (rounding)
};

// QuadraticRampsColumn — column [m] along a straight ray of
// q(h) = sum_k half_curv_k (h_k - h)_+^2 (0 above each h_k): n quadratic ramps,
// h_k [m], half_curv_k [1/m^2] of either sign (shared::quadratic_ramps_column:
// each ramp's chord inside its sphere, one 8-point Gauss-Legendre rule). Accuracy:
// ~1e-15 relative to the column of the ramps' absolute values for rays above the
// ground, plus the rounding of the radii along the ray (~1e-16 R in h_k - h, as for
// PiecewiseLinearColumn; it dominates for rays whose tangent point lies within
// metres below an h_k). Cost: ~8 square roots per ramp the ray enters. As for
// PiecewiseLinearColumn the caller stops the ray at the ground.
class QuadraticRampsColumn {
 public:
  QuadraticRampsColumn() = default;
  // InputError for non-finite or unsorted altitudes, non-finite factors or a
  // ground radius <= 0.
  QuadraticRampsColumn(const std::vector<double>& altitude_m, const std::vector<double>& half_curv, double ground_radius);
  double operator()(double r, double mu, double length) const;
  // q at altitude h [m] (0 below the ground, as the rays never go there).
  double at(double h) const;
  int ramps() const { return static_cast<int>(radius_.size()); }
  const std::vector<double>& ramp_radii() const { return radius_; }  // [m], ascending
  const std::vector<double>& half_curvatures() const { return half_curv_; }

 private:
  std::vector<double> radius_, half_curv_;
  double ground_radius_ = 0.0;
};

class OpticalDepthReference {
 public:
  // Refers to `atmosphere` (no copy): it must outlive this object. (SkyIntegrator and
  // SkyReference own a copy and build their tables from it.)
  explicit OpticalDepthReference(const Atmosphere& atmosphere, ReferenceOptions options = {});
  // Column to the top or to the ground; length < 0 means "to the end".
  // InputError for non-finite input, r <= 0, |mu| > 1, or r below the ground
  // (by more than 1e-9 R; tiny undershoots are clamped).
  RayColumn column(double r, double mu, double length = -1.0) const;
  const Atmosphere& atmosphere() const { return atm_; }

 private:
  const Atmosphere& atm_;
  ReferenceOptions opt_;
  glm::dvec3 abs_tol_;
  double rel_tol_ = 0.0;  // opt_.rel_tol, or the rounding floor eps R / H_min if larger
};

// Rays where interpolated tables do worst: around each kink altitude h_k of a profile
// (tent corners, table nodes; those outside (0, top) are skipped, duplicates merged)
// the near-horizontal rays (mu = 0, +-1e-3, +-1e-2) from 100 m below and above it, and
// the rays from 0.99999 of the top whose tangent point lies 1 m and 100 m below and
// above it: 14 per kink. Radii in metres. The atmosphere's version probes the
// kProbedKinks strongest kinks of each present profile (DensityProfile::strongest_kinks:
// all of a tent's, the outstanding nodes of a long table), so the cost stays bounded
// for tables of thousands of nodes. Used by `atmosh converge lut` and by
// OpticalDepthLut::estimate_max_rel_error.
struct ProbeRay {
  double r = 0.0, mu = 0.0;
};
inline constexpr int kProbedKinks = 32;
std::vector<ProbeRay> kink_probe_rays(double ground_radius, double top_altitude, std::vector<double> kink_altitudes);
// `which`: the constituents whose kinks are probed (default all present ones).
std::vector<ProbeRay> kink_probe_rays(const Atmosphere& atmosphere, std::array<bool, 3> which = {true, true, true});

// Optical depth tau = sum_c extinction_c * column_c, and exp(-tau) that is
// exactly 0 (never NaN) when tau is huge or +inf.
double optical_depth(const Coefficients& k, const glm::dvec3& column);
double transmittance(double tau);

inline constexpr double kSubtractedKinkRatio = 0.3;

struct LutOptions {
  int shells = 40;            // S >= 4 (40: the default scene within 1e-4 on the study's rays)
  int view_directions = 64;   // per branch (sky / ground), >= 4
  int sun_directions = 64;    // >= 4
  double uniform_share = 2.0;   // weight of rho-uniform placement vs one constituent's optical mass
  double altitude_share = 1.0;  // weight of altitude-uniform placement (the same unit)
  int gauss_points = 4;       // per piece when building
  // Tent and tabulated profiles with at most this many nodes are not tabulated:
  // their column is computed in closed form at lookup (PiecewiseLinearColumn),
  // exact to rounding. 0 interpolates every constituent from the tables.
  int analytic_max_nodes = 16;
  // Build the two view tables (view() lookups). A user that needs only rays toward
  // the top (the sky integrator: view depths are accumulated along the ray) leaves
  // them out: the sun table alone, a third of the bytes and ~70 % of the build time
  // (the sky branch of the view table has the sun table's rays: with
  // sun_directions == view_directions a full build computes them once).
  bool view_tables = true;
  // Interpolated tabulated profiles (more than analytic_max_nodes nodes, positive up
  // to the top): their `subtracted_kinks` strongest kinks (DensityProfile::
  // strongest_kink_jumps) that stand out of the sampled curvature (excess > 0.3 of the
  // smooth jump, kSubtractedKinkRatio) are taken out of the tabulated density and
  // their column added back in closed form at lookup (see above). 0: none.
  int subtracted_kinks = 8;  // [0, 15] (p has at most 16 nodes, as the GPU shaders hold)
  // With the kinks' slope jumps, subtract their curvature jumps too (the quadratic
  // ramps of the header comment above).
  bool subtract_curvature = true;
  // Worker threads of the build, one shell at a time ([0, 1024]; 0 = the hardware
  // concurrency). The entries are the same for every count.
  int threads = 0;
};

struct LutColumn {
  glm::dvec3 column{0.0};  // [m] per constituent (0 when blocked)
  bool hits_ground = false;
};

class OpticalDepthLut {
 public:
  // InputError for options out of range. Refers to `atmosphere` (no copy): it must
  // outlive the tables.
  OpticalDepthLut(const Atmosphere& atmosphere, LutOptions options = {});

  // Column along a view ray (to the top, or to the ground when it hits it).
  // std::logic_error if the tables were built without view tables.
  LutColumn view(double r, double mu) const;
  // Column toward the sun (to the top); hits_ground = true means blocked.
  LutColumn sun(double r, double mu) const;

  // The sun table at one radius as a function of the direction alone: the
  // interpolation across shells is done once for every direction sample
  // (sun_directions x 4 values), a lookup then costs the direction interpolation
  // only. For many lookups at one radius (the sky integrator's image rows: each node
  // radius meets every azimuth). at(mu) equals sun(r, mu) up to rounding (the same
  // weights, summed in another order). Refers to this table: valid while it lives.
  class SunAtRadius {
   public:
    LutColumn operator()(double mu) const {
      if (fit_.covers(mu)) {  // inline: an image row's pixels
        double v[ChebyshevFit::kMaxChannels];
        fit_.evaluate_all(mu, v);
        LutColumn out;
        out.column = glm::dvec3(v[0], v[1], v[2]);
        return out;
      }
      return lookup(mu);
    }
    // The fit over a range of mu (!valid(): none; lookups interpolate the table and
    // compute closed-form columns).
    const ChebyshevFit& fit() const { return fit_; }

   private:
    friend class OpticalDepthLut;
    LutColumn lookup(double mu) const;  // the table (no fit, or mu outside it)
    const OpticalDepthLut* lut_ = nullptr;
    double r_ = 0, rho_ = 0;
    bool outside_ = false;   // r above the top: every lookup goes through sun(r, mu)
    std::vector<double> v_;  // [direction][4]
    ChebyshevFit fit_;       // the three columns over a range of mu
  };
  SunAtRadius sun_at(double r) const;
  // The same, and its lookups fitted as functions of mu on [mu_lo, mu_hi] by a
  // checked piecewise Chebyshev interpolant (chebyshev.hpp: degree 7 per part, all
  // three columns): parts between the table's direction samples that fall in the
  // range (the lookup is one cubic in the table's direction coordinate between
  // two, smooth in mu) and the mu where a ray's tangent point lies on a node sphere
  // of a closed-form profile (a kink of its column), halved where a check fails.
  // Each column is checked to 1e-10 of its largest value in the range at 17 points
  // per part, so an optical depth is within 1e-10 of the largest in the range of
  // the lookup's. The fit uses at most max_samples lookups, else there is none.
  // Lookups inside the range then cost a constant-time search over the parts and
  // 3 x 8 multiply-adds (inline) instead of the interpolation, two exp and the closed-form
  // columns (~500 instructions with the ozone tent); outside it, or with no fit,
  // they are the lookups. No fit when a ray in the range is blocked by the ground
  // or r is above the top. Worth it for >= ~4 max_samples lookups (an image row:
  // every pixel's sun direction at one node radius).
  SunAtRadius sun_at(double r, double mu_lo, double mu_hi, int max_samples) const;

  // Subtracted kinks (LutOptions::subtracted_kinks): the piecewise-linear function
  // p_c(h) taken out of constituent c's tabulated density (nodes() == 0: none) and its
  // quadratic ramps q_c (the kinks' curvature jumps), the densities the tables hold at
  // altitude h [m] (the profiles' less p and q), and the column [m] of p + q along a
  // ray (r, mu) of length L (added to every lookup).
  const PiecewiseLinearColumn& subtracted(int c) const { return subtracted_[static_cast<std::size_t>(c)]; }
  // The curvature part q_c (LutOptions::subtract_curvature; ramps() == 0: none).
  const QuadraticRampsColumn& subtracted_curvature(int c) const {
    return subtracted_curvature_[static_cast<std::size_t>(c)];
  }
  glm::dvec3 tabulated_density(double h) const;
  glm::dvec3 subtracted_column(double r, double mu, double L) const;

  const std::vector<double>& shell_radii() const { return radii_; }
  // The table parameters of the shell interpolation (the GPU's sky_lib.glsl uploads
  // them): rho_k = sqrt(r_k^2 - R^2) of every shell [m], ascending, and for every
  // 4-shell window w (shared lut_window_start) and node i the inverse Lagrange
  // denominator 1 / prod_{j != i} (rho_{w+i} - rho_{w+j}) at [4 w + i] (shared
  // lut_shell_weight), (shells - 3) x 4 values.
  const std::vector<double>& shell_rho() const { return rho_; }
  const std::vector<double>& shell_inverse_denominators() const { return lagrange_den_; }
  // The scale height [m] by which the build splits a table ray's pieces (shared
  // lut_piece_count): the smallest of the constituents built by quadrature; infinite
  // when there is none (one sub-piece per piece).
  double build_scale_height() const;
  const LutOptions& options() const { return opt_; }
  double build_time_s() const { return build_time_s_; }
  std::size_t table_bytes() const;
  // table_bytes() of a table built with these options, before building it (shells x
  // directions x 4 doubles per table: two view tables when view_tables, and the sun
  // table). Saturates at SIZE_MAX.
  static std::size_t estimate_table_bytes(const LutOptions& options);
  // The work of building a table with these options, before building it
  // (atmosh/work.hpp): shells x (2 view tables when view_tables + 1 sun table) x
  // directions entries, each an optical-depth quadrature, at the cost of one entry
  // measured on the default atmosphere (docs/hostile-input.md, "Work estimates").
  static WorkEstimate estimate_build_work(const LutOptions& options);
  // Max relative error of the total optical depth at `wavelength_nm` (default, 0:
  // the middle wavelength of the atmosphere's grid) at the midpoints of every shell
  // interval (in rho) and every direction interval (in x) of the view tables (or the
  // sun table if there are none), and on the kink_probe_rays of the kinks of the
  // interpolated profiles (a tabulated profile's nodes), against fresh build-quality
  // integrals: an a-posteriori estimate (costs about a build, on the same
  // LutOptions::threads; not part of build_time_s).
  // Sampled, not a proven bound: against the largest error measured on the rays of
  // `atmosh converge lut` it was 0.88-1.31 times that error over 16-64 shells x 32-128
  // directions for the three presets and the default scene's atmosphere, 0.89-1.00 at
  // the default 40 x 64; on independent rays 0.92-1.19 (test
  // CliConvergeLut.ErrorEstimateTracksTheMeasuredError): it can be ~10 % below the
  // true maximum. Its cost (a fraction of the build's): docs/atmosphere.md. InputError
  // for a negative or non-finite wavelength.
  double estimate_max_rel_error(double wavelength_nm = 0.0) const;

  // Replaces the stored entries of the log-encoded constituents with `log_mean`
  // (e.g. tables built by another pass of the same shells and direction samples,
  // such as gpu::build_lut_tables): three tables, view toward the top from
  // offset 0, view toward the ground from `off_ground`, sun from `off_sun`, each
  // [shell][direction][3] = natural log of the mean relative density along the
  // table ray. Entries of other constituents are kept. InputError if the layout
  // does not match this table's shells and directions or a used entry is not
  // finite.
  void replace_log_tables(const std::vector<float>& log_mean, int off_ground, int off_sun);

 private:
  struct Table {
    int n = 0;
    bool ground = false;  // ground branch
    std::vector<double> v;  // [shell][dir][4]: constituents 0..2, padding 0
  };
  glm::dvec3 build_column(double r, double mu, double length) const;
  // Sets the closed-form columns (analytic constituents) and adds the subtracted
  // kinks' columns into `column` (the decoded tables' columns) of a ray of length L.
  void add_closed_form(glm::dvec3& column, double r, double mu, double L) const;
  glm::dvec3 interpolate(const Table& t, double rho, double x) const;  // rho = sqrt(r^2 - R^2)
  // The shells an interpolation at rho uses and their Lagrange weights (lw: window
  // of 4 from w; li: the smooth region's window of kinked profiles, if any).
  struct ShellWeights {
    int k = 0, w = 0;
    double lw[4] = {0, 0, 0, 0};
    int klo = 0, kcount = 0;
    double li[4] = {0, 0, 0, 0};
  };
  ShellWeights shell_weights(double rho) const;
  // Channel c of direction sample j summed over the kinked region's shells.
  double kinked_shell_sum(const Table& t, const ShellWeights& sw, int j, int c) const;
  // Decoded column toward the top from interpolated entries e, for a ray of length d.
  LutColumn finish_up(const glm::dvec3& e, double r, double mu, double d) const;
  glm::dvec3 encode(const glm::dvec3& mean) const;
  glm::dvec3 decode(const glm::dvec3& stored) const;
  void fill(Table& t, int n, bool ground);
  double x_up(double r, double rho, double mu, double& d) const;
  double x_ground(double r, double rho, double mu, double& d) const;
  LutColumn lookup(const Table& up, const Table* ground, double r, double mu) const;

  const Atmosphere& atm_;
  LutOptions opt_;
  double R_, T_, Hh_;
  std::vector<double> radii_, rho_;
  SortedIndex shell_index_;             // over rho_
  std::vector<double> crossing_radii_;  // shells and kinks, sorted
  std::vector<double> lagrange_den_;    // [shell window start][4] denominators
  std::array<bool, 3> log_encoded_{};
  std::array<bool, 3> present_{};   // present and interpolated from the tables
  std::array<bool, 3> analytic_{};  // closed-form column at lookup
  std::array<PiecewiseLinearColumn, 3> linear_;
  std::array<bool, 3> build_closed_{};                   // interpolated, table entries in closed form
  std::array<PiecewiseLinearColumn, 3> build_linear_;  // the tabulated density (less p, if subtracted)
  std::array<bool, 3> has_subtracted_{};             // kinks taken out of the tabulated density
  std::array<PiecewiseLinearColumn, 3> subtracted_;  // p(h) of those kinks (nodes at 0 and the kinks)
  std::array<std::vector<DensityProfile::Kink>, 3> subtracted_kinks_;
  std::array<QuadraticRampsColumn, 3> subtracted_curvature_;  // q(h) of those kinks (ramps() == 0: none)
  std::vector<int> expo_;                                // interpolated exponential constituents (quadrature)
  bool has_kinks_ = false;
  std::array<double, 3> support_top_{};  // altitude above which a kinked profile is 0
  struct KinkWindow {
    int lo = 0, count = 0;
    double inv_den[4] = {1, 1, 1, 1};
  };
  std::vector<KinkWindow> kink_windows_;
  std::vector<int> region_;  // index of the smooth region (between kinks) each shell interval ends in
  std::vector<double> gl_x_, gl_w_;
  Table view_up_, view_ground_, sun_up_;
  double build_time_s_ = 0.0;
};

}  // namespace atmosh::atmo
