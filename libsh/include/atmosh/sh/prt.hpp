// atmosh/sh/prt.hpp — precomputed radiance transfer (Sloan, Kautz & Snyder 2002,
// SIGGRAPH, "Precomputed radiance transfer for real-time rendering in dynamic,
// low-frequency lighting environments"), the mesh-independent part.
//
// Diffuse transfer of a surface point p with normal n and albedo rho (dimensionless,
// 0..1) in the SH convention of basis.hpp (real orthonormal, Condon–Shortley, index
// l(l+1)+m, L bands -> L^2 coefficients):
//   unshadowed:  T_i = (rho/pi) int max(0, n.w) Y_i(w) dw
//   shadowed:    T_i = (rho/pi) int V(p, w) max(0, n.w) Y_i(w) dw,  V = 1 if w escapes
//   interreflected (bounce b >= 1, Sloan et al. 2002 sec. 5):
//     T^b_i(p) = (rho/pi) int (1 - V(p, w)) max(0, n.w) T^(b-1)_i(q(p, w)) dw
//     with q the first surface point hit along w; the result is sum_b T^b.
// Exit radiance under a distant light of radiance L(w) with SH coefficients
// l_i = int L Y_i dw (projection.hpp) is the dot product sum_i T_i l_i, in the units
// of L (e.g. W m^-2 sr^-1); the transfer itself is dimensionless (per sr^(1/2)).
//
// Integrals over the sphere use a seeded Monte Carlo sample set (default jittered
// 45 x 45 = 2025 strata, the sampler of projection.hpp; weight 4 pi / N each).
// Accuracy (measured, tests/prt): the clamped cosine has a kink at the horizon; at
// N = 2025 the worst coefficient error over normals is about 1e-2 of the band-0 value
// (AO within 4e-3), at N = 202500 below 7.5e-4. A visibility boundary (shadow edge)
// adds an error falling roughly as N^-3/4 (below 1e-3 in AO at N = 40000 for a sphere
// of 19.5 deg angular radius). `atmosh prt converge` reports error against run time.
// unshadowed_transfer() is exact (clamped-cosine zonal coefficients, Funk–Hecke).
//
// "Simple occlusion": the band-0 coefficient of the shadowed transfer divided by its
// unoccluded value rho Y_00 = rho / (2 sqrt(pi)) is the cosine-weighted ambient
// occlusion in [0, 1] (1 = nothing occluded).
//
// Throws atmosh::InputError for bands < 1, non-finite normals or albedo outside [0, 1].
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "atmosh/sh/projection.hpp"

namespace atmosh::sh::prt {

enum class TransferMode { unshadowed, shadowed, interreflected };

/// Parses "unshadowed" | "shadowed" | "interreflected" (InputError otherwise).
TransferMode parse_transfer_mode(const std::string& name);
const char* transfer_mode_name(TransferMode m);

/// Sample directions with their SH values, shared by every point of a bake.
struct SampleSet {
  int bands = 0;
  std::vector<glm::dvec3> dirs;  ///< unit directions
  std::vector<double> ylm;       ///< ylm[s * bands^2 + i] = Y_i(dirs[s])
  double weight = 0;             ///< 4 pi / dirs.size() [sr]
  int coeffs() const { return bands * bands; }
  const double* y(std::size_t s) const { return ylm.data() + s * static_cast<std::size_t>(coeffs()); }
};

/// Jittered n x n sample set (n = strata per side, 1..20000), seeded (projection.hpp).
SampleSet jittered_samples(int bands, int strata = 45, std::uint64_t seed = 1);
/// Any Monte Carlo sampler of projection.hpp (Method::jittered: opt.samples = strata per side).
SampleSet make_samples(int bands, const ProjectOptions& opt);

/// Exact unshadowed diffuse transfer: rho/pi * A_l-weighted Y_lm(n) (out: bands^2).
void unshadowed_transfer(int bands, const glm::dvec3& normal, double albedo, double* out);

/// Monte Carlo shadowed transfer at one point: visible(s) says whether sample s escapes
/// (it is called only for samples above the tangent plane, n.w > 0). Writes bands^2
/// coefficients to out and returns the cosine-weighted visible fraction (AO estimate,
/// (1/pi) sum_s w V max(0, n.w)).
double shadowed_transfer(const SampleSet& samples, const glm::dvec3& normal, double albedo,
                         const std::function<bool(std::size_t s)>& visible, double* out);

/// Band-0 ambient occlusion from a transfer vector's first coefficient (albedo > 0).
double ambient_occlusion(double t00, double albedo);

/// What one occluded sample ray of a vertex hit: the triangle's three vertices and
/// barycentric weights (1 - b1 - b2, b1, b2); cos_weight = max(0, n.w) of the ray.
struct Hit {
  std::uint32_t v[3];
  float b1, b2;
  float cos_weight;
};

/// Per-vertex records of every occluded sample (hits[v] for vertex v).
using HitList = std::vector<std::vector<Hit>>;

struct BounceReport {
  std::vector<double> energy;  ///< sum over vertices of |T^b|^2 for b = 0..bounces
};

/// Interreflected transfer: direct (n_vertices x bands^2, row-major) is the shadowed
/// transfer (bounce 0); adds `bounces` bounces using the hit records. weight = the
/// sample weight 4 pi / N. Returns the total transfer; fills report if given. Each
/// bounce is a linear map with norm <= max albedo < 1 for closed scenes, so the sum
/// converges geometrically. threads: workers, 0 = the CPUs this process may use (atmosh::resolve_threads).
std::vector<double> interreflect(const std::vector<double>& direct, int bands, const std::vector<double>& albedo,
                                 const HitList& hits, double weight, int bounces, int threads = 1,
                                 BounceReport* report = nullptr);

/// Relighting: sum_i transfer[i] * light[i] over bands^2 coefficients.
double relight(const double* transfer, const double* light, int coeffs);

/// SH of a directional light of irradiance E (W m^-2) from direction dir (towards the
/// light): l_i = E Y_i(dir), i.e. a delta, band-limited (it rings; the relit value is
/// (rho/pi) E V max(0, n.dir) up to the band-limit).
std::vector<double> directional_light(int bands, const glm::dvec3& dir, double irradiance = 1.0);

}  // namespace atmosh::sh::prt
