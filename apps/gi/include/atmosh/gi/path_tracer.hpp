// atmosh/gi/path_tracer.hpp — the unbiased reference for diffuse global illumination: a
// CPU path tracer (Embree 3 through atmosh::prt::RayScene) with standard errors.
//
// Estimator (per sample, per channel), for the scenes of scene.hpp:
//   * paths start at the camera (pinhole, uniform jitter inside the pixel) or at a query
//     point (irradiance); each surface vertex samples the cosine-weighted hemisphere of its
//     flat normal (throughput *= albedo);
//   * next-event estimation at every vertex: the sun (a delta direction, or a uniform
//     direction inside its disc) and the emitting triangles (a triangle chosen with
//     probability proportional to area x summed emitted radiance, a uniform point on it);
//     emission reached by the hemisphere sample is combined with the emitter sample by
//     multiple importance sampling (power heuristic, Veach 1997, ch. 9); the sun is reached
//     by next-event estimation only and the environment (SH and/or equirect) by the
//     hemisphere samples only — each light is counted exactly once, so the estimator is
//     unbiased for the scene as defined;
//   * Russian roulette from the `rr_depth`-th bounce on: survival probability
//     q = min(0.95, max channel of the throughput), throughput /= q (unbiased);
//   * `bounces`: the largest number of surface reflections a light path may have (0: emitted
//     radiance seen directly only; -1: unlimited, ended by Russian roulette).
// Ray offsets: rays leave a surface at t > 1e-4 x the bounding-box diagonal (RayScene), so
// geometry nearer than that is missed (a small leak in concave corners).
// Determinism: each pixel (or query point) has its own random stream, seeded from
// (seed, index) by SplitMix64, so results are bit-identical for any thread count.
// Standard error: sample standard deviation / sqrt(samples) per pixel and channel.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/scene.hpp"

namespace atmosh::gi {

struct TraceOptions {
  int samples = 16;             ///< paths per pixel or query point, 2 .. 1e7
  int bounces = -1;             ///< -1 unlimited, else 0 .. 100000
  int rr_depth = 3;             ///< Russian roulette from this bounce on (>= 1)
  std::uint64_t seed = 1;
  int threads = 0;              ///< 0 = atmosh::resolve_threads(0)
  std::function<void(double)> progress;  ///< optional, 0..1
  /// Benchmarks only: when set (and threads == 1), every ray cast is appended as
  /// {org x, y, z, dir x, y, z, tnear, tfar}.
  std::vector<std::array<float, 8>>* ray_log = nullptr;
};

struct Stats {
  std::uint64_t rays = 0;          ///< closest-hit + shadow rays
  std::uint64_t shadow_rays = 0;
  double seconds = 0;              ///< wall time of the path tracing (rays and shading)
  double setup_seconds = 0;        ///< wall time of the Embree scene build and light tables
};

/// Per-pixel radiance; planar per channel [c][row * width + col], row 0 at the top.
struct RadianceImage {
  int width = 0, height = 0, samples = 0;
  std::array<std::vector<float>, 3> mean, stderr_;
  Stats stats;
};

struct Irradiance {
  std::vector<glm::dvec3> mean, stderr_;  ///< per query point, per channel
  Stats stats;
};

/// Pinhole image of the scene seen by `camera`, width x height pixels (1..16384 each).
/// InputError for bad options or an invalid scene (validate()).
RadianceImage render(const Scene& scene, const Camera& camera, int width, int height, const TraceOptions& opt);

/// Irradiance E = integral L cos dOmega over the hemisphere of `normals[i]` at `points[i]`
/// (the points need not lie on the mesh; rays leave at the ray offset along the normal).
/// Computed as pi x the radiance leaving a white, non-emitting Lambertian point there.
Irradiance irradiance(const Scene& scene, const std::vector<glm::dvec3>& points, const std::vector<glm::dvec3>& normals,
                      const TraceOptions& opt);

/// Radiance along rays: the path tracer's estimate of the radiance arriving at origins[i]
/// from direction dirs[i] (the radiance a camera ray (origins[i], dirs[i]) sees: emission of
/// the first surface hit, its reflected light, or the environment), opt.samples paths per
/// ray, ray i with its own random stream seeded from (opt.seed, i). dirs need not be unit.
Irradiance radiance_along(const Scene& scene, const std::vector<glm::dvec3>& origins, const std::vector<glm::dvec3>& dirs,
                          const TraceOptions& opt);
/// The same with a direction per sample: sample s of ray i leaves origins[i] along
/// direction(i, u1, u2, weight) (non-zero, finite; need not be unit), u1, u2 uniform in [0, 1)
/// drawn first from ray i's stream; the sample's radiance is multiplied by the weight the
/// function sets (e.g. a pdf ratio, for unbiased averages over a cone or texel).
using RayDirection = std::function<glm::dvec3(std::size_t ray, double u1, double u2, double& weight)>;
Irradiance radiance_along(const Scene& scene, const std::vector<glm::dvec3>& origins, const RayDirection& direction,
                          const TraceOptions& opt);

}  // namespace atmosh::gi
