// atmosh/atmo/sorted_index.hpp — constant-time search in a sorted table: the index
// of the interval that holds a value, for the profile and shell searches done at
// every quadrature node of the sky integral.
//
// SortedIndex(v) for ascending v_0 < v_1 < ... < v_{n-1} (finite) answers
// find(x) = (number of i with v_i <= x) - 1, i.e. -1 below v_0, n - 1 at or above
// v_{n-1}, and otherwise the k with v_k <= x < v_{k+1}: exactly what a bisection
// (std::upper_bound - 1) gives, for every x (tests/atmo compare the two), NaN
// included (-1). It keeps a uniform grid of `cells` buckets over [v_0, v_{n-1}],
// each holding the first candidate index; a query reads its bucket and steps
// forward over the few table values inside it (none or one when the grid is finer
// than the table's spacing, the default of 8 buckets per value for at most 4096).
// Cost: a few ns, no data-dependent branches beyond those steps.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace atmosh::atmo {

class SortedIndex {
 public:
  SortedIndex() = default;
  explicit SortedIndex(const std::vector<double>& v, int cells = 0) : v_(v) {
    if (v_.size() < 2) return;
    const int n = static_cast<int>(v_.size());
    const int g = cells > 0 ? cells : std::clamp(8 * n, 64, 4096);
    lo_ = v_.front();
    scale_ = g / (v_.back() - v_.front());
    start_.resize(static_cast<std::size_t>(g) + 1);
    int k = 0;  // last index with v_k <= bucket start
    for (int c = 0; c <= g; ++c) {
      const double x = lo_ + c / scale_;
      while (k + 1 < n && v_[static_cast<std::size_t>(k) + 1] <= x) ++k;
      start_[static_cast<std::size_t>(c)] = k;
    }
  }

  int find(double x) const {
    const int n = static_cast<int>(v_.size());
    if (n == 0 || !(x >= v_.front())) return -1;  // empty, below, or NaN
    if (x >= v_.back()) return n - 1;
    if (n < 2) return 0;
    const double c = (x - lo_) * scale_;
    int k = start_[static_cast<std::size_t>(std::min(c, static_cast<double>(start_.size() - 1)))];
    // The bucket's start can round to just above x: step back if needed.
    while (k > 0 && v_[static_cast<std::size_t>(k)] > x) --k;
    while (k + 1 < n && v_[static_cast<std::size_t>(k) + 1] <= x) ++k;
    return k;
  }

  const std::vector<double>& values() const { return v_; }

 private:
  std::vector<double> v_;
  double lo_ = 0.0, scale_ = 0.0;
  std::vector<int> start_;
};

}  // namespace atmosh::atmo
