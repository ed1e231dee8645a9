// Private to atmosh::gi: what the approximate lighting methods (radiosity, lpv) share — the
// scene's triangle normals and bounds, an estimator of the direct irradiance at a surface
// point, and the camera loop that shades the first hit of every camera ray.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/gi/path_tracer.hpp"
#include "atmosh/gi/scene.hpp"
#include "atmosh/prt/bake.hpp"
#include "sampling.hpp"

namespace atmosh::gi::detail {

inline constexpr std::uint64_t kReceiverSalt = 0x9fb21c651e98df25ULL;
inline constexpr std::uint64_t kLightSalt = 0xd6e8feb86659fd93ULL;

/// Flat unit normal of every triangle (counter-clockwise side).
std::vector<glm::dvec3> triangle_normals(const prt::Mesh& m);
/// Axis-aligned bounding box of the mesh.
void mesh_bounds(const prt::Mesh& m, glm::dvec3& lo, glm::dvec3& hi);

/// Irradiance at p (unit normal n) from a triangle of unit radiance, unoccluded: the
/// triangle clipped to n's half-space, then Lambert's polygon formula (exact).
double polygon_irradiance_factor(const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& a, const glm::dvec3& b,
                                 const glm::dvec3& c);

/// One-sample estimate of the direct irradiance at p on a surface of unit normal n (n on
/// the side the light must arrive from): the sun (delta or disc, one shadow ray; unbiased);
/// every emitting triangle's exact unoccluded irradiance (polygon_irradiance_factor) times
/// the visibility of one uniform point on it (one shadow ray; exact where the triangle is
/// wholly visible or hidden, biased only in its penumbra, bounded where the area sampling's
/// 1/d^2 is not); one cosine-distributed direction for the environment (pi L_env if
/// unoccluded; unbiased).
class DirectLight {
 public:
  DirectLight(const Scene& s, const prt::RayScene& rays);
  glm::dvec3 irradiance(Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint64_t& rays) const;
  const std::vector<glm::dvec3>& normals() const { return normal_; }
  bool has_env() const { return has_env_; }
  /// Emitting triangles and their cumulative weights (area × summed emission).
  const std::vector<std::uint32_t>& emitters() const { return emitters_; }
  const std::vector<double>& emitter_cdf() const { return cdf_; }
  std::vector<double> area;  ///< per triangle

 private:
  const Scene& s_;
  const prt::RayScene& rays_;
  std::vector<glm::dvec3> normal_;
  std::vector<std::uint32_t> emitters_;
  std::vector<double> cdf_;
  double total_ = 0, off_ = 0, sun_cos_max_ = 1;
  glm::dvec3 sun_dir_{0, 0, 1}, sun_e_{0.0};
  bool has_env_ = false;
};

/// Irradiance at a receiver: shade(rng, p, n, triangle) with n the unit normal towards the
/// camera; `rays` counts the rays it casts.
using ReceiverShade =
    std::function<glm::dvec3(Rng& rng, const glm::dvec3& p, const glm::dvec3& n, std::uint32_t tri, std::uint64_t& rays)>;

/// Pinhole image: `samples` camera rays per pixel (uniform jitter, seeded per pixel from
/// (seed, pixel)); a miss sees the environment, a hit L_e (towards the camera) + a / pi *
/// max(0, shade(...)). stderr_ over the pixel's rays. stats.seconds: the loop's wall time.
/// `salt` keeps the camera streams of different methods apart (probes: kProbeSalt).
RadianceImage render_receivers(const Scene& scene, const prt::RayScene& rays, const Camera& cam, int width, int height,
                               int samples, std::uint64_t seed, int threads, const ReceiverShade& shade,
                               std::uint64_t salt = kReceiverSalt);

}  // namespace atmosh::gi::detail
