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
  // At most n kinks, ascending, those that stand out most: ranked by how much the
  // jump of the slope at a node exceeds the mean of its neighbours' jumps (the
  // smooth curvature that every node of a sampled profile carries), relative to the
  // local density; all of them when there are at most n (tent corners). For a table
  // of the U.S. 1976 atmosphere the tropopause node ranks first.
  std::vector<double> strongest_kinks(int n) const;
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
