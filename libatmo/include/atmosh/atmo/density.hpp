// atmosh/atmo/density.hpp — relative density profiles against altitude.
//
// Units: altitude h in metres above the ground; the value is dimensionless
// (1 at the profile's reference: the ground for exponentials, the peak for a
// tent, the tabulated values as given). Evaluation is exact up to rounding:
// exp(-h/H) for Exponential, the piecewise linear interpolant for Tent and
// Tabulated (0 outside the tabulated range).
//
// kinks() lists the altitudes where the profile's derivative jumps (tent
// corners, table nodes): the exact optical-depth quadrature splits rays there.
// vertical_column(h0, h1) is the exact integral of the profile over [h0, h1] in
// metres (closed form for every kind).
#pragma once

#include <vector>

#include "atmosh/atmo/sorted_index.hpp"
#include "atmosh/atmo/spec.hpp"

namespace atmosh::atmo {

class DensityProfile {
 public:
  DensityProfile() = default;
  // Throws InputError (naming `key`, e.g. "mie.profile") for invalid parameters.
  explicit DensityProfile(const DensityProfileSpec& spec, const std::string& key = "profile");

  double operator()(double h) const;
  DensityProfileSpec::Kind kind() const { return spec_.kind; }
  const DensityProfileSpec& spec() const { return spec_; }
  const std::vector<double>& kinks() const { return kinks_; }
  // A kink and the part of its slope jump [1/m] that is not the smooth curvature of
  // the sampled profile (see strongest_kink_jumps).
  struct Kink {
    double altitude_m = 0.0;
    double excess_jump = 0.0;  // [1/m]
    double smooth_jump = 0.0;  // [1/m] the smooth curvature's share of the node's jump
    // [1/m^2] jump of the second derivative of the profile the table samples,
    // d2rho/dh2 above less below: each side's from the cubic through the node and its
    // three neighbours on that side (0 with fewer than three, for tents, and when one
    // of those neighbours has a larger |excess_jump|: a stronger kink). For a
    // table of the U.S. 1976 atmosphere with 500 m nodes: the standard's own jump to
    // 1 % at the tropopause, 5 % at 20 km.
    double curvature_jump = 0.0;
  };
  // At most n kinks, ascending, those that stand out most; all of them when there are
  // at most n (tent corners, excess = the whole jump). For a table: the jump of the
  // slope at node i, J_i = s_i+ - s_i-, less the smooth part kappa (h_i+1 - h_i-1) / 2,
  // with kappa the median curvature J_j / ((h_j+1 - h_j-1) / 2) of the interior nodes
  // j = i +- 1, i +- 2 (exact for a sampled quadratic on any grid: its excess is 0;
  // the median ignores one kinked neighbour); the end nodes keep their whole jump (to
  // or from 0 outside the table). Ranked by |excess| relative to the largest density
  // at the node and its neighbours, greedily, a node beside one already chosen
  // skipped. For a table of the U.S. 1976 atmosphere with nodes on its layer
  // boundaries the tropopause ranks first and the excess there is the standard's own
  // jump of d rho/dh to 2 %.
  // Only kinks with lo < altitude < hi are candidates (e.g. (0, top): inside the
  // atmosphere), and with |excess| > min_ratio |smooth| (a kink that stands out of the
  // sampled curvature: at the U.S. 1976 layer boundaries the ratio is 0.7-3.4, at the
  // other nodes of its 500 m table <= 0.15).
  std::vector<Kink> strongest_kink_jumps(int n, double lo = -1e300, double hi = 1e300, double min_ratio = 0.0) const;
  // The altitudes of strongest_kink_jumps(n, lo, hi), ascending.
  std::vector<double> strongest_kinks(int n, double lo = -1e300, double hi = 1e300) const;
  // True when the density is > 0 at every altitude in [0, top_m].
  bool positive_on(double top_m) const;
  // Exact integral of the profile over [h0, h1] (h0 <= h1), metres.
  double vertical_column(double h0, double h1) const;
  // Smallest length over which the profile changes appreciably: the scale height
  // for exponentials, the shortest linear piece otherwise [m].
  double feature_length() const;

 private:
  DensityProfileSpec spec_;
  std::vector<double> kinks_;
  SortedIndex index_;  // over the tabulated altitudes
};

}  // namespace atmosh::atmo
