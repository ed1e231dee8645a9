// Private to atmosh::gi: the seeded random streams and the orthonormal basis that the
// path tracer and the probes share.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/glm.hpp>

namespace atmosh::gi::detail {

inline std::uint64_t mix64(std::uint64_t z) {  // SplitMix64 finaliser (Steele, Lea & Flood 2014)
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// SplitMix64 stream number `index` of `seed`; `salt` keeps the streams of different
// passes (path tracer, probes) apart for the same seed and index.
struct Rng {
  std::uint64_t state;
  Rng(std::uint64_t seed, std::uint64_t index, std::uint64_t salt) : state(mix64(seed ^ mix64(index + salt))) {}
  double uniform() {  // [0, 1)
    state += 0x9e3779b97f4a7c15ULL;
    return static_cast<double>(mix64(state) >> 11) * 0x1.0p-53;
  }
};
inline constexpr std::uint64_t kPathSalt = 0x632be59bd9b4e019ULL;
inline constexpr std::uint64_t kProbeSalt = 0x2545f4914f6cdd1dULL;

// Orthonormal basis (t, b) around unit n (Duff et al. 2017, JCGT 6(1)).
inline void onb(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double bb = n.x * n.y * a;
  t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  b = glm::dvec3(bb, sign + n.y * n.y * a, -n.y);
}

// Uniform direction in the cone around unit `axis` whose half-angle has cosine cos_max
// (the sun's disc); draws two uniforms from rng.
inline glm::dvec3 sample_cone(Rng& rng, const glm::dvec3& axis, double cos_max) {
  constexpr double kTwoPi = 2 * std::numbers::pi;
  const double u1 = rng.uniform(), u2 = rng.uniform();
  const double ct = 1 - u1 * (1 - cos_max), st = std::sqrt(std::max(0.0, 1 - ct * ct));
  glm::dvec3 t, b;
  onb(axis, t, b);
  return glm::normalize(st * std::cos(kTwoPi * u2) * t + st * std::sin(kTwoPi * u2) * b + ct * axis);
}

}  // namespace atmosh::gi::detail
